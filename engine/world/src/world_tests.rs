use super::*;
use crate::synthetic::Scene;
use libero_protocol::percept::{Polar, Seen, SeenPlayer, Vision};

fn t1() -> RobotModel {
    RobotModel::builtin("T1").unwrap()
}

#[test]
fn localizes_from_synthetic_vision_with_head_panning() {
    let model = t1();
    let field = FieldGeometry::builtin("fifa7vs7").unwrap();
    let mut scene = Scene::new(&model, &field);
    let mut world = World::new(&model, "Libero", 2);
    scene.set("head_pitch", 20.0);
    let torso = Scene::torso(-7.3, 4.1, 0.66, 123.0, 1.0, -2.0);
    // The soles flat on the ground under the tilted torso, as a standing robot's are (the
    // world model reads the tilt from the stance leg too).
    for side in ["left", "right"] {
        scene.set(&format!("{side}_ankle_pitch"), 2.0);
        scene.set(&format!("{side}_ankle_roll"), -1.0);
    }
    let mut worst: f64 = 0.0;
    for cycle in 0..200 {
        let pan = 60.0 * (cycle as f64 * 0.05).sin();
        scene.set("head_yaw", pan);
        let p = scene.percept(&torso, 10.0 + 0.02 * cycle as f64, cycle % 2 == 0, None);
        world.update(&model, &p);
        if cycle > 20 {
            let e = &world.me;
            let err = ((e.position[0] + 7.3).powi(2) + (e.position[1] - 4.1).powi(2)).sqrt();
            worst = worst.max(err);
            assert!((e.yaw_deg - 123.0).abs() < 0.2, "yaw {}", e.yaw_deg);
        }
    }
    assert!(world.me.localized);
    assert!(worst < 0.03, "worst position error {worst}");
    assert!((world.me.height.unwrap() - 0.66).abs() < 0.03);
}

#[test]
fn relocalizes_after_being_moved_and_survives_no_landmarks() {
    let model = t1();
    let field = FieldGeometry::builtin("fifa7vs7").unwrap();
    let scene = Scene::new(&model, &field);
    let mut world = World::new(&model, "Libero", 2);
    let a = Scene::torso(5.0, -3.0, 0.66, 0.0, 0.0, 0.0);
    for cycle in 0..20 {
        world.update(
            &model,
            &scene.percept(&a, 0.02 * cycle as f64, cycle % 2 == 0, None),
        );
    }
    assert!((world.me.position[0] - 5.0).abs() < 0.03);
    let b = Scene::torso(-20.0, 10.0, 0.66, -150.0, 0.0, 0.0);
    for cycle in 20..40 {
        world.update(
            &model,
            &scene.percept(&b, 0.02 * cycle as f64, cycle % 2 == 0, None),
        );
    }
    assert!((world.me.position[0] + 20.0).abs() < 0.03, "{:?}", world.me);
    assert!((world.me.yaw_deg + 150.0).abs() < 0.3, "{:?}", world.me);
    // Vision without landmarks: the estimate stays put and finite.
    for cycle in 40..60 {
        let mut p = scene.percept(&b, 0.02 * cycle as f64, cycle % 2 == 0, None);
        if let Some(v) = p.vision.as_mut() {
            v.landmarks.clear();
        }
        world.update(&model, &p);
    }
    assert!(world.me.position.iter().all(|c| c.is_finite()));
    assert!((world.me.position[0] + 20.0).abs() < 0.05);
}

#[test]
fn strange_percepts_do_not_panic_or_produce_nan() {
    let model = t1();
    let mut world = World::new(&model, "Libero", 2);
    let weird = Polar {
        distance: f64::NAN,
        azimuth_deg: 1e308,
        elevation_deg: -0.0,
    };
    let zero = Polar {
        distance: 0.0,
        azimuth_deg: 0.0,
        elevation_deg: 0.0,
    };
    let percepts = [
        Percept::default(),
        Percept {
            time: Some(f64::NAN),
            accel: Some([0.0; 3]),
            gyro: Some([f64::INFINITY, 0.0, 0.0]),
            vision: Some(Vision::default()),
            ..Default::default()
        },
        Percept {
            time: Some(1.0),
            vision: Some(Vision {
                landmarks: [
                    Seen {
                        name: "l_luf",
                        at: zero,
                    },
                    Seen {
                        name: "l_luf",
                        at: zero,
                    },
                    Seen {
                        name: "nonsense",
                        at: weird,
                    },
                    Seen {
                        name: "g_rup",
                        at: weird,
                    },
                ]
                .into_iter()
                .collect(),
                ball: Some(weird),
                players: [SeenPlayer {
                    team: "Other",
                    unum: 3,
                    parts: [Seen {
                        name: "head",
                        at: weird,
                    }]
                    .into_iter()
                    .collect(),
                }]
                .into_iter()
                .collect(),
                ..Vision::default()
            }),
            ..Default::default()
        },
    ];
    for p in percepts.iter().cycle().take(30) {
        world.update(&model, p);
        assert!(world.me.position.iter().all(|c| c.is_finite()));
        assert!(world.me.yaw_deg.is_finite());
        assert!(world.ball.position.iter().all(|c| c.is_finite()));
        assert!(world.ball.predicted_stop.iter().all(|c| c.is_finite()));
    }
}

#[test]
fn own_frame_for_the_right_team() {
    let model = t1();
    let mut world = World::new(&model, "Libero", 2);
    assert_eq!(world.to_own_frame([3.0, 1.0]), [3.0, 1.0]);
    world.game.side = Some(Side::Right);
    assert_eq!(world.to_own_frame([3.0, 1.0]), [-3.0, -1.0]);
    assert!((world.yaw_to_own_frame(170.0) + 10.0).abs() < 1e-9);
}

#[test]
fn eval_log_lines_are_json_with_truth_kept_apart() {
    let model = t1();
    let field = FieldGeometry::builtin("fifa7vs7").unwrap();
    let scene = Scene::new(&model, &field);
    let mut world = World::new(&model, "Libero", 2);
    let mut log = eval_log::EvalLogger::new(Vec::new());
    let torso = Scene::torso(1.0, 2.0, 0.66, 30.0, 0.0, 0.0);
    for cycle in 0..4 {
        let mut p = scene.percept(&torso, 0.02 * cycle as f64, cycle % 2 == 0, None);
        p.truth_position = Some([1.0, 2.0, 0.66]);
        p.truth_orientation = Some([1.0, 0.0, 0.0, 0.0]);
        world.update(&model, &p);
        log.write(&world).unwrap();
    }
    let text = String::from_utf8(log.into_inner()).unwrap();
    let lines: Vec<serde_json::Value> = text
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    assert_eq!(lines.len(), 4);
    let last = &lines[3];
    assert!((last["me"]["position"][0].as_f64().unwrap() - 1.0).abs() < 0.05);
    assert_eq!(last["truth"]["yaw_deg"].as_f64().unwrap(), 0.0);
    // The estimate is from vision (30°), not from the (deliberately different) truth (0°).
    assert!((last["me"]["yaw_deg"].as_f64().unwrap() - 30.0).abs() < 0.5);
}
