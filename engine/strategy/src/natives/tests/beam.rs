use super::*;
use libero_skills::{ActiveSkill, BodyIntent, SkillStatus};
use libero_world::{PlayMode, Side, World};

#[test]
fn a_walking_robot_stops_before_it_beams() {
    let model = libero_model::RobotModel::builtin("T1").unwrap();
    let mut world = World::new(&model, "Libero", 4);
    world.game.side = Some(Side::Left);
    world.game.play_mode = PlayMode::Goal(Side::Left);
    world.time = 30.0;
    let status = |active| SkillStatus {
        active,
        ..SkillStatus::default()
    };
    for active in [ActiveSkill::Walk, ActiveSkill::Kick, ActiveSkill::Dribble] {
        let (s, intent) = run_action(&world, "BeamToFormation", &[], status(active));
        assert_eq!(s, Status::Running, "{active:?}");
        assert!(intent.beam.is_none(), "{active:?}");
        assert_eq!(intent.body, BodyIntent::Stand, "{active:?}");
    }
    let (s, intent) = run_action(&world, "BeamToFormation", &[], status(ActiveSkill::Stand));
    assert_eq!(s, Status::Success);
    assert!(intent.beam.is_some());
}
