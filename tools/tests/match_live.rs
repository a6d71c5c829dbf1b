//! `libero match` as a user runs it: a short match against the standing team on the real
//! server, judged from the report it writes.

use std::process::Command;

#[test]
fn a_short_match_takes_our_kick_off_at_once_and_reports_its_figures() {
    let dir = tempfile::tempdir().unwrap();
    let report = dir.path().join("report.json");
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let out = Command::new(env!("CARGO_BIN_EXE_libero"))
        .current_dir(&root)
        .args([
            "match",
            "--away",
            "tools/teams/standing",
            "--away-name",
            "Standing",
        ])
        .args(["--duration", "12", "--no-watch", "--report"])
        .arg(&report)
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{stdout}\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(stdout.contains("final: Libero"), "{stdout}");
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&report).unwrap()).unwrap();
    assert_eq!(json["home"], "Libero");
    assert_eq!(json["away"], "Standing");
    let home = &json["figures"][0];
    assert_eq!(home["observed"], true);
    // Our kick-off (the left team kicks off): the taker, beamed to its kicking place, passes
    // within 3 s; before set plays existed the referee's 15 s ran out.
    let kick_offs = home["kick_off_times_s"].as_array().unwrap();
    assert_eq!(kick_offs.len(), 1, "{home}");
    let taken = kick_offs[0].as_f64().unwrap();
    assert!(taken <= 3.0, "kick-off taken after {taken} s");
    // The figures are there and sane.
    for key in [
        "shots",
        "falls",
        "relocations",
        "passes_completed",
        "missed_cycles",
    ] {
        assert!(home[key].is_u64(), "{key}: {home}");
    }
    let error = home["localization_error_m"].as_f64().unwrap();
    assert!(error < 0.5, "localization error {error} m");
    let half = &json["halves"][0];
    assert!(half["play_time_s"].as_f64().unwrap() >= 12.0);
}
