//! Counters an agent keeps about its own connection, readable from other threads.

use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Mutex;

/// Live counters of one agent. All fields only grow.
#[derive(Debug, Default)]
pub struct AgentStats {
    /// Percepts received.
    pub percepts: AtomicU64,
    /// Replies sent (must equal `percepts` in every healthy cycle).
    pub replies: AtomicU64,
    /// Server cycles that passed without a percept reaching us (gaps in server time).
    pub missed_cycles: AtomicU64,
    /// Percepts that could not be read at all.
    pub unreadable: AtomicU64,
    /// Successful connections (the first one included).
    pub connections: AtomicU64,
    /// Server time of the last percept, in milliseconds.
    pub last_time_ms: AtomicU64,
    /// The server's ground-truth torso position in the last percept (evaluation only).
    pub truth_position: Mutex<Option<[f64; 3]>>,
    /// The agent's own estimate of its ground position in the same percept (global frame), so
    /// an evaluation compares the two cycle by cycle.
    pub self_estimate: Mutex<Option<[f64; 2]>>,
    /// The side the server gave the team: 0 not known yet, 1 left, 2 right.
    pub side: std::sync::atomic::AtomicU8,
    /// The decision trace of the last cycle, when the player shares it.
    pub trace: Mutex<Option<String>>,
    /// Whether the last cycle played a whole-body motion (get-up or save) that nothing
    /// interrupts: a harness that places robots waits for it to end.
    pub in_motion: std::sync::atomic::AtomicBool,
    /// Where the cycles' time went, stage by stage (wall time inside `Player::on_percept`).
    pub stages: StageTimes,
    /// Whether the agent has ended for good (stopped, gave up, or its cycle panicked).
    pub ended: std::sync::atomic::AtomicBool,
    /// Whether the agent's cycle panicked (it then left the match; its teammates play on).
    pub panicked: std::sync::atomic::AtomicBool,
    /// The percept payloads recorded since the player was asked to (`Player::record_frames`).
    pub recorded: Mutex<Recording>,
}

/// Percept payloads end to end in room reserved up front.
#[derive(Debug, Default)]
pub struct Recording {
    bytes: Vec<u8>,
    ends: Vec<usize>,
}

/// Room reserved per frame to record: T1 percepts are 1-8 kB, most near 3 kB.
const RECORDED_BYTES_PER_FRAME: usize = 8 * 1024;

impl Recording {
    pub(crate) fn reserve(&mut self, frames: usize) {
        self.ends.reserve(frames);
        self.bytes.reserve(frames * RECORDED_BYTES_PER_FRAME);
    }

    /// Keep `payload` if it fits the room reserved (`false`: it does not).
    pub(crate) fn push(&mut self, payload: &[u8]) -> bool {
        let fits = self.ends.len() < self.ends.capacity()
            && self.bytes.len() + payload.len() <= self.bytes.capacity();
        if fits {
            self.bytes.extend_from_slice(payload);
            self.ends.push(self.bytes.len());
        }
        fits
    }

    /// The payloads kept so far, one `Vec` each; the recording then starts over.
    fn take(&mut self) -> Vec<Vec<u8>> {
        let mut start = 0;
        let frames = self
            .ends
            .iter()
            .map(|&end| {
                let frame = self.bytes[start..end].to_vec();
                start = end;
                frame
            })
            .collect();
        self.bytes.clear();
        self.ends.clear();
        frames
    }
}

/// Time spent in each stage of the per-cycle pipe [ns], summed over the cycles.
#[derive(Debug, Default)]
pub struct StageTimes {
    /// Bytes → typed percept.
    pub parse_ns: AtomicU64,
    /// Percept → world model.
    pub world_ns: AtomicU64,
    /// World → intent (the tree tick) and the team message.
    pub decide_ns: AtomicU64,
    /// Intent → joint targets.
    pub skills_ns: AtomicU64,
    /// Joint targets → reply bytes.
    pub write_ns: AtomicU64,
}

impl StageTimes {
    /// (stage name, total ns) in pipe order.
    pub fn totals(&self) -> [(&'static str, u64); 5] {
        [
            ("parse", AgentStats::get(&self.parse_ns)),
            ("world", AgentStats::get(&self.world_ns)),
            ("decide", AgentStats::get(&self.decide_ns)),
            ("skills", AgentStats::get(&self.skills_ns)),
            ("write", AgentStats::get(&self.write_ns)),
        ]
    }
}

impl AgentStats {
    /// See [`AgentStats::in_motion`].
    pub fn is_in_motion(&self) -> bool {
        self.in_motion.load(Ordering::Relaxed)
    }

    pub fn get(counter: &AtomicU64) -> u64 {
        counter.load(Ordering::Relaxed)
    }

    /// The last ground-truth torso position the server sent.
    pub fn truth_position(&self) -> Option<[f64; 3]> {
        self.truth_position.lock().ok().and_then(|t| *t)
    }

    /// The team's side once the server has told it (`true` = left).
    pub fn plays_left(&self) -> Option<bool> {
        match self.side.load(Ordering::Relaxed) {
            1 => Some(true),
            2 => Some(false),
            _ => None,
        }
    }

    /// The agent's own position estimate in the last percept.
    pub fn self_estimate(&self) -> Option<[f64; 2]> {
        self.self_estimate.lock().ok().and_then(|t| *t)
    }

    /// The last shared decision trace.
    pub fn trace(&self) -> Option<String> {
        self.trace.lock().ok().and_then(|t| t.clone())
    }

    pub(crate) fn bump(counter: &AtomicU64) {
        counter.fetch_add(1, Ordering::Relaxed);
    }

    pub(crate) fn set_flag(flag: &std::sync::atomic::AtomicBool, value: bool) {
        flag.store(value, Ordering::Relaxed);
    }

    /// See [`AgentStats::ended`].
    pub fn has_ended(&self) -> bool {
        self.ended.load(Ordering::Relaxed)
    }

    /// See [`AgentStats::panicked`].
    pub fn has_panicked(&self) -> bool {
        self.panicked.load(Ordering::Relaxed)
    }

    pub(crate) fn add(counter: &AtomicU64, amount: u64) {
        counter.fetch_add(amount, Ordering::Relaxed);
    }

    /// The payloads recorded so far (taken: the recording goes on into an empty list).
    pub fn take_recording(&self) -> Vec<Vec<u8>> {
        self.recorded
            .lock()
            .map(|mut r| r.take())
            .unwrap_or_default()
    }
}
