//! Hot reload: a `libero_watch` thread debounces file events on the library's directories, rebuilds the
//! whole library off the agent threads and publishes it with one atomic swap. Broken edits
//! keep the last good version and are reported once.

use crate::data_files::DataFiles;
use crate::diagnostics::Report;
use crate::library::{build, fingerprint, read_sources, Library};
use crate::vocabulary::Vocabulary;
use arc_swap::ArcSwap;
use libero_watch::{Events, FileWatch};
use std::path::PathBuf;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Arc;
use std::time::Duration;

#[derive(Debug, Clone)]
pub struct ReloadOptions {
    /// Quiet time after the last file event before reloading (see `libero_watch`).
    pub debounce: Duration,
}

impl Default for ReloadOptions {
    fn default() -> Self {
        Self {
            debounce: libero_watch::DEFAULT_DEBOUNCE,
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
    /// The newest few events (see [`Events`]): nothing reads them in a running team.
    events: Arc<Events<ReloadEvent>>,
    /// Stops the reload thread when the library is dropped.
    _watch: FileWatch,
}

impl LiveLibrary {
    /// Loads the library (failing with every error if the initial files are broken) and starts
    /// watching `paths` for changes.
    pub fn start(
        paths: Vec<PathBuf>,
        vocabulary: Arc<Vocabulary>,
        data_files: Arc<dyn DataFiles>,
        options: ReloadOptions,
    ) -> Result<LiveLibrary, Report> {
        let (sources, mut report) = read_sources(&paths);
        let initial_fingerprint = fingerprint(&sources, &report);
        let library = build(&sources, &vocabulary, data_files.as_ref(), &mut report);
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
        let events = Arc::new(Events::default());
        let mut reloader = Reloader {
            paths: paths.clone(),
            vocabulary,
            data_files,
            shared: shared.clone(),
            events: Arc::clone(&events),
            last_fingerprint: initial_fingerprint,
            broken: false,
        };
        let watch = FileWatch::start("behavior-reload", &paths, options.debounce, move || {
            reloader.reload()
        })
        .map_err(|e| {
            let mut report = Report::default();
            report.push(crate::Diagnostic::error(
                "io",
                format!("cannot watch the behavior files: {e}"),
            ));
            report
        })?;
        Ok(LiveLibrary {
            shared,
            events,
            _watch: watch,
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

    /// Reload events not yet taken (the newest [`libero_watch::DEFAULT_EVENT_CAPACITY`]).
    pub fn drain_events(&self) -> Vec<ReloadEvent> {
        self.events.drain()
    }

    /// Waits up to `timeout` for the next reload event.
    pub fn next_event(&self, timeout: Duration) -> Option<ReloadEvent> {
        self.events.next(timeout)
    }

    /// The queue of reload events itself: how many wait (bounded however long the library
    /// runs), how many were sent and dropped.
    pub fn events(&self) -> &Events<ReloadEvent> {
        &self.events
    }
}

struct Reloader {
    paths: Vec<PathBuf>,
    vocabulary: Arc<Vocabulary>,
    data_files: Arc<dyn DataFiles>,
    shared: Arc<Shared>,
    events: Arc<Events<ReloadEvent>>,
    last_fingerprint: u64,
    broken: bool,
}

impl Reloader {
    fn reload(&mut self) {
        let (sources, mut report) = read_sources(&self.paths);
        let fingerprint = fingerprint(&sources, &report);
        if fingerprint == self.last_fingerprint {
            return;
        }
        self.last_fingerprint = fingerprint;
        let library = build(
            &sources,
            &self.vocabulary,
            self.data_files.as_ref(),
            &mut report,
        );
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
                self.events.push(ReloadEvent::Reloaded {
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
                self.events.push(ReloadEvent::Rejected { report });
            }
        }
    }
}
