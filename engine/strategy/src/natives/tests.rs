use super::*;
use std::collections::HashSet;

/// One call of the action `name` with `args` on the shipped files, with the skills reporting
/// `skills`: its status and the intent it wrote.
fn run_action(
    world: &libero_world::World,
    name: &str,
    args: &[Value],
    skills: libero_skills::SkillStatus,
) -> (Status, libero_skills::Intent) {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let library = crate::load(&[root.join("behaviors"), root.join("formations")]).unwrap();
    let natives = Natives::new();
    let mut memory = PlayerMemory::default();
    let mut intent = libero_skills::Intent::default();
    let mut host = AgentHost::new(
        world,
        crate::strategy_of(&library),
        &natives,
        &skills,
        &mut memory,
        &mut intent,
    );
    let id = vocabulary()
        .find(libero_behavior::NativeKind::Action, name)
        .unwrap();
    let status = host.action(id, Args(args));
    (status, intent)
}

#[test]
fn every_node_declares_a_unique_name_its_kind_and_documents_its_ports() {
    let mut names = HashSet::new();
    for native in catalogue() {
        let spec = (native.declare)();
        assert_eq!(spec.kind, native.run.kind(), "{}", spec.name);
        assert!(
            names.insert((spec.kind, spec.name.clone())),
            "{} twice",
            spec.name
        );
        assert!(!spec.doc.is_empty(), "{} has no doc", spec.name);
        for port in &spec.params {
            assert!(
                !port.doc.is_empty(),
                "{}.{} has no doc",
                spec.name,
                port.name
            );
        }
    }
    // The vocabulary and the dispatch table come from the same list, in the same order.
    let vocabulary = vocabulary();
    let natives = Natives::new();
    assert_eq!(vocabulary.nodes().len(), natives.by_id.len());
    for (i, spec) in vocabulary.nodes().iter().enumerate() {
        assert_eq!(natives.by_id[i].1.name, spec.name);
    }
}

#[test]
fn ports_are_read_by_name_whatever_their_order() {
    let spec = NodeSpec::action("A", "a")
        .param(libero_behavior::ParamSpec::new("first", libero_behavior::ValueType::Float).doc("1"))
        .param(
            libero_behavior::ParamSpec::new("second", libero_behavior::ValueType::Vec2).doc("2"),
        );
    let values = [Value::Float(2.5), Value::Vec2(Vec2::new(1.0, -1.0))];
    let ports = Ports::new(Args(&values), &spec);
    assert_eq!(ports.float("first"), 2.5);
    assert_eq!(ports.vec2("second"), Vec2::new(1.0, -1.0));
}

mod kick_to {
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
}

mod dribble_to {
    use libero_behavior::{Status, Value, Vec2};
    use libero_skills::{BodyIntent, DribbleState, HeadIntent, Intent, SkillStatus};
    use libero_world::{Side, World};

    fn tick(world: &World, target: Vec2, dribble: DribbleState) -> (Status, Intent) {
        let skills = SkillStatus {
            dribble,
            ..SkillStatus::default()
        };
        let args = [Value::Vec2(target), Value::Float(0.5), Value::Float(4.0)];
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
        } = intent.body
        else {
            panic!("no dribble: {:?}", intent.body)
        };
        assert!(
            (ball[0] - 0.8).abs() < 1e-9 && ball[1].abs() < 1e-9,
            "{ball:?}"
        );
        assert!((direction_deg - 45.0).abs() < 1e-6, "{direction_deg}");
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
}

mod shot_is_good {
    use crate::shot::ShotParams;
    use crate::{strategy_of, AgentHost, Natives, PlayerMemory};
    use libero_behavior::{Args, Host, NativeKind};
    use libero_skills::{Intent, SkillStatus};
    use libero_world::{Side, World};

    /// One `ShotIsGood` with the shipped files but `threshold`; the memory carries over.
    fn good(world: &World, threshold: f64, memory: &mut PlayerMemory) -> bool {
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
        let library = crate::load(&[root.join("behaviors"), root.join("formations")]).unwrap();
        let mut strategy = strategy_of(&library).clone();
        strategy.shot = Some(ShotParams {
            threshold,
            hysteresis: 0.1,
            ..strategy.shot.unwrap()
        });
        let natives = Natives::new();
        let skills = SkillStatus {
            kick_spread: libero_skills::kick::KickSpread {
                direction_sd_deg: 2.6,
                distance_m: 11.1,
                distance_sd_m: 1.3,
            },
            ..SkillStatus::default()
        };
        let mut intent = Intent::default();
        let host = AgentHost::new(world, &strategy, &natives, &skills, memory, &mut intent);
        let id = crate::vocabulary()
            .find(NativeKind::Condition, "ShotIsGood")
            .unwrap();
        host.condition(id, Args(&[]))
    }

    #[test]
    fn once_good_a_shot_stays_good_until_it_falls_below_the_hysteresis_band() {
        let model = libero_model::RobotModel::builtin("T1").unwrap();
        let mut world = World::new(&model, "Libero", 7);
        world.game.side = Some(Side::Left);
        world.time = 10.0;
        world.me.localized = true;
        world.me.position = [18.0, 0.0];
        world.ball.position = [19.0, 0.0];
        world.ball.last_seen_time = Some(10.0);
        let mut memory = PlayerMemory::default();
        // Find this spot's chance by the threshold it just clears.
        let chance = (0..100)
            .map(|i| f64::from(i) / 100.0)
            .rfind(|t| good(&world, *t, &mut PlayerMemory::default()))
            .unwrap();
        assert!(chance > 0.1, "an empty goal 8.5 m away: {chance}");
        // Above the threshold, then the threshold rises past the chance, within the band.
        assert!(good(&world, chance, &mut memory));
        world.time += 0.02;
        assert!(
            good(&world, chance + 0.05, &mut memory),
            "kept within the band"
        );
        // Not chosen before: the same threshold is not met.
        assert!(!good(&world, chance + 0.05, &mut PlayerMemory::default()));
        // Beyond the band it lets go, and then the plain threshold counts again.
        world.time += 0.02;
        assert!(!good(&world, chance + 0.15, &mut memory));
        world.time += 0.02;
        assert!(!good(&world, chance + 0.05, &mut memory));
    }
}

mod search_ball {
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
}

/// One evaluation of the query `name` with `args` on the shipped files, with `memory` kept
/// between calls.
fn run_query(
    world: &libero_world::World,
    name: &str,
    args: &[Value],
    memory: &mut PlayerMemory,
) -> Value {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let library = crate::load(&[root.join("behaviors"), root.join("formations")]).unwrap();
    let natives = Natives::new();
    let skills = libero_skills::SkillStatus::default();
    let mut intent = libero_skills::Intent::default();
    let host = AgentHost::new(
        world,
        crate::strategy_of(&library),
        &natives,
        &skills,
        memory,
        &mut intent,
    );
    let id = vocabulary()
        .find(libero_behavior::NativeKind::Query, name)
        .unwrap();
    host.query(id, Args(args))
}

mod team_play {
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
        // We are 14 m from the ball (28 s); every claim heard is at the ceiling (25 s), which
        // only says "25 s or more". Before, everybody far away waited for somebody else.
        let mut w = world([-4.0, 0.0], [10.0, 0.0]);
        w.heard.claims.push((3, Some(TIME_TO_BALL_MAX_S), 19.9));
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
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
        let library = crate::load(&[root.join("behaviors"), root.join("formations")]).unwrap();
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
        w.heard.claims.push((5, Some(1.0), 19.9));
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
}

mod anticipation {
    use super::*;
    use crate::pass::PassParams;
    use libero_world::{PlayMode, Relation, Side, World};

    /// Our `formation_position` with the shipped files but `anticipate_within_m`, the T1's
    /// measured long kick.
    fn target(world: &World, anticipate_within_m: f64) -> Vec2 {
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
        let library = crate::load(&[root.join("behaviors"), root.join("formations")]).unwrap();
        let mut strategy = crate::strategy_of(&library).clone();
        strategy.pass = Some(PassParams {
            anticipate_within_m,
            ..strategy.pass.unwrap()
        });
        let natives = Natives::new();
        let skills = libero_skills::SkillStatus {
            kick_spread: libero_skills::kick::KickSpread {
                direction_sd_deg: 2.6,
                distance_m: 11.1,
                distance_sd_m: 1.3,
            },
            ..libero_skills::SkillStatus::default()
        };
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
        world.heard.claims.push((4, Some(0.5), 19.9));
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
}

mod beam {
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
}
