//! `libero match`: the main job — a whole match on a server the project installs itself.

use super::setup::{build_player, ctrl_c_flag, load_robot, DataArgs, LogArgs};
use super::CliResult;
use clap::Args;
use libero_agent::{AgentConfig, AgentStats, Team};
use libero_server::{Rules, ServerOptions, ServerProcess};
use std::process::ExitCode;
use std::sync::atomic::Ordering;
use std::time::{Duration, Instant};

#[derive(Args)]
pub struct MatchArgs {
    /// Players per team.
    #[arg(long, default_value_t = 7)]
    pub players: u32,
    /// Keep 20 ms cycles instead of the fast `--sync --no-realtime` mode.
    #[arg(long)]
    pub realtime: bool,
    #[arg(long, default_value = "ssim")]
    pub rules: Rules,
    /// Stop after this much play time [s] instead of at the end of the half.
    #[arg(long)]
    pub duration: Option<f64>,
    #[arg(long, default_value = "Libero")]
    pub left: String,
    #[arg(long, default_value = "LiberoB")]
    pub right: String,
    /// Behavior and strategy files, used by both teams.
    #[command(flatten)]
    pub data: DataArgs,
    #[command(flatten)]
    pub log: LogArgs,
}

pub fn run(args: MatchArgs) -> CliResult {
    if args.players == 0 || args.players > args.rules.players_per_team() {
        return Err(format!(
            "--players must be 1–{} with {} rules",
            args.rules.players_per_team(),
            args.rules.as_arg()
        )
        .into());
    }
    let source = args.data.source()?;
    let shutdown = ctrl_c_flag();
    println!(
        "starting rcssservermj ({} mode)…",
        if args.realtime { "real-time" } else { "fast" }
    );
    let mut server = ServerProcess::start(ServerOptions {
        sync: !args.realtime,
        realtime: args.realtime,
        rules: args.rules,
        ..ServerOptions::default()
    })?;
    let model = load_robot("T1", None)?;
    let skills = args.data.skills(&model)?;
    let config = AgentConfig::new("127.0.0.1", server.agent_port);
    let monitor = server.monitor();
    let mut teams = Vec::new();
    for name in [&args.left, &args.right] {
        let mut players = Vec::new();
        for unum in 1..=args.players {
            let mut player = build_player(&model, name, unum, &source, &skills)?;
            args.log.attach(&mut player, name, unum, true)?;
            players.push(player);
        }
        println!("team {name}: {} players joining…", args.players);
        teams.push(Team::start(&config, players, shutdown.clone()));
    }
    // Let everyone beam and settle before the whistle.
    std::thread::sleep(Duration::from_millis(500));
    monitor.kick_off_left()?;
    println!("kick-off");
    let started = Instant::now();
    let mut last_print = Instant::now();
    let end_time = args.duration.unwrap_or(f64::INFINITY);
    loop {
        let s = monitor.snapshot();
        if s.play_mode == "GameOver" || s.time >= end_time || shutdown.load(Ordering::Relaxed) {
            break;
        }
        if last_print.elapsed() > Duration::from_secs(5) {
            println!(
                "t={:6.1}s  {} {} - {} {}  [{}]",
                s.time, args.left, s.score_left, s.score_right, args.right, s.play_mode
            );
            last_print = Instant::now();
        }
        std::thread::sleep(Duration::from_millis(50));
    }
    let s = monitor.snapshot();
    let missed: u64 = teams
        .iter()
        .flat_map(|t| t.stats.iter())
        .map(|(_, st)| AgentStats::get(&st.missed_cycles))
        .sum();
    shutdown.store(true, Ordering::Relaxed);
    for team in teams {
        team.join();
    }
    println!(
        "final: {} {} - {} {} | play time {:.1} s | mode {} | wall {:.1} s | missed cycles {}",
        args.left,
        s.score_left,
        s.score_right,
        args.right,
        s.time,
        s.play_mode,
        started.elapsed().as_secs_f64(),
        missed
    );
    drop(server);
    Ok(ExitCode::SUCCESS)
}
