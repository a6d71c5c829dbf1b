//! Where a process's skill parameters come from: the built-in file, a file loaded once, or a
//! file watched and hot-reloaded while the team plays (walk gains tuned live, like the trees).
//!
//! A reload is parsed and validated on the watcher's thread; a good version is published with
//! one atomic swap and every player picks it up at its next cycle. A broken edit is reported
//! once and the running version stays.

use arc_swap::ArcSwap;
use libero_behavior::files::{read_text, ReadError};
use libero_model::RobotModel;
use libero_skills::{ParamsError, SkillParams};
use libero_watch::{Events, FileWatch};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Arc;
use std::time::Duration;

/// Shared by every agent of the process. A file holds a robot family's parameters (every NAO
/// type plays nao.ron): each player takes its own type's entries from it
/// ([`SkillParams::for_type`]), so a team of mixed types shares one file and one watcher.
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
            let text = read_params(path)?;
            Ok(SkillSource::Fixed(Arc::new(
                SkillParams::from_ron_for_family(&path.display().to_string(), &text, model)?,
            )))
        }
    }

    /// The parameters a player of `model` starts with (its type's own).
    pub fn initial(&self, model: &RobotModel) -> Result<SkillParams, ParamsError> {
        match self {
            SkillSource::Builtin => SkillParams::builtin(model),
            SkillSource::Fixed(p) => Ok(p.for_type(model)),
            SkillSource::Live(live) => Ok(live.current().for_type(model)),
        }
    }

    /// The version counter a player compares each cycle (0: never changes).
    pub fn generation(&self) -> u64 {
        match self {
            SkillSource::Live(live) => live.generation(),
            _ => 0,
        }
    }

    /// The file's parameters for the whole family: a player plays
    /// [`SkillParams::for_type`] of them.
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
    /// An edit had errors (the message locates them), or the file could not be read (too
    /// large, not text); the previous version keeps running.
    Rejected { message: String },
}

/// The file's text, with bounded cost whatever it holds (see [`libero_behavior::files`]).
fn read_params(path: &Path) -> Result<String, ParamsError> {
    read_text(path).map_err(|e| {
        let error = match e {
            ReadError::Io(error) => error,
            ReadError::Missing => std::io::ErrorKind::NotFound.into(),
            other => std::io::Error::other(other.to_string()),
        };
        ParamsError::Io(path.display().to_string(), error)
    })
}

struct Shared {
    current: ArcSwap<SkillParams>,
    generation: AtomicU64,
}

/// The newest valid version of one skill parameter file.
pub struct LiveSkillParams {
    shared: Arc<Shared>,
    /// The newest few events (see [`Events`]): nothing reads them in a running team.
    events: Arc<Events<ParamsEvent>>,
    path: PathBuf,
    _watch: FileWatch,
}

impl LiveSkillParams {
    /// Load `path` (failing if it is broken now) and watch it.
    pub fn start(path: PathBuf, model: RobotModel) -> Result<Self, ParamsError> {
        let text = read_params(&path)?;
        let params = SkillParams::from_ron_for_family(&path.display().to_string(), &text, &model)?;
        let shared = Arc::new(Shared {
            current: ArcSwap::from_pointee(params),
            generation: AtomicU64::new(1),
        });
        let events = Arc::new(Events::default());
        let mut reloader = Reloader {
            path: path.clone(),
            model,
            shared: Arc::clone(&shared),
            events: Arc::clone(&events),
            last_text: text,
            unreadable: None,
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
            events,
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
        self.events.next(timeout)
    }

    /// The queue of reload events itself (bounded; how many were sent and dropped).
    pub fn events(&self) -> &Events<ParamsEvent> {
        &self.events
    }
}

struct Reloader {
    path: PathBuf,
    model: RobotModel,
    shared: Arc<Shared>,
    events: Arc<Events<ParamsEvent>>,
    last_text: String,
    /// Why the file could not be read at the last attempt: said once, not on every event.
    unreadable: Option<String>,
    broken: bool,
}

impl Reloader {
    fn reload(&mut self) {
        let text = match read_text(&self.path) {
            Ok(text) => {
                self.unreadable = None;
                text
            }
            // Gone for a moment (an editor's rename): the next event brings the new file.
            Err(ReadError::Missing) => {
                log::debug!("skill parameters {}: gone for now", self.path.display());
                return;
            }
            Err(e) => {
                let message = format!(
                    "skill parameters {}; keeping the running version",
                    e.describe(&self.path)
                );
                if self.unreadable.as_ref() != Some(&message) {
                    log::warn!("{message}");
                    self.unreadable = Some(message.clone());
                    self.broken = true;
                    // Reading it again once it is fixed must count as a change.
                    self.last_text.clear();
                    self.events.push(ParamsEvent::Rejected { message });
                }
                return;
            }
        };
        if text == self.last_text {
            return;
        }
        self.last_text = text;
        match SkillParams::from_ron_for_family(
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
                self.events.push(ParamsEvent::Reloaded {
                    generation,
                    recovered,
                });
            }
            Err(e) => {
                self.broken = true;
                let message = e.to_string();
                log::error!("skill parameters rejected, keeping the running version:\n{message}");
                self.events.push(ParamsEvent::Rejected { message });
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::Mutex;

    const WAIT: Duration = Duration::from_secs(5);

    #[test]
    fn one_family_file_gives_each_type_its_own_walk_and_get_ups() {
        // A team loads nao.ron once, against its first player's model (type 0); a type-3
        // player must still play type 3's walk and get-ups, not type 0's (it lay in a loop
        // of the common front motion's pike in every 11 v 11 until session 28).
        let type0 = RobotModel::builtin("nao_type0").unwrap();
        let type3 = RobotModel::builtin("nao_type3").unwrap();
        let path = PathBuf::from(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../skills/params/nao.ron"
        ));
        let own = SkillParams::load(&path, &type3).unwrap().to_ron();
        assert_ne!(own, SkillParams::load(&path, &type0).unwrap().to_ron());
        for watch in [false, true] {
            let source = SkillSource::from_file(&path, &type0, watch).unwrap();
            assert_eq!(
                source.initial(&type3).unwrap().to_ron(),
                own,
                "watch {watch}"
            );
            let reloaded = source.current().unwrap().for_type(&type3);
            assert_eq!(reloaded.to_ron(), own, "watch {watch}");
        }
    }

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

    /// Warnings logged by this test binary, to count what an operator would see.
    struct Warnings(Mutex<Vec<String>>);

    impl log::Log for Warnings {
        fn enabled(&self, metadata: &log::Metadata) -> bool {
            metadata.level() <= log::Level::Warn
        }
        fn log(&self, record: &log::Record) {
            if record.level() == log::Level::Warn {
                let mut seen = self.0.lock().unwrap();
                seen.push(record.args().to_string());
            }
        }
        fn flush(&self) {}
    }

    static WARNINGS: Warnings = Warnings(Mutex::new(Vec::new()));

    fn warnings_about(file: &Path) -> usize {
        let _ = log::set_logger(&WARNINGS);
        log::set_max_level(log::LevelFilter::Warn);
        let name = file.display().to_string();
        WARNINGS
            .0
            .lock()
            .unwrap()
            .iter()
            .filter(|w| w.contains(&name))
            .count()
    }

    fn wait_for_events(live: &LiveSkillParams, count: u64) {
        let start = std::time::Instant::now();
        while live.events().pushed() < count {
            assert!(start.elapsed() < WAIT, "no reload event {count}");
            std::thread::sleep(Duration::from_millis(2));
        }
    }

    #[test]
    fn an_unreadable_file_is_warned_about_once_and_a_bom_is_accepted() {
        let (_dir, path, live, text) = setup();
        assert_eq!(warnings_about(&path), 0);
        let binary: Vec<u8> = (0..=255u8).cycle().take(4096).collect();
        std::fs::write(&path, &binary).unwrap();
        wait_for_events(&live, 1);
        match live.next_event(Duration::ZERO) {
            Some(ParamsEvent::Rejected { message }) => {
                assert!(message.contains("not UTF-8"), "{message}")
            }
            other => panic!("expected a rejection, got {other:?}"),
        }
        assert_eq!(warnings_about(&path), 1);
        // Saved again unchanged: nothing new to say.
        for _ in 0..3 {
            std::fs::write(&path, &binary).unwrap();
            std::thread::sleep(libero_watch::DEFAULT_DEBOUNCE * 2);
        }
        assert_eq!(live.events().pushed(), 1);
        assert_eq!(warnings_about(&path), 1);

        // 50 MB (sparse): refused unread, with a short message naming the file and the limit.
        let start = std::time::Instant::now();
        std::fs::File::create(&path)
            .unwrap()
            .set_len(50 << 20)
            .unwrap();
        wait_for_events(&live, 2);
        assert!(
            start.elapsed() < Duration::from_secs(1),
            "{:?}",
            start.elapsed()
        );
        match live.next_event(Duration::ZERO) {
            Some(ParamsEvent::Rejected { message }) => {
                assert!(message.len() < 300, "{message}");
                assert!(
                    message.contains("t1.ron") && message.contains("1048576"),
                    "{message}"
                );
            }
            other => panic!("expected a rejection, got {other:?}"),
        }
        assert_eq!(warnings_about(&path), 2);
        assert_eq!(live.generation(), 1, "the running version stays");

        // Back to text, with a byte-order mark an editor left in front.
        std::fs::write(&path, format!("\u{feff}{text}")).unwrap();
        assert_eq!(
            live.next_event(WAIT),
            Some(ParamsEvent::Reloaded {
                generation: 2,
                recovered: true
            })
        );
        assert!(live.events().len() <= libero_watch::DEFAULT_EVENT_CAPACITY);
    }
}
