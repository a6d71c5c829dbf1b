//! A real server that stalls (SIGSTOP, then SIGCONT) under a full team of our agents: the
//! team rides the stall out and play resumes within seconds of the server continuing.

use libero_agent::AgentStats;
use libero_tests::{fast_server, sim_time, standing_team, wait_sim_seconds, wait_until};
use std::process::Command;
use std::sync::RwLock;
use std::time::{Duration, Instant};

/// The refused-team test measures how long the server takes to handle a join, which the
/// other tests' seven agents and their server inflate on two cores (CI once saw each join
/// cost 0.27 s instead of 0.2 s): it runs alone, the stall tests beside each other.
static MEASURING_ALONE: RwLock<()> = RwLock::new(());

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
    let _shared = MEASURING_ALONE.read().unwrap_or_else(|e| e.into_inner());
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

/// The wall-clock gaps between the simulated clock's advances while `during` runs, as
/// seen by polling `clock` every 2 ms: a stalled server shows as one long gap.
fn clock_gaps<T>(clock: &AgentStats, during: impl FnOnce() -> T) -> (T, Vec<Duration>) {
    let done = std::sync::atomic::AtomicBool::new(false);
    std::thread::scope(|scope| {
        let watcher = scope.spawn(|| {
            let mut gaps = Vec::new();
            let (mut last_time, mut last_change) = (sim_time(clock), Instant::now());
            while !done.load(std::sync::atomic::Ordering::Relaxed) {
                std::thread::sleep(Duration::from_millis(2));
                let now = sim_time(clock);
                if now != last_time {
                    gaps.push(last_change.elapsed());
                    (last_time, last_change) = (now, Instant::now());
                }
            }
            gaps.push(last_change.elapsed());
            gaps
        });
        let result = during();
        done.store(true, std::sync::atomic::Ordering::Relaxed);
        (result, watcher.join().expect("the clock watcher"))
    })
}

/// The gaps that are stalls: longer than five times `normal` (the longest gap of an
/// undisturbed stretch) and than 100 ms.
fn stalls(gaps: &[Duration], normal: Duration) -> Vec<Duration> {
    let threshold = (normal * 5).max(Duration::from_millis(100));
    gaps.iter().copied().filter(|g| *g > threshold).collect()
}

/// A third team on a server that takes two: every join it tries is refused, and each costs
/// the running match (the server stalls while it handles the join). The agent backs off,
/// stops after its bounded refusals with a clear error, and the match loses little play.
///
/// Measured on the match's clock, not its pace (fast mode's pace swings by half from one 3 s
/// stretch to the next on two cores): each join the server handles is a long gap between the
/// clock's advances (about 0.23 s here, against at most 16 ms undisturbed), and the gaps
/// together are the play the match lost.
#[test]
fn a_refused_team_stops_trying_without_stalling_the_match() {
    let _alone = MEASURING_ALONE.write().unwrap_or_else(|e| e.into_inner());
    let server = fast_server();
    let (home, home_stop) = standing_team(server.agent_port, "Home", 1);
    let (away, away_stop) = standing_team(server.agent_port, "Away", 1);
    let clock = &home.stats[0].1;
    wait_sim_seconds(clock, 1.0);
    let ((), undisturbed) = clock_gaps(clock, || std::thread::sleep(Duration::from_secs(3)));
    let normal = undisturbed.iter().copied().max().unwrap_or_default();
    let mut player = libero_agent::build::standing_player(&libero_tests::t1(), "Third", 1).unwrap();
    let config = libero_agent::AgentConfig::new("127.0.0.1", server.agent_port);
    let w0 = Instant::now();
    let (err, gaps) = clock_gaps(clock, || {
        libero_agent::run_agent(
            &config,
            &mut player,
            &std::sync::atomic::AtomicBool::new(false),
        )
        .unwrap_err()
        .to_string()
    });
    let wall = w0.elapsed().as_secs_f64();
    let stalls = stalls(&gaps, normal);
    let lost: Duration = stalls.iter().sum();
    eprintln!(
        "refused after {wall:.1} s: {err}\nundisturbed: longest gap {normal:?}; while refused: stalls {stalls:?}, {lost:?} in all"
    );
    assert!(err.contains("refused this agent 3 times"), "{err}");
    assert!(wall < 30.0, "took {wall:.1} s to give up");
    // The bar (#13): the match loses no more than 1 s of play to the refused team. Each join
    // the server handles stalls it for about 0.2 s, seen as one long gap or, at times, two in
    // a row (CI once counted 4 gaps, 0.67 s in all, for the three joins): the time lost is
    // the measure, and a team that kept retrying would pass it within five or six joins.
    assert!(
        lost <= Duration::from_secs(1),
        "the refused joins cost the match {lost:?} in {} stalls; the agent tries three",
        stalls.len()
    );
    home_stop.store(true, std::sync::atomic::Ordering::Relaxed);
    away_stop.store(true, std::sync::atomic::Ordering::Relaxed);
    home.join();
    away.join();
}
