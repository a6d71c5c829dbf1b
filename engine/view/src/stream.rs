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

#[derive(Clone, Default)]
pub struct Reloads(Arc<Mutex<VecDeque<ReloadNote>>>);

impl Reloads {
    fn push(&self, note: ReloadNote) {
        if let Ok(mut notes) = self.0.lock() {
            if notes.len() >= RELOADS_KEPT {
                notes.pop_front();
            }
            notes.push_back(note);
        }
    }

    pub fn list(&self) -> Vec<ReloadNote> {
        self.0
            .lock()
            .map(|n| n.iter().cloned().collect())
            .unwrap_or_default()
    }
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
        report: report.render_text(),
    }
}

/// The live loop: until `stop`, every frame period, the agents' latest copies to every browser.
pub fn broadcast(shared: &Shared, stop: &AtomicBool) {
    let Source::Live(set) = &shared.source else {
        return;
    };
    let started = Instant::now();
    // Reload events seen, by library (pointer) so a new half's libraries start afresh.
    let mut seen_reloads: Vec<(usize, u64)> = Vec::new();
    let mut views: Vec<AgentView> = Vec::new();
    let mut seq = 0u64;
    let mut last_copies: u64 = u64::MAX;
    while !stop.load(Ordering::Relaxed) {
        let tick = Instant::now();
        let libraries = set.libraries();
        seen_reloads.retain(|(id, _)| {
            libraries
                .iter()
                .any(|(_, l)| Arc::as_ptr(l) as usize == *id)
        });
        for (team, library) in &libraries {
            let id = Arc::as_ptr(library) as usize;
            let pushed = library.events().pushed();
            match seen_reloads.iter_mut().find(|(i, _)| *i == id) {
                None => seen_reloads.push((id, pushed)),
                Some((_, seen)) if *seen != pushed => {
                    *seen = pushed;
                    if let Some(event) = library.events().newest() {
                        shared
                            .reloads
                            .push(note_of(team, started.elapsed().as_secs_f64(), &event));
                    }
                }
                Some(_) => {}
            }
        }
        let agents = set.agents();
        let copies: u64 = agents.iter().map(|a| a.copies()).sum();
        if shared.clients.count() > 0 && copies != last_copies {
            last_copies = copies;
            views.clear();
            views.extend(agents.iter().filter_map(|a| a.latest()));
            let monitor = set.monitor();
            let time = monitor
                .as_ref()
                .map(|m| m.time)
                .or_else(|| views.iter().map(|v| v.time).reduce(f64::max))
                .unwrap_or(0.0);
            seq += 1;
            let frame = Frame {
                seq,
                time,
                step: None,
                monitor,
                agents: &views,
                reloads: shared.reloads.list(),
            };
            match serde_json::to_string(&frame) {
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
