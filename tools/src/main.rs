//! `libero`: run agents, teams, servers and matches; validate behavior files.

mod commands;
mod fleet;

use clap::{Parser, Subcommand};
use std::process::ExitCode;

#[derive(Parser)]
#[command(
    name = "libero",
    version,
    about = "A data-driven control agent for RoboCup 3D soccer simulation"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Play a match: install and start rcssservermj, two teams, kick-off, final score.
    Match(commands::matchup::MatchArgs),
    /// Run one agent (RoboCup start-script conventions).
    Agent(commands::agent::AgentArgs),
    /// Run a team of agents in one process.
    Team(commands::team::TeamArgs),
    /// Check behavior trees and strategy files: every error, located, with hints.
    Validate(commands::behavior::ValidateArgs),
    /// Print the native nodes behavior trees can use.
    Nodes(commands::behavior::NodesArgs),
    /// Manage a local rcssservermj.
    #[command(subcommand)]
    Server(commands::server::ServerCommand),
    /// Tune a skill's parameters with CMA-ES against real servers; writes the best back.
    Optimize(commands::optimize::OptimizeArgs),
    /// One optimizer candidate's cost on a fresh server, as JSON (a job of `optimize --ray`).
    Evaluate(commands::optimize::EvaluateArgs),
    /// Measure a skill on a real server (e.g. `libero bench walk`).
    Bench(commands::bench::BenchArgs),
    /// Run a scenario file's situation N times on a real server; success rate and times.
    Scenario(commands::scenario::ScenarioArgs),
    /// The hardening match (#13): long play with an edit every few seconds, good and broken;
    /// judged on RSS growth, connections, missed cycles and panics.
    Soak(commands::soak::SoakArgs),
    /// Many matches (or scenario runs) here or on a Ray cluster: wins, goal difference with
    /// its interval, and a sequential test that stops once the difference is clear.
    Series(commands::series::SeriesArgs),
    /// Replay evaluation logs in the field view (a web page served on loopback).
    View(commands::view::ViewCommandArgs),
}

fn main() -> ExitCode {
    env_logger::Builder::from_env(env_logger::Env::default().default_filter_or("info"))
        .format_timestamp_millis()
        .init();
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Match(args) => commands::matchup::run(args),
        Command::Agent(args) => commands::agent::run(args),
        Command::Team(args) => commands::team::run(args),
        Command::Server(cmd) => commands::server::run(cmd),
        Command::Validate(args) => commands::behavior::validate(args),
        Command::Nodes(args) => commands::behavior::nodes(args),
        Command::Optimize(args) => commands::optimize::run(args),
        Command::Evaluate(args) => commands::optimize::evaluate(args),
        Command::Bench(args) => commands::bench::run(args),
        Command::Scenario(args) => commands::scenario::run(args),
        Command::Soak(args) => commands::soak::run(args),
        Command::View(args) => commands::view::run(args),
        Command::Series(args) => commands::series::run(args),
    };
    match result {
        Ok(code) => code,
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::FAILURE
        }
    }
}
