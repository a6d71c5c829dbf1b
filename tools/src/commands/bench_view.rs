//! `libero bench view`: what the field view costs the agents, in one run.
//!
//! One fast-mode server and N of our agents (the shipped trees), all shown in a view with a
//! viewer connected to its stream. The play time is cut into phases that alternate between
//! the view off (the agents skip the copy) and on (every agent copies its view each 40 ms,
//! agent 1 — selected, as a page selects one — with its tree and blackboard, and the viewer
//! receives ≤ 25 frames a second); the agents' thread CPU (the scheduler's run
//! time) per agent-cycle is summed per kind of phase. Alternating phases in one match cancel the drift of the game and the
//! machine; the ratio is the figure.

use super::bench_cycle::threads_run_s;
use super::setup::{build_player, ctrl_c_flag, load_robot, DataArgs};
use super::CliResult;
use libero_agent::{AgentConfig, AgentStats, Team};
use libero_server::{ServerOptions, ServerProcess};
use libero_view::{LiveSet, Source, StreamCounter, ViewOptions, ViewServer};
use std::process::ExitCode;
use std::sync::atomic::Ordering;
use std::sync::Arc;
use std::time::{Duration, Instant};

pub fn bench_view(players: u32, play_s: f64, phases: u32, data: &DataArgs) -> CliResult {
    let shutdown = ctrl_c_flag();
    let mut server = ServerProcess::start(ServerOptions::default())?;
    let model = load_robot("T1", None)?;
    let source = data.source()?;
    let skills = data.skills(&model)?;
    let set = Arc::new(LiveSet::default());
    let view = ViewServer::start(
        ViewOptions {
            address: "127.0.0.1:0".parse()?,
            field: super::view::field_of(&source),
            edit: None,
        },
        Source::Live(Arc::clone(&set)),
    )?;
    let mut ours = Vec::new();
    for unum in 1..=players {
        let mut player = build_player(&model, "Libero", unum, &source, &skills)?;
        player.show_in(set.add_agent());
        if unum == 1 {
            player.record_frames(RECORDED);
        }
        ours.push(player);
    }
    let slots = set.agents();
    let set_view = |on: bool| slots.iter().for_each(|s| s.set_enabled(on));
    set_view(false);
    println!("bench view: {players} of our agents, {play_s} s of play in {phases} phases alternating the view off and on, a viewer connected…");
    let config = AgentConfig::new("127.0.0.1", server.agent_port);
    let team = Team::start(&config, ours, shutdown.clone());
    let viewer = StreamCounter::connect(view.address)?;
    let monitor = server.monitor();
    std::thread::sleep(Duration::from_millis(500));
    monitor.kick_off_left()?;
    let replies = || -> u64 {
        team.stats
            .iter()
            .map(|(_, s)| AgentStats::get(&s.replies))
            .sum()
    };
    // [off, on]: CPU seconds, agent-cycles, frames received, wall seconds.
    let mut cpu = [0.0f64; 2];
    let mut cycles = [0u64; 2];
    let mut frames = [0u64; 2];
    let mut wall = [0.0f64; 2];
    let mut copies = [0u64; 2];
    let mut view_cpu = [0.0f64; 2];
    let copies_now = || -> u64 { slots.iter().map(|s| s.copies()).sum() };
    let phase_s = play_s / f64::from(phases.max(1));
    for phase in 0..phases.max(2) {
        let on = phase % 2 == 1;
        set_view(on);
        // A moment for the switch to take and the last frames of the other phase to arrive.
        std::thread::sleep(Duration::from_millis(100));
        let (cpu0, cycles0, frames0, t0, wall0) = (
            threads_run_s("agent-"),
            replies(),
            viewer.frames.load(Ordering::Relaxed),
            monitor.snapshot().time,
            Instant::now(),
        );
        let copies0 = copies_now();
        let view0 = threads_run_s("view-");
        let mut selected_at: Option<Instant> = None;
        while monitor.snapshot().time < t0 + phase_s
            && monitor.snapshot().play_mode != "GameOver"
            && !shutdown.load(Ordering::Relaxed)
        {
            // As a page does: agent 1 selected (its tree and blackboard copied), renewed.
            if on && selected_at.is_none_or(|t| t.elapsed() > Duration::from_secs(2)) {
                StreamCounter::select(view.address, "Libero", 1)?;
                selected_at = Some(Instant::now());
            }
            std::thread::sleep(Duration::from_millis(20));
        }
        let k = usize::from(on);
        cpu[k] += threads_run_s("agent-") - cpu0;
        cycles[k] += replies() - cycles0;
        frames[k] += viewer.frames.load(Ordering::Relaxed) - frames0;
        wall[k] += wall0.elapsed().as_secs_f64();
        copies[k] += copies_now() - copies0;
        view_cpu[k] += threads_run_s("view-") - view0;
    }
    let bytes = viewer.bytes.load(Ordering::Relaxed);
    let recorded = team
        .stats
        .first()
        .map(|(_, s)| s.take_recording())
        .unwrap_or_default();
    drop(viewer);
    shutdown.store(true, Ordering::Relaxed);
    team.join();
    drop(view);
    drop(server);
    let per = |k: usize| 1e6 * cpu[k] / cycles[k].max(1) as f64;
    println!(
        "view off: {:.1} us CPU per agent-cycle ({} agent-cycles, {:.2} s CPU, {} frames received in {:.1} s)",
        per(0),
        cycles[0],
        cpu[0],
        frames[0],
        wall[0]
    );
    println!(
        "view on, viewer connected: {:.1} us CPU per agent-cycle ({} agent-cycles, {:.2} s CPU, {} frames received in {:.1} s: {:.1} frames/s, {:.0} kB/s)",
        per(1),
        cycles[1],
        cpu[1],
        frames[1],
        wall[1],
        frames[1] as f64 / wall[1].max(1e-9),
        bytes as f64 / 1e3 / wall[1].max(1e-9)
    );
    println!("ratio on / off: {:.3}", per(1) / per(0));
    println!(
        "the view's own threads (stream, HTTP, browser): {:.1} ms CPU per second of wall time with the view on, {:.1} off",
        1e3 * view_cpu[1] / wall[1].max(1e-9),
        1e3 * view_cpu[0] / wall[0].max(1e-9)
    );
    if !recorded.is_empty() {
        // Offline, one thread: agent 1's cycles replayed with a copy in every cycle and with
        // none, alternately, so the copy's own cost shows apart from the live noise.
        let mut ns = [0u128; 2];
        for round in 0..2 * REPLAYS {
            let copy = round % 2 == 1;
            let mut player = build_player(&model, "Libero", 1, &source, &skills)?;
            let slot = libero_agent::ViewSlot::new(Duration::ZERO);
            if copy {
                player.show_in(Arc::clone(&slot));
            }
            let mut out = Vec::with_capacity(4096);
            let started = Instant::now();
            for frame in &recorded {
                out.clear();
                player.on_percept(frame, &mut out);
            }
            ns[usize::from(copy)] += started.elapsed().as_nanos();
        }
        let replayed = (recorded.len() * REPLAYS) as f64;
        let (without, with) = (ns[0] as f64 / replayed / 1e3, ns[1] as f64 / replayed / 1e3);
        let live_copies_per_cycle = copies[1] as f64 / cycles[1].max(1) as f64;
        println!(
            "offline replay of agent 1's {} cycles ({REPLAYS} times each way): {without:.1} us per cycle without the view, {with:.1} us with a copy every cycle: one copy costs {:.1} us; live the agents copied every {:.1} cycles",
            recorded.len(),
            with - without,
            1.0 / live_copies_per_cycle.max(1e-9)
        );
    }
    Ok(ExitCode::SUCCESS)
}

/// Cycles agent 1 records for the offline comparison.
const RECORDED: usize = 3000;
/// Replays of the recording each way.
const REPLAYS: usize = 5;
