//! The walk's unit tests: rates, stops, the capture step, kick steps.
use super::*;

#[test]
fn a_stop_takes_no_capture_steps_for_a_small_tilt() {
    let model = RobotModel::builtin("T1").unwrap();
    let b = crate::SkillParams::builtin(&model).unwrap().walk.balance;
    assert!(b.stop_capture_min_deg > 0.0 && b.step_x_per_tilt_m > 0.0);
    let small = 0.5 * b.stop_capture_min_deg;
    assert_eq!(capture_x(small, true, &b), 0.0);
    // Walking, or leaning far, the capture step stays.
    assert!(capture_x(small, false, &b) > 0.0);
    let far = 2.0 * b.stop_capture_min_deg;
    assert!(capture_x(-far, true, &b) < 0.0);
}

/// Cycles from a stop request after 2 s of walking until the walk stands, the torso
/// pitched `tilt_deg` off the walk's lean throughout.
fn cycles_to_stop(p: &WalkParams, tilt_deg: f64) -> usize {
    let model = RobotModel::builtin("T1").unwrap();
    let mut world = libero_world::World::new(&model, "t", 1);
    world.me.pitch_deg = p.torso_lean_deg + tilt_deg;
    let mut walk = Walk::new(&model).unwrap();
    let mut pose = vec![0.0; model.joints.len()];
    let ahead = Velocity {
        forward_m_s: 0.1,
        ..Default::default()
    };
    for i in 0..100 {
        world.time = i as f64 * NOMINAL_CYCLE_S;
        walk.update(&world, Some(ahead), p, &mut pose);
    }
    assert!(walk.is_stepping());
    (1..1000)
        .find(|i| {
            world.time = (100 + i) as f64 * NOMINAL_CYCLE_S;
            walk.update(&world, None, p, &mut pose);
            !walk.is_stepping()
        })
        .unwrap_or(1000)
}

#[test]
fn a_small_tilt_does_not_keep_a_stopping_walk_stepping() {
    let model = RobotModel::builtin("T1").unwrap();
    let mut p = crate::SkillParams::builtin(&model).unwrap().walk;
    let tilt = 0.5 * p.balance.stop_capture_min_deg;
    let quick = cycles_to_stop(&p, tilt);
    // Braking from 0.1 m/s and closing: a few steps.
    let steps = (quick as f64 * NOMINAL_CYCLE_S / p.step_period_s).ceil();
    assert!(steps <= 4.0, "{quick} cycles");
    // Capture steps always: millimetre steps go on and on.
    p.balance.stop_capture_min_deg = 0.0;
    assert!(cycles_to_stop(&p, tilt) > quick + 50);
}

#[test]
fn standing_in_the_walk_posture_damps_the_sway() {
    let model = RobotModel::builtin("T1").unwrap();
    let mut p = crate::SkillParams::builtin(&model).unwrap().walk;
    assert!(p.balance.rest_correction_scale > 0.0);
    let mut world = libero_world::World::new(&model, "t", 1);
    world.me.pitch_deg = p.torso_lean_deg;
    let roll = model.joint_id("left_ankle_roll").unwrap();
    let mut at_rest = |p: &WalkParams, rate: f64| {
        world.body.gyro = [rate, 0.0, 0.0];
        let mut walk = Walk::new(&model).unwrap();
        let mut pose = vec![0.0; model.joints.len()];
        walk.update(&world, None, p, &mut pose);
        assert!(!walk.is_stepping());
        pose[roll]
    };
    let still = at_rest(&p, 0.0);
    let swaying = at_rest(&p, 10.0);
    let expected = p.balance.rest_correction_scale * p.balance.ankle_roll_per_gyro * 10.0;
    assert!(
        (swaying - still - expected).abs() < 1e-9,
        "{still} {swaying}"
    );
    p.balance.rest_correction_scale = 0.0;
    assert_eq!(at_rest(&p, 10.0), at_rest(&p, 0.0));
}

/// The highest the swing foot rises during the first step of a walk from rest [m].
fn first_step_lift(p: &WalkParams) -> f64 {
    let model = RobotModel::builtin("T1").unwrap();
    let mut world = libero_world::World::new(&model, "t", 1);
    world.me.pitch_deg = p.torso_lean_deg;
    let mut walk = Walk::new(&model).unwrap();
    let mut pose = vec![0.0; model.joints.len()];
    let ahead = Velocity {
        forward_m_s: 0.3,
        ..Default::default()
    };
    let mut first = None;
    let mut lift: f64 = 0.0;
    for i in 0..200 {
        world.time = i as f64 * NOMINAL_CYCLE_S;
        walk.update(&world, Some(ahead), p, &mut pose);
        if !walk.is_stepping() {
            continue;
        }
        let swing = *first.get_or_insert(walk.gait.swing);
        if walk.gait.swing != swing {
            return lift;
        }
        let sole = walk.gait.placements(p)[swing.index()];
        lift = lift.max(sole.z + p.torso_height_m);
    }
    panic!("the first step never ended");
}

#[test]
fn the_first_step_lifts_its_foot_by_the_start_share_of_a_step() {
    let model = RobotModel::builtin("T1").unwrap();
    let mut p = crate::SkillParams::builtin(&model).unwrap().walk;
    assert!(p.start_lift_scale > 0.0);
    let lift = first_step_lift(&p);
    assert!(
        (lift - p.start_lift_scale * p.step_height_m).abs() < 0.002,
        "{lift}"
    );
    // Absent from a file: a weight shift without lift.
    p.start_lift_scale = 0.0;
    assert_eq!(first_step_lift(&p), 0.0);
}

#[test]
fn the_walk_speeds_up_at_its_acceleration_and_slows_down_at_its_deceleration() {
    let model = RobotModel::builtin("T1").unwrap();
    let mut p = crate::SkillParams::builtin(&model).unwrap().walk;
    // Different rates, so that each is seen to apply where it should.
    p.accel_forward_m_s2 = 0.5;
    p.decel_forward_m_s2 = Some(0.3);
    let (up, down) = (p.accel_forward_m_s2, p.decel_forward_m_s2());
    let at = |v: f64| Velocity {
        forward_m_s: v,
        ..Default::default()
    };
    let dt = 0.02;
    let faster = rate_limit(at(0.3), at(0.6), &p, dt);
    assert!((faster.forward_m_s - (0.3 + up * dt)).abs() < 1e-12);
    let slower = rate_limit(at(0.6), at(0.0), &p, dt);
    assert!((slower.forward_m_s - (0.6 - down * dt)).abs() < 1e-12);
    // Backwards the same: coming back towards zero is slowing down.
    let back = rate_limit(at(-0.2), at(0.3), &p, dt);
    assert!((back.forward_m_s - (-0.2 + down * dt)).abs() < 1e-12);
    let from_rest = rate_limit(at(0.0), at(-0.2), &p, dt);
    assert!((from_rest.forward_m_s + up * dt).abs() < 1e-12);
}

#[test]
fn one_axis_gets_its_full_limit_and_combinations_share_it() {
    let model = RobotModel::builtin("T1").unwrap();
    let p = crate::SkillParams::builtin(&model).unwrap().walk;
    let ahead = clamp_command(
        Velocity {
            forward_m_s: 5.0,
            ..Default::default()
        },
        &p,
    );
    assert_eq!(ahead.forward_m_s, p.max_forward_m_s);
    let both = clamp_command(
        Velocity {
            forward_m_s: p.max_forward_m_s,
            sideways_m_s: -p.max_sideways_m_s,
            turn_deg_s: 0.0,
        },
        &p,
    );
    let half = std::f64::consts::FRAC_1_SQRT_2;
    assert!((both.forward_m_s - half * p.max_forward_m_s).abs() < 1e-12);
    assert!((both.sideways_m_s + half * p.max_sideways_m_s).abs() < 1e-12);
    let slow = Velocity {
        forward_m_s: 0.3 * p.max_forward_m_s,
        sideways_m_s: 0.3 * p.max_sideways_m_s,
        turn_deg_s: -0.3 * p.max_turn_deg_s,
    };
    assert_eq!(clamp_command(slow, &p), slow);
}

#[test]
fn a_kick_step_begins_only_when_asked_of_the_foot_that_swings_next() {
    let model = RobotModel::builtin("T1").unwrap();
    let mut p = crate::SkillParams::builtin(&model).unwrap().walk;
    p.kick_step = Some(kick_step::example());
    let mut world = libero_world::World::new(&model, "t", 1);
    world.me.pitch_deg = p.torso_lean_deg;
    let ahead = Velocity {
        forward_m_s: 0.3,
        ..Default::default()
    };
    let run = |ask: Option<(Foot, f64)>, p: &WalkParams, world: &mut libero_world::World| {
        let mut walk = Walk::new(&model).unwrap();
        let mut pose = vec![0.0; model.joints.len()];
        let mut swings_kicking = Vec::new();
        for i in 0..150 {
            world.time = i as f64 * NOMINAL_CYCLE_S;
            walk.ask_kick_step(ask);
            walk.update(world, Some(ahead), p, &mut pose);
            if walk.kicking() {
                swings_kicking.push(walk.gait.swing);
            }
        }
        (walk.kick_steps(), swings_kicking)
    };
    let (none, _) = run(None, &p, &mut world);
    assert_eq!(none, 0);
    let (left, swings) = run(Some((Foot::Left, 0.0)), &p, &mut world);
    // 3 s of walking: several left steps, each a kick step, no right one.
    assert!(left >= 2, "{left}");
    assert!(swings.iter().all(|&f| f == Foot::Left), "{swings:?}");
    // A walk without a kick step in its file makes none.
    p.kick_step = None;
    assert_eq!(run(Some((Foot::Left, 0.0)), &p, &mut world).0, 0);
}

#[test]
fn the_torso_leans_into_speeding_up_and_back_from_slowing_down() {
    let model = RobotModel::builtin("T1").unwrap();
    let mut p = crate::SkillParams::builtin(&model).unwrap().walk;
    p.balance.lean_per_accel_deg = 6.0;
    let mut world = libero_world::World::new(&model, "t", 1);
    world.me.pitch_deg = p.torso_lean_deg;
    let mut walk = Walk::new(&model).unwrap();
    let mut pose = vec![0.0; model.joints.len()];
    let mut cycle = 0;
    let mut run = |walk: &mut Walk, request: Option<Velocity>, seconds: f64| {
        for _ in 0..(seconds / NOMINAL_CYCLE_S) as usize {
            cycle += 1;
            world.time = cycle as f64 * NOMINAL_CYCLE_S;
            walk.update(&world, request, &p, &mut pose);
        }
        walk.lean_deg(&p) - p.torso_lean_deg
    };
    let fast = Velocity {
        forward_m_s: p.max_forward_m_s,
        ..Default::default()
    };
    // Speeding up at the walk's acceleration: after a few step periods the lean is the
    // acceleration's share.
    let speeding_up = run(&mut walk, Some(fast), p.settle_s + 1.0);
    let expected = p.balance.lean_per_accel_deg * p.accel_forward_m_s2;
    assert!(
        (speeding_up - expected).abs() < 0.1 * expected,
        "{speeding_up}"
    );
    // At full speed none, slowing down it leans back, standing none again.
    assert!(run(&mut walk, Some(fast), 2.0).abs() < 0.05);
    let slowing = run(&mut walk, None, 0.5);
    assert!(slowing < -0.5 * p.balance.lean_per_accel_deg * p.decel_forward_m_s2());
    assert!(run(&mut walk, None, 3.0).abs() < 0.05);
    assert!(!walk.is_stepping());
}
