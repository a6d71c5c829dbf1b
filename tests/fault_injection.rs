//! A hand-written server on loopback that misbehaves on purpose (garbage, truncated frames,
//! absurd length prefixes, byte-by-byte delivery, unknown perceptors, silence). It stands in
//! for the real server only here, where the point is faults the real one never makes.

use libero_agent::{build, run_agent, AgentConfig, AgentStats};
use libero_tests::{init_logging, t1, wait_until};
use std::io::{Read, Write};
use std::net::{TcpListener, TcpStream};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::thread::JoinHandle;
use std::time::Duration;

const GOOD: &str = include_str!("../../shared/samples/rcssservermj/T1_sync_msg0000.txt");

fn frame(payload: &[u8]) -> Vec<u8> {
    let mut out = (payload.len() as u32).to_be_bytes().to_vec();
    out.extend_from_slice(payload);
    out
}

/// Read one frame the agent sent; `None` when it closed or sent nothing in time.
fn read_reply(stream: &mut TcpStream) -> Option<String> {
    stream.set_read_timeout(Some(Duration::from_secs(5))).ok()?;
    let mut len = [0u8; 4];
    stream.read_exact(&mut len).ok()?;
    let mut body = vec![0u8; u32::from_be_bytes(len) as usize];
    stream.read_exact(&mut body).ok()?;
    String::from_utf8(body).ok()
}

/// An agent running against `port` in a thread, and its stats.
struct AgentUnderTest {
    stats: Arc<AgentStats>,
    stop: Arc<AtomicBool>,
    thread: JoinHandle<()>,
}

impl AgentUnderTest {
    fn start(port: u16, silence: Duration) -> Self {
        init_logging();
        let mut player = build::standing_player(&t1(), "Probe", 1).unwrap();
        let stats = Arc::clone(player.stats());
        let stop = Arc::new(AtomicBool::new(false));
        let flag = Arc::clone(&stop);
        let mut config = AgentConfig::new("127.0.0.1", port);
        config.silence_timeout = silence;
        config.first_percept_timeout = silence;
        config.greeting_delay = Duration::ZERO;
        let thread = std::thread::spawn(move || run_agent(&config, &mut player, &flag).unwrap());
        Self {
            stats,
            stop,
            thread,
        }
    }

    /// Stop the agent; panics (failing the test) if its thread panicked.
    fn finish(self) {
        self.stop.store(true, Ordering::Relaxed);
        self.thread.join().expect("the agent thread panicked");
    }
}

fn listener() -> (TcpListener, u16) {
    let l = TcpListener::bind("127.0.0.1:0").unwrap();
    let port = l.local_addr().unwrap().port();
    (l, port)
}

/// Accept a connection and read the agent's `init`.
fn accept_agent(l: &TcpListener) -> TcpStream {
    let (mut s, _) = l.accept().unwrap();
    let init = read_reply(&mut s).expect("init");
    assert_eq!(init, "(init T1 Probe 1)");
    s
}

#[test]
fn garbage_and_unknown_items_each_get_exactly_one_full_reply() {
    let (l, port) = listener();
    let agent = AgentUnderTest::start(port, Duration::from_secs(5));
    let mut s = accept_agent(&l);
    let inputs: [&[u8]; 6] = [
        b"\xff\xfe\x00\x01 not text",
        b"(((((unbalanced",
        b")))",
        b"(time (now 1.00))(WAT (n x) (y 1 2 3))(HJ (n q_nope)(ax 3)(vx 0))(HJ (n q_hj1)(ax nan))",
        b"",
        GOOD.as_bytes(),
    ];
    for input in inputs {
        s.write_all(&frame(input)).unwrap();
        let reply = read_reply(&mut s).expect("one reply per message, even for garbage");
        assert_eq!(
            reply.matches("(lle1 ").count(),
            1,
            "all joints every cycle: {reply}"
        );
        assert_eq!(reply.matches('(').count(), reply.matches(')').count());
    }
    assert_eq!(AgentStats::get(&agent.stats.replies), 6);
    assert_eq!(AgentStats::get(&agent.stats.unreadable), 3);
    agent.finish();
}

#[test]
fn a_frame_split_into_single_bytes_is_reassembled() {
    let (l, port) = listener();
    let agent = AgentUnderTest::start(port, Duration::from_secs(5));
    let mut s = accept_agent(&l);
    s.set_nodelay(true).unwrap();
    for byte in frame(GOOD.as_bytes()) {
        s.write_all(&[byte]).unwrap();
        s.flush().unwrap();
    }
    let reply = read_reply(&mut s).expect("reply after the last byte");
    assert!(
        reply.contains("(beam "),
        "first cycle in BeforeKickOff beams: {reply}"
    );
    assert_eq!(AgentStats::get(&agent.stats.unreadable), 0);
    agent.finish();
}

fn resident_kib() -> u64 {
    let statm = std::fs::read_to_string("/proc/self/statm").unwrap();
    let pages: u64 = statm.split_whitespace().nth(1).unwrap().parse().unwrap();
    pages * 4
}

#[test]
fn a_huge_length_prefix_or_a_truncated_frame_ends_the_connection_and_the_agent_reconnects() {
    let (l, port) = listener();
    let agent = AgentUnderTest::start(port, Duration::from_secs(5));
    let before = resident_kib();
    // 16 MiB announced: refused before any allocation, connection dropped.
    let mut s = accept_agent(&l);
    s.write_all(&(16u32 << 20).to_be_bytes()).unwrap();
    s.write_all(&[b'('; 1024]).unwrap();
    // The agent comes back on a new connection.
    let mut s2 = accept_agent(&l);
    drop(s);
    // Half a frame, then the server goes away.
    let full = frame(GOOD.as_bytes());
    s2.write_all(&full[..full.len() / 2]).unwrap();
    drop(s2);
    let mut s3 = accept_agent(&l);
    s3.write_all(&full).unwrap();
    assert!(
        read_reply(&mut s3).is_some(),
        "the agent works on the third connection"
    );
    assert_eq!(AgentStats::get(&agent.stats.connections), 3);
    let grown = resident_kib().saturating_sub(before);
    assert!(grown < 8 * 1024, "resident memory grew by {grown} KiB");
    agent.finish();
}

#[test]
fn a_silent_server_is_given_up_on_and_reconnected_to() {
    let (l, port) = listener();
    let agent = AgentUnderTest::start(port, Duration::from_millis(400));
    let _silent = accept_agent(&l);
    // No percept ever comes: after the silence timeout the agent tries again.
    let mut s = accept_agent(&l);
    s.write_all(&frame(GOOD.as_bytes())).unwrap();
    assert!(read_reply(&mut s).is_some());
    let took = wait_until(Duration::from_secs(2), || {
        AgentStats::get(&agent.stats.connections) == 2
    });
    assert!(took.is_some());
    agent.finish();
}

#[test]
fn an_unreachable_server_is_a_clear_error_when_attempts_are_bounded() {
    let (l, port) = listener();
    drop(l);
    let mut player = build::standing_player(&t1(), "Probe", 1).unwrap();
    let mut config = AgentConfig::new("127.0.0.1", port);
    config.max_connect_failures = Some(3);
    let err = run_agent(&config, &mut player, &AtomicBool::new(false))
        .unwrap_err()
        .to_string();
    assert!(err.contains("could not reach the server"), "{err}");
    assert!(
        err.contains("libero server start"),
        "the error says what to do: {err}"
    );
}

/// A server that closes every connection before the first percept (it refuses the team): the
/// agent retries with a doubling wait, each retry being a join that stalls the server's
/// match, and stops with a clear error after the bounded number of refusals.
#[test]
fn a_refused_agent_backs_off_and_stops_with_a_clear_error() {
    init_logging();
    let (l, port) = listener();
    let refusing = std::thread::spawn(move || {
        let mut at = Vec::new();
        for _ in 0..4 {
            let s = accept_agent(&l);
            at.push(std::time::Instant::now());
            drop(s);
        }
        // No fifth attempt comes.
        l.set_nonblocking(true).unwrap();
        std::thread::sleep(Duration::from_millis(1500));
        assert!(l.accept().is_err(), "a fifth attempt after four refusals");
        at
    });
    let mut player = build::standing_player(&t1(), "Probe", 1).unwrap();
    let mut config = AgentConfig::new("127.0.0.1", port);
    config.greeting_delay = Duration::ZERO;
    config.max_refusals = 4;
    config.refusal_backoff = Duration::from_millis(100);
    let err = run_agent(&config, &mut player, &AtomicBool::new(false))
        .unwrap_err()
        .to_string();
    assert!(err.contains("refused this agent 4 times"), "{err}");
    assert!(
        err.contains("team name"),
        "the error says what to check: {err}"
    );
    let at = refusing.join().unwrap();
    let gaps: Vec<f64> = at.windows(2).map(|w| (w[1] - w[0]).as_secs_f64()).collect();
    // 0.1, 0.2, 0.4 s: each wait about twice the one before.
    for pair in gaps.windows(2) {
        assert!(pair[1] > 1.6 * pair[0], "the waits do not grow: {gaps:?}");
    }
    assert!(gaps[0] >= 0.09, "{gaps:?}");
}

/// Stands until its `at`-th cycle, which panics.
struct PanicsAt {
    at: u32,
    cycles: u32,
}

impl libero_agent::Decider for PanicsAt {
    fn decide(&mut self, _world: &libero_world::World) -> libero_skills::Intent {
        self.cycles += 1;
        assert!(
            self.cycles < self.at,
            "injected fault in cycle {}",
            self.cycles
        );
        libero_skills::Intent::default()
    }
}

#[test]
fn an_agent_whose_cycle_panics_leaves_alone_and_its_teammates_on_the_same_thread_play_on() {
    init_logging();
    let (l, port) = listener();
    let model = t1();
    let mut players: Vec<_> = [1, 3]
        .into_iter()
        .map(|unum| build::standing_player(&model, "Probe", unum).unwrap())
        .collect();
    let faulty = Box::new(PanicsAt { at: 3, cycles: 0 });
    let source = libero_agent::SkillSource::Builtin;
    players.insert(
        1,
        build::player_with(&model, "Probe", 2, faulty, &source).unwrap(),
    );
    // The server: each agent gets a percept as it joins (the team joins one at a time),
    // then every agent one percept per round.
    let server = std::thread::spawn(move || {
        let mut agents: Vec<TcpStream> = Vec::new();
        for unum in 1..=3 {
            let (mut s, _) = l.accept().unwrap();
            let init = read_reply(&mut s).expect("init");
            assert_eq!(init, format!("(init T1 Probe {unum})"));
            s.write_all(&frame(GOOD.as_bytes())).unwrap();
            read_reply(&mut s).expect("the first reply");
            agents.push(s);
        }
        let mut replies = [1u32; 3];
        for _ in 0..8 {
            for (i, s) in agents.iter_mut().enumerate() {
                if s.write_all(&frame(GOOD.as_bytes())).is_ok() && read_reply(s).is_some() {
                    replies[i] += 1;
                }
            }
        }
        replies
    });
    let mut config = AgentConfig::new("127.0.0.1", port);
    config.greeting_delay = Duration::ZERO;
    let team = libero_agent::Team::start(&config, players, Arc::new(AtomicBool::new(false)));
    let replies = server.join().unwrap();
    assert_eq!(replies[0], 9, "agent 1 answered every percept: {replies:?}");
    assert_eq!(replies[2], 9, "agent 3 answered every percept: {replies:?}");
    assert_eq!(
        replies[1], 2,
        "agent 2 answered until its cycle panicked: {replies:?}"
    );
    let finished = team.finished();
    assert_eq!(finished, vec![(1, false), (2, true), (3, false)]);
    assert_eq!(team.stop_reporting_panics(), vec![2]);
}

/// CPU seconds the threads of this process named `name` have run (`schedstat`).
fn thread_cpu_s(name: &str) -> f64 {
    std::fs::read_dir("/proc/self/task")
        .unwrap()
        .flatten()
        .filter(|t| {
            std::fs::read_to_string(t.path().join("comm")).is_ok_and(|c| c.trim_end() == name)
        })
        .filter_map(|t| std::fs::read_to_string(t.path().join("schedstat")).ok())
        .filter_map(|s| s.split_whitespace().next()?.parse::<f64>().ok())
        .sum::<f64>()
        / 1e9
}

#[test]
fn an_agent_waiting_for_a_teammates_slow_join_does_not_spin() {
    init_logging();
    let (l, port) = listener();
    let model = t1();
    let players: Vec<_> = (1..=2)
        .map(|unum| build::standing_player(&model, "Probe", unum).unwrap())
        .collect();
    // Agent 1's first percept comes after a second; agent 2 waits for the join gate meanwhile.
    let server = std::thread::spawn(move || {
        let mut agents = Vec::new();
        for unum in 1..=2 {
            let (mut s, _) = l.accept().unwrap();
            assert_eq!(
                read_reply(&mut s).unwrap(),
                format!("(init T1 Probe {unum})")
            );
            if unum == 1 {
                std::thread::sleep(Duration::from_secs(1));
            }
            s.write_all(&frame(GOOD.as_bytes())).unwrap();
            read_reply(&mut s).expect("the first reply");
            agents.push(s);
        }
        agents
    });
    let mut config = AgentConfig::new("127.0.0.1", port);
    config.greeting_delay = Duration::ZERO;
    let team = libero_agent::Team::start(&config, players, Arc::new(AtomicBool::new(false)));
    let cpu = thread_cpu_s("agent-1-2");
    let _agents = server.join().unwrap();
    assert!(
        team.stats
            .iter()
            .all(|(_, s)| AgentStats::get(&s.replies) == 1),
        "both joined"
    );
    assert!(
        cpu < 0.25,
        "the team's thread ran {cpu:.2} s of the 1 s wait"
    );
    team.stop();
}
