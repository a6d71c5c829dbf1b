//! The monitor port: game state out, referee-like commands in.

use crate::fouls::FoulTally;
use crate::simspark_scene::{RobotTruth, SceneTracker};
use libero_model::ServerKind;
use libero_protocol::frame::{encode_frame, FrameReader};
use libero_protocol::sexp;
use std::io::Write;
use std::net::TcpStream;
use std::sync::{Arc, Condvar, Mutex};
use std::time::Duration;

/// Play-mode names in the order of the monitor's `play_mode` index (rcsssmj `play_mode.py`).
pub const PLAY_MODES: [&str; 23] = [
    "BeforeKickOff",
    "KickOff_Left",
    "KickOff_Right",
    "PlayOn",
    "KickIn_Left",
    "KickIn_Right",
    "corner_kick_left",
    "corner_kick_right",
    "goal_kick_left",
    "goal_kick_right",
    "offside_left",
    "offside_right",
    "GameOver",
    "Goal_Left",
    "Goal_Right",
    "free_kick_left",
    "free_kick_right",
    "direct_free_kick_left",
    "direct_free_kick_right",
    "penalty_kick_left",
    "penalty_kick_right",
    "penalty_shoot_left",
    "penalty_shoot_right",
];

/// The latest game state the monitor stream reported.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct GameSnapshot {
    /// Play time [s].
    pub time: f64,
    pub half: u32,
    pub score_left: u32,
    pub score_right: u32,
    pub play_mode: String,
    /// Frames received so far.
    pub frames: u64,
    /// Ball centre [m], world frame, from the scene graph (ground truth; `None` before the first
    /// full frame). Diff frames only carry moves of more than 5 mm, so this is that exact.
    pub ball: Option<[f64; 3]>,
    /// SimSpark only: every robot's torso (ground truth; empty on rcssservermj, whose agents
    /// get their own ground truth in the percept).
    pub robots: Vec<RobotTruth>,
    /// SimSpark only: the fouls its referee called so far.
    pub fouls: FoulTally,
}

/// A monitor connection. A thread drains the stream (the server blocks on a full socket) and
/// keeps the newest game state.
pub struct Monitor {
    writer: TcpStream,
    state: Arc<Shared>,
}

/// The newest game state and a signal for each frame applied to it (waiters wake on it instead
/// of polling).
#[derive(Default)]
struct Shared {
    snapshot: Mutex<GameSnapshot>,
    updated: Condvar,
}

impl Shared {
    fn newest(&self) -> GameSnapshot {
        self.snapshot.lock().map(|s| s.clone()).unwrap_or_default()
    }

    /// The state once `pred` holds for it, or `None` after `timeout`.
    fn wait_for(
        &self,
        timeout: Duration,
        pred: impl Fn(&GameSnapshot) -> bool,
    ) -> Option<GameSnapshot> {
        let guard = self.snapshot.lock().ok()?;
        let (guard, waited) = self
            .updated
            .wait_timeout_while(guard, timeout, |s| !pred(s))
            .ok()?;
        (!waited.timed_out() || pred(&guard)).then(|| guard.clone())
    }
}

impl Monitor {
    /// An rcssservermj monitor connection.
    pub fn connect(port: u16) -> std::io::Result<Self> {
        Self::connect_to(ServerKind::RcssMj, port)
    }

    /// A monitor connection to either server (their frames differ; the commands are the same).
    pub fn connect_to(server: ServerKind, port: u16) -> std::io::Result<Self> {
        let stream = TcpStream::connect(("127.0.0.1", port))?;
        stream.set_nodelay(true)?;
        let reader = stream.try_clone()?;
        let state = Arc::new(Shared::default());
        let shared = Arc::clone(&state);
        std::thread::Builder::new()
            .name("monitor-reader".into())
            .spawn(move || {
                let mut frames = FrameReader::with_limit(reader, 64 << 20);
                let mut modes = SimSparkModes::default();
                let mut scene = SceneTracker::default();
                while let Ok(frame) = frames.read_frame() {
                    if let Ok(text) = std::str::from_utf8(frame) {
                        if server == ServerKind::SimSpark {
                            // The scene's truth is worked out before the lock: readers
                            // (agents' truth feeds) wait on it every cycle.
                            let truth = scene.update(text).then(|| (scene.ball(), scene.robots()));
                            if let Ok(mut s) = shared.snapshot.lock() {
                                if update_simspark_state(text, &mut modes, &mut s) {
                                    s.frames += 1;
                                }
                                if let Some((ball, robots)) = truth {
                                    s.ball = ball.or(s.ball);
                                    s.robots = robots;
                                }
                            }
                            shared.updated.notify_all();
                            continue;
                        }
                        if let Some(mut snapshot) = parse_game_state(text) {
                            if let Ok(mut s) = shared.snapshot.lock() {
                                snapshot.frames = s.frames + 1;
                                snapshot.ball = parse_ball(text).or(s.ball);
                                *s = snapshot;
                            }
                            shared.updated.notify_all();
                        }
                    }
                }
            })?;
        Ok(Self {
            writer: stream,
            state,
        })
    }

    /// The newest game state.
    pub fn snapshot(&self) -> GameSnapshot {
        self.state.newest()
    }

    /// A reader of the newest game state for another thread (a field view), valid while the
    /// connection lives and frozen after it.
    pub fn reader(&self) -> impl Fn() -> GameSnapshot + Send + Sync + 'static {
        let state = Arc::clone(&self.state);
        move || state.newest()
    }

    /// A reader for another thread that hands out the game state once the monitor's play time
    /// has reached the time asked for, less `slack_s`, waiting at most `timeout` (then the
    /// newest as it is): the reader thread can fall behind a fast sync-mode server, and a truth
    /// compared with an agent's estimate must be of the same moment.
    pub fn reader_at(
        &self,
        slack_s: f64,
        timeout: Duration,
    ) -> impl Fn(f64) -> GameSnapshot + Send + Sync + 'static {
        let state = Arc::clone(&self.state);
        move |time| {
            state
                .wait_for(timeout, |s| s.time + slack_s >= time)
                .unwrap_or_else(|| state.newest())
        }
    }

    /// Send raw monitor commands, e.g. `(kickOff Left)`.
    pub fn send(&mut self, commands: &str) -> std::io::Result<()> {
        let mut out = Vec::with_capacity(commands.len() + 4);
        encode_frame(commands.as_bytes(), &mut out);
        self.writer.write_all(&out)
    }

    /// Kick off for the left team (nothing starts a game on its own).
    pub fn kick_off_left(&mut self) -> std::io::Result<()> {
        self.send("(kickOff Left)")
    }

    /// Place the ball and give it a velocity [m, m/s].
    pub fn place_ball(&mut self, pos: [f64; 3], vel: [f64; 3]) -> std::io::Result<()> {
        self.send(&format!(
            "(ball (pos {} {} {})(vel {} {} {}))",
            pos[0], pos[1], pos[2], vel[0], vel[1], vel[2]
        ))
    }

    /// Wait until `pred` holds for the game state, or the timeout passes.
    pub fn wait_for(
        &self,
        timeout: Duration,
        pred: impl Fn(&GameSnapshot) -> bool,
    ) -> Option<GameSnapshot> {
        self.state.wait_for(timeout, pred)
    }
}

impl Drop for Monitor {
    fn drop(&mut self) {
        let _ = self.writer.shutdown(std::net::Shutdown::Both);
    }
}

/// The `((gs 1 0)(time …)(half …)(score_left …)(score_right …)(play_mode …))` part of a frame.
pub fn parse_game_state(frame: &str) -> Option<GameSnapshot> {
    let start = frame.rfind("((gs ")?;
    let item = sexp::top_level(&frame[start..]).next()?.ok()?.as_list()?;
    let number = |name: &str| item.numbers::<1>(name).map(|[v]| v);
    let mode = number("play_mode")? as usize;
    Some(GameSnapshot {
        time: number("time")?,
        half: number("half").unwrap_or(1.0) as u32,
        score_left: number("score_left").unwrap_or(0.0) as u32,
        score_right: number("score_right").unwrap_or(0.0) as u32,
        play_mode: PLAY_MODES
            .get(mode)
            .map_or_else(|| format!("mode{mode}"), |m| m.to_string()),
        frames: 0,
        ball: None,
        robots: Vec::new(),
        fouls: FoulTally::default(),
    })
}

/// SimSpark's play-mode names by monitor index: the header's `play_modes` list, else the
/// 0.7.3 table (simspark.md §5.1).
#[derive(Debug, Clone)]
pub struct SimSparkModes(Vec<String>);

impl Default for SimSparkModes {
    fn default() -> Self {
        let mut names: Vec<String> = PLAY_MODES[..19].iter().map(|m| m.to_string()).collect();
        names.extend(["pass_left".to_string(), "pass_right".to_string()]);
        Self(names)
    }
}

/// Apply one SimSpark monitor frame's game-state list to `state`: the header
/// `((FieldLength 30)…(play_modes …)(time 0)…(play_mode 0))(RSG 0 1)(…)` or an update
/// `((time T)[changed items])(RDS 0 1)(…)`, which names only what changed. Returns whether the
/// frame had one.
pub fn update_simspark_state(
    frame: &str,
    modes: &mut SimSparkModes,
    state: &mut GameSnapshot,
) -> bool {
    let Some(Ok(first)) = sexp::top_level(frame).next() else {
        return false;
    };
    let Some(items) = first.as_list() else {
        return false;
    };
    let mut any = false;
    for item in items.iter().filter_map(|c| c.as_list()) {
        let number = || item.tail_numbers::<1>().map(|[v]| v);
        match item.head() {
            Some("play_modes") => {
                modes.0 = item
                    .tail()
                    .filter_map(|c| c.as_atom())
                    .map(str::to_string)
                    .collect();
            }
            Some("time") => state.time = number().unwrap_or(state.time),
            Some("half") => state.half = number().map_or(state.half, |h| h as u32),
            Some("score_left") => {
                state.score_left = number().map_or(state.score_left, |v| v as u32)
            }
            Some("score_right") => {
                state.score_right = number().map_or(state.score_right, |v| v as u32)
            }
            Some("foul") => {
                let Some(numbers) = item.tail_numbers::<4>() else {
                    continue;
                };
                state.fouls.record(state.time, numbers);
            }
            Some("play_mode") => {
                if let Some(index) = number() {
                    let index = index as usize;
                    state.play_mode = modes
                        .0
                        .get(index)
                        .cloned()
                        .unwrap_or_else(|| format!("mode{index}"));
                }
            }
            _ => continue,
        }
        any = true;
    }
    any
}

/// The ball's position from a frame's scene graph `((sg 1 0)full|diff (nd …))`, when the frame
/// carries it. The ball is the first body under the world root (rcsssmj `state_info.py` walks the
/// bodies in model order and the ball is the first body of world.xml); its node holds a `TRF`
/// node whose `SLT` matrix is column-major, translation in elements 12–14. Diff frames leave the
/// `TRF` out when the ball has not moved.
pub fn parse_ball(frame: &str) -> Option<[f64; 3]> {
    let start = frame.find("((sg ")?;
    let item = sexp::top_level(&frame[start..]).next()?.ok()?.as_list()?;
    let root = item
        .iter()
        .filter_map(|c| c.as_list())
        .find(|c| c.head() == Some("nd"))?;
    let ball = first_node(root)?;
    let transform = first_node(ball)?;
    let m = transform.child("SLT")?.tail_numbers::<16>()?;
    Some([m[12], m[13], m[14]])
}

/// The first child node `(nd …)` of a scene-graph node.
fn first_node(list: sexp::List<'_>) -> Option<sexp::List<'_>> {
    list.tail()
        .filter_map(|c| c.as_list())
        .find(|c| c.head() == Some("nd"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn simspark_game_state_from_the_header_and_from_updates() {
        let path = concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../../../shared/samples/simspark/monitor_first.txt"
        );
        let sample = std::fs::read_to_string(path).unwrap();
        // The sample file heads each message with a `### monitor message` line.
        let header = sample
            .lines()
            .find(|l| l.starts_with("((FieldLength"))
            .unwrap();
        let mut modes = SimSparkModes::default();
        let mut state = GameSnapshot::default();
        assert!(update_simspark_state(header, &mut modes, &mut state));
        assert_eq!(state.play_mode, "BeforeKickOff");
        assert_eq!((state.time, state.half), (0.0, 1));
        assert_eq!(modes.0.len(), 21);
        // Updates carry only what changed: the rest stays.
        let update = "((time 12.34)(play_mode 3)(score_left 1))(RDS 0 1)((nd))";
        assert!(update_simspark_state(update, &mut modes, &mut state));
        assert_eq!(state.time, 12.34);
        assert_eq!(state.play_mode, "PlayOn");
        assert_eq!((state.score_left, state.score_right, state.half), (1, 0, 1));
        assert!(update_simspark_state(
            "((time 13))(RDS 0 1)((nd))",
            &mut modes,
            &mut state
        ));
        assert_eq!(state.play_mode, "PlayOn");
        assert!(!update_simspark_state("garbage (", &mut modes, &mut state));
        // A foul item is counted at the frame's time, once (the server sends each once).
        let foul = "((time 20)(foul 3 4 1 6))(RDS 0 1)((nd))";
        assert!(update_simspark_state(foul, &mut modes, &mut state));
        assert!(update_simspark_state(foul, &mut modes, &mut state));
        assert_eq!(state.fouls.counts(true), vec![(6, "incapable", 1)]);
        assert_eq!(state.fouls.recent(true).next().map(|f| f.time), Some(20.0));
        // A header naming the modes differently is believed over the built-in table.
        let renamed = "((play_modes A B C D)(play_mode 3))(RSG 0 1)()";
        assert!(update_simspark_state(renamed, &mut modes, &mut state));
        assert_eq!(state.play_mode, "D");
    }

    #[test]
    fn game_state_from_a_real_monitor_frame() {
        let path = concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../../../shared/samples/rcssservermj/monitor_last_frame.txt"
        );
        let frame = std::fs::read_to_string(path).unwrap();
        let s = parse_game_state(frame.trim()).unwrap();
        assert_eq!(s.time, 3.16);
        assert_eq!(s.half, 1);
        assert_eq!((s.score_left, s.score_right), (0, 0));
        assert_eq!(s.play_mode, "KickOff_Right");
    }

    #[test]
    fn ball_position_from_full_and_diff_scene_graphs() {
        let dir = concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../../../shared/samples/rcssservermj/"
        );
        let full = std::fs::read_to_string(format!("{dir}monitor_first_frame.txt")).unwrap();
        assert_eq!(parse_ball(full.trim()), Some([0.0, 0.0, 0.1099]));
        // The sample diff frame shows a ball that had not moved: no position in it.
        let diff = std::fs::read_to_string(format!("{dir}monitor_last_frame.txt")).unwrap();
        assert_eq!(parse_ball(diff.trim()), None);
        let moved = "((RSMP 1 0)((gt 1 0)1.0)((sg 1 0)diff(nd(nd(nd TRF(SLT 1 0 0 0 0 1 0 0 0 0 1 0 3.5 -2.25 0.11 1)(nd)))(nd(nd)))))";
        assert_eq!(parse_ball(moved), Some([3.5, -2.25, 0.11]));
    }
}
