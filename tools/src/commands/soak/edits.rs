//! The soak's edits: a private copy of the team's files, changed while the team plays from it.
//!
//! Each edit writes one file (a good change or a broken one, alternately), waits for the
//! watcher's verdict, then writes the original back and waits again, so every edit starts
//! from the shipped files and the one after it is never merged with it by the debounce.

use libero_agent::AgentStats;
use libero_behavior::{LiveLibrary, ReloadEvent};
use serde::Serialize;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::{Duration, Instant};

/// One place in one shipped file, and what a good and a broken edit make of it.
pub struct Edit {
    /// Relative to the data copy's root (`behaviors/…` or `formations/…`).
    pub file: &'static str,
    /// Text that occurs exactly once in the shipped file.
    pub anchor: &'static str,
    /// A valid replacement: a number moved within its range.
    pub good: &'static str,
    /// A replacement the loader must refuse.
    pub broken: &'static str,
    /// What is wrong with `broken`, for the log.
    pub breakage: &'static str,
}

/// The edits, used in turn: the first's good edit, its broken one, the second's good edit, …
/// Three kinds of breakage: a syntax error, an unknown node, a number out of range.
pub const EDITS: [Edit; 3] = [
    Edit {
        file: "formations/shot.ron",
        anchor: "threshold: 0.3,",
        good: "threshold: 0.35,",
        broken: "threshold: (0.3,",
        breakage: "unbalanced parenthesis",
    },
    Edit {
        file: "behaviors/common.ron",
        anchor: r#"Action(name: "LookAround", amplitude: 1.2, period: 4.0)"#,
        good: r#"Action(name: "LookAround", amplitude: 1.2, period: 5.0)"#,
        broken: r#"Action(name: "LookAbout", amplitude: 1.2, period: 4.0)"#,
        breakage: "unknown node",
    },
    Edit {
        file: "formations/avoidance.ron",
        anchor: "robot_clearance_m: 0.75,",
        good: "robot_clearance_m: 0.8,",
        broken: "robot_clearance_m: 7.5,",
        breakage: "number out of range",
    },
];

/// How long the watcher gets to answer an edit (debounce 150 ms plus a reload; generous for a
/// loaded machine).
const VERDICT_TIMEOUT: Duration = Duration::from_secs(10);

/// Cycles every agent must answer after a refused edit to count as still playing.
const CYCLES_AFTER_REFUSAL: u64 = 10;

/// What the edits came to.
#[derive(Debug, Default, Clone, Serialize, PartialEq, Eq)]
pub struct EditCounts {
    pub good_written: u32,
    /// Good edits the watcher published as a new generation, now the team's library.
    pub good_taken: u32,
    pub broken_written: u32,
    /// Broken edits reported as rejected, the running generation left in place.
    pub broken_refused: u32,
    /// Refused edits after which every agent of ours went on answering percepts.
    pub played_on_after_broken: u32,
    /// Originals written back after an edit, …
    pub restores_written: u32,
    /// … and published (after a refused edit: reported as the recovery).
    pub restores_taken: u32,
}

/// The data copy the team plays from and the edits made to it.
pub struct Editor {
    root: PathBuf,
    /// The shipped text of each edited file, by `EDITS` index.
    originals: Vec<String>,
    next: usize,
    pub counts: EditCounts,
}

impl Editor {
    /// Copy `behaviors` and `formations` (flat folders of files) under `root`; check that
    /// every edit's anchor is there once. Returns the editor and the two folders to load.
    pub fn copy_data(
        root: &Path,
        behaviors: &Path,
        formations: &Path,
    ) -> Result<(Editor, Vec<PathBuf>), String> {
        let mut dirs = Vec::new();
        for (from, name) in [(behaviors, "behaviors"), (formations, "formations")] {
            let to = root.join(name);
            copy_flat(from, &to)?;
            dirs.push(to);
        }
        let mut originals = Vec::new();
        for edit in &EDITS {
            let path = root.join(edit.file);
            let text = std::fs::read_to_string(&path)
                .map_err(|e| format!("cannot read {}: {e}", path.display()))?;
            let found = text.matches(edit.anchor).count();
            if found != 1 {
                return Err(format!(
                    "the soak edits `{}` in {}, found {found} times (must be once): the shipped file changed; update EDITS in tools/src/commands/soak/edits.rs",
                    edit.anchor, edit.file
                ));
            }
            originals.push(text);
        }
        let editor = Editor {
            root: root.to_path_buf(),
            originals,
            next: 0,
            counts: EditCounts::default(),
        };
        Ok((editor, dirs))
    }

    /// Make the next edit (good and broken alternately), wait for its verdict, write the
    /// original back and wait for that. `ours` are the agents whose play must go on. Takes
    /// about two debounce windows of wall time (at most 2 × [`VERDICT_TIMEOUT`]).
    pub fn edit_and_restore(&mut self, live: &LiveLibrary, ours: &[Arc<AgentStats>]) {
        let index = (self.next / 2) % EDITS.len();
        let good = self.next.is_multiple_of(2);
        self.next += 1;
        let edit = &EDITS[index];
        let original = &self.originals[index];
        let path = self.root.join(edit.file);
        let changed = original.replacen(edit.anchor, if good { edit.good } else { edit.broken }, 1);
        // Events left from before (none are expected) must not count for this edit.
        live.drain_events();
        let generation_before = live.generation();
        let replies_before: Vec<u64> = ours.iter().map(|s| AgentStats::get(&s.replies)).collect();
        if let Err(e) = self.save(&path, &changed) {
            log::error!("soak: {e}");
            return;
        }
        let verdict = live.next_event(VERDICT_TIMEOUT);
        if good {
            self.counts.good_written += 1;
            if let Some(ReloadEvent::Reloaded { generation, .. }) = verdict {
                if generation > generation_before && live.current().generation() == generation {
                    self.counts.good_taken += 1;
                }
            } else {
                log::error!("soak: good edit of {} not taken: {verdict:?}", edit.file);
            }
        } else {
            self.counts.broken_written += 1;
            if matches!(verdict, Some(ReloadEvent::Rejected { .. }))
                && live.generation() == generation_before
            {
                self.counts.broken_refused += 1;
                if played_on(ours, &replies_before) {
                    self.counts.played_on_after_broken += 1;
                }
            } else {
                log::error!(
                    "soak: broken edit of {} ({}) not refused: {verdict:?}",
                    edit.file,
                    edit.breakage
                );
            }
        }
        let generation_edited = live.generation();
        match self.save(&path, original) {
            Ok(()) => self.counts.restores_written += 1,
            Err(e) => return log::error!("soak: {e}"),
        }
        match live.next_event(VERDICT_TIMEOUT) {
            Some(ReloadEvent::Reloaded { generation, .. }) if generation > generation_edited => {
                self.counts.restores_taken += 1;
            }
            other => log::error!("soak: restoring {} not taken: {other:?}", edit.file),
        }
    }

    /// Write `text` the way editors do: a temporary file beside the folders, renamed over
    /// the watched one (the watcher sees one finished file, never a half-written one).
    fn save(&self, path: &Path, text: &str) -> Result<(), String> {
        let tmp = self.root.join("edit.tmp");
        std::fs::write(&tmp, text)
            .and_then(|()| std::fs::rename(&tmp, path))
            .map_err(|e| format!("cannot write {}: {e}", path.display()))
    }
}

/// Whether every agent answered [`CYCLES_AFTER_REFUSAL`] more percepts than `before` within
/// a few seconds.
fn played_on(ours: &[Arc<AgentStats>], before: &[u64]) -> bool {
    let deadline = Instant::now() + Duration::from_secs(5);
    loop {
        let all = ours
            .iter()
            .zip(before)
            .all(|(s, &b)| AgentStats::get(&s.replies) >= b + CYCLES_AFTER_REFUSAL);
        if all {
            return true;
        }
        if Instant::now() > deadline {
            return false;
        }
        std::thread::sleep(Duration::from_millis(10));
    }
}

/// Copy the regular files of `from` into a new folder `to` (the shipped data folders are
/// flat).
fn copy_flat(from: &Path, to: &Path) -> Result<(), String> {
    std::fs::create_dir_all(to).map_err(|e| format!("cannot create {}: {e}", to.display()))?;
    let entries =
        std::fs::read_dir(from).map_err(|e| format!("cannot read {}: {e}", from.display()))?;
    for entry in entries {
        let path = entry
            .map_err(|e| format!("cannot read {}: {e}", from.display()))?
            .path();
        if let (true, Some(name)) = (path.is_file(), path.file_name()) {
            std::fs::copy(&path, to.join(name))
                .map_err(|e| format!("cannot copy {}: {e}", path.display()))?;
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn shipped() -> (PathBuf, PathBuf) {
        let dirs = libero_agent::build::default_data_dirs();
        (dirs[0].clone(), dirs[1].clone())
    }

    /// Each edit applied on its own to a fresh copy: good ones load, broken ones are refused
    /// with an error about the edited file.
    #[test]
    fn good_edits_load_and_broken_ones_are_refused() {
        let (behaviors, formations) = shipped();
        for edit in &EDITS {
            for good in [true, false] {
                let dir = tempfile::tempdir().unwrap();
                let (_, dirs) = Editor::copy_data(dir.path(), &behaviors, &formations).unwrap();
                let path = dir.path().join(edit.file);
                let text = std::fs::read_to_string(&path).unwrap();
                let replacement = if good { edit.good } else { edit.broken };
                std::fs::write(&path, text.replacen(edit.anchor, replacement, 1)).unwrap();
                match libero_strategy::load(&dirs) {
                    Ok(_) => assert!(good, "{} ({}) loaded", edit.file, edit.breakage),
                    Err(report) => {
                        let text = report.render_text();
                        assert!(!good, "good edit of {} refused: {text}", edit.file);
                        let name = Path::new(edit.file).file_name().unwrap();
                        assert!(
                            text.contains(name.to_str().unwrap()),
                            "{}: the error names the file: {text}",
                            edit.breakage
                        );
                    }
                }
            }
        }
    }

    #[test]
    fn a_missing_anchor_is_a_clear_error() {
        let (behaviors, formations) = shipped();
        let altered = tempfile::tempdir().unwrap();
        copy_flat(&behaviors, &altered.path().join("behaviors")).unwrap();
        copy_flat(&formations, &altered.path().join("formations")).unwrap();
        let shot = altered.path().join("formations/shot.ron");
        let text = std::fs::read_to_string(&shot).unwrap();
        std::fs::write(&shot, text.replace(EDITS[0].anchor, "threshold: 0.4,")).unwrap();
        let dir = tempfile::tempdir().unwrap();
        let err = Editor::copy_data(
            dir.path(),
            &altered.path().join("behaviors"),
            &altered.path().join("formations"),
        )
        .err()
        .expect("the missing anchor is reported");
        assert!(
            err.contains("threshold: 0.3,") && err.contains("found 0 times"),
            "{err}"
        );
    }
}
