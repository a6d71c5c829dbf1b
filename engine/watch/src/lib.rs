//! Watch data files and call a reload function once an edit has settled.
//!
//! Editors save in several steps (truncate then write; write a temporary file then rename), and
//! only the end state matters, so a reload runs after `debounce` of quiet following the last
//! relevant event. The reload runs on the watcher's own thread, never on an agent thread.
//! Behavior trees, strategy files and skill parameters all reload through this one mechanism.

mod events;

pub use events::{Events, DEFAULT_EVENT_CAPACITY};

use notify::{EventKind, RecursiveMode, Watcher};
use std::path::{Path, PathBuf};
use std::sync::mpsc::{self, Receiver, RecvTimeoutError};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

/// Quiet time after the last file event before reloading, unless a caller says otherwise.
pub const DEFAULT_DEBOUNCE: Duration = Duration::from_millis(150);

/// A running watch; dropping it stops the thread.
pub struct FileWatch {
    watcher: Option<notify::RecommendedWatcher>,
    thread: Option<JoinHandle<()>>,
}

/// Why a watch could not start.
#[derive(Debug)]
pub struct WatchError(String);

impl std::fmt::Display for WatchError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for WatchError {}

impl FileWatch {
    /// Watch `paths` (folders recursively, files alone) and call `reload` on a thread named
    /// `name` after each settled burst of changes. `reload` should compare contents itself:
    /// a burst may leave a file as it was.
    pub fn start(
        name: &str,
        paths: &[PathBuf],
        debounce: Duration,
        mut reload: impl FnMut() + Send + 'static,
    ) -> Result<FileWatch, WatchError> {
        let (events_tx, events) = mpsc::channel();
        // Links are not followed: one leading up the tree (`up -> ..`) would watch everything
        // above the folder; links inside it lead to folders watched under their own path.
        let config = notify::Config::default().with_follow_symlinks(false);
        let mut watcher = notify::RecommendedWatcher::new(
            move |event| {
                let _ = events_tx.send(event);
            },
            config,
        )
        .map_err(|e| WatchError(format!("cannot watch files: {e}")))?;
        for path in paths {
            // A single file is watched through its folder: editors that save by renaming a
            // temporary file over it replace the inode a direct file watch would follow.
            let (target, mode) = if path.is_dir() {
                (path.as_path(), RecursiveMode::Recursive)
            } else {
                (
                    path.parent()
                        .filter(|p| !p.as_os_str().is_empty())
                        .unwrap_or(Path::new(".")),
                    RecursiveMode::NonRecursive,
                )
            };
            watcher
                .watch(target, mode)
                .map_err(|e| WatchError(format!("cannot watch {}: {e}", path.display())))?;
        }
        let files: Vec<PathBuf> = paths.iter().filter(|p| !p.is_dir()).cloned().collect();
        let any_folder = paths.iter().any(|p| p.is_dir());
        let concerns = move |event: &notify::Result<notify::Event>| {
            is_relevant(event) && touches(event, &files, any_folder)
        };
        let thread = std::thread::Builder::new()
            .name(name.into())
            .spawn(move || {
                while wait_for_settled_change(&events, debounce, &concerns) {
                    reload();
                }
            })
            .map_err(|e| WatchError(format!("cannot start the {name} thread: {e}")))?;
        Ok(FileWatch {
            watcher: Some(watcher),
            thread: Some(thread),
        })
    }
}

impl Drop for FileWatch {
    fn drop(&mut self) {
        // Dropping the watcher closes its channel, which ends the thread.
        self.watcher.take();
        if let Some(thread) = self.thread.take() {
            let _ = thread.join();
        }
    }
}

/// Blocks until a relevant event has been followed by `debounce` of quiet; false once the
/// watcher is gone.
fn wait_for_settled_change(
    events: &Receiver<notify::Result<notify::Event>>,
    debounce: Duration,
    concerns: &impl Fn(&notify::Result<notify::Event>) -> bool,
) -> bool {
    loop {
        match events.recv() {
            Ok(event) if concerns(&event) => break,
            Ok(_) => continue,
            Err(_) => return false,
        }
    }
    let mut deadline = Instant::now() + debounce;
    loop {
        let remaining = deadline.saturating_duration_since(Instant::now());
        if remaining.is_zero() {
            return true;
        }
        match events.recv_timeout(remaining) {
            Ok(event) if concerns(&event) => deadline = Instant::now() + debounce,
            Ok(_) => {}
            Err(RecvTimeoutError::Timeout) => return true,
            Err(RecvTimeoutError::Disconnected) => return false,
        }
    }
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

/// Whether the event may concern what is watched. A file is watched through its folder, so
/// events about its siblings are dropped by name; with folders watched, every event counts
/// (a spurious reload costs little: reloaders compare contents).
fn touches(event: &notify::Result<notify::Event>, files: &[PathBuf], any_folder: bool) -> bool {
    let Ok(event) = event else { return true };
    if any_folder || event.paths.is_empty() {
        return true;
    }
    event.paths.iter().any(|changed| {
        files
            .iter()
            .any(|f| f.file_name().is_some() && changed.file_name() == f.file_name())
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::atomic::{AtomicUsize, Ordering};
    use std::sync::Arc;

    fn wait_for(count: &AtomicUsize, at_least: usize) -> bool {
        let deadline = Instant::now() + Duration::from_secs(5);
        while Instant::now() < deadline {
            if count.load(Ordering::SeqCst) >= at_least {
                return true;
            }
            std::thread::sleep(Duration::from_millis(10));
        }
        false
    }

    /// A watch on `file` that counts its reloads.
    fn counting_watch(file: &Path, debounce: Duration) -> (FileWatch, Arc<AtomicUsize>) {
        let count = Arc::new(AtomicUsize::new(0));
        let c = Arc::clone(&count);
        let watch = FileWatch::start("test-watch", &[file.to_path_buf()], debounce, move || {
            c.fetch_add(1, Ordering::SeqCst);
        })
        .unwrap();
        (watch, count)
    }

    #[test]
    fn a_burst_of_writes_to_a_watched_file_reloads_once() {
        let dir = tempfile::tempdir().unwrap();
        let file = dir.path().join("params.ron");
        std::fs::write(&file, "a").unwrap();
        // Writes 20 ms apart, a debounce 25 times that: a fresh-clone CI run once saw two
        // reloads with a 200 ms debounce (not reproduced in 55 runs, also under load), which a
        // scheduling pause between two writes explains.
        let (_watch, count) = counting_watch(&file, Duration::from_millis(500));
        for text in ["b", "bc", "bcd"] {
            std::fs::write(&file, text).unwrap();
            std::thread::sleep(Duration::from_millis(20));
        }
        assert!(wait_for(&count, 1), "no reload after the edit");
        std::thread::sleep(Duration::from_millis(1000));
        assert_eq!(count.load(Ordering::SeqCst), 1, "one burst, one reload");
    }

    #[test]
    fn a_save_by_rename_is_seen_and_sibling_files_are_not() {
        let dir = tempfile::tempdir().unwrap();
        let file = dir.path().join("t1.ron");
        std::fs::write(&file, "a").unwrap();
        let (_watch, count) = counting_watch(&file, Duration::from_millis(50));
        std::fs::write(dir.path().join("other.ron"), "x").unwrap();
        std::thread::sleep(Duration::from_millis(300));
        assert_eq!(count.load(Ordering::SeqCst), 0, "a sibling's edit reloaded");
        let temp = dir.path().join(".t1.ron.swp");
        std::fs::write(&temp, "b").unwrap();
        std::fs::rename(&temp, &file).unwrap();
        assert!(wait_for(&count, 1), "a rename over the file was missed");
    }
}
