//! NAO forward kinematics against simspark.md §6, worked by hand.

use libero_model::kinematics::Kinematics;
use libero_model::RobotModel;
use nalgebra::Vector3;

fn close(actual: &Vector3<f64>, expected: [f64; 3]) -> bool {
    (actual - Vector3::from(expected)).norm() < 1e-9
}

#[test]
fn zero_pose_heights_match_section_6_6() {
    // (type, torso centre above the soles, camera above the ground)
    for (t, torso, camera) in [
        (0, 0.385, 0.54),
        (1, 0.42164, 0.57664),
        (2, 0.385, 0.54),
        (3, 0.440736848, 0.595736848),
        (4, 0.385, 0.54),
    ] {
        let model = RobotModel::builtin(&format!("NAO_type{t}")).unwrap();
        assert!(
            (model.standing_torso_height - torso).abs() < 1e-9,
            "type {t}"
        );
        let kin = Kinematics::new(&model);
        let zero = vec![0.0; model.joints.len()];
        for sole in ["left_sole", "right_sole"] {
            let z = kin.frame_pose(sole, &zero).unwrap().translation.z;
            assert!((z + torso).abs() < 1e-9, "type {t} {sole}: {z}");
        }
        let cam = kin.frame_pose("camera", &zero).unwrap().translation.z;
        assert!((cam + torso - camera).abs() < 1e-9, "type {t} camera {cam}");
    }
}

#[test]
fn zero_pose_feet_sit_where_section_6_4_puts_them() {
    let model = RobotModel::builtin("NAO_type0").unwrap();
    let kin = Kinematics::new(&model);
    let zero = vec![0.0; model.joints.len()];
    // SimSpark foot centres (±0.055, 0.025, −0.375) in x-right/y-forward → ours (0.025, ∓0.055, −0.375).
    let left = kin.frame_pose("left_foot", &zero).unwrap();
    let right = kin.frame_pose("right_foot", &zero).unwrap();
    assert!(
        close(&left.translation.vector, [0.025, 0.055, -0.375]),
        "{left}"
    );
    assert!(
        close(&right.translation.vector, [0.025, -0.055, -0.375]),
        "{right}"
    );
    // Lower-arm centres (±0.098, 0.14, 0.084): arms straight forward.
    let hand = kin.frame_pose("right_hand", &zero).unwrap();
    assert!(
        close(&hand.translation.vector, [0.14, -0.098, 0.084]),
        "{hand}"
    );
}

#[test]
fn ninety_degree_knee_bend_swings_the_shank_backward() {
    let model = RobotModel::builtin("NAO_type0").unwrap();
    let kin = Kinematics::new(&model);
    let mut angles = vec![0.0; model.joints.len()];
    // Knee flexion is negative (§6.3).
    angles[model.joint_id("left_knee").unwrap()] = -90.0;
    let mut poses = kin.new_poses();
    kin.forward(&angles, &mut poses).unwrap();
    let knee = poses
        .joint_in_torso(model.joint_id("left_knee").unwrap())
        .unwrap();
    let roll = poses
        .joint_in_torso(model.joint_id("left_ankle_roll").unwrap())
        .unwrap();
    // Knee at hip (−0.01, 0.055, −0.115) + (0.005, 0, −0.12); shank (0.1 + 0.005) now points back.
    assert!(
        close(&knee.translation.vector, [-0.005, 0.055, -0.235]),
        "{knee}"
    );
    assert!(
        close(&roll.translation.vector, [-0.11, 0.055, -0.235]),
        "{roll}"
    );
    // The foot's forward axis now points straight down.
    let forward = roll.rotation * Vector3::x();
    assert!(close(&forward, [0.0, 0.0, -1.0]), "{forward}");
}

#[test]
fn hip_yaw_pitch_toes_out_and_lifts_as_section_6_3_says() {
    let model = RobotModel::builtin("NAO_type0").unwrap();
    let kin = Kinematics::new(&model);
    let mut angles = vec![0.0; model.joints.len()];
    angles[model.joint_id("left_hip_yaw_pitch").unwrap()] = -30.0;
    angles[model.joint_id("right_hip_yaw_pitch").unwrap()] = -30.0;
    for (sole, outward) in [("left_sole", 1.0), ("right_sole", -1.0)] {
        let r = kin.frame_pose(sole, &angles).unwrap().rotation;
        let toes = r * Vector3::x();
        let toe_out = (outward * toes.y).atan2(toes.x).to_degrees();
        let toe_up = toes.z.asin().to_degrees();
        // "each foot toes out by 22° with its toes raised 21°" (rounded in the doc).
        assert!((toe_out - 22.0).abs() < 1.0, "{sole}: toe out {toe_out}");
        assert!((toe_up - 21.0).abs() < 1.0, "{sole}: toe up {toe_up}");
    }
}
