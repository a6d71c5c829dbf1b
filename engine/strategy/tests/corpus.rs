//! Snapshot tests over `tests/corpus/`: each broken file (or directory of files) is validated
//! and its rendered report compared with `<case>.expected`. Run with `UPDATE_SNAPSHOTS=1` to
//! rewrite the snapshots after an intended change, then review the diff.

use libero_behavior::Severity;
use libero_strategy::validate_paths;
use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

fn corpus_root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../tests/corpus")
}

fn cases() -> Vec<PathBuf> {
    let mut cases: Vec<PathBuf> = std::fs::read_dir(corpus_root())
        .expect("tests/corpus exists")
        .map(|e| e.unwrap().path())
        .filter(|p| p.is_dir() || p.extension().is_some_and(|e| e == "ron"))
        .collect();
    cases.sort();
    cases
}

fn expected_path(case: &Path) -> PathBuf {
    let name = case
        .file_name()
        .unwrap()
        .to_string_lossy()
        .trim_end_matches(".ron")
        .to_string();
    case.with_file_name(format!("{name}.expected"))
}

#[test]
fn corpus_reports_match_snapshots() {
    let update = std::env::var_os("UPDATE_SNAPSHOTS").is_some();
    let root = corpus_root().canonicalize().unwrap();
    let mut mismatches = Vec::new();
    for case in cases() {
        let report = validate_paths(&[case.canonicalize().unwrap()]);
        assert!(
            report.error_count() + report.warning_count() > 0,
            "{} produced no diagnostics",
            case.display()
        );
        let rendered = report.render_text_relative(&root);
        let expected_file = expected_path(&case);
        if update {
            std::fs::write(&expected_file, &rendered).unwrap();
            continue;
        }
        let expected = std::fs::read_to_string(&expected_file).unwrap_or_default();
        if expected != rendered {
            mismatches.push(format!("--- {}\n{rendered}", expected_file.display()));
        }
    }
    assert!(
        mismatches.is_empty(),
        "snapshots differ:\n{}",
        mismatches.join("\n")
    );
}

/// Every class of error the validator knows has at least one case in the corpus.
#[test]
fn corpus_covers_every_error_class() {
    let mut seen = BTreeSet::new();
    for case in cases() {
        for diagnostic in validate_paths(&[case]).diagnostics {
            seen.insert((diagnostic.code, diagnostic.severity));
        }
    }
    let classes = [
        "syntax",
        "unknown-node-kind",
        "unknown-node",
        "unknown-parameter",
        "missing-parameter",
        "type-mismatch",
        "out-of-range",
        "invalid-choice",
        "unknown-query",
        "unknown-blackboard-entry",
        "unknown-tree-parameter",
        "missing-subtree",
        "subtree-cycle",
        "duplicate-tree",
        "bad-threshold",
        "empty-composite",
        "unknown-field",
        "missing-field",
        "unknown-curve",
        "conflicting-blackboard-entry",
        "unknown-file-kind",
        "off-field",
        "missing-player",
        "field-not-covered",
        "degenerate-triangle",
        "duplicate-sample",
        "unknown-formation",
        "missing-situation",
        "duplicate-definition",
        "unknown-field-kind",
        "io",
        "invalid-value",
    ];
    for class in classes {
        assert!(
            seen.contains(&(class, Severity::Error)),
            "no corpus case produces `{class}`; seen: {seen:?}"
        );
    }
    assert!(
        seen.contains(&("unused-file", Severity::Warning)),
        "no corpus case warns about unused files"
    );
}

#[test]
fn json_output_locates_errors() {
    let case = corpus_root().join("unknown_node.ron");
    let report = validate_paths(&[case]);
    let json: serde_json::Value = serde_json::from_str(&report.render_json()).unwrap();
    let first = &json["diagnostics"][0];
    assert_eq!(first["code"], "unknown-node");
    assert_eq!(first["line"], 4);
    assert_eq!(first["column"], 26);
    assert_eq!(first["hint"], "did you mean `WalkTo`?");
    assert_eq!(json["summary"]["errors"], 1);
}
