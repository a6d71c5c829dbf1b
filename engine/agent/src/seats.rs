//! Several agents answered from one thread.
//!
//! The server sends every agent its percept in one burst after its step, then waits for the
//! replies. A thread per agent meant seven wake-ups per cycle, each on caches the server's step
//! had just flushed; one thread that answers whichever sockets are ready wakes about once per
//! burst and runs the same code seven times while it is warm.
//!
//! Each agent sits in a [`Seat`] that walks the connection's life on its own clock:
//! waiting to (re)connect, greeting, playing; a seat that fails for good (unreachable,
//! refused, a panic in its cycle) ends alone while the others play on.

use crate::player::Player;
use crate::run::{AgentConfig, AgentError, JoinGate};
use crate::stats::AgentStats;
use libero_protocol::{is_timeout, FrameError, FrameReader};
use rustix::event::{PollFd, PollFlags, Timespec};
use std::any::Any;
use std::io::{self, Write};
use std::net::TcpStream;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

/// The most agents one thread answers ([`crate::Team`] starts another thread past it).
pub const MAX_SEATS: usize = 24;

/// The longest one wait for the sockets lasts: shutdown and silence are checked this often.
const POLL: Duration = Duration::from_millis(100);
/// A reply that cannot be written whole within this long means the connection is lost.
const WRITE_STALL_LIMIT: Duration = Duration::from_secs(2);
/// Longest wait between refused joins.
const REFUSAL_BACKOFF_MAX: Duration = Duration::from_secs(30);
/// A silent server is reported once it has been quiet this long.
const SILENCE_REPORTED_AFTER: Duration = Duration::from_secs(10);
/// SimSpark builds a robot in the cycle after its `scene` and sends its first percept in the
/// next: a join still waiting after this long has failed, and the sync-mode server waits for it
/// ("a hung agent stalls everyone", simspark.md §1.4) until it disconnects.
const SIMSPARK_FIRST_PERCEPT: Duration = Duration::from_secs(5);
/// How often a seat waiting for another's join looks at the gate again.
const GATE_RETRY: Duration = Duration::from_millis(5);
const BACKOFF_START: Duration = Duration::from_millis(50);
const BACKOFF_MAX: Duration = Duration::from_millis(200);

/// What one thread's waiting cost: how often it woke to answer, and how many percepts it
/// answered then (`libero bench cycle` prints their ratio).
#[derive(Debug, Default)]
pub struct WakeStats {
    pub wakeups: std::sync::atomic::AtomicU64,
    pub percepts: std::sync::atomic::AtomicU64,
}

/// How a seat's agent stopped.
pub enum SeatEnd {
    /// Asked to (shutdown), or it could not even greet.
    Stopped,
    /// Gave up: unreachable or refused.
    Failed(AgentError),
    /// Its cycle panicked; the payload, for a caller that re-raises it.
    Panicked(Box<dyn Any + Send>),
}

/// One agent's connection, non-blocking: frames in, replies out.
struct Link {
    reader: FrameReader<TcpStream>,
    writer: TcpStream,
}

impl Link {
    fn open(host: &str, port: u16) -> io::Result<Link> {
        let stream = crate::connection::connect(host, port)?;
        stream.set_nonblocking(true)?;
        let writer = stream.try_clone()?;
        Ok(Link {
            reader: FrameReader::new(stream),
            writer,
        })
    }
}

/// Write all of `bytes` to a non-blocking socket, waiting for room when it is full (a
/// server that stopped reading): an error once that lasts [`WRITE_STALL_LIMIT`].
fn write_whole(writer: &mut TcpStream, mut bytes: &[u8]) -> io::Result<()> {
    let give_up = Instant::now() + WRITE_STALL_LIMIT;
    while !bytes.is_empty() {
        match writer.write(bytes) {
            Ok(0) => return Err(io::ErrorKind::WriteZero.into()),
            Ok(n) => bytes = &bytes[n..],
            Err(e) if e.kind() == io::ErrorKind::Interrupted => {}
            Err(e) if e.kind() == io::ErrorKind::WouldBlock => {
                let now = Instant::now();
                if now >= give_up {
                    return Err(io::ErrorKind::TimedOut.into());
                }
                let mut fds = [PollFd::new(&*writer, PollFlags::OUT)];
                let _ = rustix::event::poll(&mut fds, Some(&timespec(give_up - now)));
            }
            Err(e) => return Err(e),
        }
    }
    Ok(())
}

fn timespec(d: Duration) -> Timespec {
    Timespec {
        tv_sec: d.as_secs() as _,
        tv_nsec: d.subsec_nanos() as _,
    }
}

enum Phase {
    /// Not connected; (re)connect once this time has come and the join gate is free.
    Waiting {
        until: Instant,
    },
    /// Connected, holding the gate, the greeting due at `at` (rcssservermj's pause).
    Greeting {
        link: Link,
        at: Instant,
    },
    /// Greeted: answering every percept.
    Playing {
        link: Link,
    },
    Ended(SeatEnd),
}

/// One agent's place at the table.
struct Seat<'p> {
    player: &'p mut Player,
    phase: Phase,
    /// Whether this seat holds the join gate (from connecting to the first percept).
    holds_gate: bool,
    hello: Vec<u8>,
    backoff: Duration,
    failures: u32,
    refusals: u32,
    heard_at: Instant,
    answered: u64,
    silence_reported: bool,
}

impl<'p> Seat<'p> {
    fn new(player: &'p mut Player, now: Instant) -> Self {
        Seat {
            player,
            phase: Phase::Waiting { until: now },
            holds_gate: false,
            hello: Vec::new(),
            backoff: BACKOFF_START,
            failures: 0,
            refusals: 0,
            heard_at: now,
            answered: 0,
            silence_reported: false,
        }
    }

    fn unum(&self) -> u32 {
        self.player.world.game.unum
    }

    fn release_gate(&mut self, gate: &JoinGate) {
        leave_gate(&mut self.holds_gate, gate);
    }

    fn has_ended(&self) -> bool {
        matches!(self.phase, Phase::Ended(_))
    }

    fn finish(&mut self, end: SeatEnd, gate: &JoinGate) {
        self.release_gate(gate);
        self.phase = Phase::Ended(end);
        AgentStats::set_flag(&self.player.stats().ended, true);
    }

    /// Back to waiting after the backoff, which grows with each try.
    fn retry_after_backoff(&mut self, now: Instant) {
        self.phase = Phase::Waiting {
            until: now + self.backoff,
        };
        self.backoff = (self.backoff * 2).min(BACKOFF_MAX);
    }

    /// Back to waiting after a lost connection.
    fn lose(&mut self, reason: &str, now: Instant, gate: &JoinGate) {
        self.release_gate(gate);
        log::warn!(
            "agent {}: connection lost ({reason}); reconnecting",
            self.unum()
        );
        self.retry_after_backoff(now);
    }

    /// What time alone changes: connecting, greeting, giving up on a silent server.
    fn on_clock(&mut self, now: Instant, config: &AgentConfig, gate: &JoinGate) {
        match &mut self.phase {
            Phase::Waiting { until } if now >= *until => self.connect(now, config, gate),
            Phase::Greeting { at, .. } if now >= *at => {
                let placeholder = Phase::Waiting { until: now };
                let Phase::Greeting { link, .. } = std::mem::replace(&mut self.phase, placeholder)
                else {
                    unreachable!("matched above")
                };
                self.greet(link, now, gate);
            }
            Phase::Playing { .. } => {
                let silent = now.saturating_duration_since(self.heard_at);
                let limit = if self.answered > 0 {
                    config.silence_timeout
                } else if self.player.model.server == libero_model::ServerKind::SimSpark {
                    config.first_percept_timeout.min(SIMSPARK_FIRST_PERCEPT)
                } else {
                    config.first_percept_timeout
                };
                if silent > limit {
                    self.lose(&format!("server silent for {limit:.0?}"), now, gate);
                } else if self.answered > 0
                    && !self.silence_reported
                    && silent > SILENCE_REPORTED_AFTER
                {
                    log::warn!(
                        "agent {}: server silent for {SILENCE_REPORTED_AFTER:.0?}; keeping the connection open",
                        self.unum()
                    );
                    self.silence_reported = true;
                }
            }
            _ => {}
        }
    }

    fn connect(&mut self, now: Instant, config: &AgentConfig, gate: &JoinGate) {
        if !self.holds_gate {
            if !gate.try_enter() {
                // Another agent is joining: look again shortly (not at once, which would spin).
                self.phase = Phase::Waiting {
                    until: now + GATE_RETRY,
                };
                return;
            }
            self.holds_gate = true;
        }
        let unum = self.unum();
        // The greeting is ready before the connection exists: a sync-mode SimSpark waits for
        // a connection without a body after 5 of its cycles (a few ms in fast mode), and the
        // `scene` that would give it one is then never read.
        self.player.reset_connection();
        self.hello = match self.player.greeting() {
            Ok(hello) => hello,
            Err(e) => {
                log::error!("agent {unum}: cannot greet the server: {e}");
                return self.finish(SeatEnd::Stopped, gate);
            }
        };
        match Link::open(&config.host, config.port) {
            Ok(link) => {
                self.failures = 0;
                if self.player.model.server == libero_model::ServerKind::RcssMj {
                    self.phase = Phase::Greeting {
                        link,
                        at: now + config.greeting_delay,
                    };
                } else {
                    self.greet(link, now, gate);
                }
            }
            Err(e) => {
                self.release_gate(gate);
                self.failures += 1;
                if config
                    .max_connect_failures
                    .is_some_and(|max| self.failures >= max)
                {
                    let failed = AgentError::Unreachable {
                        host: config.host.clone(),
                        port: config.port,
                        attempts: self.failures,
                        last: e,
                    };
                    return self.finish(SeatEnd::Failed(failed), gate);
                }
                if self.failures == 1 {
                    log::warn!(
                        "agent {unum}: cannot connect to {}:{} ({e}); retrying",
                        config.host,
                        config.port
                    );
                }
                self.retry_after_backoff(now);
            }
        }
    }

    fn greet(&mut self, mut link: Link, now: Instant, gate: &JoinGate) {
        if let Err(e) = write_whole(&mut link.writer, &self.hello) {
            log::warn!("agent {}: greeting not sent: {e}", self.unum());
            self.release_gate(gate);
            self.phase = Phase::Waiting { until: now };
            return;
        }
        AgentStats::bump(&self.player.stats().connections);
        self.heard_at = now;
        self.answered = 0;
        self.silence_reported = false;
        self.phase = Phase::Playing { link };
    }

    /// The socket has something: answer every whole frame that arrived; how many were.
    fn on_readable(&mut self, config: &AgentConfig, gate: &JoinGate, out: &mut Vec<u8>) -> u64 {
        let Phase::Playing { link } = &mut self.phase else {
            return 0;
        };
        let answered_before = self.answered;
        let now = Instant::now();
        let mut lost = None;
        let mut refused = false;
        let mut read_more = true;
        loop {
            // One read when the readiness came; then only frames already buffered.
            let frame = if read_more {
                read_more = false;
                link.reader.read_frame()
            } else {
                match link.reader.buffered_frame() {
                    Some(frame) => frame,
                    None => break,
                }
            };
            match frame {
                Ok(frame) => {
                    self.heard_at = now;
                    if self.silence_reported {
                        let unum = self.player.world.game.unum;
                        log::info!("agent {unum}: the server speaks again");
                        self.silence_reported = false;
                    }
                    out.clear();
                    let player = &mut *self.player;
                    if let Err(payload) =
                        catch_unwind(AssertUnwindSafe(|| player.on_percept(frame, out)))
                    {
                        let unum = self.player.world.game.unum;
                        log::error!("agent {unum}: its cycle panicked; the agent leaves");
                        AgentStats::set_flag(&self.player.stats().panicked, true);
                        self.finish(SeatEnd::Panicked(payload), gate);
                        return self.answered - answered_before;
                    }
                    if let Err(e) = write_whole(&mut link.writer, out) {
                        lost = Some(format!("send failed: {e}"));
                        break;
                    }
                    self.answered += 1;
                    // In: the next agent may join.
                    leave_gate(&mut self.holds_gate, gate);
                    self.backoff = BACKOFF_START;
                    self.refusals = 0;
                }
                Err(e) if is_timeout(&e) => break,
                Err(FrameError::Closed) if self.answered == 0 => {
                    refused = true;
                    break;
                }
                Err(e) => {
                    lost = Some(e.to_string());
                    break;
                }
            }
        }
        if refused {
            self.on_refused(config, now, gate);
        } else if let Some(reason) = lost {
            self.lose(&reason, now, gate);
        }
        self.answered - answered_before
    }

    /// The server closed the connection before the first percept.
    fn on_refused(&mut self, config: &AgentConfig, now: Instant, gate: &JoinGate) {
        self.release_gate(gate);
        self.refusals += 1;
        if self.refusals >= config.max_refusals {
            let refused = AgentError::Refused {
                host: config.host.clone(),
                port: config.port,
                attempts: self.refusals,
            };
            return self.finish(SeatEnd::Failed(refused), gate);
        }
        let wait = config
            .refusal_backoff
            .saturating_mul(1 << (self.refusals - 1).min(16))
            .min(REFUSAL_BACKOFF_MAX);
        log::warn!(
            "agent {}: the server closed the connection before the first percept ({} of {} refusals); trying again in {wait:.0?}",
            self.unum(),
            self.refusals,
            config.max_refusals
        );
        self.phase = Phase::Waiting { until: now + wait };
    }

    /// When the clock next matters to this seat.
    fn next_deadline(&self) -> Option<Instant> {
        match &self.phase {
            Phase::Waiting { until } => Some(*until),
            Phase::Greeting { at, .. } => Some(*at),
            _ => None,
        }
    }
}

/// Give the join gate back if `holds` says this seat has it.
fn leave_gate(holds: &mut bool, gate: &JoinGate) {
    if std::mem::take(holds) {
        gate.leave();
    }
}

/// Wait up to `wait` for the playing seats' sockets; mark the ones with something to read.
/// (how many have, how many were watched).
fn poll_ready(seats: &[Seat], wait: Duration, ready: &mut [bool; MAX_SEATS]) -> (usize, usize) {
    let mut fds = arrayvec::ArrayVec::<PollFd, MAX_SEATS>::new();
    let mut owner = [0usize; MAX_SEATS];
    for (i, seat) in seats.iter().enumerate() {
        if let Phase::Playing { link } = &seat.phase {
            owner[fds.len()] = i;
            fds.push(PollFd::new(link.reader.get_ref(), PollFlags::IN));
        }
    }
    ready.fill(false);
    match rustix::event::poll(&mut fds, Some(&timespec(wait))) {
        Ok(_) => {
            for (fd, &i) in fds.iter().zip(&owner) {
                ready[i] = !fd.revents().is_empty();
            }
        }
        Err(e) if e == rustix::io::Errno::INTR => {}
        Err(e) => {
            log::error!("waiting for the server: {e}");
            std::thread::sleep(POLL);
        }
    }
    (ready.iter().filter(|r| **r).count(), fds.len())
}

/// The server's rhythm as the percepts arrive: each cycle's percepts come in a burst, one
/// agent after the other (rcssservermj writes them from Python, 0.3-2 ms from first to last
/// for seven). Waking once per burst instead of once per agent is most of what a cycle
/// costs on a virtual machine, so after the first percept of a burst the thread sleeps a
/// short while for the rest: a small part of the server's period, which it spends stepping
/// before it needs the replies.
#[derive(Debug)]
struct Rhythm {
    burst_start: Instant,
    last_frame: Instant,
    /// Smoothed time between burst starts.
    period: Duration,
    waited: bool,
}

/// A pause longer than this between percepts starts a new burst.
const BURST_GAP: Duration = Duration::from_millis(3);
/// Share of the server's period the thread may wait for the rest of a burst, and at most.
const COALESCE_SHARE: u32 = 10;
const COALESCE_MAX: Duration = Duration::from_millis(2);

impl Rhythm {
    fn new(now: Instant) -> Self {
        Rhythm {
            burst_start: now,
            last_frame: now,
            period: Duration::ZERO,
            waited: true,
        }
    }

    /// Percepts are ready at `now`: how long to wait for the rest of the burst first.
    fn on_ready(&mut self, now: Instant, ready: usize, playing: usize) -> Option<Duration> {
        if now.saturating_duration_since(self.last_frame) > BURST_GAP {
            let since = now.saturating_duration_since(self.burst_start);
            // The first burst only starts the clock.
            self.waited = self.period.is_zero();
            self.period = if self.period.is_zero() {
                since
            } else {
                (self.period * 7 + since) / 8
            };
            self.burst_start = now;
        }
        self.last_frame = now;
        if self.waited || ready >= playing {
            return None;
        }
        self.waited = true;
        let window = (self.period / COALESCE_SHARE).min(COALESCE_MAX);
        (window > Duration::from_micros(100)).then_some(window)
    }
}

/// Run `players` from this thread until `shutdown` is set or every one has ended: each
/// percept answered at once with exactly one frame, lost connections retried with a short
/// backoff, joins one at a time through the config's gate. How each agent ended, in order.
pub fn run_seats(
    config: &AgentConfig,
    players: &mut [Player],
    shutdown: &AtomicBool,
    wakes: &WakeStats,
) -> Vec<SeatEnd> {
    let own_gate;
    let gate: &JoinGate = match &config.join_gate {
        Some(gate) => gate,
        None => {
            own_gate = Arc::new(JoinGate::default());
            &own_gate
        }
    };
    let now = Instant::now();
    let mut seats: Vec<Seat> = players.iter_mut().map(|p| Seat::new(p, now)).collect();
    assert!(
        seats.len() <= MAX_SEATS,
        "at most {MAX_SEATS} agents a thread"
    );
    let mut out = Vec::with_capacity(4096);
    let mut ready = [false; MAX_SEATS];
    let mut rhythm = Rhythm::new(now);
    while !shutdown.load(Ordering::Relaxed) && seats.iter().any(|s| !s.has_ended()) {
        let now = Instant::now();
        for seat in &mut seats {
            seat.on_clock(now, config, gate);
        }
        let wait = seats
            .iter()
            .filter_map(Seat::next_deadline)
            .map(|at| at.saturating_duration_since(now))
            .fold(POLL, Duration::min);
        let (ready_now, playing) = poll_ready(&seats, wait, &mut ready);
        if ready_now == 0 {
            continue;
        }
        wakes.wakeups.fetch_add(1, Ordering::Relaxed);
        if let Some(window) = rhythm.on_ready(Instant::now(), ready_now, playing) {
            std::thread::sleep(window);
            poll_ready(&seats, Duration::ZERO, &mut ready);
            wakes.wakeups.fetch_add(1, Ordering::Relaxed);
        }
        for (seat, _) in seats.iter_mut().zip(&ready).filter(|(_, r)| **r) {
            let answered = seat.on_readable(config, gate, &mut out);
            wakes.percepts.fetch_add(answered, Ordering::Relaxed);
        }
    }
    seats
        .into_iter()
        .map(|mut seat| {
            seat.release_gate(gate);
            AgentStats::set_flag(&seat.player.stats().ended, true);
            match seat.phase {
                Phase::Ended(end) => end,
                _ => SeatEnd::Stopped,
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    const MS: Duration = Duration::from_millis(1);

    #[test]
    fn the_thread_waits_once_per_burst_for_the_rest_of_it_and_only_a_share_of_the_period() {
        let t0 = Instant::now();
        let mut rhythm = Rhythm::new(t0);
        // Bursts every 20 ms: the first ones teach the period, nothing is waited for yet.
        assert_eq!(rhythm.on_ready(t0 + 20 * MS, 1, 7), None);
        // From the next burst on: one wait at its first percept, none later in the burst.
        let window = rhythm.on_ready(t0 + 40 * MS, 1, 7).expect("a wait");
        assert_eq!(window, COALESCE_MAX, "a tenth of 20 ms is 2 ms");
        assert_eq!(rhythm.on_ready(t0 + 40 * MS + window, 6, 7), None);
        assert_eq!(rhythm.on_ready(t0 + 43 * MS, 1, 7), None, "a straggler");
        // Every seat ready at once: nothing to wait for.
        assert_eq!(rhythm.on_ready(t0 + 60 * MS, 7, 7), None);
        // A fast server (2.5 ms cycles): the wait shrinks with the period.
        let mut fast = Rhythm::new(t0);
        let mut at = t0;
        let mut last = None;
        for _ in 0..40 {
            at += Duration::from_micros(3500);
            last = fast.on_ready(at, 1, 2);
        }
        let window = last.expect("a wait");
        assert!(window <= Duration::from_micros(400), "{window:?}");
    }
}
