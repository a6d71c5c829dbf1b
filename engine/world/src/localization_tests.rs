use super::*;
use crate::synthetic::Scene;
use libero_model::RobotModel;

#[test]
fn closed_form_fit_recovers_an_exact_pose() {
    let landmarks: Vec<LevelledLandmark> = [[10.0, 3.0], [-4.0, 8.0], [2.0, -6.0]]
        .iter()
        .map(|q| {
            let field = Vector3::new(q[0], q[1], 0.0);
            let (p, yaw) = (Vector2::new(1.5, -2.0), 0.7);
            let offset = rotate2(field.xy() - p, -yaw);
            LevelledLandmark {
                field,
                offset: Vector3::new(offset.x, offset.y, -0.6),
                sigma: 0.01,
            }
        })
        .collect();
    let fit = closed_form_fit(&landmarks).unwrap();
    assert!((fit.position - Vector2::new(1.5, -2.0)).norm() < 1e-9);
    assert!((fit.yaw - 0.7).abs() < 1e-9);
    assert!(fit.rms < 1e-9);
    assert!(closed_form_fit(&landmarks[..1]).is_none());
}

#[test]
fn one_landmark_keeps_position_with_known_yaw() {
    let model = RobotModel::builtin("T1").unwrap();
    let field = FieldGeometry::builtin("fifa7vs7").unwrap();
    let scene = Scene::new(&model, &field);
    let params = crate::WorldParams::builtin().localization;
    let mut loc = Localizer::new(&model, Kinematics::new(&model), params);
    let torso = Scene::torso(3.0, 1.0, 0.66, 45.0, 0.0, 0.0);
    let full = scene.percept(&torso, 0.0, true, None);
    loc.update(
        &field,
        &scene.angles,
        full.gyro,
        full.accel,
        full.vision.as_ref(),
        0.0,
        0.0,
        true,
    );
    assert!(loc.estimate().localized);
    // Only one landmark from now on, and the filter starts 0.3 m off.
    loc.state.x += 0.3;
    let mut single = full.clone();
    single.vision.as_mut().unwrap().landmarks.truncate(1);
    for k in 1..100 {
        let t = 0.02 * k as f64;
        loc.update(
            &field,
            &scene.angles,
            single.gyro,
            single.accel,
            single.vision.as_ref(),
            t,
            0.02,
            true,
        );
    }
    let e = loc.estimate();
    // One landmark fixes the distance to it (σ = 0.1 m at 30 m in world.ron); the gyro-held yaw keeps the bearing.
    let name = single.vision.as_ref().unwrap().landmarks[0].name;
    let mark = field.landmark(name).unwrap();
    let range = |p: [f64; 2]| ((p[0] - mark[0]).powi(2) + (p[1] - mark[1]).powi(2)).sqrt();
    assert!(
        (range(e.position) - range([3.0, 1.0])).abs() < 0.1,
        "{} vs {} {e:?}",
        range(e.position),
        range([3.0, 1.0])
    );
    assert!((e.yaw_deg - 45.0).abs() < 1.0, "{e:?}");
    let error = ((e.position[0] - 3.0).powi(2) + (e.position[1] - 1.0).powi(2)).sqrt();
    assert!(error < 0.3, "no worse than where it started: {e:?}");
}
