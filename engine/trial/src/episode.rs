//! One scripted episode on a real server, recorded from the ground truth.

use crate::scripted::{Confirm, Fall, ScriptedDecider};
use libero_agent::{run_agent, AgentConfig, AgentStats, Player};
use libero_model::RobotModel;
use libero_server::{Monitor, ServerKind, ServerOptions, ServerProcess};
use libero_skills::getup::Lying;
use libero_skills::{Intent, SkillParams, SkillStatus, Skills};
use libero_world::{Posture, World};
use std::sync::atomic::AtomicBool;
use std::sync::{Arc, Mutex};

/// SimSpark's monitor reports every second cycle [s]: a truth this much older than the
/// percept is of the same moment.
const MONITOR_STEP_S: f64 = 0.04;
/// How long a cycle's truth may wait for the monitor to catch up with the agent.
const MONITOR_CATCH_UP: std::time::Duration = std::time::Duration::from_millis(200);

#[derive(Debug, thiserror::Error)]
pub enum TrialError {
    #[error(transparent)]
    Server(#[from] libero_server::ServerError),
    #[error("monitor: {0}")]
    Monitor(std::io::Error),
    #[error(transparent)]
    Params(#[from] libero_skills::ParamsError),
    #[error(transparent)]
    Agent(#[from] libero_agent::run::AgentError),
    #[error("the episode recorded nothing: the agent never got a percept")]
    Empty,
    /// An evaluation run elsewhere (a job on another process or machine) failed.
    #[error("evaluation failed: {0}")]
    Elsewhere(String),
    /// The episode asks for something this server cannot do yet.
    #[error("not available on this server: {0}")]
    Unsupported(&'static str),
    #[error("checkpoint {path}: {detail}")]
    Checkpoint { path: String, detail: String },
}

/// The robot's state at one cycle, from the server's ground truth.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sample {
    /// Seconds since the script started.
    pub t: f64,
    /// Torso position [m], world frame.
    pub position: [f64; 3],
    /// Torso heading [deg], world frame.
    pub yaw_deg: f64,
    /// Torso pitch (+ nose down) and roll (+ right side down) [deg], world frame.
    pub pitch_deg: f64,
    pub roll_deg: f64,
    /// Angle between the torso's long axis and the vertical [deg]: 0 upright, 90 lying.
    pub tilt_deg: f64,
    /// The posture the agent's own fall detector reported.
    pub posture: Posture,
    /// The torso below [`FALLEN_SHARE_OF_STANDING`] of the robot's standing height.
    pub low: bool,
    /// The torso at least [`STOOD_SHARE_OF_STANDING`] of the robot's standing height (a
    /// get-up has stood once it is this high and upright).
    pub tall: bool,
    /// Where the agent believed it was (global x, y [m]), once localized: compared with
    /// `position`, the localization error.
    pub estimate: Option<[f64; 2]>,
}

impl Sample {
    /// Lying or collapsed: torso far below walking height, or the fall detector says so.
    pub fn fallen(&self) -> bool {
        self.low || self.posture != Posture::Upright
    }
}

/// Torso heights below this count as a T1's fall (walking height is about 0.6 m).
pub const FALLEN_TORSO_Z_M: f64 = 0.4;

/// A torso below this share of the model's standing height has fallen (the T1's 0.4 m of
/// 0.67 m).
pub const FALLEN_SHARE_OF_STANDING: f64 = 0.6;

/// A torso at least this share of the model's standing height stands (the T1's 0.6 m of
/// 0.67 m; its stand pose holds 0.66 m, lying below 0.3 m).
pub const STOOD_SHARE_OF_STANDING: f64 = 0.89;

/// Everything recorded during the script.
#[derive(Debug, Clone, Default)]
pub struct Recording {
    pub samples: Vec<Sample>,
    /// The intent the script asked for at each sample.
    pub intents: Vec<Intent>,
}

impl Recording {
    pub fn fell(&self) -> bool {
        self.samples.iter().any(Sample::fallen)
    }

    /// Seconds until the first fall.
    pub fn first_fall_s(&self) -> Option<f64> {
        self.samples.iter().find(|s| s.fallen()).map(|s| s.t)
    }

    /// Number of separate falls (fallen after having been upright).
    pub fn falls(&self) -> usize {
        let mut count = 0;
        let mut down = false;
        for s in &self.samples {
            if s.fallen() && !down {
                count += 1;
            }
            down = s.fallen();
        }
        count
    }
}

/// How a lying robot is placed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LyingPlacement {
    /// Face down or on the back.
    pub side: Lying,
    /// Turned about the torso's long axis from lying flat [deg]; + turns the body's left side
    /// up when face down. Real falls rarely end exactly flat.
    pub roll_deg: f64,
}

impl LyingPlacement {
    pub fn flat(side: Lying) -> Self {
        Self {
            side,
            roll_deg: 0.0,
        }
    }

    /// The torso orientation (w, x, y, z) for a robot heading `heading_deg`: turned about the
    /// world's z axis, pitched ±90° about the body's y axis onto the ground, then rolled about
    /// the torso's long (z) axis.
    pub fn orientation(&self, heading_deg: f64) -> [f64; 4] {
        let pitch = match self.side {
            Lying::Front => std::f64::consts::FRAC_PI_2,
            Lying::Back => -std::f64::consts::FRAC_PI_2,
        };
        let about = |axis: [f64; 3], angle: f64| {
            let (s, c) = (angle / 2.0).sin_cos();
            [c, axis[0] * s, axis[1] * s, axis[2] * s]
        };
        let q = quat_mul(
            about([0.0, 0.0, 1.0], heading_deg.to_radians()),
            about([0.0, 1.0, 0.0], pitch),
        );
        quat_mul(q, about([0.0, 0.0, 1.0], self.roll_deg.to_radians()))
    }
}

fn quat_mul(a: [f64; 4], b: [f64; 4]) -> [f64; 4] {
    let [aw, ax, ay, az] = a;
    let [bw, bx, by, bz] = b;
    [
        aw * bw - ax * bx - ay * by - az * bz,
        aw * bx + ax * bw + ay * bz - az * by,
        aw * by - ax * bz + ay * bw + az * bx,
        aw * bz + ax * by - ay * bx + az * bw,
    ]
}

/// What to do in an episode.
pub struct Episode<S> {
    /// Where the monitor places the robot: world x, y [m], heading [deg].
    pub start: [f64; 3],
    /// Place the robot lying instead of standing.
    pub lying: Option<LyingPlacement>,
    /// Stand this long after being placed before the script starts [s].
    pub settle_s: f64,
    /// Called every cycle with the world and the seconds since the script started; `None` ends
    /// the episode.
    pub script: S,
}

/// One server and its monitor, for many episodes.
pub struct Trial {
    server: ServerProcess,
    /// The one monitor connection of this server: rcsssmj 0.2.1 can crash when monitors
    /// connect or leave while it steps, so there is exactly one, for the server's lifetime.
    monitor: Arc<Mutex<Monitor>>,
    model: Arc<RobotModel>,
    episodes: u32,
    /// Episodes run on the current server process.
    episodes_on_server: u32,
    /// What the skills of the running episode made of the latest intent.
    status: Arc<Mutex<SkillStatus>>,
}

/// Where a trial's robot is first placed, 3.5 m out from our goal line facing +x, clear of
/// the ball at the centre: `[x, y, heading_deg]` for a server's field.
pub fn start_point(server: ServerKind) -> [f64; 3] {
    let half_length = match server {
        ServerKind::RcssMj => 27.5,
        ServerKind::SimSpark => 15.0,
    };
    [-(half_length - 3.5), 0.0, 0.0]
}

/// Torso height at which the monitor places the robot: soles just on the ground (§3.2).
const PLACE_TORSO_Z_M: f64 = 0.6735;
/// Torso height at which a lying robot is placed (just above its resting height).
const LYING_TORSO_Z_M: f64 = 0.25;
const TEAM: &str = "Libero";
/// Tries per episode when the server dies while the agent joins.
const JOIN_ATTEMPTS: u32 = 3;
const UNUM: u32 = 1;
/// rcsssmj 0.2.1 keeps about 100 MB per agent that joined and left (measured: 264 → 969 MB
/// over 8 joins), and every episode is a join: a fresh process every this many episodes keeps
/// a long optimizer run within a few GB.
const EPISODES_PER_SERVER: u32 = 20;

impl Trial {
    /// Start a fresh fast-mode rcssservermj for the T1.
    pub fn start() -> Result<Self, TrialError> {
        Self::start_on(Arc::new(
            RobotModel::builtin("T1").expect("the T1 model is built in"),
        ))
    }

    /// Start a fresh fast-mode server of `model`'s kind for it (a NAO type: SimSpark).
    pub fn start_on(model: Arc<RobotModel>) -> Result<Self, TrialError> {
        let server = ServerProcess::start(ServerOptions {
            server: model.server,
            ..ServerOptions::default()
        })?;
        let monitor = Arc::new(Mutex::new(
            Monitor::connect_to(model.server, server.monitor_port).map_err(TrialError::Monitor)?,
        ));
        Ok(Self {
            server,
            monitor,
            model,
            episodes: 0,
            episodes_on_server: 0,
            status: Arc::default(),
        })
    }

    pub fn model(&self) -> &Arc<RobotModel> {
        &self.model
    }

    /// The server's monitor, shared with the running episode.
    pub fn monitor(&self) -> Arc<Mutex<Monitor>> {
        Arc::clone(&self.monitor)
    }

    /// The skill status of the running episode, updated every cycle (scripts watch a kick's
    /// progress with it).
    pub fn skill_status(&self) -> Arc<Mutex<SkillStatus>> {
        Arc::clone(&self.status)
    }

    /// The ball's resting height on this server's field: its centre one radius up [m].
    pub fn ball_rest_z_m(&self) -> f64 {
        libero_model::FieldGeometry::builtin(self.model.server.default_field())
            .expect("shipped fields are valid")
            .ball_radius
    }

    /// The monitor command that puts the ball at rest at `at` (world frame).
    pub fn ball_placement(&self, at: [f64; 2]) -> String {
        format!(
            "(ball (pos {} {} {})(vel 0 0 0))",
            at[0],
            at[1],
            self.ball_rest_z_m()
        )
    }

    /// The torso below this height [m] (ground truth) is a fallen robot.
    pub fn fallen_below_m(&self) -> f64 {
        self.model.standing_torso_height * FALLEN_SHARE_OF_STANDING
    }

    pub fn server(&self) -> &ServerProcess {
        &self.server
    }

    /// Run one episode with `params` and return what the ground truth shows. rcsssmj 0.2.1
    /// sometimes dies while an agent joins (audio engine and monitor races); then the server
    /// is restarted and the episode run again from the start.
    pub fn run<S>(
        &mut self,
        params: &SkillParams,
        episode: Episode<S>,
    ) -> Result<Recording, TrialError>
    where
        S: FnMut(&World, f64) -> Option<Intent> + Clone + Send + 'static,
    {
        if self.episodes_on_server >= EPISODES_PER_SERVER {
            self.restart()?;
        }
        let mut attempt = 0;
        loop {
            attempt += 1;
            let copy = Episode {
                start: episode.start,
                lying: episode.lying,
                settle_s: episode.settle_s,
                script: episode.script.clone(),
            };
            match self.run_once(params, copy) {
                Err(e @ (TrialError::Agent(_) | TrialError::Empty)) if attempt < JOIN_ATTEMPTS => {
                    log::warn!("trial: episode lost ({e}); restarting the server");
                    self.restart()?;
                }
                other => return other,
            }
        }
    }

    /// A fresh server process and monitor on the same ports.
    pub fn restart(&mut self) -> Result<(), TrialError> {
        self.server.restart()?;
        self.episodes_on_server = 0;
        let monitor = Monitor::connect_to(self.model.server, self.server.monitor_port)
            .map_err(TrialError::Monitor)?;
        *self
            .monitor
            .lock()
            .map_err(|_| TrialError::Monitor(std::io::Error::other("monitor lock poisoned")))? =
            monitor;
        Ok(())
    }

    fn run_once<S>(
        &mut self,
        params: &SkillParams,
        episode: Episode<S>,
    ) -> Result<Recording, TrialError>
    where
        S: FnMut(&World, f64) -> Option<Intent> + Send + 'static,
    {
        self.episodes += 1;
        self.episodes_on_server += 1;
        if let Ok(mut s) = self.status.lock() {
            *s = SkillStatus::default();
        }
        let skills = Skills::new(&self.model, params.clone())?;
        let recording = Arc::new(Mutex::new(Recording::default()));
        let shutdown = Arc::new(AtomicBool::new(false));
        let [x, y, heading] = episode.start;
        let simspark = self.model.server == ServerKind::SimSpark;
        let place = match episode.lying {
            // SimSpark holds a placement only outside BeforeKickOff, and its move yaw 0
            // faces +y (simspark.md §7). It has no placement with a whole orientation: a lying
            // robot is placed standing and falls by a motion of its own (`motions.fall_front`
            // / `fall_back`); the roll is whatever the fall leaves. The game clock goes back to
            // 0 each episode: at 300 s the half ends, the mode becomes BeforeKickOff and the
            // referee moves a robot in the other half away mid-episode (a bench kick lost).
            _ if simspark => format!(
                "(time 0)(playMode PlayOn)(agent (unum {UNUM}) (team Left) (move {x} {y} {} {}))",
                self.model.standing_torso_height + 0.01,
                heading - 90.0
            ),
            None => format!(
                "(agent (unum {UNUM}) (team Left) (move {x} {y} {PLACE_TORSO_Z_M} {heading}))"
            ),
            Some(lying) => {
                let [w, qx, qy, qz] = lying.orientation(heading);
                format!("(agent (unum {UNUM}) (team Left) (move3d {x} {y} {LYING_TORSO_Z_M} {w} {qx} {qy} {qz}))")
            }
        };
        let low_below_m = self.model.standing_torso_height * FALLEN_SHARE_OF_STANDING;
        let fall = match episode.lying {
            Some(lying) if simspark => {
                let name = match lying.side {
                    Lying::Front => "fall_front",
                    Lying::Back => "fall_back",
                };
                let motion = params.motion_id(name).ok_or(TrialError::Unsupported(
                    "lying placements on SimSpark without the parameter file's `motions.fall_front` and `motions.fall_back` (it has no `move3d`: the robot falls by itself)",
                ))?;
                Some(Fall::by(motion))
            }
            _ => None,
        };
        let decider = ScriptedDecider {
            low_below_m,
            tall_from_m: self.model.standing_torso_height * STOOD_SHARE_OF_STANDING,
            script: episode.script,
            settle_s: episode.settle_s,
            recording: Arc::clone(&recording),
            shutdown: Arc::clone(&shutdown),
            placed_at: None,
            fall,
            place_command: place,
            // SimSpark ignores a placement of a robot whose init has not yet taken effect,
            // and the agent cannot tell it from its percepts: the monitor's truth confirms it.
            confirm: simspark.then(|| Confirm::at([x, y])),
            monitor: Arc::clone(&self.monitor),
            status: Arc::clone(&self.status),
        };
        let stats = Arc::new(AgentStats::default());
        let mut player = Player::new(
            Arc::clone(&self.model),
            skills,
            Box::new(decider),
            TEAM,
            UNUM,
            Arc::clone(&stats),
        );
        if simspark {
            // The server waits for this agent, so waiting for the monitor to reach the
            // percept's play time keeps truth and estimate in step (the reader fell ~0.3 s
            // behind: the NAO's localization read 18-19 cm at 0.6 m/s against an older truth).
            let snapshot_at = self
                .monitor
                .lock()
                .map_err(|_| TrialError::Monitor(std::io::Error::other("monitor lock poisoned")))?
                .reader_at(MONITOR_STEP_S, MONITOR_CATCH_UP);
            player.set_truth_feed(Arc::new(move |left, unum, play_time| {
                let robots = snapshot_at(play_time).robots;
                let robot = robots.iter().find(|r| r.left == left && r.unum == unum)?;
                Some(libero_world::GroundTruth {
                    torso_position: Some(robot.torso),
                    torso_orientation: Some(robot.orientation()),
                })
            }));
        }
        let mut config = AgentConfig::new("127.0.0.1", self.server.agent_port);
        config.max_connect_failures = Some(20);
        config.silence_timeout = std::time::Duration::from_secs(5);
        run_agent(&config, &mut player, &shutdown)?;
        drop(player);
        // Dynamic motions (get-ups, kicks) depend on every cycle's action arriving on time.
        let missed = AgentStats::get(&stats.missed_cycles);
        if missed > 0 {
            log::warn!("trial: the agent missed {missed} server cycles in this episode");
        }
        let recording = std::mem::take(&mut *recording.lock().expect("recording lock"));
        if recording.samples.is_empty() {
            return Err(TrialError::Empty);
        }
        Ok(recording)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// World direction of a body axis under orientation `q` (w, x, y, z).
    fn rotate(q: [f64; 4], v: [f64; 3]) -> [f64; 3] {
        let p = quat_mul(
            quat_mul(q, [0.0, v[0], v[1], v[2]]),
            [q[0], -q[1], -q[2], -q[3]],
        );
        [p[1], p[2], p[3]]
    }

    fn close(a: [f64; 3], b: [f64; 3]) -> bool {
        a.iter().zip(b).all(|(x, y)| (x - y).abs() < 1e-9)
    }

    #[test]
    fn lying_placements_face_the_ground_or_the_sky_and_roll_about_the_long_axis() {
        let front = LyingPlacement::flat(Lying::Front).orientation(0.0);
        // Chest (body x) down, head (body z) towards the heading.
        assert!(close(rotate(front, [1.0, 0.0, 0.0]), [0.0, 0.0, -1.0]));
        assert!(close(rotate(front, [0.0, 0.0, 1.0]), [1.0, 0.0, 0.0]));
        let back = LyingPlacement::flat(Lying::Back).orientation(90.0);
        assert!(close(rotate(back, [1.0, 0.0, 0.0]), [0.0, 0.0, 1.0]));
        assert!(close(rotate(back, [0.0, 0.0, 1.0]), [0.0, -1.0, 0.0]));
        // Rolled face down: the long axis stays horizontal, the left side comes up.
        let rolled = LyingPlacement {
            side: Lying::Front,
            roll_deg: 20.0,
        }
        .orientation(30.0);
        let head = rotate(rolled, [0.0, 0.0, 1.0]);
        assert!(head[2].abs() < 1e-9);
        let left = rotate(rolled, [0.0, 1.0, 0.0]);
        assert!((left[2] - 20f64.to_radians().sin()).abs() < 1e-9);
    }
}
