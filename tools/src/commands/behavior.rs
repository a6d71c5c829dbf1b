//! `libero validate` and `libero nodes`: the behavior files' checker and the node vocabulary.

use super::CliResult;
use clap::{Args, ValueEnum};
use libero_agent::build::default_data_dirs;
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
    /// Files or folders to check (default: the repository's `behaviors/` and `formations/`).
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

/// Check every tree and strategy file; exit 1 when any has an error (warnings pass).
pub fn validate(args: ValidateArgs) -> CliResult {
    let paths = if args.paths.is_empty() {
        default_data_dirs()
    } else {
        args.paths
    };
    let report = validate_paths(&paths);
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

/// Print the native nodes trees may use, from the agent's own declarations.
pub fn nodes(args: NodesArgs) -> CliResult {
    let vocabulary = vocabulary();
    match args.format {
        Format::Text => print!("{}", vocabulary.to_markdown()),
        Format::Json => println!("{}", vocabulary.to_json()),
    }
    Ok(ExitCode::SUCCESS)
}
