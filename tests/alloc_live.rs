//! No heap allocation in a steady-state agent-cycle (#13): a player's percepts recorded on the
//! real server (kick-off, walking, the ball in play) are replayed through a fresh player
//! built the same way, and a counting global allocator counts what its thread allocates over
//! 1,000 cycles after the first few hundred (the join, the beam, the first tree ticks).
//!
//! `LIBERO_ALLOC_SITES=N` prints the backtraces of the first N allocations counted.

use libero_agent::{build, AgentConfig, SkillSource, Team};
use libero_tests::{fast_server, t1, wait_sim_seconds};
use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, Mutex};

struct Counting;

static COUNTED: AtomicU64 = AtomicU64::new(0);
static SITES: Mutex<Vec<String>> = Mutex::new(Vec::new());
static SITES_WANTED: AtomicU64 = AtomicU64::new(0);

thread_local! {
    static ARMED: Cell<bool> = const { Cell::new(false) };
}

impl Counting {
    fn count(&self) {
        if !ARMED.with(Cell::get) {
            return;
        }
        COUNTED.fetch_add(1, Ordering::Relaxed);
        if SITES_WANTED.load(Ordering::Relaxed) > 0 {
            // Capturing allocates: disarmed meanwhile.
            ARMED.with(|a| a.set(false));
            SITES_WANTED.fetch_sub(1, Ordering::Relaxed);
            let trace = std::backtrace::Backtrace::force_capture().to_string();
            if let Ok(mut sites) = SITES.lock() {
                sites.push(trace);
            }
            ARMED.with(|a| a.set(true));
        }
    }
}

// SAFETY: every call is passed on to the system allocator unchanged; the counting touches a
// thread-local flag and atomics only (the backtrace path runs disarmed).
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        self.count();
        unsafe { System.alloc(layout) }
    }
    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        self.count();
        unsafe { System.alloc_zeroed(layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        self.count();
        unsafe { System.realloc(ptr, layout, new_size) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
}

#[global_allocator]
static ALLOCATOR: Counting = Counting;

const WARM_UP: usize = 300;
const COUNTED_CYCLES: usize = 1000;

#[test]
fn a_steady_state_cycle_allocates_nothing() {
    let mut server = fast_server();
    let model = t1();
    let dirs = libero_tests::copy_of_shipped_data("alloc");
    let source = build::load_library(&dirs, false).expect("shipped files load");
    let player =
        |unum| build::tree_player(&model, "Home", unum, &source, &SkillSource::Builtin).unwrap();
    // The kick-off taker (7) and its receiver (4) of the shipped kick-off, and a keeper.
    let mut home: Vec<_> = [1, 4, 7].into_iter().map(player).collect();
    home[2].record_frames(WARM_UP + COUNTED_CYCLES);
    let recorder = Arc::clone(home[2].stats());
    let stop = Arc::new(AtomicBool::new(false));
    let team = Team::start(
        &AgentConfig::new("127.0.0.1", server.agent_port),
        home,
        Arc::clone(&stop),
    );
    let (away, away_stop) = libero_tests::standing_team(server.agent_port, "Away", 1);
    wait_sim_seconds(&recorder, 0.5);
    server.monitor().kick_off_left().expect("kick-off");
    let needed = (WARM_UP + COUNTED_CYCLES) as u64;
    libero_tests::wait_until(std::time::Duration::from_secs(120), || {
        libero_agent::AgentStats::get(&recorder.percepts) >= needed
    })
    .expect("the recording fills");
    let frames = recorder.take_recording();
    stop.store(true, Ordering::Relaxed);
    away_stop.store(true, Ordering::Relaxed);
    team.join();
    away.join();
    assert_eq!(frames.len(), WARM_UP + COUNTED_CYCLES);

    let wanted = std::env::var("LIBERO_ALLOC_SITES")
        .ok()
        .and_then(|n| n.parse().ok())
        .unwrap_or(0);
    let mut replayed = player(7);
    let mut out = Vec::with_capacity(8192);
    let mut per_cycle = Vec::new();
    for (i, frame) in frames.iter().enumerate() {
        out.clear();
        if i == WARM_UP {
            SITES_WANTED.store(wanted, Ordering::Relaxed);
        }
        let before = COUNTED.load(Ordering::Relaxed);
        ARMED.with(|a| a.set(i >= WARM_UP));
        replayed.on_percept(frame, &mut out);
        ARMED.with(|a| a.set(false));
        let n = COUNTED.load(Ordering::Relaxed) - before;
        if n > 0 {
            per_cycle.push((i, n));
        }
        assert!(!out.is_empty(), "cycle {i} got no reply");
    }
    let total: u64 = per_cycle.iter().map(|(_, n)| n).sum();
    for site in SITES.lock().unwrap().iter() {
        eprintln!("--- an allocation:\n{site}");
    }
    let world = &replayed.world;
    eprintln!(
        "replayed {} cycles to {:.2} s ({:?}); allocations in the last {COUNTED_CYCLES}: {total} in {} cycles (first: {:?})",
        frames.len(),
        world.time,
        world.game.play_mode,
        per_cycle.len(),
        per_cycle.iter().take(8).collect::<Vec<_>>()
    );
    assert_eq!(
        total, 0,
        "{total} heap allocations in {COUNTED_CYCLES} steady-state cycles ({} cycles allocated; LIBERO_ALLOC_SITES=5 shows where)",
        per_cycle.len()
    );
}
