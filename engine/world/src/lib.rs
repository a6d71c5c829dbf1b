//! The agent's beliefs about itself, the game, the ball and the other players.
//!
//! Updated once per cycle from a percept ([`World::update`]), read by decisions and skills.
//!
//! * [`World::me`] — own torso pose from vision + IMU + leg odometry ([`localization`]).
//! * [`World::ball`] — ball position, velocity, and predictions ([`ball`], [`ball_motion`]).
//! * [`World::players`] — teammates and opponents, remembered with their age ([`players`]).
//! * [`World::body`], [`World::game`] — joints, IMU, posture; play mode, side, score.
//!
//! **Frames.** Every estimate is in the server's *global* field frame (origin at the centre
//! spot, +x towards the right goal, +y to the left of +x, yaw 0 = facing +x), whichever side we
//! play on. [`frames`] gives the global, own-team and robot frames distinct point types;
//! [`World::side`] and [`World::pose`] convert between them (the own frame has the own goal at −x:
//! for the right team it is the global frame turned 180°).
//!
//! **Ground truth.** The server's `pos`/`quat` (rcssservermj) are kept apart in
//! [`GroundTruth`] for logs and tests; no estimate reads them.
//!
//! Tunable constants live in `params/world.ron` ([`WorldParams`]).

pub mod ball;
pub mod ball_launch;
pub mod ball_motion;
pub mod body;
pub mod camera_calibration;
pub mod eval_log;
pub mod frames;
pub mod game;
pub mod geometry;
pub mod localization;
pub mod params;
pub mod players;
pub mod team_message;

pub use ball::BallEstimate;
pub use body::{BodyState, Posture};
pub use frames::{Global, Own, Pose, Robot, TeamSide};
pub use game::{GameState, PlayMode, Side};
pub use localization::SelfEstimate;
pub use params::{BodyParams, WorldParams};
pub use players::{PlayerEstimate, Players, Relation};

use libero_model::kinematics::Kinematics;
use libero_model::{FieldGeometry, RobotModel};
use libero_protocol::Percept;

/// A message said in answer to percept k is heard with percept k + 2 (both servers).
const HEARD_LATENCY_S: f64 = 0.04;
/// A teammate's ball sighting replaces ours only when newer by this much [s] (ours also knows
/// where the ball went since).
const HEARD_BALL_NEWER_BY_S: f64 = 0.3;
/// A player tells where it saw the ball only within this long of the sighting [s].
const TOLD_BALL_WITHIN_S: f64 = 3.0;
/// Claims older than this are forgotten [s].
const CLAIM_MEMORY_S: f64 = 2.0;

/// A teammate's latest word on the ball.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct BallClaim {
    pub unum: u32,
    /// Its time to reach the ball [s] (`None`: not claiming).
    pub time_to_ball_s: Option<f64>,
    /// It is going for the ball.
    pub going_for_ball: bool,
    /// It is lying down (its own word: a teammate seen from afar is often judged fallen).
    pub fallen: bool,
    /// When it said so [s].
    pub at: f64,
}

/// What teammates told us: each one's latest claim to the ball, and message counts.
#[derive(Debug, Clone, Default, serde::Serialize)]
pub struct HeardNews {
    /// Per teammate, its latest claim.
    pub claims: Vec<BallClaim>,
    /// Messages taken and rejected (malformed, foreign, garbage).
    pub taken: u64,
    pub rejected: u64,
}

impl HeardNews {
    fn claim(&mut self, claim: BallClaim) {
        self.claims
            .retain(|c| c.unum != claim.unum && claim.at - c.at <= CLAIM_MEMORY_S);
        self.claims.push(claim);
    }

    /// Teammates' claims said within `CLAIM_MEMORY_S` of `now`.
    pub fn recent_claims(&self, now: f64) -> impl Iterator<Item = &BallClaim> + '_ {
        self.claims
            .iter()
            .filter(move |c| now - c.at <= CLAIM_MEMORY_S)
    }
}
use localization::Localizer;
use std::sync::Arc;

/// What the server says is true, for evaluation only.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct GroundTruth {
    pub torso_position: Option<[f64; 3]>,
    /// w, x, y, z
    pub torso_orientation: Option<[f64; 4]>,
}

/// A ball sighting at most this old [s] is used as seen from the camera (vision arrives every
/// second cycle).
pub const FRESH_BALL_SIGHTING_S: f64 = 0.1;

/// Everything the agent believes at the current cycle.
#[derive(Debug, Clone)]
pub struct World {
    /// Server simulation time [s].
    pub time: f64,
    /// Cycles seen since the agent connected.
    pub cycle: u64,
    pub game: GameState,
    pub body: BodyState,
    /// Own torso pose (global frame).
    pub me: SelfEstimate,
    pub ball: BallEstimate,
    pub players: Players,
    pub truth: GroundTruth,
    /// The ball as last seen, in the robot frame (x forwards, y left) at that moment, and the
    /// time [s]. Taken straight from the camera, so errors of the self-estimate cancel.
    pub ball_seen_relative: Option<(f64, [f64; 2])>,
    /// What teammates told us lately.
    pub heard: HeardNews,
    pub field: Arc<FieldGeometry>,
    pub params: Arc<WorldParams>,
    localizer: Localizer,
    last_time: Option<f64>,
}

impl World {
    /// A world on the server's default field: `fifa7vs7` for rcssservermj robots, `simspark`
    /// for SimSpark robots, with the shipped parameters.
    pub fn new(model: &RobotModel, team: &str, unum: u32) -> Self {
        let field =
            FieldGeometry::builtin(model.server.default_field()).expect("shipped fields are valid");
        Self::with_field(model, field, team, unum)
    }

    /// A world on a given field, with the shipped parameters.
    pub fn with_field(model: &RobotModel, field: FieldGeometry, team: &str, unum: u32) -> Self {
        Self::with_params(model, field, WorldParams::builtin(), team, unum)
    }

    pub fn with_params(
        model: &RobotModel,
        field: FieldGeometry,
        params: WorldParams,
        team: &str,
        unum: u32,
    ) -> Self {
        let localizer = Localizer::new(model, Kinematics::new(model), params.localization.clone());
        Self {
            time: 0.0,
            cycle: 0,
            game: GameState::new(team, unum),
            body: BodyState::new(model),
            me: SelfEstimate::default(),
            ball: BallEstimate::new(&params.ball),
            players: Players::default(),
            truth: GroundTruth::default(),
            ball_seen_relative: None,
            heard: HeardNews::default(),
            field: Arc::new(field),
            params: Arc::new(params),
            localizer,
            last_time: None,
        }
    }

    /// Fold one percept into the beliefs.
    pub fn update(&mut self, model: &RobotModel, percept: &Percept<'_>) {
        self.cycle += 1;
        if let Some(t) = percept.time.filter(|t| t.is_finite()) {
            self.time = t;
        }
        let dt = self.last_time.map_or(0.0, |before| self.time - before);
        self.last_time = Some(self.time);
        self.game.update(&percept.game);
        self.body.update(model, percept, &self.params.body);
        self.localizer.update(
            &self.field,
            &self.body.joint_angles,
            percept.gyro,
            percept.accel,
            percept.vision.as_ref(),
            self.time,
            dt,
            self.body.posture == Posture::Upright,
        );
        self.me = self.localizer.estimate().clone();
        self.update_ball_and_players(percept);
        self.hear_teammates(&percept.heard);
        self.truth = GroundTruth {
            torso_position: percept.truth_position,
            torso_orientation: percept.truth_orientation,
        };
    }

    fn update_ball_and_players(&mut self, percept: &Percept<'_>) {
        // Ourselves first: our feet in view tell the camera's offset, taken out of the rest.
        if let Some(me) = percept.vision.as_ref().and_then(|v| {
            v.players
                .iter()
                .find(|p| p.team == self.game.team && p.unum == self.game.unum)
        }) {
            self.localizer.observe_own_parts(&me.parts);
        }
        let vision = percept.vision.as_ref().filter(|_| self.me.localized);
        let localizer = &self.localizer;
        let to_field = |p: &nalgebra::Point3<f64>| localizer.camera_to_field(p);
        let seen_ball = vision
            .and_then(|v| v.ball.as_ref())
            .and_then(geometry::polar_to_point)
            .and_then(|p| to_field(&p));
        if let Some(b) = seen_ball {
            let yaw = self.me.yaw_deg.to_radians();
            let (dx, dy) = (b.x - self.me.position[0], b.y - self.me.position[1]);
            let relative = [
                dx * yaw.cos() + dy * yaw.sin(),
                -dx * yaw.sin() + dy * yaw.cos(),
            ];
            if geometry::finite2(relative) {
                self.ball_seen_relative = Some((self.time, relative));
            }
        }
        self.ball.update(self.time, seen_ball);
        for player in vision.map(|v| v.players.as_slice()).unwrap_or_default() {
            let relation = if player.team == self.game.team {
                Relation::Teammate
            } else {
                Relation::Opponent
            };
            if relation == Relation::Teammate && player.unum == self.game.unum {
                continue;
            }
            let parts = players::parts_in_field(&player.parts, to_field);
            self.players.saw(
                &self.params.players,
                relation,
                player.unum,
                parts,
                self.time,
            );
        }
        self.players.forget_old(&self.params.players, self.time);
    }

    /// Teammates' messages: their positions and falls, a ball sighting newer than ours, their
    /// claims to the ball. Anything that fails the team check is dropped (and counted).
    fn hear_teammates(&mut self, heard: &[libero_protocol::percept::Heard<'_>]) {
        use libero_protocol::percept::HeardFrom;
        for h in heard {
            if h.from == HeardFrom::Myself || h.team.is_some_and(|t| t != self.game.team) {
                continue;
            }
            let message =
                match team_message::TeamMessage::decode(h.message, &self.game.team, &self.field) {
                    Ok(m) if m.unum != 0 && u32::from(m.unum) != self.game.unum => m,
                    Ok(_) => continue,
                    Err(_) => {
                        self.heard.rejected += 1;
                        continue;
                    }
                };
            self.heard.taken += 1;
            let said_at = self.time - HEARD_LATENCY_S;
            let unum = u32::from(message.unum);
            self.players.heard(
                Relation::Teammate,
                unum,
                message.position,
                Some(message.fallen),
                said_at,
            );
            if let Some((ball, age)) = message.ball {
                self.ball
                    .hear(self.time, said_at - age, ball, HEARD_BALL_NEWER_BY_S);
            }
            self.heard.claim(BallClaim {
                unum,
                time_to_ball_s: message.time_to_ball_s,
                going_for_ball: message.going_for_ball,
                fallen: message.fallen,
                at: said_at,
            });
        }
    }

    /// The message this player says when it has the channel: its own estimates only (what it
    /// heard is not passed on, so stale news does not circulate).
    pub fn team_message(
        &self,
        time_to_ball_s: Option<f64>,
        going_for_ball: bool,
    ) -> team_message::TeamMessage {
        let ball = self
            .ball
            .last_seen_time
            .map(|t| self.time - t)
            .filter(|age| *age <= TOLD_BALL_WITHIN_S)
            .map(|age| (self.ball.position, age));
        team_message::TeamMessage {
            unum: u8::try_from(self.game.unum).unwrap_or(0),
            position: self.me.position,
            fallen: self.body.posture != Posture::Upright,
            ball,
            time_to_ball_s,
            going_for_ball,
        }
    }

    /// Which way round our team plays: global ↔ own frame.
    pub fn side(&self) -> TeamSide {
        TeamSide::of(self.game.side)
    }

    /// Our own estimated pose on the field.
    pub fn pose(&self) -> Pose {
        Pose::new(Global::from_array(self.me.position), self.me.yaw_deg)
    }

    /// A global-frame point in our team's own frame (own goal at −x).
    pub fn to_own_frame(&self, p: [f64; 2]) -> [f64; 2] {
        self.side().own(Global::from_array(p)).to_array()
    }

    /// A global-frame heading [deg] in our team's own frame.
    pub fn yaw_to_own_frame(&self, yaw_deg: f64) -> f64 {
        self.side().own_heading_deg(yaw_deg)
    }

    /// The ball in the robot frame (x forwards, y left) [m]: the latest sighting when it is at
    /// most `fresh_s` old (callers without a reason of their own use [`FRESH_BALL_SIGHTING_S`];
    /// straight from the camera, so a wrong self-estimate does not matter), otherwise the field
    /// estimate seen from the self-estimate.
    pub fn ball_relative(&self, fresh_s: f64) -> [f64; 2] {
        match self.ball_seen_relative {
            Some((t, b)) if self.time - t <= fresh_s => b,
            _ => self
                .pose()
                .robot(Global::from_array(self.ball.position))
                .to_array(),
        }
    }

    /// Ground-truth torso position and heading [deg], when the server sends them.
    pub fn truth_pose(&self) -> Option<([f64; 3], f64)> {
        Some((
            self.truth.torso_position?,
            geometry::heading_deg_of_quaternion(self.truth.torso_orientation?),
        ))
    }
}

#[cfg(test)]
mod synthetic;
#[cfg(test)]
mod world_tests;
