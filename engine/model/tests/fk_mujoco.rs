//! Forward kinematics against MuJoCo itself: fixtures written by `tools/kinematics_fixtures.py`
//! from the server's own robot.xml files (random joint angles within limits).

use libero_model::kinematics::Kinematics;
use libero_model::RobotModel;
use nalgebra::{Isometry3, Quaternion, Translation3, UnitQuaternion};
use serde_json::Value;

const MAX_POSITION_ERROR_M: f64 = 0.001;
const MAX_ANGLE_ERROR_DEG: f64 = 0.1;

/// MuJoCo site name → our frame name.
const SITES: [(&str, &str); 4] = [
    ("camera", "camera"),
    ("head-vismarker", "head_vismarker"),
    ("lfoot-vismarker", "left_foot"),
    ("rfoot-vismarker", "right_foot"),
];

fn pose(value: &Value) -> Isometry3<f64> {
    let num = |v: &Value| v.as_f64().expect("number");
    let p: Vec<f64> = value["pos"].as_array().unwrap().iter().map(num).collect();
    let q: Vec<f64> = value["quat"].as_array().unwrap().iter().map(num).collect();
    Isometry3::from_parts(
        Translation3::new(p[0], p[1], p[2]),
        UnitQuaternion::from_quaternion(Quaternion::new(q[0], q[1], q[2], q[3])),
    )
}

/// (position error [m], angle error [deg]).
fn difference(ours: &Isometry3<f64>, theirs: &Isometry3<f64>) -> (f64, f64) {
    let dp = (ours.translation.vector - theirs.translation.vector).norm();
    let da = ours.rotation.angle_to(&theirs.rotation).to_degrees();
    (dp, da)
}

fn check_robot(robot: &str, fixture: &str) {
    let model = RobotModel::builtin(robot).unwrap();
    let kin = Kinematics::new(&model);
    let fixture: Value = serde_json::from_str(fixture).unwrap();
    let poses = fixture["poses"].as_array().unwrap();
    assert!(poses.len() >= 50, "{robot}: only {} poses", poses.len());
    let mut out = kin.new_poses();
    let (mut worst_p, mut worst_a, mut checks) = (0.0f64, 0.0f64, 0);
    for (n, record) in poses.iter().enumerate() {
        let mut angles = vec![f64::NAN; model.joints.len()];
        for (perceptor, angle) in record["angles_deg"].as_object().unwrap() {
            let id = model
                .joint_by_perceptor(perceptor)
                .unwrap_or_else(|| panic!("{robot}: no joint for {perceptor}"));
            angles[id] = angle.as_f64().unwrap();
        }
        assert!(
            angles.iter().all(|a| a.is_finite()),
            "{robot}: fixture misses a joint"
        );
        kin.forward(&angles, &mut out).unwrap();
        for (perceptor, expected) in record["joint_bodies"].as_object().unwrap() {
            let id = model.joint_by_perceptor(perceptor).unwrap();
            let (dp, da) = difference(out.joint_in_torso(id).unwrap(), &pose(expected));
            assert!(
                dp <= MAX_POSITION_ERROR_M && da <= MAX_ANGLE_ERROR_DEG,
                "{robot} pose {n} joint {perceptor}: {dp} m, {da}°"
            );
            worst_p = worst_p.max(dp);
            worst_a = worst_a.max(da);
            checks += 1;
        }
        for (site, frame) in SITES {
            let frame_id = kin.frame_id(frame).unwrap();
            let ours = out.frame_in_torso(frame_id).unwrap();
            let (dp, da) = difference(ours, &pose(&record["sites"][site]));
            assert!(
                dp <= MAX_POSITION_ERROR_M && da <= MAX_ANGLE_ERROR_DEG,
                "{robot} pose {n} site {site}: {dp} m, {da}°"
            );
            let single = kin.frame_pose(frame, &angles).unwrap();
            assert!(
                difference(&single, ours).0 < 1e-12,
                "frame_pose disagrees with forward"
            );
            worst_p = worst_p.max(dp);
            worst_a = worst_a.max(da);
            checks += 1;
        }
    }
    println!(
        "{robot}: {checks} poses checked, worst {:.3e} m, {:.3e}°",
        worst_p, worst_a
    );
}

#[test]
fn t1_matches_mujoco() {
    check_robot("T1", include_str!("fixtures/fk_t1.json"));
}

#[test]
fn k1_matches_mujoco() {
    check_robot("K1", include_str!("fixtures/fk_k1.json"));
}

#[test]
fn wrong_angle_count_is_an_error_not_a_panic() {
    let model = RobotModel::builtin("T1").unwrap();
    let kin = Kinematics::new(&model);
    let mut out = kin.new_poses();
    assert!(kin.forward(&[0.0; 3], &mut out).is_err());
    assert!(kin.frame_pose("camera", &[0.0; 3]).is_err());
    assert!(kin.frame_pose("no_such_frame", &[0.0; 23]).is_err());
}
