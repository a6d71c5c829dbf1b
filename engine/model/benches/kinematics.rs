//! Full-body FK and one leg IK per call, against a naive FK that composes 4×4 matrices into
//! freshly allocated vectors.

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use libero_model::kinematics::{Kinematics, LegIk, Side};
use libero_model::RobotModel;
use nalgebra::{Matrix4, Rotation3, Unit, Vector3};

/// The textbook version: per call, build every joint's homogeneous matrix and every pose in new
/// vectors, parents looked up by name.
fn naive_forward(model: &RobotModel, angles_deg: &[f64]) -> Vec<Matrix4<f64>> {
    let mut poses: Vec<Matrix4<f64>> = Vec::new();
    for (joint, angle) in model.joints.iter().zip(angles_deg) {
        let mut local = Matrix4::new_translation(&Vector3::from(joint.origin));
        let rotation = Rotation3::from_axis_angle(
            &Unit::new_normalize(Vector3::from(joint.axis)),
            angle.to_radians(),
        );
        local *= rotation.to_homogeneous();
        let parent = joint
            .parent
            .as_ref()
            .and_then(|p| model.joints.iter().position(|j| &j.name == p));
        let pose = match parent {
            Some(p) => poses[p] * local,
            None => local,
        };
        poses.push(pose);
    }
    poses
}

fn bench(c: &mut Criterion) {
    let model = RobotModel::builtin("T1").unwrap();
    let kin = Kinematics::new(&model);
    let mut poses = kin.new_poses();
    let mut angles = vec![0.0; model.joints.len()];
    for (name, value) in [
        ("left_hip_pitch", -23.0),
        ("left_knee", 46.0),
        ("left_ankle_pitch", -23.0),
        ("head_yaw", 20.0),
    ] {
        angles[model.joint_id(name).unwrap()] = value;
    }
    c.bench_function("t1_full_body_fk", |b| {
        b.iter(|| kin.forward(black_box(&angles), &mut poses).unwrap())
    });
    c.bench_function("t1_full_body_fk_naive_baseline", |b| {
        b.iter(|| naive_forward(&model, black_box(&angles)))
    });
    let leg = LegIk::new(&model, &kin, Side::Left).unwrap();
    let target = kin.frame_pose("left_sole", &angles).unwrap();
    c.bench_function("t1_left_leg_ik", |b| {
        b.iter(|| {
            let mut start = vec![0.0; 23];
            leg.solve(&kin, black_box(&target), &mut start).unwrap()
        })
    });
    let nao = RobotModel::builtin("NAO_type0").unwrap();
    let nao_kin = Kinematics::new(&nao);
    let nao_leg = LegIk::new(&nao, &nao_kin, Side::Right).unwrap();
    let mut nao_angles = vec![0.0; nao.joints.len()];
    for (name, value) in [
        ("right_hip_pitch", 30.0),
        ("right_knee", -60.0),
        ("right_ankle_pitch", 30.0),
    ] {
        nao_angles[nao.joint_id(name).unwrap()] = value;
    }
    let nao_target = nao_kin.frame_pose("right_sole", &nao_angles).unwrap();
    c.bench_function("nao_right_leg_ik", |b| {
        b.iter(|| {
            let mut start = vec![0.0; nao.joints.len()];
            nao_leg
                .solve(&nao_kin, black_box(&nao_target), &mut start)
                .unwrap()
        })
    });
}

criterion_group!(benches, bench);
criterion_main!(benches);
