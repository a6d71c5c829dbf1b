//! Running one agent on a socket until shutdown, reconnecting when the server goes away.

use crate::connection::Connection;
use crate::player::Player;
use crate::stats::AgentStats;
use libero_protocol::{is_timeout, FrameError};
use std::io::Write;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

/// Where and how one agent connects.
#[derive(Debug, Clone)]
pub struct AgentConfig {
    pub host: String,
    pub port: u16,
    /// A server that sends nothing for this long is given up on and reconnected to.
    pub silence_timeout: Duration,
    /// Stop after this many failed connection attempts in a row (`None`: keep trying).
    pub max_connect_failures: Option<u32>,
    /// Pause between connecting and the first message. rcsssmj 0.2.1 crashes when an agent
    /// is activated before the simulation's first step, which is what happens when agents
    /// retrying in a loop reach a server the moment it starts listening.
    pub greeting_delay: Duration,
}

impl AgentConfig {
    pub fn new(host: &str, port: u16) -> Self {
        Self {
            host: host.to_string(),
            port,
            silence_timeout: Duration::from_secs(10),
            max_connect_failures: None,
            greeting_delay: Duration::from_millis(150),
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
}

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
    let mut out = Vec::with_capacity(4096);
    while !shutdown.load(Ordering::Relaxed) {
        let mut conn = match Connection::open(&config.host, config.port) {
            Ok(c) => c,
            Err(e) => {
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
        AgentStats::bump(&player.stats().connections);
        player.reset_connection();
        sleep_unless_shutdown(config.greeting_delay, shutdown);
        match player.greeting() {
            Ok(hello) => {
                if let Err(e) = conn.send(&hello) {
                    log::warn!("agent {unum}: greeting not sent: {e}");
                    continue;
                }
            }
            Err(e) => {
                log::error!("agent {unum}: cannot greet the server: {e}");
                return Ok(());
            }
        }
        let mut heard_at = Instant::now();
        let mut answered = 0u64;
        let reason = loop {
            if shutdown.load(Ordering::Relaxed) {
                return Ok(());
            }
            let (reader, writer) = conn.parts();
            match reader.read_frame() {
                Ok(frame) => {
                    heard_at = Instant::now();
                    out.clear();
                    player.on_percept(frame, &mut out);
                    if let Err(e) = writer.write_all(&out) {
                        break format!("send failed: {e}");
                    }
                    answered += 1;
                    backoff = BACKOFF_START;
                }
                Err(e) if is_timeout(&e) => {
                    if heard_at.elapsed() > config.silence_timeout {
                        break format!("server silent for {:.0?}", config.silence_timeout);
                    }
                }
                Err(FrameError::Closed) if answered == 0 => {
                    break "the server closed the connection before the first percept: team name, uniform number or robot refused? (rcssservermj takes two team names, unique numbers, 7 players a side with ssim rules)".to_string();
                }
                Err(e) => break e.to_string(),
            }
        };
        log::warn!("agent {unum}: connection lost ({reason}); reconnecting");
        sleep_unless_shutdown(backoff, shutdown);
        backoff = (backoff * 2).min(BACKOFF_MAX);
    }
    Ok(())
}

fn sleep_unless_shutdown(d: Duration, shutdown: &AtomicBool) {
    let end = Instant::now() + d;
    while Instant::now() < end && !shutdown.load(Ordering::Relaxed) {
        std::thread::sleep(Duration::from_millis(10).min(d));
    }
}
