//! Hot reload: a watcher thread debounces file events on the library's directories, rebuilds the
//! whole library off the agent threads and publishes it with one atomic swap. Broken edits
//! keep the last good version and are reported once.

use crate::diagnostics::Report;
use crate::library::{build, fingerprint, read_sources, Library};
use crate::vocabulary::Vocabulary;
use arc_swap::ArcSwap;
use notify::{EventKind, RecursiveMode, Watcher};
use std::path::PathBuf;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::mpsc::{self, Receiver, RecvTimeoutError};
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

#[derive(Debug, Clone)]
pub struct ReloadOptions {
    /// Quiet time after the last file event before reloading: editors save in several steps
    /// (truncate then write, write a temporary then rename) and only the end state matters.
    pub debounce: Duration,
}

impl Default for ReloadOptions {
    fn default() -> Self {
        Self {
            debounce: Duration::from_millis(150),
        }
    }
}

/// What the watcher did, for the agent's log and for tests.
#[derive(Debug, Clone)]
pub enum ReloadEvent {
    /// A new version is live. `recovered` is true when it replaces a rejected edit.
    Reloaded {
        generation: u64,
        recovered: bool,
        warnings: Report,
    },
    /// An edit had errors; the previous version keeps running. Sent once per distinct content.
    Rejected { report: Report },
}

struct Shared {
    current: ArcSwap<Library>,
    generation: AtomicU64,
}

/// The newest valid library of a directory set, kept up to date by a watcher thread.
pub struct LiveLibrary {
    shared: Arc<Shared>,
    events: Mutex<Receiver<ReloadEvent>>,
    watcher: Option<notify::RecommendedWatcher>,
    thread: Option<JoinHandle<()>>,
}

impl LiveLibrary {
    /// Loads the library (failing with every error if the initial files are broken) and starts
    /// watching `paths` for changes.
    pub fn start(
        paths: Vec<PathBuf>,
        vocabulary: Arc<Vocabulary>,
        options: ReloadOptions,
    ) -> Result<LiveLibrary, Report> {
        let (sources, mut report) = read_sources(&paths);
        let initial_fingerprint = fingerprint(&sources);
        let library = build(&sources, &vocabulary, &mut report);
        report.sort();
        let mut library = match library {
            Some(library) if !report.has_errors() => library,
            _ => return Err(report),
        };
        library.set_generation(1);
        for warning in &report.diagnostics {
            log::warn!("{}", warning.message);
        }
        let shared = Arc::new(Shared {
            current: ArcSwap::from_pointee(library),
            generation: AtomicU64::new(1),
        });
        let (file_events_tx, file_events) = mpsc::channel();
        let mut watcher = notify::recommended_watcher(move |event| {
            let _ = file_events_tx.send(event);
        })
        .map_err(|e| watch_error(&e))?;
        for path in &paths {
            let mode = if path.is_dir() {
                RecursiveMode::Recursive
            } else {
                RecursiveMode::NonRecursive
            };
            watcher.watch(path, mode).map_err(|e| watch_error(&e))?;
        }
        let (events_tx, events) = mpsc::channel();
        let mut reloader = Reloader {
            paths,
            vocabulary,
            shared: shared.clone(),
            events: events_tx,
            last_fingerprint: initial_fingerprint,
            broken: false,
        };
        let thread = std::thread::Builder::new()
            .name("behavior-reload".into())
            .spawn(move || reloader.run(file_events, options.debounce))
            .map_err(|e| {
                let mut report = Report::default();
                report.push(crate::Diagnostic::error(
                    "io",
                    format!("cannot start the reload thread: {e}"),
                ));
                report
            })?;
        Ok(LiveLibrary {
            shared,
            events: Mutex::new(events),
            watcher: Some(watcher),
            thread: Some(thread),
        })
    }

    /// The newest library; call once at the start of a cycle and tick every agent with it.
    pub fn current(&self) -> Arc<Library> {
        self.shared.current.load_full()
    }

    /// The generation of the newest library: a cheap check for "did anything change?".
    pub fn generation(&self) -> u64 {
        self.shared.generation.load(Ordering::Acquire)
    }

    /// Reload events not yet taken.
    pub fn drain_events(&self) -> Vec<ReloadEvent> {
        let events = self
            .events
            .lock()
            .unwrap_or_else(|poisoned| poisoned.into_inner());
        events.try_iter().collect()
    }

    /// Waits up to `timeout` for the next reload event.
    pub fn next_event(&self, timeout: Duration) -> Option<ReloadEvent> {
        let events = self
            .events
            .lock()
            .unwrap_or_else(|poisoned| poisoned.into_inner());
        events.recv_timeout(timeout).ok()
    }
}

impl Drop for LiveLibrary {
    fn drop(&mut self) {
        // Dropping the watcher closes its channel, which ends the reload thread.
        self.watcher.take();
        if let Some(thread) = self.thread.take() {
            let _ = thread.join();
        }
    }
}

fn watch_error(error: &notify::Error) -> Report {
    let mut report = Report::default();
    report.push(crate::Diagnostic::error(
        "io",
        format!("cannot watch the behavior directories: {error}"),
    ));
    report
}

struct Reloader {
    paths: Vec<PathBuf>,
    vocabulary: Arc<Vocabulary>,
    shared: Arc<Shared>,
    events: mpsc::Sender<ReloadEvent>,
    last_fingerprint: u64,
    broken: bool,
}

/// Reads (our own reload) and metadata changes say nothing about content.
fn is_relevant(event: &notify::Result<notify::Event>) -> bool {
    match event {
        Ok(event) => match event.kind {
            EventKind::Access(notify::event::AccessKind::Close(
                notify::event::AccessMode::Write,
            )) => true,
            EventKind::Access(_) | EventKind::Modify(notify::event::ModifyKind::Metadata(_)) => {
                false
            }
            _ => true,
        },
        // Errors (e.g. a queue overflow) may hide changes: reload to be sure.
        Err(_) => true,
    }
}

impl Reloader {
    fn run(&mut self, file_events: Receiver<notify::Result<notify::Event>>, debounce: Duration) {
        loop {
            match file_events.recv() {
                Ok(event) if is_relevant(&event) => {}
                Ok(_) => continue,
                Err(_) => return,
            }
            let mut deadline = Instant::now() + debounce;
            loop {
                let remaining = deadline.saturating_duration_since(Instant::now());
                if remaining.is_zero() {
                    break;
                }
                match file_events.recv_timeout(remaining) {
                    Ok(event) if is_relevant(&event) => deadline = Instant::now() + debounce,
                    Ok(_) => {}
                    Err(RecvTimeoutError::Timeout) => break,
                    Err(RecvTimeoutError::Disconnected) => return,
                }
            }
            self.reload();
        }
    }

    fn reload(&mut self) {
        let (sources, mut report) = read_sources(&self.paths);
        let fingerprint = fingerprint(&sources);
        if fingerprint == self.last_fingerprint {
            return;
        }
        self.last_fingerprint = fingerprint;
        let library = build(&sources, &self.vocabulary, &mut report);
        report.sort();
        match library {
            Some(mut library) if !report.has_errors() => {
                let generation = self.shared.generation.load(Ordering::Acquire) + 1;
                library.set_generation(generation);
                self.shared.current.store(Arc::new(library));
                self.shared.generation.store(generation, Ordering::Release);
                let recovered = std::mem::take(&mut self.broken);
                if recovered {
                    log::info!("behavior files fixed; generation {generation} is live");
                } else {
                    log::info!("behavior files reloaded; generation {generation} is live");
                }
                let _ = self.events.send(ReloadEvent::Reloaded {
                    generation,
                    recovered,
                    warnings: report,
                });
            }
            _ => {
                self.broken = true;
                log::error!(
                    "behavior files rejected, keeping the running version:\n{}",
                    report.render_text()
                );
                let _ = self.events.send(ReloadEvent::Rejected { report });
            }
        }
    }
}
