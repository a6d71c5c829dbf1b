//! `libero soak` as a user runs it, shortened for CI: one minute of play, 3 of ours against 1
//! standing robot, an edit every 5 s. Judged from the JSON figures, bar by bar.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

/// The text of every file of the repository's data folders, to prove the soak never edits them.
fn shipped_files(root: &Path) -> BTreeMap<PathBuf, String> {
    let mut files = BTreeMap::new();
    for dir in ["behaviors", "formations"] {
        for entry in std::fs::read_dir(root.join(dir)).unwrap() {
            let path = entry.unwrap().path();
            if path.is_file() {
                files.insert(path.clone(), std::fs::read_to_string(&path).unwrap());
            }
        }
    }
    files
}

#[test]
fn a_minute_of_play_with_edits_keeps_memory_connections_and_cycles() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let before = shipped_files(&root);
    let started = Instant::now();
    let out = Command::new(env!("CARGO_BIN_EXE_libero"))
        .current_dir(&root)
        .args(["soak", "--minutes", "1", "--edit-every", "5"])
        .args(["--players", "3", "--away-players", "1"])
        // The first minute is all the play there is: the baseline comes after 20 s.
        .args(["--rss-baseline-at", "20", "--format", "json"])
        .output()
        .unwrap();
    let wall = started.elapsed();
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    eprintln!("soak took {wall:?}\n{stdout}");
    assert!(out.status.success(), "{stdout}\n{stderr}");
    let r: serde_json::Value = serde_json::from_str(&stdout).unwrap();
    assert_eq!(r["passed"], true, "{}", r["failures"]);
    assert_eq!(r["ended"], "full");
    assert!(r["play_time_s"].as_f64().unwrap() >= 60.0, "{r}");

    // Edits at 5, 10, … 55 s: good ones taken, broken ones refused with the team playing on,
    // every original written back and taken again.
    let e = &r["edits"];
    let count = |key: &str| e[key].as_u64().unwrap();
    assert!(count("good_written") >= 5, "{e}");
    assert_eq!(count("good_taken"), count("good_written"), "{e}");
    assert!(count("broken_written") >= 5, "{e}");
    assert_eq!(count("broken_refused"), count("broken_written"), "{e}");
    assert_eq!(
        count("played_on_after_broken"),
        count("broken_written"),
        "{e}"
    );
    assert_eq!(
        count("restores_written"),
        count("good_written") + count("broken_written"),
        "{e}"
    );
    assert_eq!(count("restores_taken"), count("restores_written"), "{e}");

    // Every agent of both teams: connected once, still answering at the end, no panic, no
    // missed cycle, every percept readable.
    let agents = r["agents"].as_array().unwrap();
    assert_eq!(agents.len(), 4, "{r}");
    for a in agents {
        assert_eq!(a["connections"], 1, "{a}");
        assert_eq!(a["answering_at_end"], true, "{a}");
        assert_eq!(a["panicked"], false, "{a}");
        assert_eq!(a["missed_cycles"], 0, "{a}");
        assert_eq!(a["unreadable"], 0, "{a}");
        // 60 s of play is 3000 cycles of 20 ms.
        assert!(a["percepts"].as_u64().unwrap() >= 3000, "{a}");
    }
    assert_eq!(r["missed_cycles"], 0);

    let baseline = r["rss_baseline_mb"].as_f64().unwrap();
    let growth = r["rss_growth_mb"].as_f64().unwrap();
    assert!(baseline > 1.0, "{r}");
    assert!(growth <= 5.0, "RSS grew {growth} MB");
    assert_eq!(r["rss_by_minute_mb"].as_array().unwrap().len(), 1, "{r}");

    assert!(
        shipped_files(&root) == before,
        "the soak changed the repository's behaviors/ or formations/"
    );
}
