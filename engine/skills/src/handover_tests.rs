//! Hand-overs between skills that share the walk's gait.

use crate::{ActiveSkill, BodyIntent, Intent, JointTargets, SkillParams, Skills};
use libero_model::RobotModel;
use libero_world::World;

fn intent(body: BodyIntent) -> Intent {
    Intent {
        body,
        ..Intent::default()
    }
}

/// Walking on into a dribble (the walk to the ball handing over to the dribble skill) and back
/// is one gait: no blend from the pose sent last, which held the legs back mid-stride for the
/// walk's `settle_s` and tipped a robot at speed over its feet. A start from standing still
/// blends as before.
#[test]
fn walking_into_a_dribble_and_back_keeps_the_gait_without_a_blend() {
    let model = RobotModel::builtin("T1").unwrap();
    let params = SkillParams::builtin(&model).unwrap();
    let mut world = World::new(&model, "t", 1);
    world.me.pitch_deg = params.walk.torso_lean_deg;
    let mut skills = Skills::new(&model, params).unwrap();
    let mut out = JointTargets::default();
    let walk = intent(BodyIntent::Walk {
        forward_m_s: 0.5,
        sideways_m_s: 0.0,
        turn_deg_s: 0.0,
    });
    // The ball straight ahead, pushed straight on: the dribble pushes at once.
    let dribble = intent(BodyIntent::Dribble {
        ball: [0.6, 0.1],
        direction_deg: 0.0,
        kick_steps: false,
    });
    let mut step = |skills: &mut Skills, world: &mut World, what: &Intent| {
        world.time += 0.02;
        skills.act(&model, world, what, &mut out);
        world.body.joint_angles = out.joints.iter().map(|j| j.q_deg).collect();
    };
    step(&mut skills, &mut world, &walk);
    assert_eq!(skills.active(), ActiveSkill::Walk);
    assert!(skills.blend.is_some(), "a walk from standing blends in");
    for _ in 0..100 {
        step(&mut skills, &mut world, &walk);
    }
    assert!(skills.blend.is_none());
    step(&mut skills, &mut world, &dribble);
    assert_eq!(skills.active(), ActiveSkill::Dribble);
    assert!(
        skills.blend.is_none(),
        "the hand-over to the dribble blended"
    );
    for _ in 0..20 {
        step(&mut skills, &mut world, &dribble);
    }
    step(&mut skills, &mut world, &walk);
    assert_eq!(skills.active(), ActiveSkill::Walk);
    assert!(
        skills.blend.is_none(),
        "the hand-over back to the walk blended"
    );
}
