use super::*;
use crate::pass::PassParams;
use libero_world::{PlayMode, Relation, Side, World};

/// Our `formation_position` with the shipped files but `anticipate_within_m`, the T1's
/// measured long kick.
fn target(world: &World, anticipate_within_m: f64) -> Vec2 {
    let library = shipped_library();
    let mut strategy = crate::strategy_of(&library).clone();
    strategy.pass = Some(PassParams {
        anticipate_within_m,
        ..strategy.pass.unwrap()
    });
    let natives = Natives::new();
    let skills = t1_kick_skills();
    let mut memory = PlayerMemory::default();
    let mut intent = libero_skills::Intent::default();
    let host = AgentHost::new(
        world,
        &strategy,
        &natives,
        &skills,
        &mut memory,
        &mut intent,
    );
    let id = vocabulary()
        .find(libero_behavior::NativeKind::Query, "formation_position")
        .unwrap();
    host.query(id, Args(&[Value::Float(0.0)])).as_vec2()
}

/// Teammate 4 at `winner` (by the ball at (1, 1.5) after our kick-off), claiming the ball;
/// the others in their kick-off places; we (7) 3 m up the field, the nearest to where its
/// long kick would stop (11 m on, towards their goal).
fn world(winner: [f64; 2]) -> World {
    let model = libero_model::RobotModel::builtin("T1").unwrap();
    let mut world = World::new(&model, "Libero", 7);
    world.game.side = Some(Side::Left);
    world.game.play_mode = PlayMode::PlayOn;
    world.time = 20.0;
    world.me.localized = true;
    world.me.position = [3.0, 0.5];
    world.ball.position = [1.0, 1.5];
    world.ball.last_seen_time = Some(20.0);
    world.heard.claims.push(libero_world::BallClaim {
        unum: 4,
        time_to_ball_s: Some(0.5),
        going_for_ball: true,
        fallen: false,
        at: 19.9,
    });
    for (unum, at) in [
        (4, winner),
        (2, [-12.0, 5.0]),
        (3, [-12.0, -5.0]),
        (5, [-7.0, 0.0]),
        (6, [0.0, -7.0]),
    ] {
        world
            .players
            .heard(Relation::Teammate, unum, at, Some(false), 19.9);
    }
    world
}

#[test]
fn while_a_teammate_is_at_the_ball_the_slot_nearest_its_pass_moves_beside_where_it_stops() {
    let w = world([0.6, 1.4]);
    let plain = target(&w, 0.0);
    let waiting = target(&w, 5.0);
    // Without: the striker's slot, 10 m ahead of the ball, drawn towards it.
    assert!(plain.x < 11.0, "{plain:?}");
    // With: beside the pass's stop point, 11 m on from the ball and a metre off its path.
    let from_ball = ((waiting.x - 1.0).powi(2) + (waiting.y - 1.5).powi(2)).sqrt();
    assert!(
        (from_ball - (11.1f64.powi(2) + 1.0).sqrt()).abs() < 0.3,
        "{waiting:?} ({from_ball:.2} m from the ball)"
    );
    // The teammate farther than `anticipate_within_m` from the ball: nothing moves yet.
    let far = world([-6.0, 1.5]);
    assert_eq!(target(&far, 5.0), target(&far, 0.0));
    // A rolling ball: the receivers go by where it will stop, as before.
    let mut rolling = world([0.6, 1.4]);
    rolling.ball.velocity = [2.0, 0.0];
    rolling.ball.predicted_stop = [4.0, 1.5];
    assert_eq!(target(&rolling, 5.0), target(&rolling, 0.0));
}
