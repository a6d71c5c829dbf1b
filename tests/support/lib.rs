//! Shared helpers for the live tests: a real server, teams of real agents, waiting on
//! simulated time.

use libero_agent::{build, AgentConfig, AgentStats, Team};
use libero_model::RobotModel;
use libero_server::{ServerOptions, ServerProcess};
use std::sync::atomic::AtomicBool;
use std::sync::Arc;
use std::time::{Duration, Instant};

/// Log to the test output (shown for failing tests).
pub fn init_logging() {
    let _ = env_logger::builder()
        .is_test(true)
        .filter_level(log::LevelFilter::Info)
        .try_init();
}

/// A real rcssservermj in fast mode (`--sync --no-realtime`) on free loopback ports.
///
/// Live tests of one binary take turns (the guard is held in the returned value): on two
/// cores, servers running side by side would make each other's timing checks meaningless.
pub fn fast_server() -> LiveServer {
    init_logging();
    let turn = LIVE_TURN
        .lock()
        .unwrap_or_else(|poisoned| poisoned.into_inner());
    let server = ServerProcess::start(ServerOptions::default()).expect("starting rcssservermj");
    LiveServer {
        server,
        _turn: turn,
    }
}

static LIVE_TURN: std::sync::Mutex<()> = std::sync::Mutex::new(());

/// This test's turn on the machine, for live tests that start their own server (skill trials):
/// held while the test runs. A get-up is a dynamic motion whose actions must arrive on their
/// cycle; with five trials side by side on two cores the agents miss cycles and it fails.
pub fn live_turn() -> std::sync::MutexGuard<'static, ()> {
    init_logging();
    LIVE_TURN
        .lock()
        .unwrap_or_else(|poisoned| poisoned.into_inner())
}

/// A server plus this test's turn on the machine.
pub struct LiveServer {
    pub server: ServerProcess,
    _turn: std::sync::MutexGuard<'static, ()>,
}

impl std::ops::Deref for LiveServer {
    type Target = ServerProcess;
    fn deref(&self) -> &ServerProcess {
        &self.server
    }
}

impl std::ops::DerefMut for LiveServer {
    fn deref_mut(&mut self) -> &mut ServerProcess {
        &mut self.server
    }
}

pub fn t1() -> Arc<RobotModel> {
    Arc::new(RobotModel::builtin("T1").unwrap())
}

/// A team of standing T1 players numbered 1…n, joined one by one.
pub fn standing_team(port: u16, team: &str, n: u32) -> (Team, Arc<AtomicBool>) {
    let model = t1();
    let players = (1..=n)
        .map(|u| build::standing_player(&model, team, u).unwrap())
        .collect();
    let shutdown = Arc::new(AtomicBool::new(false));
    let config = AgentConfig::new("127.0.0.1", port);
    (
        Team::start(&config, players, Arc::clone(&shutdown)),
        shutdown,
    )
}

/// Server time [s] an agent last saw.
pub fn sim_time(stats: &AgentStats) -> f64 {
    AgentStats::get(&stats.last_time_ms) as f64 / 1000.0
}

/// Wait until `seconds` of simulated time have passed for `stats`' agent (bounded by a
/// generous wall-clock limit so a stalled server fails the test instead of hanging it).
pub fn wait_sim_seconds(stats: &AgentStats, seconds: f64) {
    let start = sim_time(stats);
    let deadline = Instant::now() + Duration::from_secs_f64(60.0 + seconds * 4.0);
    while sim_time(stats) < start + seconds {
        assert!(
            Instant::now() < deadline,
            "simulated time stalled at {}",
            sim_time(stats)
        );
        std::thread::sleep(Duration::from_millis(10));
    }
}

/// Wait for a condition with a wall-clock limit; returns how long it took.
pub fn wait_until(limit: Duration, mut pred: impl FnMut() -> bool) -> Option<Duration> {
    let start = Instant::now();
    while start.elapsed() < limit {
        if pred() {
            return Some(start.elapsed());
        }
        std::thread::sleep(Duration::from_millis(5));
    }
    None
}

/// A private copy of the shipped `behaviors/` and `formations/` that a test (`name`) may edit:
/// live tests run side by side, each on its own copy. Returns the two folders.
pub fn copy_of_shipped_data(name: &str) -> Vec<std::path::PathBuf> {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    // Copies left by test runs that were killed go first.
    libero_server::scratch::remove_orphaned_dirs(&std::env::temp_dir(), "libero-data");
    let dest = std::env::temp_dir().join(format!("libero-data-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dest);
    let mut dirs = Vec::new();
    for sub in ["behaviors", "formations"] {
        let to = dest.join(sub);
        std::fs::create_dir_all(&to).unwrap();
        for entry in std::fs::read_dir(root.join(sub)).unwrap() {
            let from = entry.unwrap().path();
            // Files only: a subfolder with its own team file (formations/simspark/) is another
            // team's set.
            if from.is_file() {
                std::fs::copy(&from, to.join(from.file_name().unwrap())).unwrap();
            }
        }
        dirs.push(to);
    }
    dirs
}
