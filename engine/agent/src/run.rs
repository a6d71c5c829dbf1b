//! Running one agent on a socket until shutdown, reconnecting when the server goes away.

use crate::connection::Connection;
use crate::player::Player;
use crate::stats::AgentStats;
use libero_protocol::{is_timeout, FrameError};
use std::io::Write;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

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

/// Lets the agents of a team join the server one at a time.
#[derive(Debug, Default)]
pub struct JoinGate(Mutex<()>);

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

/// Longest wait between refused joins.
const REFUSAL_BACKOFF_MAX: Duration = Duration::from_secs(30);
/// A silent server is reported once it has been quiet this long.
const SILENCE_REPORTED_AFTER: Duration = Duration::from_secs(10);

const BACKOFF_START: Duration = Duration::from_millis(50);
const BACKOFF_MAX: Duration = Duration::from_millis(200);

/// Run `player` until `shutdown` is set. Every percept is answered at once with exactly one
/// frame. Lost connections are retried with a short backoff, so agents are back within a
/// fraction of a second of the server.
pub fn run_agent(
    config: &AgentConfig,
    player: &mut Player,
    shutdown: &AtomicBool,
) -> Result<(), AgentError> {
    let unum = player.world.game.unum;
    let mut backoff = BACKOFF_START;
    let mut failures = 0u32;
    let mut refusals = 0u32;
    let mut out = Vec::with_capacity(4096);
    while !shutdown.load(Ordering::Relaxed) {
        // Held from connecting to the first percept (or the end of the attempt).
        let mut gate = config
            .join_gate
            .as_ref()
            .map(|g| g.0.lock().unwrap_or_else(|poisoned| poisoned.into_inner()));
        // The greeting is ready before the connection exists: a sync-mode SimSpark waits for
        // a connection without a body after 5 of its cycles (a few ms in fast mode), and the
        // `scene` that would give it one is then never read.
        player.reset_connection();
        let hello = match player.greeting() {
            Ok(hello) => hello,
            Err(e) => {
                log::error!("agent {unum}: cannot greet the server: {e}");
                return Ok(());
            }
        };
        let mut conn = match Connection::open(&config.host, config.port) {
            Ok(c) => c,
            Err(e) => {
                drop(gate);
                failures += 1;
                if config
                    .max_connect_failures
                    .is_some_and(|max| failures >= max)
                {
                    return Err(AgentError::Unreachable {
                        host: config.host.clone(),
                        port: config.port,
                        attempts: failures,
                        last: e,
                    });
                }
                if failures == 1 {
                    log::warn!(
                        "agent {unum}: cannot connect to {}:{} ({e}); retrying",
                        config.host,
                        config.port
                    );
                }
                sleep_unless_shutdown(backoff, shutdown);
                backoff = (backoff * 2).min(BACKOFF_MAX);
                continue;
            }
        };
        failures = 0;
        if player.model.server == libero_model::ServerKind::RcssMj {
            sleep_unless_shutdown(config.greeting_delay, shutdown);
        }
        if let Err(e) = conn.send(&hello) {
            log::warn!("agent {unum}: greeting not sent: {e}");
            continue;
        }
        AgentStats::bump(&player.stats().connections);
        let mut heard_at = Instant::now();
        let mut answered = 0u64;
        let mut silence_reported = false;
        let reason = loop {
            if shutdown.load(Ordering::Relaxed) {
                return Ok(());
            }
            let (reader, writer) = conn.parts();
            match reader.read_frame() {
                Ok(frame) => {
                    heard_at = Instant::now();
                    if silence_reported {
                        log::info!("agent {unum}: the server speaks again");
                        silence_reported = false;
                    }
                    out.clear();
                    player.on_percept(frame, &mut out);
                    if let Err(e) = writer.write_all(&out) {
                        break format!("send failed: {e}");
                    }
                    answered += 1;
                    // In: the next agent may join.
                    gate = None;
                    backoff = BACKOFF_START;
                    refusals = 0;
                }
                Err(e) if is_timeout(&e) => {
                    let silent = heard_at.elapsed();
                    let limit = if answered == 0 {
                        config.first_percept_timeout
                    } else {
                        config.silence_timeout
                    };
                    if silent > limit {
                        break format!("server silent for {limit:.0?}");
                    }
                    if answered > 0 && !silence_reported && silent > SILENCE_REPORTED_AFTER {
                        log::warn!(
                            "agent {unum}: server silent for {SILENCE_REPORTED_AFTER:.0?}; keeping the connection open"
                        );
                        silence_reported = true;
                    }
                }
                Err(FrameError::Closed) if answered == 0 => {
                    gate = None;
                    refusals += 1;
                    if refusals >= config.max_refusals {
                        return Err(AgentError::Refused {
                            host: config.host.clone(),
                            port: config.port,
                            attempts: refusals,
                        });
                    }
                    let wait = config
                        .refusal_backoff
                        .saturating_mul(1 << (refusals - 1).min(16))
                        .min(REFUSAL_BACKOFF_MAX);
                    log::warn!(
                        "agent {unum}: the server closed the connection before the first percept ({refusals} of {} refusals); trying again in {wait:.0?}",
                        config.max_refusals
                    );
                    sleep_unless_shutdown(wait, shutdown);
                    break String::new();
                }
                Err(e) => break e.to_string(),
            }
        };
        drop(gate);
        if !reason.is_empty() {
            log::warn!("agent {unum}: connection lost ({reason}); reconnecting");
            sleep_unless_shutdown(backoff, shutdown);
            backoff = (backoff * 2).min(BACKOFF_MAX);
        }
    }
    Ok(())
}

fn sleep_unless_shutdown(d: Duration, shutdown: &AtomicBool) {
    let end = Instant::now() + d;
    while Instant::now() < end && !shutdown.load(Ordering::Relaxed) {
        std::thread::sleep(Duration::from_millis(10).min(d));
    }
}
