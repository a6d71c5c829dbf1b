//! `libero validate` and `libero nodes`: the behavior files' checker and the node vocabulary.

use super::CliResult;
use clap::{Args, ValueEnum};
use libero_agent::build::default_data_dirs;
use libero_behavior::Report;
use libero_scenario::{default_scenarios_dir, is_scenario_file};
use libero_strategy::{validate_paths, vocabulary};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum Format {
    Text,
    Json,
}

#[derive(Args)]
pub struct ValidateArgs {
    /// Files or folders to check (default: the repository's `behaviors/`, `formations/` and
    /// `scenarios/`). Files whose top is `Scenario(...)` are checked as scenario files.
    pub paths: Vec<PathBuf>,
    /// `json` prints one document with every diagnostic (for CI annotations).
    #[arg(long, value_enum, default_value = "text")]
    pub format: Format,
}

#[derive(Args)]
pub struct NodesArgs {
    /// `text` prints Markdown.
    #[arg(long, value_enum, default_value = "text")]
    pub format: Format,
}

/// Check every tree, strategy and scenario file; exit 1 when any has an error (warnings pass).
pub fn validate(args: ValidateArgs) -> CliResult {
    let paths = if args.paths.is_empty() {
        let mut dirs = default_data_dirs();
        let scenarios = default_scenarios_dir();
        if scenarios.is_dir() {
            dirs.push(scenarios);
        }
        dirs
    } else {
        args.paths
    };
    let (data, scenarios) = split_scenarios(&paths);
    let mut report = if data.is_empty() {
        Report::default()
    } else {
        validate_paths(&data)
    };
    report.extend(libero_scenario::validate_files(&scenarios));
    report.sort();
    match args.format {
        Format::Text => eprint!("{}", report.render_text()),
        Format::Json => println!("{}", report.render_json()),
    }
    Ok(if report.has_errors() {
        ExitCode::FAILURE
    } else {
        ExitCode::SUCCESS
    })
}

/// Scenario files apart from the tree and strategy files they may sit beside. A folder without
/// scenario files is passed on whole (the library reports on it as before); a folder with some
/// is passed on as its other `.ron` files.
fn split_scenarios(paths: &[PathBuf]) -> (Vec<PathBuf>, Vec<PathBuf>) {
    fn ron_files(dir: &Path, out: &mut Vec<PathBuf>) {
        let Ok(entries) = std::fs::read_dir(dir) else {
            return;
        };
        for entry in entries.flatten() {
            let path = entry.path();
            if path.is_dir() {
                ron_files(&path, out);
            } else if path.extension().is_some_and(|e| e == "ron") {
                out.push(path);
            }
        }
    }
    let (mut data, mut scenarios) = (Vec::new(), Vec::new());
    for path in paths {
        if path.is_dir() {
            let mut files = Vec::new();
            ron_files(path, &mut files);
            files.sort();
            let (s, other): (Vec<PathBuf>, Vec<PathBuf>) =
                files.into_iter().partition(|f| is_scenario_file(f));
            if s.is_empty() {
                data.push(path.clone());
            } else {
                scenarios.extend(s);
                data.extend(other);
            }
        } else if path.is_file() && is_scenario_file(path) {
            scenarios.push(path.clone());
        } else {
            data.push(path.clone());
        }
    }
    (data, scenarios)
}

/// Print the native nodes trees may use, from the agent's own declarations.
pub fn nodes(args: NodesArgs) -> CliResult {
    let vocabulary = vocabulary();
    match args.format {
        Format::Text => print!("{}", vocabulary.to_markdown()),
        Format::Json => println!("{}", vocabulary.to_json()),
    }
    Ok(ExitCode::SUCCESS)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scenario_files_are_told_apart_from_trees_and_strategy_files() {
        let scenarios = default_scenarios_dir();
        let mut paths = default_data_dirs();
        paths.push(scenarios.clone());
        let (data, found) = split_scenarios(&paths);
        // The tree and strategy folders go to the library whole; the scenarios are checked apart.
        assert_eq!(data, default_data_dirs());
        assert!(found.len() >= 4 && found.iter().all(|f| f.starts_with(&scenarios)));
        let single = scenarios.join("keeper_shots.ron");
        let (data, found) = split_scenarios(std::slice::from_ref(&single));
        assert!(data.is_empty());
        assert_eq!(found, vec![single]);
    }
}
