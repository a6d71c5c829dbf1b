//! The live stream: at most 25 frames a second built from the agents' slots, sent to every
//! browser through a short queue; a browser whose queue is full is dropped.

use crate::http::Shared;
use crate::{MonitorView, Source};
use libero_agent::AgentView;
use libero_behavior::ReloadEvent;
use serde::Serialize;
use std::collections::VecDeque;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{SyncSender, TrySendError};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

/// Frames between two sends at most 25 per second.
pub const FRAME_PERIOD: Duration = Duration::from_millis(40);
/// Frames a browser may be behind before it is dropped.
pub const CLIENT_QUEUE: usize = 8;
/// Reload events kept for the panel.
const RELOADS_KEPT: usize = 12;

/// The browsers connected to the stream.
#[derive(Clone, Default)]
pub struct Clients(Arc<Mutex<Vec<SyncSender<Arc<str>>>>>);

impl Clients {
    pub fn add(&self, sender: SyncSender<Arc<str>>) {
        if let Ok(mut clients) = self.0.lock() {
            clients.push(sender);
        }
    }

    /// Send `frame` to everyone; drop those who are full or gone. Returns how many remain.
    pub fn send(&self, frame: &Arc<str>) -> usize {
        let Ok(mut clients) = self.0.lock() else {
            return 0;
        };
        clients.retain(|c| match c.try_send(Arc::clone(frame)) {
            Ok(()) => true,
            Err(TrySendError::Full(_)) => {
                log::warn!("field view: a browser fell {CLIENT_QUEUE} frames behind; dropped");
                false
            }
            Err(TrySendError::Disconnected(_)) => false,
        });
        clients.len()
    }

    pub fn count(&self) -> usize {
        self.0.lock().map_or(0, |c| c.len())
    }
}

/// One reload as the panel shows it.
#[derive(Debug, Clone, Serialize)]
pub struct ReloadNote {
    /// Which library (team) it was.
    pub team: String,
    /// Seconds since the view started.
    pub at_s: f64,
    pub accepted: bool,
    pub generation: Option<u64>,
    /// Files the diagnostics name, and the diagnostics as `libero validate` prints them.
    pub files: Vec<String>,
    pub report: String,
}

/// The last reload that concerned one file: when, whether it was taken, and what
/// `libero validate` said of that file.
#[derive(Debug, Clone, Serialize)]
pub struct FileReload {
    pub team: String,
    pub file: String,
    pub at_s: f64,
    pub accepted: bool,
    pub generation: Option<u64>,
    pub diagnostics: String,
}

/// Files followed at most (a folder full of junk must not grow the panel without bound).
const FILES_KEPT: usize = 256;

#[derive(Clone, Default)]
pub struct Reloads {
    events: Arc<Mutex<VecDeque<ReloadNote>>>,
    files: Arc<Mutex<Vec<FileReload>>>,
}

impl Reloads {
    fn push(&self, note: ReloadNote) {
        if let Ok(mut notes) = self.events.lock() {
            if notes.len() >= RELOADS_KEPT {
                notes.pop_front();
            }
            notes.push_back(note);
        }
    }

    fn note_file(&self, entry: FileReload) {
        let Ok(mut files) = self.files.lock() else {
            return;
        };
        files.retain(|f| !(f.team == entry.team && f.file == entry.file));
        if files.len() >= FILES_KEPT {
            // The one reloaded longest ago makes room.
            if let Some(oldest) =
                (0..files.len()).min_by(|&a, &b| files[a].at_s.total_cmp(&files[b].at_s))
            {
                files.remove(oldest);
            }
        }
        files.push(entry);
        files.sort_by(|a, b| (&a.team, &a.file).cmp(&(&b.team, &b.file)));
    }

    pub fn list(&self) -> Vec<ReloadNote> {
        self.events
            .lock()
            .map(|n| n.iter().cloned().collect())
            .unwrap_or_default()
    }

    pub fn files(&self) -> Vec<FileReload> {
        self.files.lock().map(|f| f.clone()).unwrap_or_default()
    }
}

type FileTime = (std::path::PathBuf, Option<std::time::SystemTime>);

/// Modification times of a library's files, to tell which ones a reload took up.
fn mtimes(library: &libero_behavior::LiveLibrary) -> Vec<FileTime> {
    library
        .current()
        .files()
        .iter()
        .map(|f| {
            (
                f.clone(),
                std::fs::metadata(f).and_then(|m| m.modified()).ok(),
            )
        })
        .collect()
}

/// The files one reload concerned, each with the diagnostics that name it: those whose
/// modification time moved (or that are new), and those the report names.
fn file_reloads(
    team: &str,
    note: &ReloadNote,
    event: &ReloadEvent,
    before: &[FileTime],
    after: &[FileTime],
) -> Vec<FileReload> {
    let report = match event {
        ReloadEvent::Reloaded { warnings, .. } => warnings,
        ReloadEvent::Rejected { report } => report,
    };
    let mut files: Vec<std::path::PathBuf> = after
        .iter()
        .filter(|(f, t)| {
            before
                .iter()
                .find(|(g, _)| g == f)
                .is_none_or(|(_, u)| u != t)
        })
        .map(|(f, _)| f.clone())
        .collect();
    for d in &report.diagnostics {
        if let Some(location) = &d.location {
            if !files.contains(&location.file.path) {
                files.push(location.file.path.clone());
            }
        }
    }
    files
        .into_iter()
        .map(|file| {
            let mine = libero_behavior::Report {
                diagnostics: report
                    .diagnostics
                    .iter()
                    .filter(|d| d.location.as_ref().is_some_and(|l| l.file.path == file))
                    .cloned()
                    .collect(),
            };
            FileReload {
                team: team.to_string(),
                file: file.display().to_string(),
                at_s: note.at_s,
                accepted: note.accepted,
                generation: note.generation,
                diagnostics: rendered(&mine),
            }
        })
        .collect()
}

/// What the page receives each frame (live) or asks for by step (replay).
#[derive(Serialize)]
pub struct Frame<'a> {
    pub seq: u64,
    pub time: f64,
    /// The replay step, when replaying.
    pub step: Option<usize>,
    pub monitor: Option<MonitorView>,
    pub agents: &'a [AgentView],
    pub reloads: Vec<ReloadNote>,
    pub files: Vec<FileReload>,
}

/// A report as `libero validate` prints it; nothing for an empty one (not its "0 errors").
fn rendered(report: &libero_behavior::Report) -> String {
    if report.diagnostics.is_empty() {
        String::new()
    } else {
        report.render_text()
    }
}

fn note_of(team: &str, at_s: f64, event: &ReloadEvent) -> ReloadNote {
    let (accepted, generation, report) = match event {
        ReloadEvent::Reloaded {
            generation,
            warnings,
            ..
        } => (true, Some(*generation), warnings),
        ReloadEvent::Rejected { report } => (false, None, report),
    };
    let mut files: Vec<String> = report
        .diagnostics
        .iter()
        .filter_map(|d| d.location.as_ref())
        .map(|l| l.file.path.display().to_string())
        .collect();
    files.dedup();
    ReloadNote {
        team: team.to_string(),
        at_s,
        accepted,
        generation,
        files,
        report: rendered(report),
    }
}

/// This moment's live frame as JSON: the agents' latest copies (into `views`, reused), the
/// monitor, the reload panels.
pub fn live_frame(
    shared: &Shared,
    set: &crate::LiveSet,
    seq: u64,
    views: &mut Vec<AgentView>,
) -> serde_json::Result<String> {
    views.clear();
    views.extend(set.agents().iter().filter_map(|a| a.latest()));
    let monitor = set.monitor();
    let time = monitor
        .as_ref()
        .map(|m| m.time)
        .or_else(|| views.iter().map(|v| v.time).reduce(f64::max))
        .unwrap_or(0.0);
    serde_json::to_string(&Frame {
        seq,
        time,
        step: None,
        monitor,
        agents: views,
        reloads: shared.reloads.list(),
        files: shared.reloads.files(),
    })
}

/// A library whose reloads the panel follows.
struct Followed {
    library: Arc<libero_behavior::LiveLibrary>,
    seen: u64,
    times: Vec<FileTime>,
}

/// The live loop: until `stop`, every frame period, the agents' latest copies to every browser.
pub fn broadcast(shared: &Shared, stop: &AtomicBool) {
    let Source::Live(set) = &shared.source else {
        return;
    };
    let started = Instant::now();
    // Reload events seen and file times, by library, so a new half's libraries start afresh.
    let mut followed: Vec<Followed> = Vec::new();
    let mut views: Vec<AgentView> = Vec::new();
    let mut seq = 0u64;
    let mut last_copies: u64 = u64::MAX;
    while !stop.load(Ordering::Relaxed) {
        let tick = Instant::now();
        let libraries = set.libraries();
        followed.retain(|f| libraries.iter().any(|(_, l)| Arc::ptr_eq(l, &f.library)));
        for (team, library) in &libraries {
            let pushed = library.events().pushed();
            let Some(f) = followed
                .iter_mut()
                .find(|f| Arc::ptr_eq(&f.library, library))
            else {
                followed.push(Followed {
                    library: Arc::clone(library),
                    seen: pushed,
                    times: mtimes(library),
                });
                continue;
            };
            if f.seen == pushed {
                continue;
            }
            f.seen = pushed;
            if let Some(event) = library.events().newest() {
                let note = note_of(team, started.elapsed().as_secs_f64(), &event);
                let now = mtimes(library);
                for entry in file_reloads(team, &note, &event, &f.times, &now) {
                    shared.reloads.note_file(entry);
                }
                f.times = now;
                shared.reloads.push(note);
            }
        }
        let copies: u64 = set.agents().iter().map(|a| a.copies()).sum();
        if shared.clients.count() > 0 && copies != last_copies {
            last_copies = copies;
            seq += 1;
            match live_frame(shared, set, seq, &mut views) {
                Ok(json) => {
                    shared.clients.send(&Arc::from(json));
                }
                Err(e) => log::error!("field view: frame not encoded: {e}"),
            }
        }
        if let Some(rest) = FRAME_PERIOD.checked_sub(tick.elapsed()) {
            std::thread::sleep(rest);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_browser_that_does_not_read_is_dropped_not_waited_for() {
        let clients = Clients::default();
        let (reading, read_side) = std::sync::mpsc::sync_channel(CLIENT_QUEUE);
        let (stuck, _stuck_side) = std::sync::mpsc::sync_channel(CLIENT_QUEUE);
        clients.add(reading);
        clients.add(stuck);
        let frame: Arc<str> = Arc::from("{}");
        for sent in 1..=CLIENT_QUEUE {
            assert_eq!(clients.send(&frame), 2, "frame {sent} fits both queues");
            read_side.recv().unwrap();
        }
        assert_eq!(clients.send(&frame), 1, "the stuck one is full: dropped");
        assert_eq!(read_side.try_iter().count(), 1);
        drop(read_side);
        assert_eq!(clients.send(&frame), 0, "a closed browser goes too");
    }
}
