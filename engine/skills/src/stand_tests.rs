//! Standing after a walk: in the walk's posture with its balance corrections, or in the stand
//! pose (`SkillParams::stand_in_walk_posture`).

use crate::walk::Walk;
use crate::{ActiveSkill, BodyIntent, Intent, JointTargets, SkillParams, Skills};
use libero_model::RobotModel;
use libero_world::World;

/// The knee and ankle-roll targets once a robot that walked has stood for a while, with the
/// torso rolling at `roll_rate` [deg/s].
fn standing_after_a_walk(in_walk_posture: bool, roll_rate: f64) -> (ActiveSkill, f64, f64) {
    let model = RobotModel::builtin("T1").unwrap();
    let mut params = SkillParams::builtin(&model).unwrap();
    params.stand_in_walk_posture = in_walk_posture;
    let mut world = World::new(&model, "t", 1);
    // The torso holds the walk's lean, so the walk has no tilt to catch when it stops.
    world.me.pitch_deg = params.walk.torso_lean_deg;
    let mut skills = Skills::new(&model, params).unwrap();
    let mut out = JointTargets::default();
    let walk = Intent {
        body: BodyIntent::Walk {
            forward_m_s: 0.3,
            sideways_m_s: 0.0,
            turn_deg_s: 0.0,
        },
        ..Intent::default()
    };
    let stand = Intent {
        body: BodyIntent::Stand,
        ..Intent::default()
    };
    for i in 0..300 {
        world.time += 0.02;
        world.body.gyro = if i >= 250 {
            [roll_rate, 0.0, 0.0]
        } else {
            [0.0; 3]
        };
        skills.act(
            &model,
            &world,
            if i < 100 { &walk } else { &stand },
            &mut out,
        );
        // The joints follow their targets.
        world.body.joint_angles = out.joints.iter().map(|j| j.q_deg).collect();
    }
    let knee = model.joint_id("left_knee").unwrap();
    let roll = model.joint_id("left_ankle_roll").unwrap();
    (
        skills.active(),
        out.joints[knee].q_deg,
        out.joints[roll].q_deg,
    )
}

#[test]
fn after_a_walk_the_robot_stands_in_the_walk_posture_and_keeps_balancing() {
    let model = RobotModel::builtin("T1").unwrap();
    let params = SkillParams::builtin(&model).unwrap();
    assert!(
        params.stand_in_walk_posture,
        "the shipped T1 stands balanced"
    );
    // The walk's own rest posture, for comparison.
    let mut rest = params.stand_pose(&model).unwrap();
    Walk::new(&model)
        .unwrap()
        .update(&World::new(&model, "t", 1), None, &params.walk, &mut rest);
    let knee = model.joint_id("left_knee").unwrap();
    let stand_knee = params.stand["left_knee"];
    assert!(
        (rest[knee] - stand_knee).abs() > 1.0,
        "the two postures differ"
    );

    let (active, knee_deg, roll_still) = standing_after_a_walk(true, 0.0);
    assert_eq!(active, ActiveSkill::Stand);
    assert!(
        (knee_deg - rest[knee]).abs() < 0.5,
        "{knee_deg} vs {}",
        rest[knee]
    );
    // The walk's balance corrections act on a rolling torso.
    let (_, _, roll_swaying) = standing_after_a_walk(true, 10.0);
    assert!(
        (roll_swaying - roll_still).abs() > 0.1,
        "{roll_still} {roll_swaying}"
    );

    // Without it, the robot goes back to the stand pose, which does not balance.
    let (active, knee_deg, roll_still) = standing_after_a_walk(false, 0.0);
    assert_eq!(active, ActiveSkill::Stand);
    assert!((knee_deg - stand_knee).abs() < 1e-6, "{knee_deg}");
    let (_, _, roll_swaying) = standing_after_a_walk(false, 10.0);
    assert_eq!(roll_swaying, roll_still);
}

#[test]
fn a_robot_the_server_put_down_stands_in_the_stand_pose_until_it_walks_again() {
    let model = RobotModel::builtin("T1").unwrap();
    let params = SkillParams::builtin(&model).unwrap();
    let knee = model.joint_id("left_knee").unwrap();
    let stand_knee = params.stand["left_knee"];
    let mut world = World::new(&model, "t", 1);
    // The torso holds the walk's lean, so the walk has no tilt to catch when it stops.
    world.me.pitch_deg = params.walk.torso_lean_deg;
    let mut skills = Skills::new(&model, params).unwrap();
    let mut out = JointTargets::default();
    let intent = |body| Intent {
        body,
        ..Intent::default()
    };
    let walk = intent(BodyIntent::Walk {
        forward_m_s: 0.3,
        sideways_m_s: 0.0,
        turn_deg_s: 0.0,
    });
    let stand = intent(BodyIntent::Stand);
    let mut run = |world: &mut World, intent: &Intent, cycles: usize, placed: bool| {
        for i in 0..cycles {
            world.time += 0.02;
            skills.act(&model, world, intent, &mut out);
            world.body.joint_angles = if placed && i == 0 {
                // A placement: the server straightens every joint.
                vec![0.0; out.joints.len()]
            } else {
                out.joints.iter().map(|j| j.q_deg).collect()
            };
        }
        out.joints[knee].q_deg
    };
    run(&mut world, &walk, 100, false);
    let walked = run(&mut world, &stand, 100, false);
    assert!((walked - stand_knee).abs() > 1.0, "{walked}");
    // Put down while standing: the stand pose, until it walks again.
    let placed = run(&mut world, &stand, 100, true);
    assert!((placed - stand_knee).abs() < 1e-6, "{placed}");
    run(&mut world, &walk, 100, false);
    let walked_again = run(&mut world, &stand, 100, false);
    assert!(
        (walked_again - walked).abs() < 0.5,
        "{walked_again} vs {walked}"
    );
}
