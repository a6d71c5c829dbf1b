use super::*;
use libero_world::{PlayMode, Relation, Side, World};

/// Player 2 of the left team in play at `me`, facing +x, the ball at `ball`.
fn world(me: [f64; 2], ball: [f64; 2]) -> World {
    let model = libero_model::RobotModel::builtin("T1").unwrap();
    let mut world = World::new(&model, "Libero", 2);
    world.game.side = Some(Side::Left);
    world.game.play_mode = PlayMode::PlayOn;
    world.time = 20.0;
    world.me.localized = true;
    world.me.position = me;
    world.ball.position = ball;
    world.ball.last_seen_time = Some(20.0);
    world
}

fn winner(world: &World, memory: &mut PlayerMemory) -> bool {
    let args = [
        Value::Float(0.5),
        Value::Float(60.0),
        Value::Float(5.0),
        Value::Float(0.5),
    ];
    run_query(world, "am_ball_winner", &args, memory).as_bool()
}

/// Teammate `unum`'s word heard 0.1 s ago.
fn claim(unum: u32, time_to_ball_s: f64, going_for_ball: bool) -> libero_world::BallClaim {
    libero_world::BallClaim {
        unum,
        time_to_ball_s: Some(time_to_ball_s),
        going_for_ball,
        fallen: false,
        at: 19.9,
    }
}

#[test]
fn of_two_players_going_for_the_ball_the_slower_gives_way_and_the_one_going_keeps_it() {
    // We are 2 m from the ball (4 s), teammate 3 says 3.6 s.
    let mut w = world([8.0, 0.0], [10.0, 0.0]);
    w.players
        .heard(Relation::Teammate, 3, [11.8, 0.0], Some(false), 19.9);
    let going = PlayerMemory::default();
    going.ball_winner.set(true);
    // It does not go (yet): we went, and keep the ball within our head start (0.5 s).
    w.heard.claims.push(claim(3, 3.6, false));
    assert!(winner(&w, &mut going.clone()));
    // It goes too: bare times, and it is quicker. With a head start each (the old rule) both
    // kept going and ran into each other.
    w.heard.claims[0] = claim(3, 3.6, true);
    assert!(!winner(&w, &mut going.clone()));
    // Not going ourselves, a teammate that goes keeps the ball even when we are a little
    // quicker ...
    w.heard.claims[0] = claim(3, 4.4, true);
    assert!(!winner(&w, &mut PlayerMemory::default()));
    // ... but not when we are quicker by more than its head start.
    w.heard.claims[0] = claim(3, 4.6, true);
    assert!(winner(&w, &mut PlayerMemory::default()));
    // Both going and equally quick as the messages tell it: the lower number goes, on both
    // sides alike (we are 2).
    w.heard.claims[0] = claim(3, 4.0, true);
    assert!(winner(&w, &mut going.clone()));
}

#[test]
fn the_ball_winner_is_whoever_gets_there_first_not_whoever_is_nearest() {
    let mut w = world([8.0, 0.0], [10.0, 0.0]); // 2 m ahead: 4 s
    let mut memory = PlayerMemory::default();
    assert!(winner(&w, &mut memory), "alone");
    assert_eq!(memory.time_to_ball.get(), Some(4.0));
    // A teammate 1 m from the ball (2 s): it goes.
    w.players
        .heard(Relation::Teammate, 3, [11.0, 0.0], Some(false), 20.0);
    let mut memory = PlayerMemory::default();
    assert!(!winner(&w, &mut memory));
    // The same teammate lying down (2 s + 5 s to get up): we go.
    w.players
        .heard(Relation::Teammate, 3, [11.0, 0.0], Some(true), 20.01);
    assert!(winner(&w, &mut memory));
    // Our own back to the ball costs the turn: facing away (180° at 60°/s = 3 s) we are
    // slower (7 s) than the lying teammate (7 s) by nothing, but winners keep the ball
    // within the hysteresis.
    w.me.yaw_deg = 180.0;
    assert!(winner(&w, &mut memory));
    let mut fresh = PlayerMemory::default();
    assert!(winner(&w, &mut fresh), "a tie goes to us");
    // The goalkeeper's position never counts.
    w.players
        .heard(Relation::Teammate, 1, [10.0, 0.2], Some(false), 20.02);
    assert!(winner(&w, &mut PlayerMemory::default()));
}

#[test]
fn a_claim_at_the_messages_ceiling_is_judged_from_where_the_teammate_is() {
    use libero_world::team_message::TIME_TO_BALL_MAX_S;
    // We are 14 m from the ball (28 s); every claim heard is at the ceiling (12.4 s), which
    // only says "12.4 s or more". Before, everybody far away waited for somebody else.
    let mut w = world([-4.0, 0.0], [10.0, 0.0]);
    w.heard.claims.push(claim(3, TIME_TO_BALL_MAX_S, false));
    w.players
        .heard(Relation::Teammate, 3, [-10.0, 0.0], Some(false), 19.9);
    assert!(
        winner(&w, &mut PlayerMemory::default()),
        "the teammate is 20 m away"
    );
    w.players
        .heard(Relation::Teammate, 3, [-3.0, 0.0], Some(false), 19.95);
    assert!(
        !winner(&w, &mut PlayerMemory::default()),
        "the teammate is 13 m away"
    );
    // Seen lying from afar (vision misjudges heads far away) while it says it stands: its
    // word counts.
    w.players.known.iter_mut().for_each(|p| p.fallen = true);
    assert!(
        !winner(&w, &mut PlayerMemory::default()),
        "the teammate says it stands"
    );
}

/// The ball lies at (10, 0) for a second, then is kicked along +x at 5.4 m/s (the server's
/// own roll, from the launch table), seen every 20 ms for 0.3 s; `kicker` stands at the
/// spot it left.
fn kicked_ball(kicker: Relation) -> World {
    kicked_ball_at(kicker, 5.4, [16.0, 1.0])
}

/// The same kick at `speed` [m/s], this player at `me`.
fn kicked_ball_at(kicker: Relation, speed: f64, me: [f64; 2]) -> World {
    let mut w = world(me, [10.0, 0.0]);
    let table = libero_world::WorldParams::builtin().ball.launch_table;
    let mut t = 19.0;
    for _ in 0..50 {
        w.ball
            .update(t, Some(nalgebra::Vector3::new(10.0, 0.0, 0.11)));
        t += 0.02;
    }
    let launch = t;
    for _ in 0..15 {
        t += 0.02;
        let x = 10.0 + table.distance(speed, 0.0, t - launch);
        w.ball.update(t, Some(nalgebra::Vector3::new(x, 0.0, 0.11)));
    }
    w.time = t;
    w.players.heard(kicker, 3, [9.7, 0.0], Some(false), t);
    w
}

fn meeting(world: &World) -> (f64, libero_world::Own) {
    let library = shipped_library();
    let natives = Natives::new();
    let skills = libero_skills::SkillStatus::default();
    let mut intent = libero_skills::Intent::default();
    let mut memory = PlayerMemory::default();
    let host = AgentHost::new(
        world,
        crate::strategy_of(&library),
        &natives,
        &skills,
        &mut memory,
        &mut intent,
    );
    host.meeting(host.me(), 0.5)
}

#[test]
fn a_pass_of_ours_is_met_where_it_stops_a_kick_of_theirs_on_its_way() {
    let ours = kicked_ball(Relation::Teammate);
    let stop = ours.ball.predicted_stop;
    assert!(ours.ball.launched_from().is_some(), "a launch from rest");
    assert!(stop[0] > 17.0, "the roll goes on past us: {stop:?}");
    // Our teammate kicked it: we walk to where it stops.
    let (_, at) = meeting(&ours);
    assert!(
        (at.x - stop[0]).hypot(at.y - stop[1]) < 1e-9,
        "{at:?} vs {stop:?}"
    );
    // Theirs: we meet it on its way, before it gets there.
    let theirs = kicked_ball(Relation::Opponent);
    let (_, at) = meeting(&theirs);
    assert!(at.x < stop[0] - 0.5, "{at:?} vs {stop:?}");
}

fn kick_to(world: &World) -> libero_skills::BodyIntent {
    let args = [
        Value::Vec2(libero_behavior::Vec2::new(27.5, 0.0)),
        Value::Float(0.0),
        Value::Float(4.0),
    ];
    let skills = libero_skills::SkillStatus::default();
    super::run_action(world, "KickTo", &args, skills).1.body
}

#[test]
fn the_receiver_of_our_pass_waits_beside_its_stop_point_a_nudged_ball_is_kicked() {
    use libero_skills::BodyIntent;
    // Our pass rolls on past us to (17+, 0): we walk to beside where it stops, facing it,
    // not onto its path.
    let w = kicked_ball(Relation::Teammate);
    let stop = w.ball.predicted_stop;
    let BodyIntent::WalkTo { target, .. } = kick_to(&w) else {
        panic!("no walk: {:?}", kick_to(&w))
    };
    // The walk's first waypoint, robot frame (facing +x from (16, 1)): ahead, not across
    // the ball's line (y = 0 in the field, -1 m to our right).
    assert!(target[1] > -1.0 + 0.3, "{target:?} (stop {stop:?})");
    // A ball we nudged at our feet (rolling slowly on from where we stand): kicked as it
    // lies. Waiting beside it, a robot stood at the ball for two minutes.
    let w = kicked_ball_at(Relation::Teammate, 0.9, [9.8, 0.1]);
    assert!(w.ball.velocity != [0.0; 2], "the nudged ball rolls");
    assert!(
        matches!(kick_to(&w), BodyIntent::Kick { .. }),
        "{:?}",
        kick_to(&w)
    );
}

#[test]
fn a_receiver_beside_the_path_short_of_the_stop_point_keeps_off_the_path() {
    use libero_skills::BodyIntent;
    // Our pass rolls along y = 0 from (10, 0) to 17+; we stand 0.9 m to its right, short
    // of where it stops, facing +x. The way to the waiting point runs beside the path.
    for me in [[13.0, -0.9], [14.0, -0.8], [12.5, 0.9]] {
        let w = kicked_ball_at(Relation::Teammate, 5.4, me);
        let BodyIntent::WalkTo { target, .. } = kick_to(&w) else {
            panic!("no walk: {:?}", kick_to(&w))
        };
        let across = me[1] + target[1];
        assert!(
            across.abs() > 0.6 && across.signum() == me[1].signum(),
            "from {me:?} the walk goes to {target:?} (robot frame): {across:.2} m off the path"
        );
    }
}

#[test]
fn in_play_a_player_takes_the_formation_slot_the_assignment_gives_it() {
    // The ball at the centre: in `attack`, slot 2 is at (-12, 5) and slot 3 at (-12, -5).
    let mut w = world([-12.0, -5.0], [0.0, 0.0]);
    w.players
        .heard(Relation::Teammate, 3, [-12.0, 5.0], Some(false), 20.0);
    let mut memory = PlayerMemory::default();
    let at = run_query(&w, "formation_position", &[Value::Float(0.0)], &mut memory).as_vec2();
    assert!(
        (at.x + 12.0).abs() < 0.01 && (at.y + 5.0).abs() < 0.01,
        "{at:?}"
    );
    // Before kick-off every player keeps its own.
    w.game.play_mode = PlayMode::BeforeKickOff;
    let at = run_query(&w, "formation_position", &[Value::Float(0.0)], &mut memory).as_vec2();
    assert!(at.y > 0.0, "{at:?}");
}

fn formation_position(world: &World, memory: &mut PlayerMemory) -> Vec2 {
    run_query(world, "formation_position", &[Value::Float(0.0)], memory).as_vec2()
}

#[test]
fn the_ball_winner_takes_the_slot_nearest_the_ball_and_the_others_share_the_rest() {
    // In `attack` with the ball at the centre the slot nearest the ball is the centre
    // midfielder's (5) at (-4, 0); the striker's (7) is at (10, 0), drawn a tenth of the way
    // to the ball: (9, 0).
    let mut w = world([9.5, 0.0], [0.0, 0.0]);
    let mut memory = PlayerMemory::default();
    memory.ball_winner.set(true);
    let at = formation_position(&w, &mut memory);
    assert!(
        (at.x + 4.0).abs() < 0.01 && at.y.abs() < 0.01,
        "winner: {at:?}"
    );
    // Not the winner: teammate 5 claims the ball (heard), so it is out of the assignment;
    // we stand by the striker's slot and the striker (7) by ours, the left back's at
    // (-12, 5): we swap.
    memory.ball_winner.set(false);
    w.heard.claims.push(claim(5, 1.0, false));
    w.players
        .heard(Relation::Teammate, 5, [0.5, 0.0], Some(false), 19.9);
    w.players
        .heard(Relation::Teammate, 7, [-11.5, 5.0], Some(false), 19.9);
    let at = formation_position(&w, &mut PlayerMemory::default());
    assert!(
        (at.x - 9.0).abs() < 0.01 && at.y.abs() < 0.01,
        "supporter: {at:?}"
    );
}
