//! Communication on the real server: a player that cannot see the ball knows where it is from
//! what a teammate who sees it says (thesis 6.4), judged against the server's ground truth.

use libero_agent::decide::StandAndBeam;
use libero_agent::{AgentConfig, AgentStats, Player, Team};
use libero_skills::{SkillParams, Skills};
use libero_tests::{fast_server, t1, wait_sim_seconds};
use std::sync::atomic::AtomicBool;
use std::sync::Arc;

/// One line of a player's evaluation log, as far as this test reads it.
#[derive(serde::Deserialize)]
struct Line {
    time: f64,
    ball: Option<LoggedBall>,
    heard: LoggedHeard,
}

#[derive(serde::Deserialize)]
struct LoggedBall {
    position: [f64; 2],
    last_seen_time: Option<f64>,
    heard_time: Option<f64>,
}

#[derive(serde::Deserialize)]
struct LoggedHeard {
    taken: u64,
}

fn player(unum: u32, pose: [f64; 3], log: &std::path::Path) -> Player {
    let model = t1();
    let skills = Skills::new(&model, SkillParams::builtin(&model).unwrap()).unwrap();
    let mut player = Player::new(
        Arc::clone(&model),
        skills,
        Box::new(StandAndBeam { beam_pose: pose }),
        "Libero",
        unum,
        Arc::new(AgentStats::default()),
    );
    player.log_to(
        libero_world::eval_log::EvalLogger::create(log).unwrap(),
        false,
    );
    player
}

fn lines(path: &std::path::Path) -> Vec<Line> {
    std::fs::read_to_string(path)
        .unwrap()
        .lines()
        .filter_map(|l| serde_json::from_str(l).ok())
        .collect()
}

#[test]
fn players_facing_away_from_the_ball_know_where_it_is_from_a_teammate() {
    let mut server = fast_server();
    let dir = tempfile::tempdir().unwrap();
    // Player 2 faces the ball 3 m ahead; 3 and 4 stand with their backs to it (the head's
    // pan and the camera's field of view do not reach behind).
    let poses = [
        (2, [-3.0, 0.0, 0.0]),
        (3, [-6.0, 3.0, 180.0]),
        (4, [-6.0, -3.0, 180.0]),
    ];
    let logs: Vec<_> = poses
        .iter()
        .map(|(u, _)| dir.path().join(format!("player{u}.jsonl")))
        .collect();
    let players = poses
        .iter()
        .zip(&logs)
        .map(|((u, pose), log)| player(*u, *pose, log))
        .collect();
    let shutdown = Arc::new(AtomicBool::new(false));
    let team = Team::start(
        &AgentConfig::new("127.0.0.1", server.agent_port),
        players,
        Arc::clone(&shutdown),
    );
    let stats = Arc::clone(&team.stats[0].1);
    wait_sim_seconds(&stats, 2.0);
    let monitor = server.monitor();
    // Play on (in kick-off modes the referee keeps the ball on the centre spot).
    monitor.send("(dropBall)").unwrap();
    wait_sim_seconds(&stats, 0.5);
    assert_eq!(monitor.snapshot().play_mode, "PlayOn");
    // The ball at two places in turn, each in front of player 2 only.
    let places = [[0.0, 0.0], [-1.0, 1.2]];
    let mut windows = Vec::new();
    for place in places {
        monitor
            .place_ball([place[0], place[1], 0.11], [0.0; 3])
            .unwrap();
        let from = libero_tests::sim_time(&stats);
        wait_sim_seconds(&stats, 4.0);
        let ball = monitor.snapshot().ball.unwrap();
        assert!(
            (ball[0] - place[0]).hypot(ball[1] - place[1]) < 0.1,
            "the ball is at {ball:?}, not {place:?}"
        );
        windows.push((from, libero_tests::sim_time(&stats), place));
    }
    shutdown.store(true, std::sync::atomic::Ordering::Relaxed);
    team.join();
    // When the one who can see the ball (player 2, its head scanning) first saw it at each
    // new place: from then on its teammates are judged.
    let seer = lines(&logs[0]);
    let seen_at: Vec<f64> = windows
        .iter()
        .map(|(from, to, truth)| {
            seer.iter()
                .filter(|l| l.time >= *from && l.time <= *to)
                .find(|l| {
                    l.ball.as_ref().is_some_and(|b| {
                        b.last_seen_time == Some(l.time)
                            && (b.position[0] - truth[0]).hypot(b.position[1] - truth[1]) < 0.3
                    })
                })
                .unwrap_or_else(|| panic!("player 2 never saw the ball at {truth:?}"))
                .time
        })
        .collect();
    for (log, (unum, _)) in logs.iter().zip(&poses).skip(1) {
        let lines = lines(log);
        // Before its beam the robot stood at the touchline facing the field and saw the ball
        // there; after it, never.
        let start = windows[0].0;
        assert!(
            lines.iter().filter(|l| l.time >= start).all(|l| l
                .ball
                .as_ref()
                .is_none_or(|b| b.last_seen_time.is_none_or(|t| t < start - 1.0))),
            "player {unum} saw the ball itself: the test's premise fails"
        );
        assert!(
            lines.last().is_some_and(|l| l.heard.taken > 20),
            "player {unum} heard little"
        );
        for ((_, to, truth), seen) in windows.iter().zip(&seen_at) {
            // Half a second after the seer saw it (its turn on the channel, two cycles of
            // latency): within 1 m of the truth at every cycle.
            let judged: Vec<&Line> = lines
                .iter()
                .filter(|l| l.time >= seen + 0.5 && l.time <= *to)
                .collect();
            assert!(judged.len() > 40, "player {unum}: {} cycles", judged.len());
            for line in judged {
                let ball = line
                    .ball
                    .as_ref()
                    .unwrap_or_else(|| panic!("player {unum} knows no ball at {:.2}", line.time));
                let error = (ball.position[0] - truth[0]).hypot(ball.position[1] - truth[1]);
                assert!(
                    error <= 1.0 && ball.heard_time.is_some(),
                    "player {unum} at {:.2}: ball {:?}, truth {truth:?} ({error:.2} m)",
                    line.time,
                    ball.position
                );
            }
        }
    }
}
