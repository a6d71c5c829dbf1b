//! `libero scenario FILE`: a situation from a scenario file, run N times on a real server.

use super::behavior::Format;
use super::setup::{ctrl_c_flag, load_robot, DataArgs};
use super::CliResult;
use clap::Args;
use libero_scenario::{load_file, run_series, Report, RunData, Summary};
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Args)]
pub struct ScenarioArgs {
    /// The scenario file (`scenarios/*.ron`).
    pub file: PathBuf,
    /// Runs, each drawn from the file's ranges.
    #[arg(long, default_value_t = 1)]
    pub runs: usize,
    /// Seed of the draws: the same seed gives the same situations.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// `json` prints one document with the figures and every run.
    #[arg(long, value_enum, default_value = "text")]
    pub format: Format,
    /// Also write the JSON document to this file.
    #[arg(long, value_name = "FILE")]
    pub report: Option<PathBuf>,
    /// Each robot writes its evaluation log (JSON lines with tree traces, server truth) to
    /// FILE.TEAM.UNUM.
    #[arg(long, value_name = "FILE")]
    pub log: Option<PathBuf>,
    /// Behavior, strategy and skill files of the Libero robots (watched: edits apply to the
    /// running scenario unless `--no-watch`).
    #[command(flatten)]
    pub data: DataArgs,
    #[command(flatten)]
    pub view: super::view::ViewArgs,
}

pub fn run(args: ScenarioArgs) -> CliResult {
    let mut report = Report::default();
    let scenario = load_file(&args.file, &mut report);
    report.sort();
    if !report.diagnostics.is_empty() {
        eprint!("{}", report.render_text());
    }
    let Some(scenario) = scenario else {
        return Ok(ExitCode::FAILURE);
    };
    if args.runs == 0 {
        return Err("--runs must be at least 1".into());
    }
    let model = load_robot("T1", None)?;
    let library = args.data.source()?;
    let view =
        super::view::LiveView::start(&args.view, super::view::field_of(&library), &args.data)?;
    let watcher = view.map(|view| {
        view.watch_library(libero_scenario::OUR_TEAM, &library);
        Box::new(view) as Box<dyn libero_scenario::Watcher>
    });
    let data = RunData {
        library,
        skills: args.data.skills(&model)?,
        interrupt: ctrl_c_flag(),
        watcher,
        log: args.log.clone(),
    };
    eprintln!(
        "scenario {}: {} run(s), seed {}, on a fresh fast-mode rcssservermj…",
        scenario.name, args.runs, args.seed
    );
    let (summary, error) = run_series(&scenario, &args.file, &data, args.runs, args.seed, |r| {
        eprintln!("{}", Summary::run_line(r));
    });
    match args.format {
        Format::Text => print!("{}", summary.render_text()),
        Format::Json => println!("{}", summary.render_json()),
    }
    if let Some(path) = &args.report {
        std::fs::write(path, summary.render_json() + "\n")
            .map_err(|e| format!("cannot write the report {}: {e}", path.display()))?;
    }
    match error {
        Some(e) => Err(format!(
            "the series stopped after {} of {} runs: {e}",
            summary.runs.len(),
            args.runs
        )
        .into()),
        None => Ok(ExitCode::SUCCESS),
    }
}
