use libero_behavior::{Status, Value, Vec2};
use libero_skills::{BodyIntent, DribbleState, HeadIntent, Intent, SkillStatus};
use libero_world::{Side, World};

fn tick(world: &World, target: Vec2, dribble: DribbleState) -> (Status, Intent) {
    tick_kicking_beyond(world, target, dribble, 1000.0)
}

/// `DribbleTo` with kick steps while the ball is farther than `kick_beyond` from the target.
fn tick_kicking_beyond(
    world: &World,
    target: Vec2,
    dribble: DribbleState,
    kick_beyond: f64,
) -> (Status, Intent) {
    let skills = SkillStatus {
        dribble,
        ..SkillStatus::default()
    };
    let args = [
        Value::Vec2(target),
        Value::Float(0.5),
        Value::Float(kick_beyond),
        Value::Float(4.0),
    ];
    super::run_action(world, "DribbleTo", &args, skills)
}

/// The right team (own frame = global turned 180°), facing the opponents' goal, the ball
/// 0.8 m ahead (own (0, 2)).
fn world(me_own_x: f64) -> World {
    let model = libero_model::RobotModel::builtin("T1").unwrap();
    let mut world = World::new(&model, "Libero", 2);
    world.game.side = Some(Side::Right);
    world.time = 10.0;
    world.me.localized = true;
    world.me.position = [-me_own_x, -2.0];
    world.me.yaw_deg = 180.0;
    world.ball.position = [0.0, -2.0];
    world.ball.last_seen_time = Some(10.0);
    world
}

#[test]
fn near_the_ball_it_asks_the_skill_to_walk_it_along_the_line_to_the_target() {
    // Target ahead and to the left of the ball (own +x, +y): 45° to the left.
    let (status, intent) = tick(&world(-0.8), Vec2::new(4.0, 6.0), DribbleState::Idle);
    assert_eq!(status, Status::Running);
    let BodyIntent::Dribble {
        ball,
        direction_deg,
        kick_steps,
    } = intent.body
    else {
        panic!("no dribble: {:?}", intent.body)
    };
    assert!(
        (ball[0] - 0.8).abs() < 1e-9 && ball[1].abs() < 1e-9,
        "{ball:?}"
    );
    assert!((direction_deg - 45.0).abs() < 1e-6, "{direction_deg}");
    // No kick steps unless the tree asks for them.
    assert!(!kick_steps);
    // The dribble skill keeps the head on the ball itself.
    assert_eq!(intent.head, HeadIntent::Hold);
}

#[test]
fn far_from_the_ball_it_walks_behind_it_and_there_it_succeeds() {
    // 5 m behind the ball: walk (round obstacles) to 0.7 m behind it on the line.
    let (status, intent) = tick(&world(-5.0), Vec2::new(4.0, 2.0), DribbleState::Idle);
    assert_eq!(status, Status::Running);
    let BodyIntent::WalkTo { target, .. } = intent.body else {
        panic!("no walk: {:?}", intent.body)
    };
    assert!(
        (target[0] - 4.3).abs() < 1e-6 && target[1].abs() < 1e-6,
        "{target:?}"
    );
    // The ball within the tolerance of the target: done.
    let (status, _) = tick(&world(-0.8), Vec2::new(0.3, 2.0), DribbleState::Pushing);
    assert_eq!(status, Status::Success);
    // Unseen for longer than `lost_after`: give up.
    let mut w = world(-0.8);
    w.time = 15.0;
    let (status, _) = tick(&w, Vec2::new(4.0, 2.0), DribbleState::Pushing);
    assert_eq!(status, Status::Failure);
}

#[test]
fn kick_steps_are_asked_for_while_the_ball_is_farther_from_the_target_than_kick_beyond() {
    // The ball at own (0, 2), the target 4 m ahead of it and 4 m to the side: 5.66 m away.
    let kicks = |kick_beyond: f64| {
        let (_, intent) = tick_kicking_beyond(
            &world(-0.8),
            Vec2::new(4.0, 6.0),
            DribbleState::Pushing,
            kick_beyond,
        );
        match intent.body {
            BodyIntent::Dribble { kick_steps, .. } => kick_steps,
            other => panic!("no dribble: {other:?}"),
        }
    };
    assert!(kicks(5.0));
    assert!(!kicks(6.0));
}
