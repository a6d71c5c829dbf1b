//! `libero match` as a user runs it, on the real server, judged from the report it writes.

use std::process::Command;

/// The matches of this file take turns: two servers and their teams side by side on two cores
/// (debug builds in CI) slow the agents until the kick-off measured here depends on the load
/// (3.96 s once, against 2.28 s in every run alone).
static ONE_MATCH_AT_A_TIME: std::sync::Mutex<()> = std::sync::Mutex::new(());

/// Run `libero match ARGS --no-watch --report FILE` from the repository with `envs`; the
/// report's JSON and the standard output.
fn run_match(args: &[&str], envs: &[(&str, &str)]) -> (serde_json::Value, String) {
    let _turn = ONE_MATCH_AT_A_TIME
        .lock()
        .unwrap_or_else(|poisoned| poisoned.into_inner());
    let dir = tempfile::tempdir().unwrap();
    let report = dir.path().join("report.json");
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let out = Command::new(env!("CARGO_BIN_EXE_libero"))
        .current_dir(&root)
        .envs(envs.iter().copied())
        .arg("match")
        .args(args)
        .args(["--no-watch", "--report"])
        .arg(&report)
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
    assert!(
        out.status.success(),
        "{stdout}\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let json = serde_json::from_str(&std::fs::read_to_string(&report).unwrap()).unwrap();
    (json, stdout)
}

#[test]
fn a_short_match_takes_our_kick_off_at_once_and_reports_its_figures() {
    let (json, stdout) = run_match(
        &[
            "--away",
            "tools/teams/standing",
            "--away-name",
            "Standing",
            "--duration",
            "12",
        ],
        &[],
    );
    assert!(stdout.contains("final: Libero"), "{stdout}");
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
    assert!(json["halves"][0]["play_time_s"].as_f64().unwrap() >= 12.0);
}

#[test]
fn an_external_team_plays_through_its_start_command_and_is_stopped_at_the_end() {
    let (json, stdout) = run_match(
        &[
            "--players",
            "2",
            "--away-cmd",
            "tools/teams/standing/start.sh",
            "--away-name",
            "Outsiders",
            "--duration",
            "6",
        ],
        &[
            ("LIBERO", env!("CARGO_BIN_EXE_libero")),
            ("PLAYERS", "2"),
            ("TEAM", "Outsiders"),
        ],
    );
    assert!(
        stdout.contains("starting `tools/teams/standing/start.sh 127.0.0.1"),
        "{stdout}"
    );
    assert_eq!(json["figures"][0]["observed"], true);
    assert_eq!(json["figures"][1]["observed"], false);
    assert!(json["halves"][0]["play_time_s"].as_f64().unwrap() >= 6.0);
    // The external team's processes are gone: none of them still holds its name.
    let leftover = Command::new("pgrep")
        .args(["-f", "--", "--team Outsiders"])
        .output()
        .unwrap();
    assert!(
        String::from_utf8_lossy(&leftover.stdout).trim().is_empty(),
        "left running: {}",
        String::from_utf8_lossy(&leftover.stdout)
    );
}
