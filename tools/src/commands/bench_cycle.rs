//! `libero bench cycle`: what one agent-cycle costs, against a same-run baseline.
//!
//! One fast-mode server, N of our agents (the shipped trees, one team) and N agents that only
//! answer each percept with `(syn)` (the other team), all in this process on their own named
//! threads. After the play time, the CPU each thread used (the scheduler's run time,
//! `/proc/self/task/*/schedstat`; the kernel's share from `stat`'s ticks) is summed
//! per kind and divided by the cycles it answered: ours, the baseline's, their ratio, and the
//! server's CPU per cycle (`/proc/<pid>/stat`). Machines are noisy; the ratio from one run is
//! the figure to compare.

use super::setup::{build_player, ctrl_c_flag, load_robot, proc_status_mb, DataArgs};
use super::CliResult;
use libero_agent::connection::Connection;
use libero_agent::{build, AgentConfig, AgentStats, Team};
use libero_protocol::is_timeout;
use libero_server::{ServerOptions, ServerProcess};
use std::process::ExitCode;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

/// Linux reports thread and process CPU times in clock ticks of this many per second
/// (`USER_HZ`, fixed by the kernel's ABI).
const TICKS_PER_S: f64 = 100.0;

/// Name prefix of the baseline's threads (ours are `agent-N`, from `Team`).
const BASELINE_THREAD: &str = "answer-";

/// user + system CPU time [s] in a `/proc/.../stat` line (fields 14 and 15; the command
/// name in parentheses may hold spaces, so count from its closing parenthesis).
fn cpu_seconds(stat: &str) -> Option<f64> {
    cpu_split(stat).map(|(user, kernel)| user + kernel)
}

/// (user, kernel) CPU time [s] in a `/proc/.../stat` line.
fn cpu_split(stat: &str) -> Option<(f64, f64)> {
    let rest = &stat[stat.rfind(')')? + 1..];
    let fields: Vec<&str> = rest.split_whitespace().collect();
    // After ")": state is field 3, so utime (14) and stime (15) are at 11 and 12.
    let utime: f64 = fields.get(11)?.parse().ok()?;
    let stime: f64 = fields.get(12)?.parse().ok()?;
    Some((utime / TICKS_PER_S, stime / TICKS_PER_S))
}

/// Kernel CPU seconds of this process's threads whose name starts with `prefix`.
fn threads_kernel_cpu(prefix: &str) -> f64 {
    threads_stats(prefix)
        .filter_map(|s| cpu_split(&s))
        .map(|(_, kernel)| kernel)
        .sum()
}

/// The `stat` lines of this process's threads whose name starts with `prefix`.
fn threads_stats(prefix: &str) -> impl Iterator<Item = String> + '_ {
    threads_files(prefix, "stat")
}

/// One `/proc/self/task/<tid>/<file>` per thread of this process whose name starts with
/// `prefix`.
fn threads_files<'a>(prefix: &'a str, file: &'a str) -> impl Iterator<Item = String> + 'a {
    std::fs::read_dir("/proc/self/task")
        .into_iter()
        .flatten()
        .flatten()
        .filter(move |t| {
            std::fs::read_to_string(t.path().join("comm"))
                .is_ok_and(|name| name.trim_end().starts_with(prefix))
        })
        .filter_map(move |t| std::fs::read_to_string(t.path().join(file)).ok())
}

/// CPU seconds of this process's threads whose name starts with `prefix`, from the
/// scheduler's nanosecond run times (`schedstat`): the ticks of `stat` are too coarse for a
/// few seconds of a few threads.
pub(super) fn threads_run_s(prefix: &str) -> f64 {
    threads_files(prefix, "schedstat")
        .filter_map(|s| s.split_whitespace().next()?.parse::<f64>().ok())
        .sum::<f64>()
        / 1e9
}

fn process_cpu(pid: u32) -> f64 {
    std::fs::read_to_string(format!("/proc/{pid}/stat"))
        .ok()
        .and_then(|s| cpu_seconds(&s))
        .unwrap_or(f64::NAN)
}

/// Peak resident memory of this process [MB] (`VmHWM`).
fn peak_rss_mb() -> f64 {
    proc_status_mb("VmHWM").unwrap_or(f64::NAN)
}

/// An agent that only answers: the greeting, then `(syn)` for every percept.
fn answer_only(port: u16, unum: u32, replies: Arc<AtomicU64>, stop: Arc<AtomicBool>) {
    let model = match libero_model::RobotModel::builtin("T1") {
        Ok(m) => Arc::new(m),
        Err(e) => return log::error!("baseline {unum}: {e}"),
    };
    let greeting = match build::standing_player(&model, "Baseline", unum)
        .map_err(|e| e.to_string())
        .and_then(|mut p| p.greeting().map_err(|e| e.to_string()))
    {
        Ok(g) => g,
        Err(e) => return log::error!("baseline {unum}: {e}"),
    };
    let mut syn = Vec::new();
    libero_protocol::encode_frame(b"(syn)", &mut syn);
    let mut conn = match Connection::open("127.0.0.1", port) {
        Ok(c) => c,
        Err(e) => return log::error!("baseline {unum}: {e}"),
    };
    // As our agents do: rcsssmj 0.2.1 crashes on an agent activated before its first step.
    std::thread::sleep(Duration::from_millis(150));
    if let Err(e) = conn.send(&greeting) {
        return log::error!("baseline {unum}: {e}");
    }
    while !stop.load(Ordering::Relaxed) {
        match conn.read_frame() {
            Ok(_) => {
                if conn.send(&syn).is_err() {
                    return;
                }
                replies.fetch_add(1, Ordering::Relaxed);
            }
            Err(e) if is_timeout(&e) => {}
            Err(_) => return,
        }
    }
}

pub fn bench_cycle(players: u32, play_s: f64, data: &DataArgs) -> CliResult {
    let shutdown = ctrl_c_flag();
    let mut server = ServerProcess::start(ServerOptions::default())?;
    let server_pid = server.pid().ok_or("the server is not running")?;
    let model = load_robot("T1", None)?;
    let source = data.source()?;
    let skills = data.skills(&model)?;
    let config = AgentConfig::new("127.0.0.1", server.agent_port);
    let mut ours = (1..=players)
        .map(|unum| build_player(&model, "Libero", unum, &source, &skills))
        .collect::<Result<Vec<_>, _>>()?;
    if let Some(first) = ours.first_mut() {
        first.record_frames(RECORDED_MAX);
    }
    println!("bench cycle: {players} of our agents and {players} that only answer, {play_s} s of play on a fast-mode rcssservermj…");
    let team = Team::start(&config, ours, shutdown.clone());
    let stop = Arc::new(AtomicBool::new(false));
    let mut baseline = Vec::new();
    for unum in 1..=players {
        let replies = Arc::new(AtomicU64::new(0));
        let (r, s, port) = (Arc::clone(&replies), Arc::clone(&stop), server.agent_port);
        let thread = std::thread::Builder::new()
            .name(format!("{BASELINE_THREAD}{unum}"))
            .spawn(move || answer_only(port, unum, r, s))?;
        // One at a time, as `Team` joins (simultaneous joins stall the server).
        let deadline = Instant::now() + Duration::from_secs(30);
        while replies.load(Ordering::Relaxed) == 0 && Instant::now() < deadline {
            std::thread::sleep(Duration::from_millis(5));
        }
        baseline.push((thread, replies));
    }
    let monitor = server.monitor();
    std::thread::sleep(Duration::from_millis(500));
    monitor.kick_off_left()?;
    // Measure from here: joins (the server recompiling its model) are not agent cycles.
    let ours_replies = || -> u64 {
        team.stats
            .iter()
            .map(|(_, s)| AgentStats::get(&s.replies))
            .sum()
    };
    let base_replies = |b: &[(std::thread::JoinHandle<()>, Arc<AtomicU64>)]| -> u64 {
        b.iter().map(|(_, r)| r.load(Ordering::Relaxed)).sum()
    };
    let stages_before = stage_totals(&team);
    let each_before = agent_stage_totals(&team);
    let wakes_before = team.wakeups();
    let kernel_before = (
        threads_kernel_cpu("agent-"),
        threads_kernel_cpu(BASELINE_THREAD),
    );
    let start = (
        threads_run_s("agent-"),
        threads_run_s(BASELINE_THREAD),
        process_cpu(server_pid),
        ours_replies(),
        base_replies(&baseline),
        monitor.snapshot().time,
        Instant::now(),
    );
    while monitor.snapshot().time < start.5 + play_s
        && monitor.snapshot().play_mode != "GameOver"
        && !shutdown.load(Ordering::Relaxed)
    {
        std::thread::sleep(Duration::from_millis(50));
    }
    let ours_cpu = threads_run_s("agent-") - start.0;
    let ours_kernel = threads_kernel_cpu("agent-") - kernel_before.0;
    let base_kernel = threads_kernel_cpu(BASELINE_THREAD) - kernel_before.1;
    let stages: Vec<(&str, u64)> = stage_totals(&team)
        .iter()
        .zip(&stages_before)
        .map(|(&(name, after), &(_, before))| (name, after - before))
        .collect();
    let each_after = agent_stage_totals(&team);
    let wakes_after = team.wakeups();
    let base_cpu = threads_run_s(BASELINE_THREAD) - start.1;
    let server_cpu = process_cpu(server_pid) - start.2;
    let ours_cycles = ours_replies() - start.3;
    let base_cycles = base_replies(&baseline) - start.4;
    let played = monitor.snapshot().time - start.5;
    let wall = start.6.elapsed().as_secs_f64();
    let missed: u64 = team
        .stats
        .iter()
        .map(|(_, s)| AgentStats::get(&s.missed_cycles))
        .sum();
    let recorded = team_recording(&team);
    shutdown.store(true, Ordering::Relaxed);
    stop.store(true, Ordering::Relaxed);
    team.join();
    for (thread, _) in baseline {
        let _ = thread.join();
    }
    drop(server);
    let per = |cpu: f64, cycles: u64| 1e6 * cpu / cycles.max(1) as f64;
    let ours_us = per(ours_cpu, ours_cycles);
    let base_us = per(base_cpu, base_cycles);
    // The server steps once per cycle for everyone: its cycles are one agent's.
    let server_cycles = ours_cycles / u64::from(players.max(1));
    println!("play time: {played:.1} s in {wall:.1} s of wall time");
    println!("ours: {ours_us:.1} us CPU per agent-cycle, {:.1} of it in the kernel ({ours_cycles} agent-cycles, {ours_cpu:.2} s CPU, {missed} missed cycles)", per(ours_kernel, ours_cycles));
    println!("baseline (answer only): {base_us:.1} us CPU per agent-cycle, {:.1} of it in the kernel ({base_cycles} agent-cycles, {base_cpu:.2} s CPU)", per(base_kernel, base_cycles));
    println!("ratio ours / baseline: {:.2}", ours_us / base_us);
    println!(
        "ours by stage (wall time inside the cycle): {}",
        stage_line(&stages, ours_cycles)
    );
    println!(
        "ours by agent (wall time inside the cycle, us per cycle): {}",
        each_after
            .iter()
            .zip(&each_before)
            .map(
                |((unum, after, cycles_after), (_, before, cycles_before))| {
                    let cycles = (cycles_after - cycles_before).max(1);
                    format!(
                        "{unum}: {:.1}",
                        (after - before) as f64 / 1e3 / cycles as f64
                    )
                }
            )
            .collect::<Vec<_>>()
            .join(", ")
    );
    let (wakeups, answered) = (
        wakes_after.0 - wakes_before.0,
        wakes_after.1 - wakes_before.1,
    );
    println!(
        "our thread woke {wakeups} times to answer, {:.2} percepts per wake-up",
        answered as f64 / wakeups.max(1) as f64
    );
    println!(
        "server: {:.0} us CPU per cycle ({server_cycles} cycles, {server_cpu:.2} s CPU)",
        per(server_cpu, server_cycles)
    );
    println!(
        "peak RSS of this process (both teams): {:.1} MB",
        peak_rss_mb()
    );
    if !recorded.is_empty() {
        let (cpu_us, stages) = replay(&recorded, &model, &source, &skills, Replay::Warm)?;
        println!(
            "replay of agent 1's {} recorded cycles, offline ({REPLAYS} times on one thread, no sockets): {cpu_us:.1} us CPU per cycle; by stage: {}",
            recorded.len(),
            stage_line(&stages, (recorded.len() * REPLAYS) as u64)
        );
        let (_, cold) = replay(&recorded, &model, &source, &skills, Replay::ColdAlone)?;
        let cycles = recorded.len() as u64;
        let total: u64 = cold.iter().map(|(_, ns)| ns).sum();
        println!(
            "the same with the caches flushed before each cycle ({} MiB written, as the server's step does live): {:.1} us per cycle inside it; by stage: {}",
            FLUSH_BYTES >> 20,
            total as f64 / 1e3 / cycles.max(1) as f64,
            stage_line(&cold, cycles)
        );
        let (paced_us, paced) = replay(&recorded, &model, &source, &skills, Replay::Paced)?;
        println!(
            "the same paced, asleep 20 ms before each cycle as live: {paced_us:.1} us CPU per cycle; by stage: {}",
            stage_line(&paced, PACED_CYCLES.min(recorded.len()) as u64)
        );
        let n = players as usize;
        let (round_us, round) = replay(&recorded, &model, &source, &skills, Replay::ColdRound(n))?;
        println!(
            "{n} players answering the same cycles in turn on one thread, flushed before each round: {round_us:.1} us CPU per agent-cycle; by stage: {}",
            stage_line(&round, cycles * n as u64)
        );
    }
    Ok(ExitCode::SUCCESS)
}

/// Percepts agent 1 records for the offline replay (60 s of play).
const RECORDED_MAX: usize = 3000;
/// Cycles of the paced replay (20 ms asleep before each).
const PACED_CYCLES: usize = 250;
/// How often the replay runs the recording (each time on a fresh player).
const REPLAYS: usize = 20;
/// What a cold replay writes between cycles: more than this machine's L3 (32 MiB), so each cycle starts
/// the way a live one does, after the server's step has filled the caches with its own data.
const FLUSH_BYTES: usize = 48 << 20;

/// (stage, total ns) in pipe order.
type StageSums = Vec<(&'static str, u64)>;

fn stage_totals(team: &Team) -> StageSums {
    let mut sums: StageSums = Vec::new();
    for (_, stats) in &team.stats {
        for (i, (name, ns)) in stats.stages.totals().into_iter().enumerate() {
            match sums.get_mut(i) {
                Some(sum) => sum.1 += ns,
                None => sums.push((name, ns)),
            }
        }
    }
    sums
}

/// (uniform number, ns inside the cycle, cycles answered) per agent.
fn agent_stage_totals(team: &Team) -> Vec<(u32, u64, u64)> {
    team.stats
        .iter()
        .map(|(unum, stats)| {
            let ns = stats.stages.totals().iter().map(|(_, ns)| ns).sum();
            (*unum, ns, AgentStats::get(&stats.replies))
        })
        .collect()
}

fn stage_line(stages: &[(&str, u64)], cycles: u64) -> String {
    stages
        .iter()
        .map(|(name, ns)| format!("{name} {:.1} us", *ns as f64 / 1e3 / cycles.max(1) as f64))
        .collect::<Vec<_>>()
        .join(", ")
}

fn team_recording(team: &Team) -> Vec<Vec<u8>> {
    team.stats
        .first()
        .map(|(_, stats)| stats.take_recording())
        .unwrap_or_default()
}

/// How the offline replay feeds the recording to fresh copies of agent 1.
#[derive(Clone, Copy)]
enum Replay {
    /// [`REPLAYS`] players one after the other, caches as they are.
    Warm,
    /// One player, the caches flushed before each cycle.
    ColdAlone,
    /// `n` players fed each percept in turn, the caches flushed before each round: a team
    /// answering on one thread after the server's step.
    ColdRound(usize),
    /// One player, the thread asleep for a server cycle before each percept, as live.
    Paced,
}

/// Run `frames` through fresh copies of agent 1 on a thread of its own: the CPU per
/// agent-cycle and the stage totals.
fn replay(
    frames: &[Vec<u8>],
    model: &std::sync::Arc<libero_model::RobotModel>,
    source: &libero_agent::LibrarySource,
    skills: &libero_agent::SkillSource,
    how: Replay,
) -> Result<(f64, StageSums), Box<dyn std::error::Error>> {
    // (players fed together, times the recording runs, flush)
    let (together, runs, cold) = match how {
        Replay::Warm => (1, REPLAYS, false),
        Replay::ColdAlone => (1, 1, true),
        Replay::ColdRound(n) => (n.max(1), 1, true),
        Replay::Paced => (1, 1, false),
    };
    let paced = matches!(how, Replay::Paced);
    let frames = if paced {
        &frames[..frames.len().min(PACED_CYCLES)]
    } else {
        frames
    };
    let teams = (0..runs)
        .map(|_| {
            (0..together)
                .map(|_| build_player(model, "Libero", 1, source, skills))
                .collect::<Result<Vec<_>, _>>()
        })
        .collect::<Result<Vec<_>, _>>()?;
    let thread = std::thread::Builder::new().name("replay-1".into()).spawn({
        let frames = frames.to_vec();
        move || {
            let before = threads_run_s("replay-");
            let mut out = Vec::with_capacity(4096);
            let mut stages = vec![("", 0u64); 5];
            let mut flush = if cold {
                vec![0u8; FLUSH_BYTES]
            } else {
                Vec::new()
            };
            let mut flush_s = 0.0;
            for mut team in teams {
                for frame in &frames {
                    let flushing = Instant::now();
                    for (i, b) in flush.iter_mut().enumerate().step_by(64) {
                        *b = b.wrapping_add(i as u8);
                    }
                    flush_s += flushing.elapsed().as_secs_f64();
                    if paced {
                        std::thread::sleep(Duration::from_millis(20));
                    }
                    for player in &mut team {
                        out.clear();
                        player.on_percept(frame, &mut out);
                    }
                }
                for player in &team {
                    for (sum, (name, ns)) in stages.iter_mut().zip(player.stats().stages.totals()) {
                        *sum = (name, sum.1 + ns);
                    }
                }
            }
            std::hint::black_box(&flush);
            (threads_run_s("replay-") - before - flush_s, stages)
        }
    })?;
    let (cpu_s, stages) = thread.join().map_err(|_| "the replay panicked")?;
    let cycles = frames.len() * runs * together;
    Ok((1e6 * cpu_s / cycles.max(1) as f64, stages))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cpu_times_are_read_from_a_stat_line_whose_name_has_spaces() {
        let line = "4242 (agent 7 (x)) S 1 2 3 4 5 6 7 8 9 10 250 50 0 0 20 0 1 0";
        assert_eq!(cpu_seconds(line), Some(3.0));
        assert_eq!(cpu_seconds("garbage"), None);
    }

    #[test]
    fn a_threads_cpu_time_is_found_by_its_name() {
        // A busy thread and a sleeping one, 300 ms each: the busy one used CPU (at least a
        // third of the time even on a loaded machine), the sleeper next to none.
        let run = |name: &str, busy: bool| {
            let prefix = name.to_string();
            std::thread::Builder::new()
                .name(name.into())
                .spawn(move || {
                    let until = Instant::now() + Duration::from_millis(300);
                    let mut x = 0u64;
                    while Instant::now() < until {
                        if busy {
                            x = x.wrapping_mul(31).wrapping_add(1);
                        } else {
                            std::thread::sleep(Duration::from_millis(10));
                        }
                    }
                    std::hint::black_box(x);
                    let ticks: f64 = threads_stats(&prefix).filter_map(|s| cpu_seconds(&s)).sum();
                    (ticks, threads_run_s(&prefix))
                })
                .unwrap()
                .join()
                .unwrap()
        };
        let (busy, busy_run) = run("cpubusy-1", true);
        let (idle, idle_run) = run("cpuidle-1", false);
        assert!((0.1..=0.5).contains(&busy), "busy: {busy} s");
        assert!(idle < 0.05, "sleeping: {idle} s");
        // The scheduler's run time says the same, in nanoseconds.
        assert!((0.1..=0.5).contains(&busy_run), "busy: {busy_run} s");
        assert!(idle_run < 0.05, "sleeping: {idle_run} s");
        assert!((busy_run - busy).abs() < 0.05, "{busy_run} vs {busy}");
        assert!(peak_rss_mb() > 1.0);
    }
}
