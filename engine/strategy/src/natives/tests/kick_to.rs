use libero_behavior::{Status, Value, Vec2};
use libero_skills::kick::KickState;
use libero_skills::{BodyIntent, HeadIntent, Intent, SkillStatus};
use libero_world::{Side, World};

fn tick(world: &World, target: Vec2, kick: KickState) -> (Status, Intent) {
    let skills = SkillStatus {
        kick,
        ..SkillStatus::default()
    };
    let args = [Value::Vec2(target), Value::Float(0.0), Value::Float(4.0)];
    super::run_action(world, "KickTo", &args, skills)
}

/// The right team (own frame = global turned 180°), the robot 0.8 m behind the ball in the
/// own frame, facing the opponents' goal.
fn world() -> World {
    let model = libero_model::RobotModel::builtin("T1").unwrap();
    let mut world = World::new(&model, "Libero", 2);
    world.game.side = Some(Side::Right);
    world.time = 10.0;
    world.me.localized = true;
    world.me.position = [0.8, -2.0]; // own (-0.8, 2)
    world.me.yaw_deg = 180.0;
    world.ball.position = [0.0, -2.0]; // own (0, 2)
    world.ball.last_seen_time = Some(10.0);
    world
}

#[test]
fn asks_for_a_kick_in_the_robot_frame_and_succeeds_once_it_is_done() {
    let world = world();
    // Target straight beyond the ball along own +x: straight ahead of the robot.
    let (status, intent) = tick(&world, Vec2::new(4.0, 2.0), KickState::Idle);
    assert_eq!(status, Status::Running);
    let BodyIntent::Kick {
        ball,
        direction_deg,
        distance_m,
    } = intent.body
    else {
        panic!("no kick asked for: {:?}", intent.body)
    };
    assert!(
        (ball[0] - 0.8).abs() < 1e-9 && ball[1].abs() < 1e-9,
        "{ball:?}"
    );
    assert!(direction_deg.abs() < 1e-9, "{direction_deg}");
    assert!((distance_m - 4.0).abs() < 1e-9, "{distance_m}");
    let (status, intent) = tick(&world, Vec2::new(4.0, 2.0), KickState::Done);
    assert_eq!(status, Status::Success);
    assert_eq!(intent.body, BodyIntent::Stand);
}

#[test]
fn far_from_the_ball_it_walks_to_a_point_behind_it_facing_it() {
    let mut world = world();
    world.me.position = [5.0, -2.0]; // own (-5, 2): 5 m behind the ball
    let (status, intent) = tick(&world, Vec2::new(4.0, 2.0), KickState::Idle);
    assert_eq!(status, Status::Running);
    let BodyIntent::WalkTo {
        target,
        heading_deg,
        ..
    } = intent.body
    else {
        panic!("no walk: {:?}", intent.body)
    };
    // 0.7 m behind the ball on the kick line: 4.3 m straight ahead, facing the ball.
    assert!(
        (target[0] - 4.3).abs() < 1e-6 && target[1].abs() < 1e-6,
        "{target:?}"
    );
    assert!(heading_deg.abs() < 1e-6);
    assert!(matches!(intent.head, HeadIntent::LookAt { .. }));
}

#[test]
fn with_the_way_clear_the_kick_skill_takes_over_early_with_a_robot_in_it_not() {
    // 2.5 m behind the ball: inside `clear_handover_m` (3 m), beyond `handover_m` (1.2 m).
    let mut world = world();
    world.me.position = [2.5, -2.0]; // own (-2.5, 2)
    let (_, intent) = tick(&world, Vec2::new(4.0, 2.0), KickState::Idle);
    assert!(
        matches!(intent.body, BodyIntent::Kick { .. }),
        "{:?}",
        intent.body
    );
    // An opponent between the robot and the ball: walk round it first.
    world.players.known.push(libero_world::PlayerEstimate {
        relation: libero_world::Relation::Opponent,
        unum: 3,
        position: [1.3, -2.0], // own (-1.3, 2)
        heading_deg: None,
        head_height: None,
        fallen: false,
        last_update_time: 10.0,
        source: libero_world::players::Source::Vision,
    });
    let (_, intent) = tick(&world, Vec2::new(4.0, 2.0), KickState::Idle);
    assert!(
        matches!(intent.body, BodyIntent::WalkTo { .. }),
        "{:?}",
        intent.body
    );
    // A rolling ball is met first, whatever the way.
    world.players.known.clear();
    world.ball.velocity = [0.0, 1.5];
    let (_, intent) = tick(&world, Vec2::new(4.0, 2.0), KickState::Idle);
    assert!(
        matches!(intent.body, BodyIntent::WalkTo { .. }),
        "{:?}",
        intent.body
    );
}

#[test]
fn a_short_gap_in_sight_keeps_an_approach_going_a_long_one_gives_up() {
    let mut world = world();
    world.time = 11.0; // unseen for 1 s
    let (status, intent) = tick(&world, Vec2::new(4.0, 2.0), KickState::Approaching);
    assert_eq!(status, Status::Running);
    assert!(
        matches!(intent.body, BodyIntent::Kick { .. }),
        "{:?}",
        intent.body
    );
    // Not yet kicking: search for the ball first.
    let (status, intent) = tick(&world, Vec2::new(4.0, 2.0), KickState::Idle);
    assert_eq!(status, Status::Running);
    assert!(matches!(intent.head, HeadIntent::LookAround { .. }));
    assert!(!matches!(intent.body, BodyIntent::Kick { .. }));
    // Unseen for longer than `lost_after` (4 s): give up.
    world.time = 15.0;
    let (status, _) = tick(&world, Vec2::new(4.0, 2.0), KickState::Approaching);
    assert_eq!(status, Status::Failure);
}

#[test]
fn an_approach_under_way_is_kept_when_a_ball_at_rest_is_fitted_a_slow_roll() {
    // 2.8 m behind the ball with the way clear: the kick skill's approach is under way.
    let mut world = world();
    world.me.position = [2.8, -2.0]; // own (-2.8, 2)
                                     // The tracker fits a slow roll to a ball at rest now and then (0.3 m/s, 0.1 m to go):
                                     // that must not hand the approach back to the walk behind the ball (it swapped every few
                                     // cycles, turning the robot each time).
    world.ball.velocity = [-0.3, 0.0];
    let (_, intent) = tick(&world, Vec2::new(4.0, 2.0), KickState::Approaching);
    assert!(
        matches!(intent.body, BodyIntent::Kick { .. }),
        "{:?}",
        intent.body
    );
    // A ball that rolled on beyond twice the clear hand-over is walked after again.
    world.me.position = [6.5, -2.0]; // own (-6.5, 2)
    let (_, intent) = tick(&world, Vec2::new(4.0, 2.0), KickState::Approaching);
    assert!(
        matches!(intent.body, BodyIntent::WalkTo { .. }),
        "{:?}",
        intent.body
    );
}
