//! `libero team`: N players in one process.

use super::setup::{
    build_player, ctrl_c_flag, load_robot, robot_for_unum, team_robot_types, DataArgs, LogArgs,
};
use super::CliResult;
use clap::Args;
use libero_agent::{AgentConfig, Team};
use libero_model::ServerKind;
use std::process::ExitCode;
use std::sync::atomic::Ordering;

#[derive(Args)]
pub struct TeamArgs {
    #[arg(long, short = 'n', default_value_t = 7)]
    pub players: u32,
    #[arg(long, default_value = "127.0.0.1")]
    pub host: String,
    #[arg(long, short, default_value_t = 60000)]
    pub port: u16,
    #[arg(long, short, default_value = "Libero")]
    pub team: String,
    /// Built-in robot model: T1 for rcssservermj, NAO for SimSpark (types chosen per the
    /// server's heterogeneous-team rules).
    #[arg(long, default_value = "T1")]
    pub robot: String,
    #[command(flatten)]
    pub data: DataArgs,
    #[command(flatten)]
    pub log: LogArgs,
    #[command(flatten)]
    pub view: super::view::ViewArgs,
}

pub fn run(args: TeamArgs) -> CliResult {
    let shutdown = ctrl_c_flag();
    let server = load_robot(&robot_for_unum(&args.robot, 1, None), None)?.server;
    let source = args.data.source_for(server)?;
    let view =
        super::view::LiveView::start(&args.view, super::view::field_of(&source), &args.data)?;
    if let Some(view) = &view {
        view.watch_library(&args.team, &source);
    }
    let mut players = Vec::new();
    let types = team_robot_types(&source);
    // One parameter file (and watcher) for the whole team, checked against the first robot:
    // every NAO type shares nao.ron.
    let mut skills = None;
    let simspark = args.robot.eq_ignore_ascii_case("nao");
    for unum in 1..=args.players {
        let name = robot_for_unum(&args.robot, unum, types.as_deref());
        let model = load_robot(&name, None)?;
        if simspark && model.server != ServerKind::SimSpark {
            return Err(format!("{name} is not a SimSpark robot").into());
        }
        let skills = match &skills {
            Some(s) => s,
            None => skills.insert(args.data.skills(&model)?),
        };
        let mut player = build_player(&model, &args.team, unum, &source, skills)?;
        args.log.attach(&mut player, &args.team, unum, true)?;
        if let Some(view) = &view {
            view.show(&mut player);
        }
        players.push(player);
    }
    let team = Team::start(
        &AgentConfig::new(&args.host, args.port),
        players,
        shutdown.clone(),
    );
    log::info!(
        "team {} with {} players running; Ctrl-C stops it",
        args.team,
        args.players
    );
    while !shutdown.load(Ordering::Relaxed) {
        std::thread::sleep(std::time::Duration::from_millis(100));
    }
    team.join();
    Ok(ExitCode::SUCCESS)
}
