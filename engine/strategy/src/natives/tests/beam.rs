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

#[test]
fn the_kick_off_taker_is_beamed_nearer_the_ball_by_the_stand_poses_lead() {
    let model = libero_model::RobotModel::builtin("T1").unwrap();
    let mut world = World::new(&model, "Libero", 7);
    world.game.side = Some(Side::Left);
    world.game.play_mode = PlayMode::BeforeKickOff;
    let beam_for = |beam_nearer_m: f64| {
        let skills = SkillStatus {
            kick_geometry: libero_skills::kick::KickGeometry {
                beam_nearer_m,
                ..libero_skills::kick::KickGeometry::default()
            },
            ..SkillStatus::default()
        };
        let target = libero_behavior::Value::Vec2(libero_behavior::Vec2::new(1.0, 1.75));
        let (status, intent) = run_action(&world, "BeamToKickPlace", &[target], skills);
        assert_eq!(status, Status::Success);
        let [x, y, _] = intent.beam.expect("a beam");
        x.hypot(y)
    };
    let geometry = libero_skills::kick::KickGeometry::default();
    let place = geometry.ball_ahead_m.hypot(geometry.ball_beside_m);
    assert!((beam_for(0.0) - place).abs() < 1e-6, "{}", beam_for(0.0));
    let nearer = (geometry.ball_ahead_m - 0.06).hypot(geometry.ball_beside_m);
    assert!((beam_for(0.06) - nearer).abs() < 1e-6, "{}", beam_for(0.06));
}
