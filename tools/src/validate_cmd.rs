//! `libero validate` and `libero nodes`, over the behavior engine's library API.

use libero_behavior::{validate_paths, Vocabulary};
use std::path::PathBuf;

/// Output format of `validate` and `nodes`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum OutputFormat {
    Text,
    Json,
}

/// Validates `paths` (default: `behaviors/` and `formations/`), prints every diagnostic and
/// returns the process exit code: 0 when there is no error (warnings allowed), 1 otherwise.
pub fn run_validate(paths: &[PathBuf], vocabulary: &Vocabulary, format: OutputFormat) -> i32 {
    let paths = if paths.is_empty() {
        vec![PathBuf::from("behaviors"), PathBuf::from("formations")]
    } else {
        paths.to_vec()
    };
    let report = validate_paths(&paths, vocabulary);
    match format {
        OutputFormat::Text => eprint!("{}", report.render_text()),
        OutputFormat::Json => println!("{}", report.render_json()),
    }
    i32::from(report.has_errors())
}

/// Prints the node vocabulary (Markdown for text).
pub fn run_nodes(vocabulary: &Vocabulary, format: OutputFormat) {
    match format {
        OutputFormat::Text => print!("{}", vocabulary.to_markdown()),
        OutputFormat::Json => println!("{}", vocabulary.to_json()),
    }
}
