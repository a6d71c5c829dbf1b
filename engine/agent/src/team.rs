//! Several agents in one process, answered from one thread (see [`crate::seats`]).

use crate::player::Player;
use crate::run::{AgentConfig, JoinGate};
use crate::seats::{run_seats, SeatEnd, WakeStats, MAX_SEATS};
use crate::stats::AgentStats;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

/// A running team.
pub struct Team {
    pub stats: Vec<(u32, Arc<AgentStats>)>,
    /// One thread per [`MAX_SEATS`] agents, with the uniform numbers it answers.
    threads: Vec<(Vec<u32>, JoinHandle<()>)>,
    wakes: Vec<Arc<WakeStats>>,
    shutdown: Arc<AtomicBool>,
}

impl Team {
    /// Start the players' thread and wait until each has received its first percept, in
    /// order: they join one at a time (joins recompile the server's model; simultaneous
    /// joins stall servers). The agents share a join gate, so after a stall that drops them
    /// all they rejoin one at a time too.
    pub fn start(config: &AgentConfig, players: Vec<Player>, shutdown: Arc<AtomicBool>) -> Team {
        let mut config = config.clone();
        if config.join_gate.is_none() {
            config.join_gate = Some(Arc::new(JoinGate::default()));
        }
        let mut team = Team {
            stats: players
                .iter()
                .map(|p| (p.world.game.unum, Arc::clone(p.stats())))
                .collect(),
            threads: Vec::new(),
            wakes: Vec::new(),
            shutdown,
        };
        let mut players = players.into_iter().peekable();
        while players.peek().is_some() {
            let mut seated: Vec<Player> = players.by_ref().take(MAX_SEATS).collect();
            let unums: Vec<u32> = seated.iter().map(|p| p.world.game.unum).collect();
            let name = match (unums.first(), unums.last()) {
                (Some(a), Some(b)) if a != b => format!("agent-{a}-{b}"),
                (Some(a), _) => format!("agent-{a}"),
                _ => "agent".into(),
            };
            let (config, stop) = (config.clone(), Arc::clone(&team.shutdown));
            let wakes = Arc::new(WakeStats::default());
            team.wakes.push(Arc::clone(&wakes));
            let handle = std::thread::Builder::new()
                .name(name)
                .spawn(move || {
                    let ends = run_seats(&config, &mut seated, &stop, &wakes);
                    for (player, end) in seated.iter().zip(ends) {
                        if let SeatEnd::Failed(e) = end {
                            log::error!("agent {}: {e}", player.world.game.unum);
                        }
                    }
                })
                .expect("spawning the agents' thread");
            team.threads.push((unums, handle));
        }
        for (_, stats) in &team.stats {
            let deadline = Instant::now() + Duration::from_secs(30);
            while AgentStats::get(&stats.percepts) == 0
                && !stats.has_ended()
                && Instant::now() < deadline
                && !team.shutdown.load(Ordering::Relaxed)
            {
                std::thread::sleep(Duration::from_millis(5));
            }
        }
        team
    }

    /// The team's threads' wake-ups to answer and the percepts answered then, so far.
    pub fn wakeups(&self) -> (u64, u64) {
        self.wakes.iter().fold((0, 0), |(w, p), s| {
            (
                w + AgentStats::get(&s.wakeups),
                p + AgentStats::get(&s.percepts),
            )
        })
    }

    /// Ask every agent to stop and wait for them.
    pub fn stop(self) {
        self.shutdown.store(true, Ordering::Relaxed);
        self.join();
    }

    /// Wait for the agents to end (after the shutdown flag is set elsewhere).
    pub fn join(mut self) {
        for (_, t) in self.threads.drain(..) {
            let _ = t.join();
        }
    }

    /// Whether each agent has ended (uniform number, ended), without waiting: in a running
    /// match an agent ends only on a panic or an error it could not recover from.
    pub fn finished(&self) -> Vec<(u32, bool)> {
        self.stats
            .iter()
            .map(|(unum, stats)| {
                let thread_gone = self
                    .threads
                    .iter()
                    .any(|(unums, t)| unums.contains(unum) && t.is_finished());
                (*unum, stats.has_ended() || thread_gone)
            })
            .collect()
    }

    /// Ask every agent to stop, wait for them, and name the ones whose cycle panicked.
    pub fn stop_reporting_panics(mut self) -> Vec<u32> {
        self.shutdown.store(true, Ordering::Relaxed);
        let mut panicked: Vec<u32> = Vec::new();
        for (unums, t) in self.threads.drain(..) {
            if t.join().is_err() {
                // The thread itself died: every agent it answered went with it.
                panicked.extend(unums);
            }
        }
        for (unum, stats) in &self.stats {
            if stats.has_panicked() && !panicked.contains(unum) {
                panicked.push(*unum);
            }
        }
        panicked.sort_unstable();
        panicked
    }
}
