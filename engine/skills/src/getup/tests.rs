use super::*;
use libero_model::RobotModel;
use libero_world::{BodyState, Posture, World};
use std::collections::BTreeMap;

fn frame(duration_s: f64, knee: f64, until: Option<Condition>) -> Keyframe {
    Keyframe {
        duration_s,
        pose: BTreeMap::from([("left_knee".to_string(), knee)]),
        until,
        timeout_s: 0.5,
        hold_s: 0.0,
        on_timeout: None,
        timeout_goes_on: false,
        balance_pitch_deg: None,
    }
}

fn builtin_get_up() -> GetUpParams {
    let model = RobotModel::builtin("T1").unwrap();
    let mut p = crate::SkillParams::builtin(&model).unwrap().get_up;
    p.rest_s = 0.0;
    p
}

/// A get-up driven cycle by cycle while the fall detector reports `posture`.
struct Driven {
    model: RobotModel,
    p: GetUpParams,
    world: World,
    getup: GetUp,
    pose: Vec<f64>,
}

impl Driven {
    fn lying(p: GetUpParams, posture: Posture, gravity: [f64; 3]) -> Self {
        let model = RobotModel::builtin("T1").unwrap();
        let mut world = World::new(&model, "t", 1);
        world.body.gravity = gravity;
        world.body.posture = posture;
        Self {
            pose: vec![0.0; model.joints.len()],
            model,
            p,
            world,
            getup: GetUp::new(),
        }
    }

    /// The left knee's target at `t` (the get-up must be running).
    fn knee_at(&mut self, t: f64) -> f64 {
        self.world.time = t;
        assert!(self
            .getup
            .update(&self.world, false, &self.p, &self.model, &mut self.pose));
        self.pose[self.model.joint_id("left_knee").unwrap()]
    }
}

fn start(model: &RobotModel) -> Playhead {
    Playhead::start(&vec![0.0; model.joints.len()], 0.0)
}

fn pitched(deg: f64) -> Sensed {
    Sensed {
        attitude: Attitude {
            pitch_deg: deg,
            ..Attitude::default()
        },
        from_face_down_deg: 90.0,
        rate_deg_s: 0.0,
    }
}

#[test]
fn a_sensed_frame_holds_until_its_condition_then_moves_on() {
    let model = RobotModel::builtin("T1").unwrap();
    let knee = model.joint_id("left_knee").unwrap();
    let motion = [
        frame(0.2, 90.0, Some(Condition::TorsoPitchBelow(30.0))),
        frame(0.2, 10.0, None),
    ];
    let mut run = start(&model);
    let mut pose = vec![0.0; model.joints.len()];
    let lying = pitched(80.0);
    assert!(matches!(
        step(&mut run, &motion, 0.1, &lying, &model, &mut pose),
        Step::Playing
    ));
    assert!((pose[knee] - 45.0).abs() < 1e-9, "halfway: {}", pose[knee]);
    // Past the duration but still lying: hold the target.
    step(&mut run, &motion, 0.4, &lying, &model, &mut pose);
    assert_eq!((run.frame, pose[knee]), (0, 90.0));
    // The torso has come up: the next frame starts now, from the held target.
    step(&mut run, &motion, 0.5, &pitched(20.0), &model, &mut pose);
    assert_eq!((run.frame, pose[knee]), (1, 90.0));
    step(&mut run, &motion, 0.6, &pitched(20.0), &model, &mut pose);
    assert!((pose[knee] - 50.0).abs() < 1e-9, "halfway: {}", pose[knee]);
    assert!(matches!(
        step(&mut run, &motion, 0.8, &pitched(20.0), &model, &mut pose),
        Step::Ended
    ));
}

#[test]
fn a_condition_that_never_comes_gives_up() {
    let model = RobotModel::builtin("T1").unwrap();
    let motion = [frame(0.2, 90.0, Some(Condition::UprightWithin(20.0)))];
    let mut run = start(&model);
    let mut pose = vec![0.0; model.joints.len()];
    let lying = pitched(80.0);
    assert!(matches!(
        step(&mut run, &motion, 0.69, &lying, &model, &mut pose),
        Step::Playing
    ));
    assert!(matches!(
        step(&mut run, &motion, 0.71, &lying, &model, &mut pose),
        Step::TimedOut(None)
    ));
}

#[test]
fn balance_pushes_back_against_a_forward_lean() {
    let model = RobotModel::builtin("T1").unwrap();
    let b = GetUpBalance {
        ankle_per_deg: 0.5,
        ankle_per_gyro: 0.0,
        hip_per_deg: 0.2,
        hip_per_gyro: 0.0,
        max_deg: 4.0,
    };
    let mut pose = vec![0.0; model.joints.len()];
    balance(&b, &pitched(15.0).attitude, 5.0, &model, &mut pose);
    let at = |n: &str| pose[model.joint_id(n).unwrap()];
    assert_eq!(at("right_ankle_pitch"), 4.0, "clamped to max_deg");
    assert!((at("left_hip_pitch") - 2.0).abs() < 1e-9);
}

#[test]
fn face_down_is_told_from_lying_on_a_side() {
    let model = RobotModel::builtin("T1").unwrap();
    let mut body = BodyState::new(&model);
    let sensed = |body: &BodyState| Sensed::from_body(body);
    body.gravity = [-9.81, 0.0, 0.0];
    assert!(sensed(&body).from_face_down_deg < 1e-9);
    // On the right side, slightly nose down: pitch reads far above 60° ...
    body.gravity = [-0.5, 9.8, 0.1];
    let side = sensed(&body);
    assert!(side.attitude.pitch_deg > 60.0, "{side:?}");
    assert!(Condition::TorsoPitchAbove(60.0).holds(&side));
    // ... but the torso's front is nearly level: not face down.
    let face_down = Condition::FaceDown {
        within_deg: 35.0,
        rate_below_deg_s: 40.0,
    };
    assert!(!face_down.holds(&side), "{side:?}");
    // Face down with 20° of roll towards the side still counts ...
    let roll = 20f64.to_radians();
    body.gravity = [-9.81 * roll.cos(), 9.81 * roll.sin(), 0.0];
    assert!(face_down.holds(&sensed(&body)));
    // ... unless the body is still rolling.
    body.gyro = [50.0, 10.0, 0.0];
    assert!(!face_down.holds(&sensed(&body)));
    // On the back: as far from face down as can be.
    body.gravity = [9.81, 0.0, 0.0];
    assert!((sensed(&body).from_face_down_deg - 180.0).abs() < 1e-9);
}

#[test]
fn the_back_motion_runs_on_into_the_front_motion_when_asked() {
    let mut p = builtin_get_up();
    p.back = vec![frame(0.1, 20.0, None)];
    p.front = vec![frame(0.1, 50.0, None), frame(0.2, 80.0, None)];
    p.back_then_front_from = Some(1);
    let mut r = Driven::lying(p, Posture::FallenBack, [9.81, 0.0, 0.0]);
    r.knee_at(0.0);
    assert_eq!(r.knee_at(0.1), 20.0, "the roll has played out");
    // Still lying on the back as far as the detector knows, yet the front motion goes
    // on from its frame 1 (80°), skipping frame 0 (50°).
    assert!((r.knee_at(0.2) - 50.0).abs() < 1e-9, "halfway 20 → 80");
    assert_eq!(r.knee_at(0.3), 80.0);
    r.p.back_then_front_from = Some(2);
    assert!(r
        .p
        .validate(&r.model)
        .unwrap_err()
        .contains("back_then_front_from"));
}

#[test]
fn validation_names_a_bad_condition() {
    let model = RobotModel::builtin("T1").unwrap();
    let mut p = crate::SkillParams::builtin(&model).unwrap().get_up;
    p.back[0].until = Some(Condition::UprightWithin(120.0));
    let err = p.validate(&model).unwrap_err();
    assert!(err.contains("get_up.back[0].until"), "{err}");
}

#[test]
fn a_condition_must_hold_for_hold_s_without_a_break() {
    let model = RobotModel::builtin("T1").unwrap();
    let mut waiting = frame(0.2, 90.0, Some(Condition::TorsoPitchBelow(30.0)));
    waiting.hold_s = 0.06;
    let motion = [waiting, frame(0.2, 10.0, None)];
    let mut run = start(&model);
    let mut pose = vec![0.0; model.joints.len()];
    // One cycle's jolt reads upright, the next does not: the frame goes on waiting.
    step(&mut run, &motion, 0.30, &pitched(20.0), &model, &mut pose);
    step(&mut run, &motion, 0.32, &pitched(40.0), &model, &mut pose);
    step(&mut run, &motion, 0.34, &pitched(20.0), &model, &mut pose);
    step(&mut run, &motion, 0.38, &pitched(20.0), &model, &mut pose);
    assert_eq!(run.frame, 0, "held 0.04 s of 0.06");
    step(&mut run, &motion, 0.40, &pitched(20.0), &model, &mut pose);
    assert_eq!(run.frame, 1, "held 0.06 s");
}

#[test]
fn a_timed_out_wait_switches_to_its_recovery_motion_from_the_held_pose() {
    let mut p = builtin_get_up();
    let mut squat = frame(0.1, 120.0, Some(Condition::UprightWithin(15.0)));
    squat.timeout_s = 0.2;
    squat.on_timeout = Some("rise_slowly".into());
    p.front = vec![squat, frame(0.1, 0.0, None)];
    p.recover
        .insert("rise_slowly".to_string(), vec![frame(0.4, 40.0, None)]);
    let mut r = Driven::lying(p, Posture::FallenFront, [-9.81, 0.0, 0.0]);
    r.p.validate(&r.model).unwrap();
    r.knee_at(0.0);
    assert_eq!(r.knee_at(0.25), 120.0, "waiting");
    assert_eq!(r.getup.recovering(), None);
    // Still face down at the timeout: the recovery starts from the held 120°, not the front
    // motion's next frame (0°) and not from the ground.
    r.knee_at(0.31);
    assert_eq!(r.getup.recovering(), Some("rise_slowly"));
    assert!((r.knee_at(0.51) - 80.0).abs() < 1e-6, "halfway 120 → 40");
    assert_eq!(r.knee_at(0.72), 40.0);
    // Played out: the get-up is over (the detector starts a new one if still down).
    r.world.body.posture = Posture::Upright;
    r.world.time = 0.73;
    assert!(!r.getup.update(&r.world, false, &r.p, &r.model, &mut r.pose));
}

#[test]
fn validation_names_an_unknown_recovery_motion() {
    let model = RobotModel::builtin("T1").unwrap();
    let mut p = crate::SkillParams::builtin(&model).unwrap().get_up;
    let k = p.front.iter().position(|f| f.until.is_some()).unwrap();
    p.front[k].on_timeout = Some("sit_down".into());
    let err = p.validate(&model).unwrap_err();
    assert!(
        err.contains(&format!("get_up.front[{k}].on_timeout")) && err.contains("sit_down"),
        "{err}"
    );
    p.front[k].on_timeout = None;
    p.front[0].on_timeout = Some("sit_down".into());
    if p.front[0].until.is_none() {
        assert!(p.validate(&model).unwrap_err().contains("no `until`"));
    }
}

#[test]
fn a_body_still_rolling_is_left_to_come_to_rest_before_the_get_up_starts() {
    let mut p = builtin_get_up();
    p.rest_s = 0.3;
    p.rest_until_still = Some(RestUntilStill {
        rate_below_deg_s: 30.0,
        at_most_s: 1.5,
    });
    let mut d = Driven::lying(p, Posture::FallenBack, [9.8, 0.0, 0.0]);
    let mut starts_at = |gyro: [f64; 3], still_from: f64| {
        d.getup = GetUp::new();
        (0..200).map(|k| f64::from(k) * 0.02).find(|&t| {
            d.world.time = t;
            d.world.body.gyro = if t < still_from { gyro } else { [0.0; 3] };
            d.getup.update(&d.world, false, &d.p, &d.model, &mut d.pose)
        })
    };
    // Lying still: after rest_s, as before.
    let still = starts_at([0.0; 3], 0.0).unwrap();
    assert!((still - 0.3).abs() < 0.03, "{still}");
    // Rocking at 100 deg/s until 0.8 s: the motion waits for the rocking to end ...
    let rocking = starts_at([0.0, 100.0, 0.0], 0.8).unwrap();
    assert!((rocking - 0.8).abs() < 0.03, "{rocking}");
    // ... but not for ever: a body that never comes to rest is got up after at_most_s.
    let restless = starts_at([0.0, 100.0, 0.0], f64::INFINITY).unwrap();
    assert!((restless - 1.5).abs() < 0.03, "{restless}");
}

#[test]
fn the_shipped_back_roll_tries_the_other_side_when_it_does_not_reach_face_down() {
    let model = RobotModel::builtin("T1").unwrap();
    let p = crate::SkillParams::builtin(&model).unwrap().get_up;
    let timeout_to = |motion: &[Keyframe]| -> Vec<Option<String>> {
        motion
            .iter()
            .map(|f| f.on_timeout.as_deref().map(str::to_string))
            .collect()
    };
    assert!(timeout_to(&p.back).contains(&Some("back_mirrored".to_string())));
    let mirrored = &p.recover["back_mirrored"];
    assert_eq!(mirrored.len(), p.back.len());
    // Each frame is the mirror image of the roll's (the saves' rule), so the roll goes the
    // other way.
    for (m, b) in mirrored.iter().zip(&p.back) {
        assert_eq!(m.pose, crate::save::mirror_frame(b).pose);
    }
}

#[test]
fn after_a_get_up_the_robot_stands_until_settled_or_out_of_time() {
    let p = SettleAfter {
        upright_within_deg: 10.0,
        rate_below_deg_s: 20.0,
        calm_s: 0.3,
        at_most_s: 1.5,
    };
    let body = |pitch_deg: f64, rate_deg_s: f64| Sensed {
        rate_deg_s,
        ..pitched(pitch_deg)
    };
    let mut s = Settling::new(0.0);
    // Leaning 15° forward as the front motion ends: not settled.
    assert!(s.goes_on(&p, &body(15.0, 5.0), 0.1));
    // Upright but still swaying: not yet.
    assert!(s.goes_on(&p, &body(3.0, 40.0), 0.3));
    // Upright and calm: settled once that has lasted calm_s.
    assert!(s.goes_on(&p, &body(3.0, 5.0), 0.4));
    assert!(s.goes_on(&p, &body(3.0, 5.0), 0.6));
    assert!(!s.goes_on(&p, &body(3.0, 5.0), 0.71));
    // A body that never settles is let go after at_most_s.
    let mut s = Settling::new(0.0);
    assert!(s.goes_on(&p, &body(15.0, 5.0), 1.4));
    assert!(!s.goes_on(&p, &body(15.0, 5.0), 1.5));
}

#[test]
fn the_skills_stand_after_a_get_up_until_the_body_is_calm_then_walk() {
    use crate::{ActiveSkill, BodyIntent, Intent, JointTargets, SkillParams, Skills};
    let model = RobotModel::builtin("T1").unwrap();
    let mut params = SkillParams::builtin(&model).unwrap();
    params.get_up.rest_s = 0.0;
    params.get_up.rest_until_still = None;
    params.get_up.front = vec![frame(0.1, 30.0, None), frame(0.1, 0.0, None)];
    let settle = SettleAfter {
        upright_within_deg: 10.0,
        rate_below_deg_s: 20.0,
        calm_s: 0.3,
        at_most_s: 1.5,
    };
    params.get_up.settle = Some(settle);
    let mut skills = Skills::new(&model, params).unwrap();
    let mut world = World::new(&model, "t", 1);
    let mut out = JointTargets::default();
    let walk = Intent {
        body: BodyIntent::Walk {
            forward_m_s: 0.3,
            sideways_m_s: 0.0,
            turn_deg_s: 0.0,
        },
        ..Intent::default()
    };
    let mut cycle = |world: &mut World| {
        world.time += 0.02;
        skills.act(&model, world, &walk, &mut out);
        skills.active()
    };
    world.body.gravity = [-9.81, 0.0, 0.0];
    world.body.posture = Posture::FallenFront;
    assert_eq!(cycle(&mut world), ActiveSkill::GetUp);
    // Up, but the torso still sways: the walk waits.
    world.body.gravity = [0.0, 0.0, 9.81];
    world.body.posture = Posture::Upright;
    world.body.gyro = [0.0, 40.0, 0.0];
    let mut t = 0.0;
    while cycle(&mut world) == ActiveSkill::GetUp {
        t += 0.02;
        assert!(t < 1.0, "the get-up never ended");
    }
    for _ in 0..20 {
        assert_eq!(cycle(&mut world), ActiveSkill::Stand);
    }
    // Calm: after calm_s of it, walking.
    world.body.gyro = [0.0; 3];
    let calm_from = world.time;
    while cycle(&mut world) == ActiveSkill::Stand {
        assert!(
            world.time - calm_from < settle.calm_s + 0.05,
            "still standing"
        );
    }
    assert!(world.time - calm_from >= settle.calm_s - 1e-9);
    assert_eq!(skills.active(), ActiveSkill::Walk);
}

#[test]
fn a_wait_that_may_go_on_plays_the_next_frame_at_its_timeout_instead_of_starting_over() {
    let model = RobotModel::builtin("T1").unwrap();
    let mut flat = frame(0.2, 0.0, Some(Condition::TorsoPitchBelow(30.0)));
    flat.timeout_s = 0.3;
    flat.timeout_goes_on = true;
    let motion = [flat.clone(), frame(0.2, 90.0, None)];
    let mut run = start(&model);
    let mut pose = vec![0.0; model.joints.len()];
    // Never below 30°: at 0.2 + 0.3 s the tuck comes anyway, and no start over.
    assert!(matches!(
        step(&mut run, &motion, 0.49, &pitched(60.0), &model, &mut pose),
        Step::Playing
    ));
    assert_eq!(run.frame, 0, "still waiting");
    assert!(matches!(
        step(&mut run, &motion, 0.50, &pitched(60.0), &model, &mut pose),
        Step::Playing
    ));
    assert_eq!(run.frame, 1, "went on");
    // The condition come in time ends the wait at once, as any `until`.
    let mut run = start(&model);
    step(&mut run, &motion, 0.21, &pitched(10.0), &model, &mut pose);
    assert_eq!(run.frame, 1);
    // Validated: it needs an `until`, and it cannot also switch to a recovery.
    let mut p = builtin_get_up();
    p.front = vec![flat.clone(), frame(0.2, 90.0, None)];
    p.validate(&model).unwrap();
    p.front[0].until = None;
    assert!(p.validate(&model).unwrap_err().contains("timeout_goes_on"));
    p.front[0] = Keyframe {
        on_timeout: Some("x".into()),
        ..flat
    };
    p.recover
        .insert("x".to_string(), vec![frame(0.2, 0.0, None)]);
    assert!(p.validate(&model).unwrap_err().contains("timeout_goes_on"));
}
