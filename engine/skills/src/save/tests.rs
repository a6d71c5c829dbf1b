use super::*;
use crate::getup::Condition;
use libero_model::RobotModel;
use libero_world::World;

/// A plain timed key frame (no IMU condition), for tests of anything that plays frames.
pub(crate) fn frame(duration_s: f64, pose: &[(&str, f64)]) -> Keyframe {
    Keyframe {
        duration_s,
        pose: pose.iter().map(|(j, a)| (j.to_string(), *a)).collect(),
        until: None,
        timeout_s: 1.0,
        hold_s: 0.0,
        on_timeout: None,
        timeout_goes_on: false,
        balance_pitch_deg: None,
    }
}

fn t1() -> RobotModel {
    RobotModel::builtin("T1").unwrap()
}

fn two_frame_params() -> SaveParams {
    SaveParams {
        left: vec![
            frame(
                0.1,
                &[
                    ("left_hip_roll", 30.0),
                    ("waist", 10.0),
                    ("left_knee", 40.0),
                ],
            ),
            frame(0.1, &[("left_shoulder_roll", -20.0)]),
        ],
        right: None,
        block: vec![frame(
            0.2,
            &[("left_hip_roll", 20.0), ("right_hip_roll", -20.0)],
        )],
        gains: BTreeMap::from([(
            "left_shoulder_roll".to_string(),
            Gains { kp: 300.0, kd: 2.0 },
        )]),
    }
}

#[test]
fn the_builtin_t1_parameters_have_all_three_saves_and_they_validate() {
    let model = t1();
    let p = crate::SkillParams::builtin(&model).unwrap().save;
    for side in [DiveSide::Left, DiveSide::Right, DiveSide::Centre] {
        assert!(!p.motion(side).is_empty(), "{side:?}");
    }
    p.validate(&model).unwrap();
}

#[test]
fn the_right_dive_mirrors_the_left_one() {
    let p = two_frame_params();
    let right = p.motion(DiveSide::Right);
    assert_eq!(right[0].pose["right_hip_roll"], -30.0);
    assert_eq!(right[0].pose["waist"], -10.0);
    assert_eq!(right[0].pose["right_knee"], 40.0);
    assert!(!right[0].pose.contains_key("left_hip_roll"));
    assert_eq!(right[1].pose["right_shoulder_roll"], 20.0);
    assert_eq!(right[1].duration_s, 0.1);
    let gains = p.gains_for(DiveSide::Right);
    assert_eq!(gains[0].0, "right_shoulder_roll");
    // Mirroring twice gives the motion back.
    let back: Vec<Keyframe> = right.iter().map(mirror_frame).collect();
    assert_eq!(back, p.left);
    // The stand pose is symmetric: its mirror image is itself.
    let model = t1();
    let stand = crate::SkillParams::builtin(&model).unwrap().stand;
    let standing = frame(
        0.1,
        &stand
            .iter()
            .map(|(j, a)| (j.as_str(), *a))
            .collect::<Vec<_>>(),
    );
    assert_eq!(mirror_frame(&standing), standing);
}

#[test]
fn validation_names_the_bad_frame_also_in_the_mirrored_dive() {
    let model = t1();
    let mut p = two_frame_params();
    p.left[1].duration_s = 0.0;
    let err = p.validate(&model).unwrap_err();
    assert!(err.contains("save.left[1].duration_s"), "{err}");

    // Beyond the joint's limits.
    let mut p = two_frame_params();
    p.block[0].pose.insert("left_knee".into(), 150.0);
    let err = p.validate(&model).unwrap_err();
    assert!(err.contains("save.block[0].pose.left_knee"), "{err}");

    let mut p = two_frame_params();
    p.left[0].pose.insert("tail".into(), 1.0);
    let err = p.validate(&model).unwrap_err();
    assert!(err.contains("`tail` is not a joint"), "{err}");

    // An explicitly given, empty right dive is an error; a missing one mirrors the left.
    let mut p = two_frame_params();
    p.right = Some(vec![]);
    let err = p.validate(&model).unwrap_err();
    assert!(
        err.contains("save.right: the motion has no key frames"),
        "{err}"
    );

    // A save has no recovery motions to switch to.
    let mut p = two_frame_params();
    p.left[0].until = Some(Condition::TorsoPitchAbove(10.0));
    p.left[0].on_timeout = Some("x".into());
    let err = p.validate(&model).unwrap_err();
    assert!(err.contains("save.left[0].on_timeout"), "{err}");

    p.left[0].on_timeout = None;
    p.left[0].until = Some(Condition::UprightWithin(120.0));
    let err = p.validate(&model).unwrap_err();
    assert!(err.contains("save.left[0].until"), "{err}");

    let mut p = two_frame_params();
    p.gains
        .insert("left_knee".into(), Gains { kp: -1.0, kd: 0.0 });
    let err = p.validate(&model).unwrap_err();
    assert!(err.contains("save.gains.left_knee.kp"), "{err}");

    // No save motions at all is valid (a robot that cannot save).
    SaveParams::default().validate(&model).unwrap();
}

/// The skill driven cycle by cycle (10 ms) while standing.
struct Driven {
    model: RobotModel,
    p: SaveParams,
    world: World,
    save: Save,
    pose: Vec<f64>,
}

impl Driven {
    fn new() -> Self {
        let model = t1();
        let world = World::new(&model, "t", 1);
        Self {
            pose: vec![0.0; model.joints.len()],
            p: two_frame_params(),
            world,
            save: Save::new(),
            model,
        }
    }

    fn cycle(&mut self, request: Option<DiveSide>) -> bool {
        self.world.time += 0.01;
        self.save.update(
            &self.world,
            request,
            true,
            &self.p.motions(),
            &self.model,
            &mut self.pose,
        )
    }

    fn angle(&self, joint: &str) -> f64 {
        self.pose[self.model.joint_id(joint).unwrap()]
    }
}

#[test]
fn a_request_dives_at_once_then_is_done_and_a_new_request_while_diving_is_ignored() {
    let mut d = Driven::new();
    assert!(!d.cycle(None));
    assert_eq!(d.save.state(), SaveState::Idle);
    // First cycle of the request: the motion plays already.
    assert!(d.cycle(Some(DiveSide::Left)));
    assert_eq!(d.save.state(), SaveState::Diving(DiveSide::Left));
    assert!(d.angle("left_hip_roll") > 0.0);
    // Asked for the other side, or for nothing, mid-dive: the dive goes on.
    assert!(d.cycle(Some(DiveSide::Right)));
    assert!(d.cycle(None));
    assert_eq!(d.save.state(), SaveState::Diving(DiveSide::Left));
    assert_eq!(d.angle("right_hip_roll"), 0.0);
    let mut cycles = 3;
    while d.save.is_running() {
        d.cycle(Some(DiveSide::Left));
        cycles += 1;
        assert!(cycles < 100, "the dive never ended");
    }
    // Two 0.1 s frames.
    assert!((19..=22).contains(&cycles), "{cycles} cycles");
    assert_eq!(d.save.state(), SaveState::Done(DiveSide::Left));
    assert_eq!(d.angle("left_shoulder_roll"), -20.0);
    // Holding the request does not dive again.
    assert!(!d.cycle(Some(DiveSide::Left)));
    assert_eq!(d.save.state(), SaveState::Done(DiveSide::Left));
    // A cycle without a request resets; the next request plays the (mirrored) right dive.
    assert!(!d.cycle(None));
    assert_eq!(d.save.state(), SaveState::Idle);
    assert!(d.cycle(Some(DiveSide::Right)));
    assert_eq!(d.save.state(), SaveState::Diving(DiveSide::Right));
    assert!(d.angle("right_hip_roll") < 0.0);
}

#[test]
fn a_save_does_not_start_when_it_may_not_or_has_no_motion() {
    let mut d = Driven::new();
    d.world.time += 0.01;
    let started = d.save.update(
        &d.world,
        Some(DiveSide::Centre),
        false,
        &d.p.motions(),
        &d.model,
        &mut d.pose,
    );
    assert!(!started);
    assert_eq!(d.save.state(), SaveState::Idle);
    d.p.block.clear();
    assert!(!d.cycle(Some(DiveSide::Centre)));
    assert_eq!(d.save.state(), SaveState::Idle);
}

#[test]
fn the_skills_dive_in_the_first_cycle_even_while_walking_and_report_it() {
    use crate::{ActiveSkill, BodyIntent, Intent, JointTargets, SkillParams, Skills};
    let model = t1();
    let mut params = SkillParams::builtin(&model).unwrap();
    params.save = two_frame_params();
    let mut skills = Skills::new(&model, params).unwrap();
    let mut world = World::new(&model, "t", 1);
    world.body.gravity = [0.0, 0.0, 9.81];
    let mut out = JointTargets::default();
    let walk = Intent {
        body: BodyIntent::Walk {
            forward_m_s: 0.3,
            sideways_m_s: 0.0,
            turn_deg_s: 0.0,
        },
        ..Intent::default()
    };
    for _ in 0..50 {
        world.time += 0.02;
        skills.act(&model, &world, &walk, &mut out);
    }
    assert_eq!(skills.active(), ActiveSkill::Walk);
    let dive = Intent {
        body: BodyIntent::Dive {
            side: DiveSide::Left,
        },
        ..Intent::default()
    };
    world.time += 0.02;
    skills.act(&model, &world, &dive, &mut out);
    assert_eq!(skills.active(), ActiveSkill::Save);
    assert_eq!(skills.status().save, SaveState::Diving(DiveSide::Left));
    // Back to walking mid-dive: the dive goes on.
    world.time += 0.02;
    skills.act(&model, &world, &walk, &mut out);
    assert_eq!(skills.active(), ActiveSkill::Save);
    for _ in 0..20 {
        world.time += 0.02;
        skills.act(&model, &world, &dive, &mut out);
    }
    assert_eq!(skills.status().save, SaveState::Done(DiveSide::Left));
}

#[test]
fn after_a_dive_the_robot_stays_down_while_the_request_is_held_then_gets_up() {
    use crate::{ActiveSkill, BodyIntent, Intent, JointTargets, SkillParams, Skills};
    use libero_world::Posture;
    let model = t1();
    let mut params = SkillParams::builtin(&model).unwrap();
    params.save = two_frame_params();
    params.get_up.rest_s = 0.0;
    let mut skills = Skills::new(&model, params).unwrap();
    let mut world = World::new(&model, "t", 1);
    let mut out = JointTargets::default();
    let dive = Intent {
        body: BodyIntent::Dive {
            side: DiveSide::Left,
        },
        ..Intent::default()
    };
    let mut cycle = |world: &mut World, intent: &Intent| {
        world.time += 0.02;
        skills.act(&model, world, intent, &mut out);
        (skills.active(), skills.status().save)
    };
    cycle(&mut world, &dive);
    // The body goes down during the dive (left side down).
    world.body.gravity = [0.0, 9.81, 0.0];
    world.body.posture = Posture::FallenSide;
    for _ in 0..15 {
        cycle(&mut world, &dive);
    }
    // Done and held: down in the end pose, no get-up.
    for _ in 0..20 {
        assert_eq!(
            cycle(&mut world, &dive),
            (ActiveSkill::Save, SaveState::Done(DiveSide::Left))
        );
    }
    // Let go: the get-up starts.
    let stand = Intent::default();
    let (active, state) = cycle(&mut world, &stand);
    assert_eq!(state, SaveState::Idle);
    let mut active = active;
    for _ in 0..3 {
        active = cycle(&mut world, &stand).0;
    }
    assert_eq!(active, ActiveSkill::GetUp);
}

#[test]
fn a_mirrored_angle_turns_each_shipped_robots_joint_into_its_partners_mirror_image() {
    // Reflecting the body in its sagittal plane maps a rotation axis (x, y, z) to (−x, y, −z);
    // the partner joint turns the mirror way when that equals `sign` times its own axis.
    for name in RobotModel::builtin_names() {
        let model = RobotModel::builtin(name).unwrap();
        for joint in model.joints.iter().filter(|j| j.name.starts_with("left_")) {
            let (partner, sign) = mirror_joint(&joint.name);
            let Some(other) = model.joints.iter().find(|j| j.name == partner) else {
                continue;
            };
            let [x, y, z] = joint.axis;
            let reflected = [-x, y, -z];
            for (r, o) in reflected.iter().zip(other.axis) {
                assert!(
                    (r - sign * o).abs() < 1e-9,
                    "{name}: {} mirrored with sign {sign} is not {partner}",
                    joint.name
                );
            }
        }
    }
}
