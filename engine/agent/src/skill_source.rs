//! Where a process's skill parameters come from: the built-in file, a file loaded once, or a
//! file watched and hot-reloaded while the team plays (walk gains tuned live, like the trees).
//!
//! A reload is parsed and validated on the watcher's thread; a good version is published with
//! one atomic swap and every player picks it up at its next cycle. A broken edit is reported
//! once and the running version stays.

use arc_swap::ArcSwap;
use libero_model::RobotModel;
use libero_skills::{ParamsError, SkillParams};
use libero_watch::FileWatch;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::mpsc::{self, Receiver};
use std::sync::{Arc, Mutex};
use std::time::Duration;

/// Shared by every agent of the process.
#[derive(Clone)]
pub enum SkillSource {
    /// Each player uses the parameters built into the binary for its robot.
    Builtin,
    /// One file, loaded once.
    Fixed(Arc<SkillParams>),
    /// One file, watched.
    Live(Arc<LiveSkillParams>),
}

impl SkillSource {
    /// Load `path` (checked against `model`), watching it when `watch` is set.
    pub fn from_file(path: &Path, model: &RobotModel, watch: bool) -> Result<Self, ParamsError> {
        if watch {
            Ok(SkillSource::Live(Arc::new(LiveSkillParams::start(
                path.to_path_buf(),
                model.clone(),
            )?)))
        } else {
            Ok(SkillSource::Fixed(Arc::new(SkillParams::load(
                path, model,
            )?)))
        }
    }

    /// The parameters a player of `model` starts with.
    pub fn initial(&self, model: &RobotModel) -> Result<SkillParams, ParamsError> {
        match self {
            SkillSource::Builtin => SkillParams::builtin(model),
            SkillSource::Fixed(p) => Ok((**p).clone()),
            SkillSource::Live(live) => Ok((*live.current()).clone()),
        }
    }

    /// The version counter a player compares each cycle (0: never changes).
    pub fn generation(&self) -> u64 {
        match self {
            SkillSource::Live(live) => live.generation(),
            _ => 0,
        }
    }

    pub fn current(&self) -> Option<Arc<SkillParams>> {
        match self {
            SkillSource::Live(live) => Some(live.current()),
            SkillSource::Fixed(p) => Some(Arc::clone(p)),
            SkillSource::Builtin => None,
        }
    }
}

/// What the watcher did, for the log and for tests.
#[derive(Debug, Clone, PartialEq)]
pub enum ParamsEvent {
    /// A new version is live; `recovered` when it replaces a rejected edit.
    Reloaded { generation: u64, recovered: bool },
    /// An edit had errors (the message locates them); the previous version keeps running.
    Rejected { message: String },
}

struct Shared {
    current: ArcSwap<SkillParams>,
    generation: AtomicU64,
}

/// The newest valid version of one skill parameter file.
pub struct LiveSkillParams {
    shared: Arc<Shared>,
    events: Mutex<Receiver<ParamsEvent>>,
    path: PathBuf,
    _watch: FileWatch,
}

impl LiveSkillParams {
    /// Load `path` (failing if it is broken now) and watch it.
    pub fn start(path: PathBuf, model: RobotModel) -> Result<Self, ParamsError> {
        let text = std::fs::read_to_string(&path)
            .map_err(|e| ParamsError::Io(path.display().to_string(), e))?;
        let params = SkillParams::from_ron(&path.display().to_string(), &text, &model)?;
        let shared = Arc::new(Shared {
            current: ArcSwap::from_pointee(params),
            generation: AtomicU64::new(1),
        });
        let (events_tx, events) = mpsc::channel();
        let mut reloader = Reloader {
            path: path.clone(),
            model,
            shared: Arc::clone(&shared),
            events: events_tx,
            last_text: text,
            broken: false,
        };
        let watch = FileWatch::start(
            "skill-params-reload",
            std::slice::from_ref(&path),
            libero_watch::DEFAULT_DEBOUNCE,
            move || reloader.reload(),
        )
        .map_err(|e| ParamsError::Io(path.display().to_string(), std::io::Error::other(e)))?;
        Ok(Self {
            shared,
            events: Mutex::new(events),
            path,
            _watch: watch,
        })
    }

    pub fn path(&self) -> &Path {
        &self.path
    }

    pub fn current(&self) -> Arc<SkillParams> {
        self.shared.current.load_full()
    }

    pub fn generation(&self) -> u64 {
        self.shared.generation.load(Ordering::Acquire)
    }

    /// Waits up to `timeout` for the next reload event.
    pub fn next_event(&self, timeout: Duration) -> Option<ParamsEvent> {
        let events = self.events.lock().unwrap_or_else(|p| p.into_inner());
        events.recv_timeout(timeout).ok()
    }
}

struct Reloader {
    path: PathBuf,
    model: RobotModel,
    shared: Arc<Shared>,
    events: mpsc::Sender<ParamsEvent>,
    last_text: String,
    broken: bool,
}

impl Reloader {
    fn reload(&mut self) {
        let text = match std::fs::read_to_string(&self.path) {
            Ok(text) => text,
            // Gone for a moment (an editor's rename) or unreadable: the next event retries.
            Err(e) => {
                log::debug!("skill parameters {}: {e}", self.path.display());
                return;
            }
        };
        if text == self.last_text {
            return;
        }
        self.last_text = text;
        match SkillParams::from_ron(
            &self.path.display().to_string(),
            &self.last_text,
            &self.model,
        ) {
            Ok(params) => {
                self.shared.current.store(Arc::new(params));
                let generation = self.shared.generation.fetch_add(1, Ordering::AcqRel) + 1;
                let recovered = std::mem::take(&mut self.broken);
                log::info!(
                    "skill parameters {} {}; version {generation} is live",
                    self.path.display(),
                    if recovered { "fixed" } else { "reloaded" }
                );
                let _ = self.events.send(ParamsEvent::Reloaded {
                    generation,
                    recovered,
                });
            }
            Err(e) => {
                self.broken = true;
                let message = e.to_string();
                log::error!("skill parameters rejected, keeping the running version:\n{message}");
                let _ = self.events.send(ParamsEvent::Rejected { message });
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const WAIT: Duration = Duration::from_secs(5);

    fn setup() -> (tempfile::TempDir, PathBuf, LiveSkillParams, String) {
        let model = RobotModel::builtin("T1").unwrap();
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("t1.ron");
        let text = SkillParams::builtin(&model).unwrap().to_ron();
        std::fs::write(&path, &text).unwrap();
        let live = LiveSkillParams::start(path.clone(), model).unwrap();
        (dir, path, live, text)
    }

    #[test]
    fn a_good_edit_goes_live_a_broken_one_is_reported_and_the_fix_recovers() {
        let (_dir, path, live, text) = setup();
        let period = live.current().walk.step_period_s;
        let edited = text.replacen(
            &format!("step_period_s: {period}"),
            "step_period_s: 0.41",
            1,
        );
        assert_ne!(edited, text, "the edit must change the file");
        std::fs::write(&path, &edited).unwrap();
        assert_eq!(
            live.next_event(WAIT),
            Some(ParamsEvent::Reloaded {
                generation: 2,
                recovered: false
            })
        );
        assert_eq!(live.current().walk.step_period_s, 0.41);

        // Out of range: rejected with the field named; the running version stays.
        std::fs::write(
            &path,
            edited.replace("step_period_s: 0.41", "step_period_s: 9.0"),
        )
        .unwrap();
        match live.next_event(WAIT) {
            Some(ParamsEvent::Rejected { message }) => {
                assert!(message.contains("step_period_s"), "{message}")
            }
            other => panic!("expected a rejection, got {other:?}"),
        }
        assert_eq!(live.generation(), 2);
        assert_eq!(live.current().walk.step_period_s, 0.41);

        // A syntax error is located in the file.
        std::fs::write(&path, edited.replacen("walk:", "walk", 1)).unwrap();
        match live.next_event(WAIT) {
            Some(ParamsEvent::Rejected { message }) => {
                assert!(message.contains("t1.ron:"), "{message}")
            }
            other => panic!("expected a rejection, got {other:?}"),
        }

        std::fs::write(&path, &text).unwrap();
        assert_eq!(
            live.next_event(WAIT),
            Some(ParamsEvent::Reloaded {
                generation: 3,
                recovered: true
            })
        );
        assert_eq!(live.current().walk.step_period_s, period);
    }
}
