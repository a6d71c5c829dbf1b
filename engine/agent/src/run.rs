//! How an agent connects, and running one on this thread until shutdown.

use crate::player::Player;
use crate::seats::{run_seats, SeatEnd, WakeStats};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::Duration;

/// Where and how one agent connects.
#[derive(Debug, Clone)]
pub struct AgentConfig {
    pub host: String,
    pub port: u16,
    /// A connection that has carried percepts and then stays silent this long is given up on
    /// and reconnected to. Long: a stalled server keeps its sockets open, and riding the
    /// stall out on the open connection keeps the player in the match (a server that died
    /// closes them, which is noticed at once).
    pub silence_timeout: Duration,
    /// After connecting, the first percept may take this long: rcssservermj admits agents
    /// one at a time, 2-4 s each, so the last of seven joining together waits ~25 s.
    pub first_percept_timeout: Duration,
    /// Stop after this many failed connection attempts in a row (`None`: keep trying).
    pub max_connect_failures: Option<u32>,
    /// Stop after the server closed this many connections in a row before the first percept
    /// (it refuses the team, the number or the robot). Each refused join stalls the match the
    /// server runs, so the retries back off from `refusal_backoff` doubling up to 30 s.
    pub max_refusals: u32,
    pub refusal_backoff: Duration,
    /// Pause between connecting and the first message (rcssservermj only). rcsssmj 0.2.1
    /// crashes when an agent is activated before the simulation's first step, which is what
    /// happens when agents retrying in a loop reach a server the moment it starts listening.
    /// SimSpark gets its `scene` at once: a connection without a body stalls a sync-mode
    /// SimSpark for every agent after 5 cycles (simspark.md §1.4).
    pub greeting_delay: Duration,
    /// Agents sharing a gate join one at a time (from connecting to the first percept), also
    /// when they reconnect together after a stall: simultaneous joins stall the server.
    pub join_gate: Option<Arc<JoinGate>>,
}

/// Lets the agents of a team join the server one at a time: held by one agent from
/// connecting to its first percept.
#[derive(Debug, Default)]
pub struct JoinGate(AtomicBool);

impl JoinGate {
    /// Take the gate if nobody holds it.
    pub fn try_enter(&self) -> bool {
        self.0
            .compare_exchange(false, true, Ordering::Acquire, Ordering::Relaxed)
            .is_ok()
    }

    /// Give the gate back (only its holder does).
    pub fn leave(&self) {
        self.0.store(false, Ordering::Release);
    }
}

impl AgentConfig {
    pub fn new(host: &str, port: u16) -> Self {
        Self {
            host: host.to_string(),
            port,
            silence_timeout: Duration::from_secs(300),
            first_percept_timeout: Duration::from_secs(60),
            max_connect_failures: None,
            max_refusals: 3,
            refusal_backoff: Duration::from_secs(1),
            greeting_delay: Duration::from_millis(150),
            join_gate: None,
        }
    }
}

/// Why an agent stopped other than by shutdown.
#[derive(Debug, thiserror::Error)]
pub enum AgentError {
    #[error("could not reach the server at {host}:{port} after {attempts} attempts: {last}\nhint: is the server running? `libero server start` runs one")]
    Unreachable {
        host: String,
        port: u16,
        attempts: u32,
        last: std::io::Error,
    },
    #[error("the server at {host}:{port} refused this agent {attempts} times in a row (it closed the connection before the first percept): team name, uniform number or robot not accepted? (rcssservermj takes two team names, unique numbers, 7 players a side with ssim rules)")]
    Refused {
        host: String,
        port: u16,
        attempts: u32,
    },
}

/// Run `player` until `shutdown` is set (see [`run_seats`]): a team of one on this thread.
/// A panic in its cycle is raised again here.
pub fn run_agent(
    config: &AgentConfig,
    player: &mut Player,
    shutdown: &AtomicBool,
) -> Result<(), AgentError> {
    let wakes = WakeStats::default();
    let ends = run_seats(config, std::slice::from_mut(player), shutdown, &wakes);
    match ends.into_iter().next() {
        Some(SeatEnd::Failed(e)) => Err(e),
        Some(SeatEnd::Panicked(payload)) => std::panic::resume_unwind(payload),
        Some(SeatEnd::Stopped) | None => Ok(()),
    }
}
