//! Damped least-squares IK on arbitrary chains: arms to a point, head look-at, legs as a
//! cross-check of the closed form, absurd targets without NaN.

use libero_model::kinematics::{Chain, IkOptions, IkTarget, Kinematics, NumericIk};
use libero_model::RobotModel;
use nalgebra::{Unit, Vector3};
use proptest::prelude::*;

fn in_limits(model: &RobotModel, fractions: &[f64]) -> Vec<f64> {
    model
        .joints
        .iter()
        .zip(fractions.iter().cycle())
        .map(|(j, f)| j.limits_deg.0 + f * (j.limits_deg.1 - j.limits_deg.0))
        .collect()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(500))]

    #[test]
    fn arm_reaches_points_made_by_fk(
        fractions in proptest::collection::vec(0.05..=0.95f64, 23),
        start in proptest::collection::vec(0.05..=0.95f64, 23),
    ) {
        let model = RobotModel::builtin("T1").unwrap();
        let kin = Kinematics::new(&model);
        let chain = Chain::to_joint(&kin, Some("left_shoulder_pitch"), "left_elbow_yaw").unwrap();
        let ik = NumericIk::new(chain.clone(), IkOptions::default());
        let truth = in_limits(&model, &fractions);
        let goal = chain.tip_pose(&kin, &truth).unwrap().translation.vector;
        let mut angles = in_limits(&model, &start);
        let report = ik.solve(&kin, &IkTarget::Position(goal), &mut angles).unwrap();
        let reached = chain.tip_pose(&kin, &angles).unwrap().translation.vector;
        // A 3-joint position task can stall at a joint limit from a far start; when the solver
        // says it arrived it must have, and it must say so most of the time (checked below).
        if report.reached {
            prop_assert!((reached - goal).norm() <= 5e-4, "{report:?}");
        }
        prop_assert!((reached - goal).norm() - report.position_error < 1e-12);
    }

    #[test]
    fn absurd_targets_never_give_nan(
        point in proptest::array::uniform3(-1e9..1e9f64),
        which in 0..3usize,
    ) {
        let model = RobotModel::builtin("NAO_type0").unwrap();
        let kin = Kinematics::new(&model);
        let chain = Chain::to_frame(&kin, None, ["camera", "left_hand", "right_sole"][which]).unwrap();
        let ik = NumericIk::new(chain, IkOptions::default());
        let mut angles = vec![0.0; model.joints.len()];
        let target = IkTarget::Position(Vector3::from(point));
        let report = ik.solve(&kin, &target, &mut angles).unwrap();
        prop_assert!(angles.iter().all(|a| a.is_finite()));
        prop_assert!(report.position_error.is_finite());
    }
}

#[test]
fn arm_position_ik_mostly_converges_from_a_random_start() {
    let model = RobotModel::builtin("T1").unwrap();
    let kin = Kinematics::new(&model);
    let chain = Chain::to_joint(&kin, Some("left_shoulder_pitch"), "left_elbow_yaw").unwrap();
    let ik = NumericIk::new(chain.clone(), IkOptions::default());
    let mut seed = 7u64;
    let mut rnd = || {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        0.05 + 0.9 * ((seed >> 11) as f64 / (1u64 << 53) as f64)
    };
    let mut reached = 0;
    for _ in 0..500 {
        let truth = in_limits(&model, &(0..23).map(|_| rnd()).collect::<Vec<_>>());
        let mut angles = in_limits(&model, &(0..23).map(|_| rnd()).collect::<Vec<_>>());
        let goal = chain.tip_pose(&kin, &truth).unwrap().translation.vector;
        if ik
            .solve(&kin, &IkTarget::Position(goal), &mut angles)
            .unwrap()
            .reached
        {
            reached += 1;
        }
    }
    // Measured: 429 of 500 (seed 7). Starts drawn across the whole range sometimes end in a
    // limit-bound local minimum; callers start from last cycle's angles, which are close.
    assert!(reached >= 420, "only {reached} of 500 reached");
}

#[test]
fn head_looks_at_a_point() {
    let model = RobotModel::builtin("NAO_type0").unwrap();
    let kin = Kinematics::new(&model);
    let chain = Chain::to_frame(&kin, Some("head_yaw"), "camera").unwrap();
    let ik = NumericIk::new(chain.clone(), IkOptions::default());
    let ball = Vector3::new(1.0, 0.4, -0.3);
    let mut angles = vec![0.0; model.joints.len()];
    let target = IkTarget::LookAt {
        point: ball,
        axis: Unit::new_normalize(Vector3::x()),
    };
    let report = ik.solve(&kin, &target, &mut angles).unwrap();
    assert!(report.reached, "{report:?}");
    let camera = chain.tip_pose(&kin, &angles).unwrap();
    let view = camera.rotation * Vector3::x();
    let wanted = (ball - camera.translation.vector).normalize();
    assert!(view.angle(&wanted).to_degrees() < 0.01);
    // Left and down: head yaw positive (left), head pitch negative (down) in SimSpark's signs.
    assert!(angles[model.joint_id("head_yaw").unwrap()] > 0.0);
    assert!(angles[model.joint_id("head_pitch").unwrap()] < 0.0);
}

#[test]
fn numeric_leg_ik_agrees_with_fk_from_a_near_start() {
    let model = RobotModel::builtin("T1").unwrap();
    let kin = Kinematics::new(&model);
    let chain = Chain::to_frame(&kin, Some("right_hip_pitch"), "right_sole").unwrap();
    assert_eq!(chain.joints().len(), 6);
    let ik = NumericIk::new(chain.clone(), IkOptions::default());
    let mut truth = vec![0.0; 23];
    for (name, value) in [
        ("right_hip_pitch", -25.0),
        ("right_knee", 50.0),
        ("right_ankle_pitch", -25.0),
        ("waist", 10.0),
    ] {
        truth[model.joint_id(name).unwrap()] = value;
    }
    let goal = chain.tip_pose(&kin, &truth).unwrap();
    // Start 5° off in every leg joint. (From the all-zero pose the knee sits on its 0° stop where
    // shortening the leg needs a negative knee, so a projected numeric solver stays there; the
    // closed-form leg IK exists for that reason.)
    let mut angles = truth.clone();
    for &j in chain.joints() {
        angles[j] += 5.0;
    }
    let report = ik.solve(&kin, &IkTarget::Pose(goal), &mut angles).unwrap();
    assert!(report.reached, "{report:?}");
    for (j, (a, t)) in angles.iter().zip(&truth).enumerate() {
        assert!((a - t).abs() < 0.01, "joint {j}: {a} vs {t}");
    }
}
