//! Running a scenario on a real fast-mode rcssservermj, judged from its ground truth.
//!
//! One server and one set of agents serve every run of a series: each run drops the ball
//! (`(dropBall)` is the monitor's way to PlayOn; `(playMode …)` does nothing in rcsssmj
//! 0.2.1), places robots and ball with the monitor (resending moves the server ignored), lets
//! the robots settle for `settle_s` with the ball at rest, launches the ball and judges every
//! monitor update until the condition is decided, play stops or time runs out. Ground truth
//! (torsos from each agent's percepts, ball from the monitor's scene graph) is only read here,
//! never by the agents' decisions.

use crate::eval_logs::Logs;
use crate::judge::{Judge, Observation, Verdict};
use crate::shot_judge::GoalMouth;
use crate::spec::{Placement, Play, RunSetup, Scenario};
use crate::summary::{LaunchMeasure, RobotTravel, RunOutcome};
use libero_agent::build::{standing_player, tree_player};
use libero_agent::{AgentConfig, AgentStats, LibrarySource, Player, SkillSource, Team};
use libero_model::RobotModel;
use libero_server::{Monitor, ServerOptions, ServerProcess};
use libero_world::params::BallParams;
use libero_world::WorldParams;

use crate::summary::{FallCounter, STANDING_TORSO_Z_M};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

/// Our team's name (connects first: plays from the left).
pub const OUR_TEAM: &str = "Libero";
/// The other team's name (plays from the right).
pub const THEIR_TEAM: &str = "Opponent";
/// Torso height for monitor placements: soles just on the ground.
const PLACE_TORSO_Z_M: f64 = 0.6735;
const BALL_Z_M: f64 = 0.11;
/// A placement counts as done when ground truth is this close [m].
const PLACED_WITHIN_M: f64 = 0.1;
/// Resend a placement the server has not carried out after this much simulated time [s].
const RESEND_AFTER_S: f64 = 0.4;
const PLACE_ATTEMPTS: u32 = 8;
/// The launch direction and speed are measured over this much simulated time [s].
const LAUNCH_WINDOW_S: f64 = 0.3;
/// A stalled server (simulated time not advancing) fails the series after this long.
const STALL: Duration = Duration::from_secs(30);

#[derive(Debug, thiserror::Error)]
pub enum RunError {
    #[error(transparent)]
    Server(#[from] libero_server::ServerError),
    #[error("monitor: {0}")]
    Monitor(#[from] std::io::Error),
    #[error(transparent)]
    Build(#[from] libero_agent::build::BuildError),
    #[error("{0}")]
    Setup(String),
    #[error("interrupted")]
    Interrupted,
}

/// Where the agents' data comes from.
pub struct RunData {
    pub library: LibrarySource,
    pub skills: SkillSource,
    /// Set (e.g. by Ctrl-C) to end the series at once, server stopped.
    pub interrupt: Arc<AtomicBool>,
    /// Whoever watches the series (a field view): told of each player built and of the
    /// server's monitor.
    pub watcher: Option<Box<dyn Watcher>>,
    /// Each robot writes its evaluation log (with tree traces) to this path with
    /// `.TEAM.UNUM` appended.
    pub log: Option<std::path::PathBuf>,
}

/// What a watcher of a series is given.
pub trait Watcher {
    /// A robot of the scenario, before it joins (`team` is [`OUR_TEAM`] or [`THEIR_TEAM`]).
    fn player(&self, team: &str, player: &mut Player);
    /// The server's monitor, once it runs.
    fn monitor(&self, monitor: &libero_server::Monitor);
}

struct Robot {
    unum: u32,
    ours: bool,
    stats: Arc<AgentStats>,
}

/// A server with both teams connected, for one series of runs.
pub struct Arena {
    server: ServerProcess,
    robots: Vec<Robot>,
    teams: Vec<Team>,
    shutdown: Arc<AtomicBool>,
    interrupt: Arc<AtomicBool>,
    ball: BallParams,
}

impl Arena {
    /// Start a fast-mode server and connect the scenario's robots (ours first, so ours play
    /// from the left).
    pub fn start(scenario: &Scenario, data: &RunData, logs: Logs) -> Result<Self, RunError> {
        let mut server = ServerProcess::start(ServerOptions::default())?;
        if let Some(watcher) = &data.watcher {
            watcher.monitor(server.monitor());
        }
        let model = Arc::new(
            RobotModel::builtin("T1").map_err(|e| RunError::Setup(format!("T1 model: {e}")))?,
        );
        let shutdown = Arc::new(AtomicBool::new(false));
        let config = AgentConfig::new("127.0.0.1", server.agent_port);
        let mut robots = Vec::new();
        let mut teams = Vec::new();
        for (team, list, ours) in [
            (OUR_TEAM, &scenario.ours, true),
            (THEIR_TEAM, &scenario.theirs, false),
        ] {
            if list.is_empty() {
                continue;
            }
            let mut players: Vec<Player> = Vec::new();
            for r in list {
                let mut player = match r.play {
                    Play::Tree => tree_player(&model, team, r.unum, &data.library, &data.skills)?,
                    Play::Stand => standing_player(&model, team, r.unum)?,
                };
                if let Some(watcher) = &data.watcher {
                    watcher.player(team, &mut player);
                }
                if let Some(path) = &data.log {
                    player.log_to(logs.open(path, team, r.unum)?, true);
                }
                robots.push(Robot {
                    unum: r.unum,
                    ours,
                    stats: Arc::clone(player.stats()),
                });
                players.push(player);
            }
            teams.push(Team::start(&config, players, Arc::clone(&shutdown)));
        }
        let arena = Self {
            server,
            robots,
            teams,
            shutdown,
            interrupt: Arc::clone(&data.interrupt),
            ball: WorldParams::builtin().ball,
        };
        // Every agent must be answering before the first placement.
        let deadline = Instant::now() + Duration::from_secs(60);
        while arena
            .robots
            .iter()
            .any(|r| AgentStats::get(&r.stats.percepts) == 0)
        {
            if Instant::now() > deadline {
                return Err(RunError::Setup("the robots did not all connect".into()));
            }
            std::thread::sleep(Duration::from_millis(20));
        }
        Ok(arena)
    }

    /// The ball model used to aim launches (the world model's).
    pub fn ball_params(&self) -> &BallParams {
        &self.ball
    }

    /// Server time [s]: the newest any agent has seen.
    fn now(&self) -> f64 {
        self.robots
            .iter()
            .map(|r| AgentStats::get(&r.stats.last_time_ms) as f64 / 1000.0)
            .fold(0.0, f64::max)
    }

    fn monitor(&mut self) -> &mut Monitor {
        self.server.monitor()
    }

    /// Wait until simulated time reaches `until` [s].
    fn wait_until(&self, until: f64) -> Result<(), RunError> {
        self.wait_while(until, || true)
    }

    /// Wait while `busy` holds, until simulated time reaches `until` [s] at the latest.
    fn wait_while(&self, until: f64, busy: impl Fn() -> bool) -> Result<(), RunError> {
        let mut last = (self.now(), Instant::now());
        while self.now() < until && busy() {
            if self.interrupt.load(Ordering::Relaxed) {
                return Err(RunError::Interrupted);
            }
            let now = self.now();
            if now > last.0 {
                last = (now, Instant::now());
            } else if last.1.elapsed() > STALL {
                return Err(RunError::Setup(format!(
                    "the server stalled at {now:.2} s of simulated time"
                )));
            }
            std::thread::sleep(Duration::from_millis(5));
        }
        Ok(())
    }

    fn truth(&self, ours: bool) -> Vec<(u32, [f64; 2])> {
        self.robots
            .iter()
            .filter(|r| r.ours == ours)
            .filter_map(|r| r.stats.truth_position().map(|p| (r.unum, [p[0], p[1]])))
            .collect()
    }

    /// Wait (at most 15 s of simulated time) until every robot is upright and none plays a
    /// get-up or save motion. A robot placed while it lay (before its get-up began) was put
    /// down standing by the server while its own fall detector still said lying: the get-up
    /// it then started from standing threw it over, again at every placement, and pass.ron's
    /// series stopped with "did not stand still after four placements" (NOTES.md, session 33).
    fn wait_until_standing_still(&self) -> Result<(), RunError> {
        self.wait_while(self.now() + 15.0, || !self.all_standing_still())
    }

    /// Every robot upright (ground truth) and none in a get-up or save motion.
    fn all_standing_still(&self) -> bool {
        self.robots.iter().all(|r| {
            !r.stats.is_in_motion()
                && r.stats
                    .truth_position()
                    .is_some_and(|p| p[2] > STANDING_TORSO_Z_M)
        })
    }

    /// Drop the ball (PlayOn), place robots and ball, and check the ground truth, resending
    /// what was ignored.
    fn place(&mut self, setup: &RunSetup) -> Result<(), RunError> {
        // A goal's Goal_X turns into a kick-off 3 s later on its own; wait for that first.
        let wait_from = Instant::now();
        while self.monitor().snapshot().play_mode.starts_with("Goal_")
            && wait_from.elapsed() < Duration::from_secs(20)
        {
            std::thread::sleep(Duration::from_millis(10));
        }
        let mut command = String::from("(dropBall)");
        command.push_str(&format!(
            "(ball (pos {} {} {BALL_Z_M})(vel 0 0 0))",
            setup.ball[0], setup.ball[1]
        ));
        for (side, list) in [("Left", &setup.ours), ("Right", &setup.theirs)] {
            for p in list.iter() {
                command.push_str(&move_command(side, p));
            }
        }
        for attempt in 1..=PLACE_ATTEMPTS {
            let sent = self.now();
            self.monitor().send(&command)?;
            // Effects show two perceptions later.
            self.wait_until(sent + 0.06)?;
            let deadline = sent + RESEND_AFTER_S;
            while self.now() < deadline {
                if self.placed(setup) {
                    return Ok(());
                }
                self.wait_until(self.now() + 0.02)?;
            }
            log::debug!("scenario: placement ignored (attempt {attempt}); sending it again");
        }
        Err(RunError::Setup(format!(
            "the server did not carry out the placement in {PLACE_ATTEMPTS} attempts"
        )))
    }

    fn placed(&mut self, setup: &RunSetup) -> bool {
        let near =
            |a: [f64; 2], b: [f64; 2], within: f64| (a[0] - b[0]).hypot(a[1] - b[1]) < within;
        let snapshot = self.monitor().snapshot();
        let ball_ok = snapshot
            .ball
            .is_some_and(|b| near([b[0], b[1]], setup.ball, 0.05));
        let robots_ok = [(true, &setup.ours), (false, &setup.theirs)]
            .into_iter()
            .all(|(ours, list)| {
                let truth = self.truth(ours);
                list.iter().all(|p| {
                    truth
                        .iter()
                        .find(|(u, _)| *u == p.unum)
                        .is_some_and(|(_, t)| near(*t, [p.pose[0], p.pose[1]], PLACED_WITHIN_M))
                })
            });
        ball_ok && robots_ok && snapshot.play_mode == "PlayOn"
    }

    /// Run one situation to its verdict.
    pub fn run(&mut self, scenario: &Scenario, setup: &RunSetup) -> Result<RunOutcome, RunError> {
        // Each run starts from robots standing still where the file puts them: a robot still
        // in a get-up or save from the run before (one set of agents serves the series) is
        // waited for, and a placement that ends in a fall is made again.
        for attempt in 0.. {
            self.wait_until_standing_still()?;
            self.place(setup)?;
            self.wait_until(self.now() + scenario.settle_s)?;
            if self.all_standing_still() {
                break;
            }
            for r in &self.robots {
                log::debug!(
                    "placement {attempt}: robot {} in motion {} torso {:?}",
                    r.unum,
                    r.stats.is_in_motion(),
                    r.stats.truth_position()
                );
            }
            if attempt == 3 {
                return Err(RunError::Setup(
                    "the robots did not stand still after four placements".into(),
                ));
            }
        }
        let start = self.monitor().snapshot();
        let launch = format!(
            "(ball (pos {} {} {BALL_Z_M})(vel {} {} 0))",
            setup.ball[0], setup.ball[1], setup.ball_velocity[0], setup.ball_velocity[1]
        );
        self.monitor().send(&launch)?;
        let t0 = self.now();
        log::info!("scenario: run {} starts at t {t0:.2}", setup.index + 1);
        let start_truth: Vec<(bool, u32, [f64; 2])> = [true, false]
            .into_iter()
            .flat_map(|ours| self.truth(ours).into_iter().map(move |(u, p)| (ours, u, p)))
            .collect();
        let mut judge = Judge::new(
            &scenario.success,
            &self.ball,
            GoalMouth::of(&scenario.field),
        );
        let mut measure = LaunchTracker::new(setup.ball, scenario.field.half_extent().0);
        let mut last_progress = (t0, Instant::now());
        let mut last_in_play = None;
        let mut falls = FallCounter::new(self.robots.len());
        let mut first_touch = None;
        // Whether play had stopped when the run ended (a goal, the ball out, a free kick).
        let mut play_stopped;
        let (verdict, ended) = loop {
            std::thread::sleep(Duration::from_millis(5));
            if self.interrupt.load(Ordering::Relaxed) {
                return Err(RunError::Interrupted);
            }
            let now = self.now();
            if now > last_progress.0 {
                last_progress = (now, Instant::now());
            } else if last_progress.1.elapsed() > STALL {
                return Err(RunError::Setup(format!(
                    "the server stalled at {now:.2} s of simulated time"
                )));
            }
            let t = now - t0;
            for (i, r) in self.robots.iter().enumerate() {
                falls.observe(i, r.stats.truth_position().map(|p| p[2]));
            }
            let s = self.monitor().snapshot();
            let o = Observation {
                t,
                ball: s.ball,
                ours: self.truth(true),
                theirs: self.truth(false),
                goals_for: s.score_left.saturating_sub(start.score_left),
                goals_against: s.score_right.saturating_sub(start.score_right),
            };
            // At a goal the ball stays where it went; at a goal kick or corner the referee
            // has already moved it.
            let ball_where_play_left_it =
                s.play_mode == "PlayOn" || s.play_mode.starts_with("Goal_");
            measure.observe(t, s.ball, ball_where_play_left_it);
            play_stopped = t > 0.1 && s.play_mode != "PlayOn";
            if s.play_mode == "PlayOn" {
                last_in_play = s.ball.map(|b| [b[0], b[1]]);
            }
            if first_touch.is_none() && o.ours_touch_ball() {
                first_touch = Some(t);
            }
            judge.observe(&o);
            let v = judge.verdict();
            if v.decided() {
                let end = describe_end(&v);
                break (v, end);
            }
            // The launch takes effect after the next step; a mode change after that is play
            // stopping (goal, ball out of play, free kick).
            if s.play_mode == "GameOver" {
                // The server's game clock ran out under the series: not the robots' doing.
                return Err(RunError::Setup(
                    "the game clock ran out during the run (GameOver)".into(),
                ));
            }
            if t > 0.1 && s.play_mode != "PlayOn" {
                let why = format!("play stopped ({})", s.play_mode);
                break (judge.finish(t, &why), why);
            }
            if t >= scenario.time_limit_s {
                let why = "time ran out".to_string();
                break (judge.finish(scenario.time_limit_s, &why), why);
            }
        };
        let s = self.monitor().snapshot();
        let robots = start_truth
            .iter()
            .map(|&(ours, unum, from)| {
                let to = self
                    .truth(ours)
                    .into_iter()
                    .find(|(u, _)| *u == unum)
                    .map_or(from, |(_, p)| p);
                let falls = self
                    .robots
                    .iter()
                    .position(|r| r.ours == ours && r.unum == unum)
                    .map_or(0, |i| falls.of(i));
                RobotTravel {
                    ours,
                    unum,
                    from,
                    to,
                    falls,
                }
            })
            .collect();
        let (success, time_s, why) = match verdict {
            Verdict::Succeeded { t } => (true, Some(t), None),
            Verdict::Failed { why, .. } => (false, None, Some(why)),
            _ => (false, None, Some("undecided".into())),
        };
        Ok(RunOutcome {
            index: setup.index,
            success,
            time_s,
            why,
            ended,
            setup: setup.clone(),
            launch: measure.result(),
            goals_for: s.score_left.saturating_sub(start.score_left),
            goals_against: s.score_right.saturating_sub(start.score_right),
            closest_m: judge.closest.map(|(g, _)| g),
            first_touch_s: first_touch,
            ball_travel_m: measure.max_travel,
            goal_line_y: measure.goal_line_crossing(play_stopped),
            ball_end: last_in_play,
            robots,
        })
    }

    /// Stop the agents and the server.
    pub fn stop(mut self) {
        self.shutdown.store(true, Ordering::Relaxed);
        for team in self.teams.drain(..) {
            team.join();
        }
        self.server.stop();
    }
}

fn describe_end(v: &Verdict) -> String {
    match v {
        Verdict::Succeeded { .. } => "condition met".into(),
        Verdict::Failed { .. } => "condition broken".into(),
        _ => String::new(),
    }
}

fn move_command(side: &str, p: &Placement) -> String {
    format!(
        "(agent (unum {}) (team {side}) (move {} {} {PLACE_TORSO_Z_M} {}))",
        p.unum, p.pose[0], p.pose[1], p.pose[2]
    )
}

/// The ball's measured launch (ground truth) and where it went.
struct LaunchTracker {
    from: [f64; 2],
    goal_line_x: f64,
    /// Ball position at the first sample after the launch, and its time.
    first: Option<(f64, [f64; 2])>,
    window: Option<(f64, [f64; 2])>,
    max_travel: f64,
    goal_line_y: Option<f64>,
    /// The last two ball positions in play.
    last: Option<[f64; 2]>,
    before_last: Option<[f64; 2]>,
}

impl LaunchTracker {
    fn new(from: [f64; 2], goal_line_x: f64) -> Self {
        Self {
            from,
            goal_line_x,
            first: None,
            window: None,
            max_travel: 0.0,
            goal_line_y: None,
            last: None,
            before_last: None,
        }
    }

    /// One ground-truth sample; `in_play` false when the referee may have moved the ball
    /// already (such samples are ignored).
    fn observe(&mut self, t: f64, ball: Option<[f64; 3]>, in_play: bool) {
        let Some(b) = ball.map(|b| [b[0], b[1]]).filter(|_| in_play) else {
            return;
        };
        let travel = (b[0] - self.from[0]).hypot(b[1] - self.from[1]);
        self.max_travel = self.max_travel.max(travel);
        // The launch starts from the placement; the first sample that moved dates it.
        if self.first.is_none() && travel > 0.02 {
            self.first = Some((t, b));
        }
        if let Some((t1, _)) = self.first {
            if t - t1 <= LAUNCH_WINDOW_S {
                self.window = Some((t, b));
            }
        }
        // Where the ball first crossed a goal line: interpolated.
        if let (Some(last), None) = (self.last, self.goal_line_y) {
            for line in [-self.goal_line_x, self.goal_line_x] {
                if (last[0] - line).signum() != (b[0] - line).signum()
                    && (b[0] - last[0]).abs() > 1e-9
                {
                    let w = (line - last[0]) / (b[0] - last[0]);
                    self.goal_line_y = Some(last[1] + w * (b[1] - last[1]));
                }
            }
        }
        // The monitor updates less often than it is read: a repeated sample is no step.
        if self.last != Some(b) {
            self.before_last = self.last;
            self.last = Some(b);
        }
    }

    /// Where the ball crossed a goal line: seen, or, when play stopped on the crossing (the
    /// referee moves the ball for a goal kick or corner before the next sample), extrapolated
    /// from the last two samples in play when the line lies within 1.5 m ahead. A run that
    /// ended with play going on (its time ran out) has a ball still rolling, maybe towards the
    /// line: nothing is extrapolated then (CI once saw a "crossing" 1.2 m short of the line).
    fn goal_line_crossing(&self, play_stopped: bool) -> Option<f64> {
        if self.goal_line_y.is_some() || !play_stopped {
            return self.goal_line_y;
        }
        let (a, b) = (self.before_last?, self.last?);
        let dx = b[0] - a[0];
        if dx.abs() < 1e-9 {
            return None;
        }
        let line = self.goal_line_x.copysign(dx);
        let w = (line - a[0]) / dx;
        let ahead_m = (line - b[0]).abs();
        (w >= 1.0 && ahead_m <= 1.5).then(|| a[1] + w * (b[1] - a[1]))
    }

    fn result(&self) -> Option<LaunchMeasure> {
        let (t1, p1) = self.first?;
        let (t2, p2) = self.window?;
        let dt = t2 - t1;
        let (dx, dy) = (p2[0] - p1[0], p2[1] - p1[1]);
        Some(LaunchMeasure {
            direction_deg: dy.atan2(dx).to_degrees(),
            mean_speed_m_s: if dt > 0.0 { dx.hypot(dy) / dt } else { 0.0 },
        })
    }
}

#[cfg(test)]
mod tests {
    use super::LaunchTracker;

    #[test]
    fn a_crossing_hidden_by_the_referee_moving_the_ball_is_extrapolated() {
        let mut t = LaunchTracker::new([20.0, 0.0], 27.5);
        // In play, rolling towards +x and +y; then play stops (goal kick) and the referee has
        // already put the ball in the goal area at the next sample.
        t.observe(0.0, Some([20.0, 0.0, 0.11]), true);
        t.observe(1.0, Some([26.5, 1.3, 0.11]), true);
        t.observe(1.1, Some([27.0, 1.4, 0.11]), true);
        // Read again before the monitor's next update.
        t.observe(1.15, Some([27.0, 1.4, 0.11]), true);
        t.observe(1.2, Some([26.5, 0.0, 0.11]), false);
        let y = t.goal_line_crossing(true).expect("extrapolated");
        assert!((y - 1.5).abs() < 1e-9, "{y}");
        // The same ball with play going on at the end (the run's time ran out): it may still
        // stop short, so no crossing is made up.
        assert_eq!(t.goal_line_crossing(false), None);
        // A ball that stopped far short of the line crossed nothing.
        let mut short = LaunchTracker::new([10.0, 0.0], 27.5);
        short.observe(0.0, Some([10.0, 0.0, 0.11]), true);
        short.observe(1.0, Some([20.0, 0.0, 0.11]), true);
        short.observe(1.1, Some([20.1, 0.0, 0.11]), true);
        assert_eq!(short.goal_line_crossing(true), None);
    }
}
