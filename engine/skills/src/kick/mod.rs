//! Kicks (thesis 6.3.2): walk to the kicking place behind the ball from wherever the robot is,
//! then kick with a motion whose foot targets are placed relative to the ball by the leg IK.
//!
//! [`approach`] plans the walk there (around the ball when coming from its front), [`motion`]
//! the kick itself: weight onto the support leg, wind-up, a fast swing through the ball with stiff
//! kicking-leg gains, and back to standing. The long kick swings hard enough for 6 m or more,
//! the short kick gently; [`params::KickParams::long_kick_from_m`] chooses by requested distance.

mod aim;
pub mod approach;
pub mod motion;
pub mod params;

pub use aim::{aimed_for_curve, KickGeometry};

use crate::walk::balance::Attitude;
use crate::walk::gait::{Foot, SolePlacement};
use crate::walk::{Velocity, WalkParams};
use approach::ApproachStep;
use libero_model::kinematics::{Kinematics, KinematicsError, LegIk};
use libero_model::RobotModel;
use libero_world::World;
use motion::{MotionPlan, Phase};
use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};
pub use params::{ApproachPath, KickApproach, KickFrames, KickMotion, KickParams, KickSpread};

/// Where a kick request stands; callers (behavior nodes) succeed on `Done`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum KickState {
    /// No kick requested.
    Idle,
    /// Walking to the kicking place.
    Approaching,
    /// The kick motion runs.
    Kicking,
    /// The kick motion has finished. Stays so while the same kick is requested; request
    /// something else for one cycle to kick again.
    Done,
}

/// The kick request of one cycle, robot frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct KickRequest {
    pub ball: [f64; 2],
    pub direction_deg: f64,
    pub distance_m: f64,
}

/// What the kick wants from the rest of the skill layer this cycle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum KickOutput {
    /// Walk with this command (`None`: come to a stop).
    Walk(Option<Velocity>),
    /// The kick motion owns the legs: [`Kick::write_pose`] fills them in.
    Motion,
    /// Stand.
    Stand,
}

/// What the kick needs to know of the body this cycle.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct BodyNow {
    /// The walk is still making steps (also its closing steps after a stop).
    pub walk_stepping: bool,
    /// The velocity the walk executes (after its rate limits).
    pub walk_velocity: Velocity,
    /// The torso's largest roll or pitch rate [deg/s].
    pub rate_deg_s: f64,
}

/// Ball positions asked for while standing still: their bounding box and mean.
#[derive(Debug, Clone, Copy, Default)]
struct Sightings {
    lo: [f64; 2],
    hi: [f64; 2],
    sum: [f64; 2],
    count: u32,
}

impl Sightings {
    fn add(&mut self, ball: [f64; 2]) {
        if self.count == 0 {
            self.lo = ball;
            self.hi = ball;
        }
        for (i, v) in ball.into_iter().enumerate() {
            self.lo[i] = self.lo[i].min(v);
            self.hi[i] = self.hi[i].max(v);
            self.sum[i] += v;
        }
        self.count += 1;
    }

    /// The larger side of the bounding box [m].
    fn spread(&self) -> f64 {
        (self.hi[0] - self.lo[0]).max(self.hi[1] - self.lo[1])
    }

    fn mean(&self) -> [f64; 2] {
        let n = f64::from(self.count.max(1));
        [self.sum[0] / n, self.sum[1] / n]
    }
}

/// A kick motion in progress.
#[derive(Debug, Clone)]
struct Running {
    plan: MotionPlan,
    started_s: f64,
    long: bool,
    /// Key frames play instead of the plan (`KickMotion::keyframes`).
    keyframed: bool,
}

/// The kick skill of one robot.
pub struct Kick {
    kin: Kinematics,
    legs: [LegIk; 2],
    state: KickState,
    /// The foot chosen when alignment began (kept so the robot does not dither between sides).
    foot: Option<Foot>,
    running: Option<Running>,
    /// Since when the robot has stood still near the kicking place (`None`: stepping).
    still_since: Option<f64>,
    /// Since when its torso rates have stayed below `calm_rate_deg_s` (`None`: swaying).
    calm_since: Option<f64>,
    /// The ball positions asked for since the robot stood still (robot frame).
    seen_while_still: Option<Sightings>,
    /// Whether the walk was stepping when last waited for (for logging).
    stepping_seen: bool,
    /// A correction walk near the kicking place runs until then.
    correcting_until: Option<f64>,
    /// Stopped (or correcting) near the kicking place.
    looking: bool,
    /// Looks at the kicking place since the last free walk that did not find it ready.
    failed_looks: u32,
    /// Stepping back from the kicking place for a fresh approach until then.
    retreating_until: Option<f64>,
    angles: Vec<f64>,
    /// The key-frame kick's playhead (started from the measured angles at its first cycle)
    /// and whether its frames have played out.
    head: crate::getup::Playhead,
    frames_started: bool,
    frames_ended: bool,
}

impl Kick {
    pub fn new(model: &RobotModel) -> Result<Self, KinematicsError> {
        let kin = Kinematics::new(model);
        let legs = LegIk::both(model, &kin)?;
        Ok(Self {
            kin,
            legs,
            state: KickState::Idle,
            foot: None,
            running: None,
            still_since: None,
            calm_since: None,
            seen_while_still: None,
            stepping_seen: false,
            correcting_until: None,
            looking: false,
            failed_looks: 0,
            retreating_until: None,
            angles: vec![0.0; model.joints.len()],
            head: crate::getup::Playhead::with_room(model.joints.len()),
            frames_started: false,
            frames_ended: false,
        })
    }

    pub fn state(&self) -> KickState {
        self.state
    }

    /// The foot of the kick in progress or being aligned for.
    pub fn foot(&self) -> Option<Foot> {
        self.foot
    }

    /// True while the long kick's swing is running (its gains apply).
    fn swinging(&self, now: f64) -> bool {
        self.running.as_ref().is_some_and(|r| {
            !r.keyframed
                && matches!(
                    r.plan.at(now - r.started_s).phase,
                    Phase::Windup | Phase::Swing | Phase::Retract
                )
        })
    }

    /// Forget the kick (another intent, a fall).
    pub fn reset(&mut self) {
        self.state = KickState::Idle;
        self.foot = None;
        self.running = None;
        self.still_since = None;
        self.calm_since = None;
        self.seen_while_still = None;
        self.correcting_until = None;
        self.looking = false;
        self.failed_looks = 0;
        self.retreating_until = None;
    }

    /// Standing still from now on (or still), with `ball` asked for this cycle: the ball
    /// position to judge the kicking place by (the look's mean) once the look is over, after
    /// `look_s`, or after `steady_look_s` when the ball positions asked for since the robot
    /// stopped agree within `steady_m`.
    fn look(&mut self, ball: [f64; 2], now: f64, a: &KickApproach) -> Option<[f64; 2]> {
        if self.still_since.is_none() {
            log::debug!("kick: t {now:.2} standing still: look");
        }
        let still = *self.still_since.get_or_insert(now);
        let seen = self.seen_while_still.get_or_insert_with(Sightings::default);
        seen.add(ball);
        let looked = now - still;
        let done = looked >= a.look_s || (seen.spread() <= a.steady_m && looked >= a.steady_look_s);
        if done {
            log::trace!(
                "kick: t {now:.2} looked {looked:.2} s, {} sightings within {:.3} m",
                seen.count,
                seen.spread()
            );
        }
        done.then(|| seen.mean())
    }

    /// Stepping again: the next look starts afresh.
    fn not_still(&mut self) {
        self.still_since = None;
        self.calm_since = None;
        self.seen_while_still = None;
    }

    /// Whether the torso rates have stayed below `calm_rate_deg_s` for `calm_s`.
    fn calm(&mut self, rate_deg_s: f64, now: f64, a: &KickApproach) -> bool {
        if rate_deg_s > a.calm_rate_deg_s {
            self.calm_since = None;
            return false;
        }
        now - *self.calm_since.get_or_insert(now) >= a.calm_s
    }

    /// One cycle without a kick request: a kick motion under way plays on to its end (a
    /// one-cycle change of mind, e.g. the tree's fall check tripped by the swing's own jolt,
    /// must not leave the robot standing on one leg mid-swing); otherwise the kick is
    /// forgotten. `None` when no motion runs.
    pub fn carry_on(&mut self, now: f64) -> Option<KickOutput> {
        if self.state != KickState::Kicking {
            self.reset();
            return None;
        }
        if self.motion_over(now) {
            self.reset();
            return None;
        }
        Some(KickOutput::Motion)
    }

    /// The kick motion has played out (or none runs).
    fn motion_over(&self, now: f64) -> bool {
        self.running.as_ref().is_none_or(|r| {
            if r.keyframed {
                self.frames_ended
            } else {
                now - r.started_s >= r.plan.duration_s()
            }
        })
    }

    /// A key-frame kick is playing (its gains are the model's, and nothing blends into it).
    pub fn playing_keyframes(&self) -> bool {
        self.running.as_ref().is_some_and(|r| r.keyframed)
    }

    /// One cycle of a kick request. The kick starts only once the robot stands still at the
    /// kicking place and its body has stopped swaying.
    pub fn update(
        &mut self,
        request: KickRequest,
        now: f64,
        body: BodyNow,
        k: &KickParams,
        w: &WalkParams,
    ) -> KickOutput {
        match self.state {
            KickState::Done => return KickOutput::Stand,
            KickState::Kicking => {
                if self.motion_over(now) {
                    self.running = None;
                    self.state = KickState::Done;
                    return KickOutput::Stand;
                }
                return KickOutput::Motion;
            }
            KickState::Idle | KickState::Approaching => {}
        }
        if self.state == KickState::Idle {
            log::debug!("kick: t {now:.2} requested, ball at {:.3?}", request.ball);
        }
        self.state = KickState::Approaching;
        let a = &k.approach;
        let near = request.ball[0].hypot(request.ball[1]) < a.align_within_m + a.ball_ahead_m;
        let foot = match self.foot {
            Some(f) if near => f,
            _ => approach::natural_foot(request.ball, request.direction_deg),
        };
        self.foot = near.then_some(foot);
        // A key-frame kick sends the ball off the heading by its own aim: face off by as much.
        let long = request.distance_m >= k.long_kick_from_m;
        let m = if long { &k.long } else { &k.short };
        let facing_deg = if m.keyframes.is_some() {
            request.direction_deg + foot.sign() * m.keyframe_aim_deg
        } else {
            request.direction_deg
        };
        // Near the place the estimates taken while walking are too rough for the kick's
        // tolerances (the walk sways the camera): stop, look while standing, then either kick
        // or walk a short correction and look again.
        if let Some(until) = self.retreating_until {
            if now < until {
                return KickOutput::Walk(Some(Velocity {
                    forward_m_s: -a.align_speed_m_s,
                    ..Velocity::default()
                }));
            }
            self.retreating_until = None;
        }
        let travel = if body.walk_stepping {
            approach::stopping_travel(body.walk_velocity, a, w)
        } else {
            [0.0; 3]
        };
        // Walking (on the move or correcting), the robot stops only well within the tolerances;
        // standing, it is judged by them.
        let walking = body.walk_stepping || self.correcting_until.is_some();
        let moving = approach::Moving {
            looking: self.looking,
            travel,
            tolerance_scale: if walking { a.stop_within } else { 1.0 },
        };
        let step = approach::step(request.ball, facing_deg, foot, moving, a, w);
        let looking = !matches!(step, ApproachStep::Walk(_));
        if looking != self.looking {
            log::debug!(
                "kick: t {now:.2} {} ({step:?}, ball at ({:.3}, {:.3}), stop travel {travel:.3?}, walking at {:.3} m/s)",
                if looking {
                    "near the place: stop"
                } else {
                    "walk on"
                },
                request.ball[0],
                request.ball[1],
                body.walk_velocity.forward_m_s,
            );
        }
        self.looking = looking;
        let correction = match step {
            ApproachStep::Walk(v) => {
                log::trace!(
                    "kick: t {now:.2} approach {v:?}, ball at {:.3?}",
                    request.ball
                );
                self.failed_looks = 0;
                self.correcting_until = None;
                self.not_still();
                return KickOutput::Walk(Some(v));
            }
            ApproachStep::Align(v) => v,
            ApproachStep::Ready => Velocity::default(),
        };
        if let Some(until) = self.correcting_until {
            if now < until && step != ApproachStep::Ready {
                return KickOutput::Walk(Some(correction));
            }
            self.correcting_until = None;
        }
        if body.walk_stepping {
            if !self.stepping_seen {
                log::debug!("kick: t {now:.2} stopping");
            }
            self.stepping_seen = true;
            self.not_still();
            return KickOutput::Walk(None);
        }
        self.stepping_seen = false;
        // The look runs from the moment the feet stand still; the errors are judged (and the
        // kick started) once it is over and the body has stopped swaying: a body still
        // swaying from the last steps starts the kick tilted, and the swing's own sideways
        // jolt then throws it over.
        let looked = self.look(request.ball, now, a);
        let calm = self.calm(body.rate_deg_s, now, a);
        let Some(ball) = looked.filter(|_| calm) else {
            return KickOutput::Walk(None);
        };
        let request = KickRequest { ball, ..request };
        let step = approach::step(
            ball,
            facing_deg,
            foot,
            approach::Moving {
                looking: true,
                travel: [0.0; 3],
                tolerance_scale: 1.0,
            },
            a,
            w,
        );
        let correction = match step {
            ApproachStep::Walk(v) | ApproachStep::Align(v) => v,
            ApproachStep::Ready => Velocity::default(),
        };
        match step {
            ApproachStep::Walk(_) | ApproachStep::Align(_) => {
                log::debug!(
                    "kick: t {now:.2} not ready: ball at ({:.3}, {:.3}), direction {:.1}°; correcting with {correction:?}",
                    request.ball[0],
                    request.ball[1],
                    request.direction_deg
                );
                self.not_still();
                self.failed_looks += 1;
                // Short corrections that do not get there (small sideways steps barely move the
                // robot) are given up for a fresh approach, which aligns on the move.
                if self.failed_looks >= a.looks_before_retreat {
                    self.failed_looks = 0;
                    self.retreating_until = Some(now + a.retreat_s);
                    log::debug!("kick: t {now:.2} step back");
                    return KickOutput::Walk(None);
                }
                self.correcting_until = Some(now + a.correction_s);
                KickOutput::Walk(Some(correction))
            }
            ApproachStep::Ready => {
                // The residual direction error is made up by turning the kicking foot.
                let plan = MotionPlan::new(
                    foot,
                    request.ball,
                    request.direction_deg,
                    k.ball_radius_m,
                    k.toe_ahead_of_ankle_m,
                    m,
                    w,
                );
                log::debug!(
                    "kick: t {now:.2} {} kick with the {foot:?} foot, ball at ({:.3}, {:.3}), direction {:.1}°",
                    if long { "long" } else { "short" },
                    request.ball[0],
                    request.ball[1],
                    request.direction_deg
                );
                self.foot = Some(foot);
                self.running = Some(Running {
                    plan,
                    started_s: now,
                    long,
                    keyframed: m.keyframes.is_some(),
                });
                self.frames_started = false;
                self.frames_ended = false;
                self.state = KickState::Kicking;
                KickOutput::Motion
            }
        }
    }

    /// The kick motion's leg angles for this cycle into `pose` [deg per joint].
    pub fn write_pose(
        &mut self,
        world: &World,
        k: &KickParams,
        frames: &KickFrames,
        model: &RobotModel,
        pose: &mut [f64],
    ) {
        let Some(r) = &self.running else { return };
        if r.keyframed {
            if !self.frames_started {
                self.head.restart(&world.body.joint_angles, world.time);
                self.frames_started = true;
            }
            let sensed = crate::getup::Sensed::from_body(&world.body);
            let motion = frames.get(r.long, r.plan.foot);
            match crate::getup::step(&mut self.head, motion, world.time, &sensed, model, pose) {
                crate::getup::Step::Playing => {}
                crate::getup::Step::Ended | crate::getup::Step::TimedOut(_) => {
                    self.frames_ended = true;
                }
            }
            return;
        }
        let now = world.time;
        let frame = r.plan.at(now - r.started_s);
        let level_to_torso =
            UnitQuaternion::from_axis_angle(&Vector3::y_axis(), -frame.lean_deg.to_radians());
        let m = if r.long { &k.long } else { &k.short };
        // Coming back down, the kicking foot looks for the ground where it is below the tilted
        // torso (the agent's own filtered roll and pitch).
        let landing = matches!(frame.phase, Phase::Retract | Phase::Recover);
        let tilt = UnitQuaternion::from_euler_angles(
            world.me.roll_deg.to_radians(),
            world.me.pitch_deg.to_radians(),
            0.0,
        );
        let landing_to_torso = landing_rotation(level_to_torso, tilt, m.landing_tilt_gain);
        self.angles.copy_from_slice(pose);
        for (i, (leg, sole)) in self.legs.iter().zip(&frame.soles).enumerate() {
            let to_torso = if landing && i == r.plan.foot.index() {
                landing_to_torso
            } else {
                level_to_torso
            };
            let target =
                Isometry3::from_parts(Translation3::identity(), to_torso) * sole_pose(sole);
            // The IK never writes NaN and gives the closest pose when out of reach; an error
            // only means a non-finite target.
            if let Err(e) = leg.solve(&self.kin, &target, &mut self.angles) {
                log::warn!("kick: leg IK failed: {e}");
            }
        }
        // Gyro damping on the stance ankle, as in the walk: one foot carries the body and its
        // rolling and pitching must be stopped early.
        let attitude = Attitude::from_body(&world.body);
        let limit = |v: f64| v.clamp(-m.stance_max_correction_deg, m.stance_max_correction_deg);
        let stance = self.legs[r.plan.foot.other().index()].joints();
        // Booster and NAO legs both end in ankle pitch, ankle roll.
        self.angles[stance[4]] += limit(m.stance_pitch_per_gyro * attitude.pitch_rate_deg_s);
        self.angles[stance[5]] += limit(m.stance_roll_per_gyro * attitude.roll_rate_deg_s);
        pose.copy_from_slice(&self.angles);
    }

    /// The kicking foot and whether the kick is long, while the swing is on (the kicking
    /// leg is stiffened then).
    pub fn swinging_with(&self, now: f64) -> Option<(Foot, bool)> {
        let running = self.running.as_ref()?;
        self.swinging(now)
            .then_some((running.plan.foot, running.long))
    }
}

/// From the level frame of the plan to the torso frame for a foot coming down: the planned
/// lean, blended by `gain` towards the torso's measured `tilt` (torso to level), which already
/// holds the lean.
fn landing_rotation(
    level_to_torso: UnitQuaternion<f64>,
    tilt: UnitQuaternion<f64>,
    gain: f64,
) -> UnitQuaternion<f64> {
    level_to_torso.slerp(&tilt.inverse(), gain)
}

fn sole_pose(s: &SolePlacement) -> Isometry3<f64> {
    Isometry3::from_parts(
        Translation3::new(s.x, s.y, s.z),
        UnitQuaternion::from_axis_angle(&Vector3::z_axis(), s.yaw_deg.to_radians()),
    )
}

#[cfg(test)]
mod tests;
