//! A real server that stalls (SIGSTOP, then SIGCONT) under a full team of our agents: the
//! team rides the stall out and play resumes within seconds of the server continuing.

use libero_agent::AgentStats;
use libero_tests::{fast_server, sim_time, standing_team, wait_sim_seconds, wait_until};
use std::process::Command;
use std::time::{Duration, Instant};

fn signal(pid: u32, name: &str) {
    let status = Command::new("kill")
        .arg(format!("-{name}"))
        .arg(pid.to_string())
        .status()
        .expect("running kill");
    assert!(status.success(), "kill -{name} {pid}");
}

/// Seven agents, a stall of `stall`, then: every agent answering percepts again and the
/// simulation advancing, within 10 s of the server continuing.
fn ride_out(stall: Duration) {
    let server = fast_server();
    let (team, stop) = standing_team(server.agent_port, "Home", 7);
    for (_, stats) in &team.stats {
        wait_sim_seconds(stats, 0.5);
    }
    let pid = server.pid().expect("the server runs");
    signal(pid, "STOP");
    std::thread::sleep(stall);
    let before: Vec<(u64, f64)> = team
        .stats
        .iter()
        .map(|(_, s)| (AgentStats::get(&s.replies), sim_time(s)))
        .collect();
    signal(pid, "CONT");
    let continued = Instant::now();
    let took = wait_until(Duration::from_secs(10), || {
        team.stats
            .iter()
            .zip(&before)
            .all(|((_, s), &(replies, time))| {
                AgentStats::get(&s.replies) > replies + 50 && sim_time(s) > time + 1.0
            })
    });
    let report: Vec<String> = team
        .stats
        .iter()
        .map(|(unum, s)| {
            format!(
                "{unum}: connections {} replies {} sim time {:.2}",
                AgentStats::get(&s.connections),
                AgentStats::get(&s.replies),
                sim_time(s)
            )
        })
        .collect();
    eprintln!(
        "after a {stall:?} stall: all back in {:?} ({:?} since continuing)\n{}",
        took,
        continued.elapsed(),
        report.join("\n")
    );
    assert!(
        took.is_some(),
        "not all agents back and playing within 10 s of the server continuing:\n{}",
        report.join("\n")
    );
    stop.store(true, std::sync::atomic::Ordering::Relaxed);
    team.join();
}

#[test]
fn a_team_rides_out_a_twelve_second_server_stall() {
    ride_out(Duration::from_secs(12));
}

#[test]
fn a_team_rides_out_a_sixty_second_server_stall() {
    ride_out(Duration::from_secs(60));
}

/// A third team on a server that takes two: every join it tries is refused, and each costs
/// the running match (the server stalls while it handles the join). The agent backs off,
/// stops after its bounded refusals with a clear error, and the match loses little play.
#[test]
fn a_refused_team_stops_trying_without_stalling_the_match() {
    let server = fast_server();
    let (home, home_stop) = standing_team(server.agent_port, "Home", 1);
    let (away, away_stop) = standing_team(server.agent_port, "Away", 1);
    let clock = &home.stats[0].1;
    wait_sim_seconds(clock, 1.0);
    // The match's pace without the third team, over 3 s of wall time.
    let pace = |wall: Duration| {
        let (t0, w0) = (sim_time(clock), Instant::now());
        std::thread::sleep(wall);
        (sim_time(clock) - t0) / w0.elapsed().as_secs_f64()
    };
    let before = pace(Duration::from_secs(3));
    let mut player = libero_agent::build::standing_player(&libero_tests::t1(), "Third", 1).unwrap();
    let config = libero_agent::AgentConfig::new("127.0.0.1", server.agent_port);
    let (t0, w0) = (sim_time(clock), Instant::now());
    let err = libero_agent::run_agent(
        &config,
        &mut player,
        &std::sync::atomic::AtomicBool::new(false),
    )
    .unwrap_err()
    .to_string();
    let wall = w0.elapsed().as_secs_f64();
    let played = sim_time(clock) - t0;
    // How long the match stood still: in real-time mode, the play it loses.
    let stalled = wall - played / before;
    eprintln!(
        "refused after {wall:.1} s: {err}\nthe match played {played:.1} s in it at {before:.2} s of play per s before: stalled {stalled:.2} s"
    );
    assert!(err.contains("refused this agent 3 times"), "{err}");
    assert!(wall < 30.0, "took {wall:.1} s to give up");
    assert!(
        stalled <= 1.0,
        "the refused joins stalled the match for {stalled:.2} s"
    );
    home_stop.store(true, std::sync::atomic::Ordering::Relaxed);
    away_stop.store(true, std::sync::atomic::Ordering::Relaxed);
    home.join();
    away.join();
}
