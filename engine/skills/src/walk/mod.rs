//! Omnidirectional walk: velocity command → step pattern → leg IK → IMU corrections.
//!
//! [`gait`] places the soles step by step in a level frame that moves with the torso;
//! [`Walk`] turns those placements into joint angles with the model's leg IK and adds the
//! balance loop of [`balance`]. The executed command follows the requested one within the
//! acceleration limits of the parameter file, and a new command only shapes the next step,
//! so changes mid-walk are smooth. Starting blends into the walk posture and shifts weight
//! before the first lift; stopping walks the feet back together before the walk goes idle.

pub mod balance;
pub mod gait;
pub mod kick_step;
pub mod params;
pub mod walk_to;

use balance::{corrections, Attitude};
use gait::{Foot, Gait, SolePlacement, Step};
use libero_model::kinematics::{Kinematics, KinematicsError, LegIk};
use libero_model::{JointId, RobotModel};
use libero_world::World;
use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};
pub use params::{BalanceParams, WalkParams, WalkToParams};

/// The serde default of the `face_travel_beyond_deg` fields (kick approach, dribble): off, an
/// arc round the ball is never longer than 180°.
pub(crate) fn face_travel_off() -> f64 {
    360.0
}

/// A walk command in the robot's own frame.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Velocity {
    /// [m/s], + forwards
    pub forward_m_s: f64,
    /// [m/s], + to the left
    pub sideways_m_s: f64,
    /// [deg/s], + counter-clockwise (to the left)
    pub turn_deg_s: f64,
}

impl Velocity {
    /// The same direction of travel with the translational speed at most `limit` [m/s].
    pub fn capped(self, limit: Option<f64>) -> Velocity {
        let speed = self.forward_m_s.hypot(self.sideways_m_s);
        match limit {
            Some(limit) if speed > limit && speed > 0.0 => {
                let k = limit.max(0.0) / speed;
                Velocity {
                    forward_m_s: self.forward_m_s * k,
                    sideways_m_s: self.sideways_m_s * k,
                    ..self
                }
            }
            _ => self,
        }
    }

    /// Within the walk's forward, backward and sideways limits, keeping the direction of
    /// travel (both components scaled together when one exceeds its limit).
    pub fn within_limits(self, p: &WalkParams) -> Velocity {
        let forward_limit = if self.forward_m_s >= 0.0 {
            p.max_forward_m_s
        } else {
            p.max_backward_m_s
        };
        let scale = [
            self.forward_m_s.abs() / forward_limit.max(1e-6),
            self.sideways_m_s.abs() / p.max_sideways_m_s.max(1e-6),
            1.0,
        ]
        .into_iter()
        .fold(0.0f64, f64::max);
        Velocity {
            forward_m_s: self.forward_m_s / scale,
            sideways_m_s: self.sideways_m_s / scale,
            ..self
        }
    }

    fn is_zero(&self) -> bool {
        self.forward_m_s.abs() < 1e-4
            && self.sideways_m_s.abs() < 1e-4
            && self.turn_deg_s.abs() < 1e-2
    }
}

#[derive(Debug, Clone, Copy, PartialEq)]
enum Phase {
    /// Holding the walk posture, not stepping.
    Idle,
    /// Holding the walk posture until the blend into it is done [s left].
    Settling(f64),
    Walking,
}

/// The joints the walk touches besides the IK's six per leg.
#[derive(Debug, Clone, Copy)]
struct LegJoints {
    hip_pitch: JointId,
    hip_roll: JointId,
    ankle_pitch: JointId,
    ankle_roll: JointId,
    shoulder_pitch: Option<JointId>,
}

impl LegJoints {
    fn find(model: &RobotModel, side: &str) -> Result<Self, KinematicsError> {
        let id = |short: &str| {
            let name = format!("{side}_{short}");
            model
                .joint_id(&name)
                .ok_or(KinematicsError::UnknownJoint(name))
        };
        Ok(Self {
            hip_pitch: id("hip_pitch")?,
            hip_roll: id("hip_roll")?,
            ankle_pitch: id("ankle_pitch")?,
            ankle_roll: id("ankle_roll")?,
            shoulder_pitch: id("shoulder_pitch").ok(),
        })
    }
}

/// The walk engine of one robot.
pub struct Walk {
    kin: Kinematics,
    legs: [LegIk; 2],
    joints: [LegJoints; 2],
    gait: Gait,
    phase: Phase,
    /// The command being executed (the request, rate-limited).
    executed: Velocity,
    last_time: Option<f64>,
    /// The latest joint solution, reused as the IK's starting point.
    angles: Vec<f64>,
    /// The foot a kick step is asked of this cycle and its shift across (see
    /// [`Walk::ask_kick_step`]).
    kick_step_foot: Option<(Foot, f64)>,
    /// Kick steps begun since the walk was made.
    kick_steps: u32,
    /// The lean added to `torso_lean_deg` for the executed command's acceleration [deg].
    accel_lean_deg: f64,
}

/// Server cycle [s], used when the percept carries no usable time step.
const NOMINAL_CYCLE_S: f64 = 0.02;

impl Walk {
    pub fn new(model: &RobotModel) -> Result<Self, KinematicsError> {
        let kin = Kinematics::new(model);
        let legs = LegIk::both(model, &kin)?;
        Ok(Self {
            joints: [
                LegJoints::find(model, "left")?,
                LegJoints::find(model, "right")?,
            ],
            kin,
            legs,
            gait: Gait::default(),
            phase: Phase::Idle,
            executed: Velocity::default(),
            last_time: None,
            angles: vec![0.0; model.joints.len()],
            kick_step_foot: None,
            kick_steps: 0,
            accel_lean_deg: 0.0,
        })
    }

    /// Ask that the next step of `foot` be a kick step (`walk.kick_step`) whose strike
    /// shifts the foot `across_m` sideways (+ left), for this cycle's update only: the step
    /// begins as a kick step if it begins during that update. `None` withdraws the request.
    pub fn ask_kick_step(&mut self, kick: Option<(Foot, f64)>) {
        self.kick_step_foot = kick;
    }

    /// Kick steps begun since the walk was made.
    pub fn kick_steps(&self) -> u32 {
        self.kick_steps
    }

    /// True during a kick step.
    pub fn kicking(&self) -> bool {
        self.phase == Phase::Walking && self.gait.kick().is_some()
    }

    /// True while steps are being made (including the closing steps after a stop request).
    pub fn is_stepping(&self) -> bool {
        self.phase == Phase::Walking
    }

    /// The command currently executed (after rate limits).
    pub fn executed(&self) -> Velocity {
        self.executed
    }

    /// Forget any motion in progress (after a fall or a beam).
    pub fn reset(&mut self) {
        self.phase = Phase::Idle;
        self.gait = Gait::default();
        self.executed = Velocity::default();
        self.accel_lean_deg = 0.0;
    }

    /// The torso's lean from vertical the walk holds now [deg]: the file's lean plus the
    /// lean into the executed command's acceleration.
    fn lean_deg(&self, p: &WalkParams) -> f64 {
        p.torso_lean_deg + self.accel_lean_deg
    }

    /// One cycle. `request` = walk with this velocity; `None` = come to a stop. Writes the leg
    /// (and arm swing) angles into `pose`, leaving other joints as they are.
    pub fn update(
        &mut self,
        world: &World,
        request: Option<Velocity>,
        p: &WalkParams,
        pose: &mut [f64],
    ) {
        let dt = match self.last_time {
            Some(t) if world.time > t && world.time - t < 0.1 => world.time - t,
            _ => NOMINAL_CYCLE_S,
        };
        self.last_time = Some(world.time);
        let wanted = request.map(|v| clamp_command(v, p)).unwrap_or_default();
        let forward_before = self.executed.forward_m_s;
        match self.phase {
            Phase::Idle if request.is_some() => self.phase = Phase::Settling(p.settle_s),
            Phase::Idle => {}
            Phase::Settling(left) if left > dt => self.phase = Phase::Settling(left - dt),
            Phase::Settling(_) => {
                self.phase = Phase::Walking;
                self.executed = Velocity::default();
                // Weight shift first: a step without a stride (and a low lift), led by the foot
                // on the side the command goes to.
                let first = if wanted.sideways_m_s < 0.0 || wanted.turn_deg_s < 0.0 {
                    Foot::Right
                } else {
                    Foot::Left
                };
                self.gait
                    .begin_step(first, Step::default(), p.start_lift_scale);
            }
            Phase::Walking => {
                self.executed = rate_limit(self.executed, wanted, p, dt);
                let period = self.gait.period_s(p);
                if self.gait.advance(dt, period) {
                    if request.is_none() && self.executed.is_zero() && self.gait.feet_together() {
                        self.phase = Phase::Idle;
                    } else {
                        // Leaning back, the next step lands further back to catch the body
                        // (and further forward when leaning forward).
                        let tilt = Attitude::from_world(world).pitch_deg - self.lean_deg(p);
                        let stopping = request.is_none() && self.executed.is_zero();
                        let step = Step {
                            x: self.executed.forward_m_s * p.step_period_s
                                + capture_x(tilt, stopping, &p.balance),
                            y: self.executed.sideways_m_s * p.step_period_s,
                            yaw_deg: self.executed.turn_deg_s * p.step_period_s,
                        };
                        let swing = self.gait.swing.other();
                        match (p.kick_step, self.kick_step_foot) {
                            (Some(kick), Some((foot, across)))
                                if foot == swing && request.is_some() =>
                            {
                                self.kick_steps += 1;
                                log::debug!(
                                    "walk: t {:.2} kick step {swing:?} across {across:.3} at {:.2} m/s",
                                    world.time,
                                    self.executed.forward_m_s
                                );
                                self.gait.begin_kick_step(swing, step, kick, across);
                            }
                            _ => self.gait.begin_step(swing, step, 1.0),
                        }
                    }
                }
            }
        }
        self.kick_step_foot = None;
        self.follow_acceleration(forward_before, p, dt);
        let placements = if self.phase == Phase::Walking {
            self.gait.placements(p)
        } else {
            Gait::default().placements_at_rest(p)
        };
        self.solve(world, &placements, p, pose);
    }

    /// Move the acceleration lean towards `lean_per_accel_deg` times this cycle's change of
    /// the executed forward speed (from `forward_before`), over one step period; standing, back
    /// to none.
    fn follow_acceleration(&mut self, forward_before: f64, p: &WalkParams, dt: f64) {
        let accel = if self.phase == Phase::Walking {
            (self.executed.forward_m_s - forward_before) / dt
        } else {
            0.0
        };
        let wanted = p.balance.lean_per_accel_deg * accel;
        self.accel_lean_deg += (wanted - self.accel_lean_deg) * (dt / p.step_period_s).min(1.0);
    }

    fn solve(
        &mut self,
        world: &World,
        soles: &[SolePlacement; 2],
        p: &WalkParams,
        pose: &mut [f64],
    ) {
        let lean_deg = self.lean_deg(p);
        let level_to_torso =
            UnitQuaternion::from_axis_angle(&Vector3::y_axis(), -lean_deg.to_radians());
        self.angles.copy_from_slice(pose);
        for (leg, sole) in self.legs.iter().zip(soles) {
            let in_level = Isometry3::from_parts(
                Translation3::new(sole.x, sole.y, sole.z),
                UnitQuaternion::from_axis_angle(&Vector3::z_axis(), sole.yaw_deg.to_radians()),
            );
            let in_torso =
                Isometry3::from_parts(Translation3::identity(), level_to_torso) * in_level;
            // The IK never writes NaN and returns the closest pose when out of reach, which
            // is the best the robot can do; an error only means a non-finite target.
            if let Err(e) = leg.solve(&self.kin, &in_torso, &mut self.angles) {
                log::warn!("walk: leg IK failed: {e}");
            }
        }
        let attitude = Attitude::from_world(world);
        let c = corrections(&p.balance, &attitude, lean_deg);
        let c = if self.phase == Phase::Walking {
            c
        } else {
            c.scaled(p.balance.rest_correction_scale)
        };
        for (k, j) in self.joints.iter().enumerate() {
            self.angles[j.ankle_pitch] += c.ankle_pitch;
            self.angles[j.hip_pitch] += c.hip_pitch;
            self.angles[j.ankle_roll] += c.ankle_roll;
            self.angles[j.hip_roll] += c.hip_roll;
            // Arms swing with the opposite leg, as in human gait, to cancel the legs' yaw moment.
            if let Some(shoulder) = j.shoulder_pitch {
                let other_foot_x = soles[1 - k].x - p.foot_x_offset_m;
                self.angles[shoulder] = pose[shoulder] - p.arm_swing_deg_per_m * other_foot_x;
            }
        }
        pose.copy_from_slice(&self.angles);
    }
}

impl Gait {
    /// Both soles at their neutral places, flat on the ground.
    pub fn placements_at_rest(&self, p: &WalkParams) -> [SolePlacement; 2] {
        [Foot::Left, Foot::Right].map(|foot| SolePlacement {
            x: p.foot_x_offset_m,
            y: foot.sign() * p.foot_y_offset_m,
            z: -p.torso_height_m,
            yaw_deg: 0.0,
        })
    }
}

/// The request within the parameter file's speed limits. Each limit holds alone, and a
/// combined forward + sideways + turn command is scaled down (direction kept) onto the
/// ellipsoid through the three limits: full speed one way and full speed another at once is
/// a step the legs cannot make (diagonal commands at both limits fell in 300 s courses).
pub fn clamp_command(v: Velocity, p: &WalkParams) -> Velocity {
    let clamped = Velocity {
        forward_m_s: v.forward_m_s.clamp(-p.max_backward_m_s, p.max_forward_m_s),
        sideways_m_s: v
            .sideways_m_s
            .clamp(-p.max_sideways_m_s, p.max_sideways_m_s),
        turn_deg_s: v.turn_deg_s.clamp(-p.max_turn_deg_s, p.max_turn_deg_s),
    };
    let forward_limit = if clamped.forward_m_s >= 0.0 {
        p.max_forward_m_s
    } else {
        p.max_backward_m_s
    };
    let share = |value: f64, limit: f64| if limit > 0.0 { value / limit } else { 0.0 };
    let norm = (share(clamped.forward_m_s, forward_limit).powi(2)
        + share(clamped.sideways_m_s, p.max_sideways_m_s).powi(2)
        + share(clamped.turn_deg_s, p.max_turn_deg_s).powi(2))
    .sqrt();
    if norm <= 1.0 {
        return clamped;
    }
    Velocity {
        forward_m_s: clamped.forward_m_s / norm,
        sideways_m_s: clamped.sideways_m_s / norm,
        turn_deg_s: clamped.turn_deg_s / norm,
    }
}

/// Move `from` towards `to` by at most one cycle's worth of each acceleration limit.
/// The capture step's shift of the next foot placement [m] for a pitch error `tilt_deg`:
/// none for a small error while the walk is coming to a stop (`stopping`), so the feet can
/// come together.
fn capture_x(tilt_deg: f64, stopping: bool, b: &BalanceParams) -> f64 {
    if stopping && tilt_deg.abs() < b.stop_capture_min_deg {
        0.0
    } else {
        b.step_x_per_tilt_m * tilt_deg
    }
}

/// The forward axis's rate limit for a change from `from` to `to` [m/s²]: slowing down (a
/// smaller speed, or one the other way) at the deceleration, speeding up at the acceleration.
fn forward_rate(from: Velocity, to: Velocity, p: &WalkParams) -> f64 {
    if from.forward_m_s * (to.forward_m_s - from.forward_m_s) < 0.0 {
        p.decel_forward_m_s2()
    } else {
        p.accel_forward_m_s2
    }
}

fn rate_limit(from: Velocity, to: Velocity, p: &WalkParams, dt: f64) -> Velocity {
    let towards = |a: f64, b: f64, max_step: f64| a + (b - a).clamp(-max_step, max_step);
    Velocity {
        forward_m_s: towards(
            from.forward_m_s,
            to.forward_m_s,
            forward_rate(from, to, p) * dt,
        ),
        sideways_m_s: towards(
            from.sideways_m_s,
            to.sideways_m_s,
            p.accel_sideways_m_s2 * dt,
        ),
        turn_deg_s: towards(from.turn_deg_s, to.turn_deg_s, p.accel_turn_deg_s2 * dt),
    }
}

#[cfg(test)]
mod tests;
