//! `libero agent`: one player.

use super::setup::{
    build_player, ctrl_c_flag, load_robot, robot_for_unum, team_robot_types, DataArgs, LogArgs,
};
use super::CliResult;
use clap::Args;
use libero_agent::{run_agent, AgentConfig};
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Args)]
pub struct AgentArgs {
    #[arg(long, default_value = "127.0.0.1")]
    pub host: String,
    #[arg(long, short, default_value_t = 60000)]
    pub port: u16,
    #[arg(long, short, default_value = "Libero")]
    pub team: String,
    #[arg(long, short, default_value_t = 1)]
    pub unum: u32,
    /// Built-in robot model: T1, K1, or NAO (the SimSpark type the team rules give this
    /// uniform number) or one NAO type as nao_type0…4.
    #[arg(long, default_value = "T1")]
    pub robot: String,
    /// A robot model RON file instead of a built-in one.
    #[arg(long)]
    pub robot_file: Option<PathBuf>,
    #[command(flatten)]
    pub data: DataArgs,
    #[command(flatten)]
    pub log: LogArgs,
    #[command(flatten)]
    pub view: super::view::ViewArgs,
}

pub fn run(args: AgentArgs) -> CliResult {
    let name = robot_for_unum(&args.robot, args.unum, None);
    let mut model = load_robot(&name, args.robot_file.as_ref())?;
    let source = args.data.source_for(model.server)?;
    // A NAO plays the type its team file names for its number (a robot file is taken as is).
    let named = robot_for_unum(&args.robot, args.unum, team_robot_types(&source).as_deref());
    if args.robot_file.is_none() && named != name {
        model = load_robot(&named, None)?;
    }
    let skills = args.data.skills(&model)?;
    let mut player = build_player(&model, &args.team, args.unum, &source, &skills)?;
    args.log.attach(&mut player, &args.team, args.unum, false)?;
    let view =
        super::view::LiveView::start(&args.view, super::view::field_of(&source), &args.data)?;
    if let Some(view) = &view {
        view.show(&mut player);
        view.watch_library(&args.team, &source);
    }
    let shutdown = ctrl_c_flag();
    run_agent(
        &AgentConfig::new(&args.host, args.port),
        &mut player,
        &shutdown,
    )?;
    Ok(ExitCode::SUCCESS)
}
