//! `libero validate` and `libero nodes`: the behavior files' checker and the node vocabulary.

use super::CliResult;
use clap::{Args, ValueEnum};
use libero_agent::build::default_data_dirs;
use libero_behavior::files::ron_files;
use libero_behavior::Report;
use libero_scenario::{default_scenarios_dir, is_scenario_file};
use libero_strategy::{validate_paths, vocabulary};
use std::path::PathBuf;
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
    let report = check(&paths);
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

/// Every diagnostic of the tree, strategy and scenario files under `paths`, sorted.
fn check(paths: &[PathBuf]) -> Report {
    let (data, scenarios, mut report) = split_scenarios(paths);
    if !data.is_empty() {
        report.extend(validate_paths(&data));
    }
    // A subfolder with its own team file (formations/simspark/) is another team's set: checked
    // with the other paths given (the trees) in place of the folder it sits in. Only its own
    // files' diagnostics are new; the trees' were reported above.
    for (outer, team) in team_sets(&data) {
        let mut set: Vec<PathBuf> = data.iter().filter(|p| **p != outer).cloned().collect();
        set.push(team.clone());
        let team_report = validate_paths(&set);
        report
            .diagnostics
            .extend(team_report.diagnostics.into_iter().filter(|d| {
                d.location
                    .as_ref()
                    .is_some_and(|l| l.file.path.starts_with(&team))
            }));
    }
    report.extend(libero_scenario::validate_files(&scenarios));
    report.sort();
    report
}

/// (folder given, team subfolder in it) for every subfolder below a given folder that holds
/// its own team file.
fn team_sets(paths: &[PathBuf]) -> Vec<(PathBuf, PathBuf)> {
    fn walk(dir: &std::path::Path, depth: usize, out: &mut Vec<PathBuf>) {
        let Ok(entries) = std::fs::read_dir(dir) else {
            return;
        };
        let mut dirs: Vec<PathBuf> = entries
            .flatten()
            .filter(|e| e.file_type().is_ok_and(|t| t.is_dir()))
            .map(|e| e.path())
            .collect();
        dirs.sort();
        for sub in dirs {
            if sub.join(libero_behavior::files::TEAM_FILE).is_file() {
                out.push(sub.clone());
            }
            // Real folders only, a few levels: data folders are shallow.
            if depth < 4 {
                walk(&sub, depth + 1, out);
            }
        }
    }
    let mut sets = Vec::new();
    for outer in paths.iter().filter(|p| p.is_dir()) {
        let mut found = Vec::new();
        walk(outer, 0, &mut found);
        sets.extend(found.into_iter().map(|team| (outer.clone(), team)));
    }
    sets
}

/// Scenario files apart from the tree and strategy files they may sit beside. A folder without
/// scenario files is passed on whole (the library reports on it as before); a folder with some
/// is passed on as its other `.ron` files, and what its walk found (links skipped) is reported
/// here, since the library then sees the files alone.
fn split_scenarios(paths: &[PathBuf]) -> (Vec<PathBuf>, Vec<PathBuf>, Report) {
    let (mut data, mut scenarios) = (Vec::new(), Vec::new());
    let mut report = Report::default();
    for path in paths {
        if path.is_dir() {
            let mut walk_report = Report::default();
            let files = ron_files(std::slice::from_ref(path), &mut walk_report);
            let (s, other): (Vec<PathBuf>, Vec<PathBuf>) =
                files.into_iter().partition(|f| is_scenario_file(f));
            if s.is_empty() {
                data.push(path.clone());
            } else {
                scenarios.extend(s);
                data.extend(other);
                report.extend(walk_report);
            }
        } else if path.is_file() && is_scenario_file(path) {
            scenarios.push(path.clone());
        } else {
            data.push(path.clone());
        }
    }
    (data, scenarios, report)
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
        let (data, found, _) = split_scenarios(&paths);
        // The tree and strategy folders go to the library whole; the scenarios are checked apart.
        assert_eq!(data, default_data_dirs());
        assert!(found.len() >= 4 && found.iter().all(|f| f.starts_with(&scenarios)));
        let single = scenarios.join("keeper_shots.ron");
        let (data, found, _) = split_scenarios(std::slice::from_ref(&single));
        assert!(data.is_empty());
        assert_eq!(found, vec![single]);
    }

    /// A copy of the shipped trees and strategy files, a scenario beside them (so the folder
    /// is split file by file), and links that loop or lead out.
    #[cfg(unix)]
    /// Plain files and folders (formations/simspark/ too), as the repository has them.
    fn copy_tree(from: &std::path::Path, to: &std::path::Path) {
        std::fs::create_dir_all(to).unwrap();
        for entry in std::fs::read_dir(from).unwrap() {
            let path = entry.unwrap().path();
            let target = to.join(path.file_name().unwrap());
            if path.is_dir() {
                copy_tree(&path, &target);
            } else {
                std::fs::copy(&path, target).unwrap();
            }
        }
    }

    #[test]
    fn a_second_team_set_is_checked_on_its_own() {
        let repo = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..");
        let dir = tempfile::tempdir().unwrap();
        for sub in ["behaviors", "formations"] {
            copy_tree(&repo.join(sub), &dir.path().join(sub));
        }
        let paths = [dir.path().join("behaviors"), dir.path().join("formations")];
        let report = check(&paths);
        assert_eq!(report.error_count(), 0, "{}", report.render_text());
        // A position off SimSpark's 30 x 20 field in the NAO set: named there, and only once.
        let kickoff = dir.path().join("formations/simspark/kickoff.ron");
        let text = std::fs::read_to_string(&kickoff).unwrap();
        std::fs::write(
            &kickoff,
            text.replacen("1: (-13.9, 0.0)", "1: (-19.9, 0.0)", 1),
        )
        .unwrap();
        let report = check(&paths);
        let text = report.render_text();
        let off_field: Vec<_> = report
            .diagnostics
            .iter()
            .filter(|d| d.code == "off-field")
            .collect();
        assert_eq!(off_field.len(), 1, "{text}");
        assert!(
            text.contains("simspark/kickoff.ron") && text.contains("simspark field"),
            "{text}"
        );
    }

    #[test]
    fn a_folder_of_link_loops_validates_at_once_and_defines_nothing_twice() {
        use std::os::unix::fs::symlink;
        let repo = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..");
        let dir = tempfile::tempdir().unwrap();
        let root = dir.path().join("team");
        for (from, to) in [
            ("behaviors", "behaviors"),
            ("formations", "formations"),
            ("scenarios", "scenarios"),
        ] {
            copy_tree(&repo.join(from), &root.join(to));
        }
        symlink("b", root.join("a")).unwrap();
        symlink("a", root.join("b")).unwrap();
        symlink(".", root.join("self")).unwrap();
        symlink("..", root.join("up")).unwrap();
        let start = std::time::Instant::now();
        let report = check(std::slice::from_ref(&root));
        let took = start.elapsed();
        let text = report.render_text();
        assert!(took < std::time::Duration::from_secs(1), "{took:?}");
        assert!(!text.contains("defined twice"), "{text}");
        assert_eq!(report.error_count(), 0, "{text}");
        assert_eq!(
            report
                .diagnostics
                .iter()
                .filter(|d| d.code == "link")
                .count(),
            3,
            "{text}"
        );
    }
}
