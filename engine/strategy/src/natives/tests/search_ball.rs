use libero_behavior::{Status, Value};
use libero_skills::{BodyIntent, HeadIntent, Intent, SkillStatus};
use libero_world::{Side, World};

fn tick(world: &World) -> (Status, Intent) {
    let args = [Value::Float(40.0), Value::Float(0.5)];
    super::run_action(world, "SearchBall", &args, SkillStatus::default())
}

#[test]
fn a_lost_ball_is_searched_for_turning_its_way_and_found_once_seen() {
    let model = libero_model::RobotModel::builtin("T1").unwrap();
    let mut world = World::new(&model, "Libero", 7);
    world.game.side = Some(Side::Left);
    world.me.localized = true;
    world.me.position = [0.0, 0.0];
    world.me.yaw_deg = 0.0;
    // Last believed behind the robot and to its right, 5 s ago.
    world.ball.position = [-1.0, -0.5];
    world.ball.last_seen_time = Some(5.0);
    world.time = 10.0;
    let (status, intent) = tick(&world);
    assert_eq!(status, Status::Running);
    let BodyIntent::Walk {
        forward_m_s,
        sideways_m_s,
        turn_deg_s,
    } = intent.body
    else {
        panic!("not turning: {:?}", intent.body)
    };
    assert!(forward_m_s == 0.0 && sideways_m_s == 0.0);
    assert!(
        (turn_deg_s + 40.0).abs() < 1e-9,
        "turns right: {turn_deg_s}"
    );
    assert!(matches!(intent.head, HeadIntent::LookAround { .. }));
    // Seen just now: found.
    world.ball.last_seen_time = Some(9.8);
    assert_eq!(tick(&world).0, Status::Success);
}
