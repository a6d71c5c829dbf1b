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

/// Feed the tilt filter `seconds` of IMU readings from `imu(t) -> (gyro deg/s, accel)`.
fn run_tilt(
    loc: &mut Localizer,
    seconds: f64,
    mut imu: impl FnMut(f64) -> ([f64; 3], [f64; 3]),
    mut check: impl FnMut(f64, &Localizer),
) {
    for k in 0..(seconds / 0.02) as usize {
        let t = 0.02 * k as f64;
        let (gyro, accel) = imu(t);
        loc.update_tilt(Some(gyro), Some(accel), 0.02, None);
        check(t, loc);
    }
}

fn tilt_localizer() -> Localizer {
    let model = RobotModel::builtin("T1").unwrap();
    let params = crate::WorldParams::builtin().localization;
    Localizer::new(&model, Kinematics::new(&model), params)
}

fn roll_pitch_deg(loc: &Localizer) -> (f64, f64) {
    let (roll, pitch, _) = loc.tilt.euler_angles();
    (roll.to_degrees(), pitch.to_degrees())
}

#[test]
fn walking_sway_does_not_read_as_tilt() {
    // An upright torso swaying sideways at ±2.5 m/s² (a walk's lateral acceleration): the
    // specific force leans ±14°, the torso does not turn at all.
    let mut loc = tilt_localizer();
    let mut worst: f64 = 0.0;
    run_tilt(
        &mut loc,
        10.0,
        |t| {
            let lateral = 2.5 * (std::f64::consts::TAU * t / 0.7).sin();
            ([0.0, 0.0, 0.0], [0.0, lateral, 9.81])
        },
        |t, loc| {
            if t > 1.0 {
                let (roll, pitch) = roll_pitch_deg(loc);
                worst = worst.max(roll.abs()).max(pitch.abs());
            }
        },
    );
    // The accelerometer alone reads the full ±14°; the filter leaves a ripple of about 2°.
    assert!(worst < 3.0, "sway read as {worst:.1}° of tilt");
}

#[test]
fn the_gyro_carries_a_real_lean_and_a_still_body_trusts_the_accelerometer() {
    let mut loc = tilt_localizer();
    // Lean forward at 20°/s for 1 s while the accelerometer is shaken by ±3 m/s² along x: the
    // estimate follows the gyro.
    let rate = 20.0f64;
    run_tilt(
        &mut loc,
        1.0,
        |t| {
            let pitch = (rate * t).to_radians();
            let shake = 3.0 * (std::f64::consts::TAU * t / 0.35).sin();
            (
                [0.0, rate, 0.0],
                [-9.81 * pitch.sin() + shake, 0.0, 9.81 * pitch.cos()],
            )
        },
        |_, _| {},
    );
    let (_, pitch) = roll_pitch_deg(&loc);
    assert!(
        (pitch - 20.0).abs() < 2.0,
        "pitch {pitch:.1}° after a 20° lean"
    );
    // Then moved by a monitor to 10° of roll, standing still: the accelerometer wins quickly.
    let roll = 10f64.to_radians();
    run_tilt(
        &mut loc,
        0.5,
        |_| ([0.0, 0.0, 0.0], [0.0, 9.81 * roll.sin(), 9.81 * roll.cos()]),
        |_, _| {},
    );
    let (r, p) = roll_pitch_deg(&loc);
    assert!(
        (r - 10.0).abs() < 1.0 && p.abs() < 1.0,
        "roll {r:.1}°, pitch {p:.1}°"
    );
}

#[test]
fn a_still_body_found_upside_down_from_the_estimate_is_trusted_within_half_a_second() {
    let mut loc = tilt_localizer();
    // Lying on the back, still: the estimate settles there.
    run_tilt(&mut loc, 0.5, |_| ([0.0; 3], [9.81, 0.0, 0.0]), |_, _| {});
    let (_, pitch) = roll_pitch_deg(&loc);
    assert!((pitch + 90.0).abs() < 1.0, "on the back: pitch {pitch:.1}°");
    // Turned face down by a monitor move the gyro never saw, then lying still with a little
    // contact jitter (the opposite of the estimate: a linear blend does not turn it at all).
    let mut face_down_at = None;
    run_tilt(
        &mut loc,
        1.0,
        |t| {
            let jitter = 0.05 * (std::f64::consts::TAU * t / 0.1).sin();
            ([0.0; 3], [-9.81, jitter, 0.0])
        },
        |t, loc| {
            let up = loc.up;
            if face_down_at.is_none() && up.x < -0.99 {
                face_down_at = Some(t);
            }
        },
    );
    // About 0.2 s until the smoothed accelerometer has settled and the body counts as still,
    // then a 180° error shrinks by 30 % per cycle.
    assert!(
        face_down_at.is_some_and(|t| t < 0.5),
        "face down read at {face_down_at:?} s; up {:?}",
        loc.up
    );
}

#[test]
fn once_localized_two_landmarks_relocalize_only_when_two_frames_agree_three_at_once() {
    let mut loc = tilt_localizer();
    let fit = PoseFit {
        position: Vector2::new(1.0, 0.0),
        yaw: 0.0,
        rms: 0.01,
        spread: 5.0,
    };
    // Not yet localized: any consistent fit starts the estimate.
    assert!(loc.should_relocalize(&fit, 2, None));
    loc.reset_to(&PoseFit {
        position: Vector2::zeros(),
        ..fit
    });
    // 1 m off the estimate: two landmarks fix a pose whatever a tilted camera made of them,
    // three check each other ...
    assert!(!loc.should_relocalize(&fit, 2, None));
    assert!(loc.should_relocalize(&fit, 3, None));
    // ... and two do when the frame before said the same (a robot moved stays moved), not
    // when it said something else.
    assert!(loc.should_relocalize(&fit, 2, Some(&fit)));
    let elsewhere = PoseFit {
        position: Vector2::new(0.0, 0.5),
        ..fit
    };
    assert!(!loc.should_relocalize(&fit, 2, Some(&elsewhere)));
}

/// Joint angles of a stance whose soles are flat while the torso leans 5° forward of them (the
/// walk's: knees bent, the ankles making up for the hips): hip −17°, knee 24°, ankle −12°;
/// the left leg's hip and ankle `left_forward_deg` further forward and back (the left foot a
/// step ahead, still flat).
fn leaning_stance(loc: &Localizer, left_forward_deg: f64) -> (Vec<f64>, f64) {
    let model = RobotModel::builtin("T1").unwrap();
    let mut angles = vec![0.0; model.joints.len()];
    for side in ["left", "right"] {
        let shift = if side == "left" {
            left_forward_deg
        } else {
            0.0
        };
        for (joint, deg) in [
            ("hip_pitch", -17.0 - shift),
            ("knee", 24.0),
            ("ankle_pitch", -12.0 + shift),
        ] {
            angles[model.joint_id(&format!("{side}_{joint}")).unwrap()] = deg;
        }
    }
    let mut poses = loc.kinematics.new_poses();
    loc.kinematics.forward(&angles, &mut poses).unwrap();
    let foot = poses.frame_in_torso(loc.foot_frames.unwrap()[1]).unwrap();
    let (_, pitch, _) = foot.rotation.inverse().euler_angles();
    (angles, pitch.to_degrees())
}

/// 5 s of a gyro that reads 0.5°/s nose-up the whole time (the walk's drift, a little more)
/// and an accelerometer shaken ±3 m/s² along x, the body still at `lean_deg`: the pitch the
/// localizer ends with.
fn pitch_after_drift(loc: &mut Localizer, angles: &[f64], lean_deg: f64, upright: bool) -> f64 {
    let field = FieldGeometry::builtin("fifa7vs7").unwrap();
    let shake = |t: f64| 3.0 * (std::f64::consts::TAU * t / 0.35).sin();
    let pitch = lean_deg.to_radians();
    for k in 0..250 {
        let t = 0.02 * k as f64;
        let accel = [-9.81 * pitch.sin() + shake(t), 0.0, 9.81 * pitch.cos()];
        loc.update(
            &field,
            angles,
            Some([0.0, -0.5, 0.0]),
            Some(accel),
            None,
            t,
            0.02,
            upright,
        );
    }
    roll_pitch_deg(loc).1
}

fn with_leg_gains(leg: f64, stand: f64) -> Localizer {
    let mut loc = tilt_localizer();
    loc.params.tilt_leg_correction = leg;
    loc.params.tilt_stand_correction = stand;
    loc.params.tilt_leg_gate_deg = 5.0;
    loc
}

#[test]
fn upright_the_stance_leg_holds_the_tilt_against_a_drifting_gyro_and_a_shaken_accelerometer() {
    let mut loc = with_leg_gains(0.1, 0.0);
    // One foot a step ahead: stepping, not standing.
    let (angles, lean) = leaning_stance(&loc, 10.0);
    assert!((lean - 5.0).abs() < 0.5, "the stance leans {lean:.2}°");
    let upright = pitch_after_drift(&mut loc, &angles, lean, true);
    assert!(
        (upright - lean).abs() < 0.3,
        "upright: {upright:.2}° for {lean:.2}°"
    );
    // Without the leg (lying, or the leg switched off) the accelerometer's pull leaves the
    // drift and the shake in it.
    let shaken = pitch_after_drift(&mut with_leg_gains(0.0, 0.0), &angles, lean, true);
    let not_upright = pitch_after_drift(&mut with_leg_gains(0.1, 0.0), &angles, lean, false);
    for (what, pitch) in [("without the leg", shaken), ("not upright", not_upright)] {
        assert!(
            (pitch - lean).abs() > 0.5,
            "{what}: {pitch:.2}° for {lean:.2}°"
        );
    }
}

#[test]
fn standing_on_both_feet_the_legs_hold_the_tilt_and_a_step_apart_they_are_left_to_their_own_gain() {
    // Only the standing gain on: feet side by side take it ...
    let mut loc = with_leg_gains(0.0, 0.1);
    let (together, lean) = leaning_stance(&loc, 0.0);
    let standing = pitch_after_drift(&mut loc, &together, lean, true);
    assert!(
        (standing - lean).abs() < 0.3,
        "standing: {standing:.2}° for {lean:.2}°"
    );
    // ... a foot a step ahead does not (walking stays on the accelerometer's pull while the
    // walking gain is off).
    let (apart, lean) = leaning_stance(&loc, 10.0);
    let stepping = pitch_after_drift(&mut with_leg_gains(0.0, 0.1), &apart, lean, true);
    assert!(
        (stepping - lean).abs() > 0.5,
        "stepping: {stepping:.2}° for {lean:.2}°"
    );
}
