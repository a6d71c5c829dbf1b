//! Getting up from lying: key-frame motions from the parameter file, one for lying face down
//! and one for lying on the back, started by the fall detector. A frame that waits for an IMU
//! condition may switch to a recovery motion when the condition does not come.

mod motion;
#[cfg(test)]
mod tests;

pub(crate) use motion::validate_frames;
pub use motion::{
    Condition, GetUpBalance, GetUpParams, Keyframe, RestUntilStill, Sensed, SettleAfter,
};

use crate::walk::balance::Attitude;
use libero_model::RobotModel;
use libero_world::{Posture, World};

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Lying {
    Front,
    Back,
}

/// A get-up in progress.
#[derive(Debug, Clone)]
pub struct GetUp {
    running: Option<Run>,
    /// The last run's playhead, kept for the next one's memory.
    spare: Option<Playhead>,
    /// Since when the fall detector has reported lying without a break [s].
    lying_since: Option<f64>,
}

#[derive(Debug, Clone)]
struct Run {
    motion: Motion,
    head: Playhead,
}

/// Where a key-frame motion stands: the key frame being played, when it started, and the
/// pose it starts from (the measured angles for the first frame, the previous frame's target
/// after that). Shared by every key-frame skill (get-ups, saves).
#[derive(Debug, Clone)]
pub(crate) struct Playhead {
    pub(crate) frame: usize,
    pub(crate) frame_started_s: f64,
    pub(crate) from: Vec<f64>,
    /// The current frame's target pose (working memory of [`step`]).
    target: Vec<f64>,
    /// Since when the frame's `until` has held without a break.
    pub(crate) held_since: Option<f64>,
}

impl Playhead {
    /// At the first frame from `from` (usually the measured angles), now.
    pub(crate) fn start(from: &[f64], now: f64) -> Self {
        let mut head = Self {
            frame: 0,
            frame_started_s: now,
            from: Vec::new(),
            target: Vec::new(),
            held_since: None,
        };
        head.restart(from, now);
        head
    }

    /// A playhead with room for `joints` joints, for motions started later during play.
    pub(crate) fn with_room(joints: usize) -> Self {
        Self {
            frame: 0,
            frame_started_s: 0.0,
            from: Vec::with_capacity(joints),
            target: Vec::with_capacity(joints),
            held_since: None,
        }
    }

    /// As [`Playhead::start`], in this playhead's memory (a motion starts during play).
    pub(crate) fn restart(&mut self, from: &[f64], now: f64) {
        self.frame = 0;
        self.frame_started_s = now;
        self.from.clear();
        self.from.extend_from_slice(from);
        self.held_since = None;
    }
}

/// Which motion of the parameter file a run plays.
#[derive(Debug, Clone, PartialEq)]
enum Motion {
    Front,
    Back,
    Recover(std::sync::Arc<str>),
}

impl Motion {
    fn of(lying: Lying) -> Self {
        match lying {
            Lying::Front => Motion::Front,
            Lying::Back => Motion::Back,
        }
    }

    /// Its key frames; none when a reload removed a recovery motion mid-run (it then ends).
    fn frames<'p>(&self, p: &'p GetUpParams) -> &'p [Keyframe] {
        match self {
            Motion::Front => &p.front,
            Motion::Back => &p.back,
            Motion::Recover(name) => p.recover.get(&**name).map_or(&[], Vec::as_slice),
        }
    }
}

impl GetUp {
    pub fn new() -> Self {
        Self {
            running: None,
            spare: None,
            lying_since: None,
        }
    }

    /// Make room for a robot of `joints` joints now rather than at the first fall.
    pub fn with_room(mut self, joints: usize) -> Self {
        self.spare = Some(Playhead::with_room(joints));
        self
    }

    pub fn is_running(&self) -> bool {
        self.running.is_some()
    }

    /// Which way the robot lies, if it does. Lying on a side counts as the back: the back
    /// motion starts by rolling the body flat.
    pub fn lying(posture: Posture) -> Option<Lying> {
        match posture {
            Posture::Upright => None,
            Posture::FallenFront => Some(Lying::Front),
            Posture::FallenBack | Posture::FallenSide => Some(Lying::Back),
        }
    }

    /// One cycle: start when lying (or asked to), play the motion, and finish when it has
    /// played out. Returns false when no get-up is running, leaving `pose` alone.
    pub fn update(
        &mut self,
        world: &World,
        requested: bool,
        p: &GetUpParams,
        model: &RobotModel,
        pose: &mut [f64],
    ) -> bool {
        let lying = Self::lying(world.body.posture);
        self.lying_since = match (lying, self.lying_since) {
            (Some(_), Some(since)) => Some(since),
            (Some(_), None) => Some(world.time),
            (None, _) => None,
        };
        if self.running.is_none() {
            // Start only once the detector has reported lying for `rest_s` (or at once when
            // asked): a jolt, e.g. being placed by the referee, can fake a fall for a moment,
            // and a get-up started while standing throws the robot down.
            let lain = self.lying_since.map_or(0.0, |since| world.time - since);
            let settled = self.lying_since.is_some()
                && lain >= p.rest_s
                && p.rest_until_still.is_none_or(|r| {
                    lain >= r.at_most_s
                        || Sensed::from_body(&world.body).rate_deg_s < r.rate_below_deg_s
                });
            let Some(lying) = lying.filter(|_| settled || requested) else {
                return false;
            };
            let head = match self.spare.take() {
                Some(mut head) => {
                    head.restart(&world.body.joint_angles, world.time);
                    head
                }
                None => Playhead::start(&world.body.joint_angles, world.time),
            };
            let sensed = Sensed::from_body(&world.body);
            log::debug!(
                "get-up: t {:.2} {lying:?} motion starts after {:.2} s lying; pitch {:.0}°, roll {:.0}°, rate {:.0}°/s",
                world.time,
                lain,
                sensed.attitude.pitch_deg,
                sensed.attitude.roll_deg,
                sensed.rate_deg_s
            );
            self.running = Some(Run {
                motion: Motion::of(lying),
                head,
            });
        }
        let run = self.running.as_mut().expect("started above");
        let motion = run.motion.frames(p);
        let sensed = Sensed::from_body(&world.body);
        match step(&mut run.head, motion, world.time, &sensed, model, pose) {
            Step::Playing => {
                if let Some(lean) = motion.get(run.head.frame).and_then(|f| f.balance_pitch_deg) {
                    balance(&p.balance, &sensed.attitude, lean, model, pose);
                }
            }
            Step::Ended => match (&run.motion, p.back_then_front_from) {
                // The roll is over (its last frame waited for face down): on into the
                // front motion, from the pose the roll ended in.
                (Motion::Back, Some(k)) => run.switch_to(Motion::Front, k, world.time),
                _ => {
                    log::debug!(
                        "get-up: t {:.2} {:?} played out; pitch {:.0}°, roll {:.0}°, rate {:.0}°/s",
                        world.time,
                        run.motion,
                        sensed.attitude.pitch_deg,
                        sensed.attitude.roll_deg,
                        sensed.rate_deg_s
                    );
                    self.finish()
                }
            },
            // A sensed condition never came: play the frame's recovery motion from the pose
            // held now, or, without one, start over next cycle from the new posture if still
            // lying.
            Step::TimedOut(Some(recovery)) => {
                log::debug!(
                    "get-up: t {:.2} frame {} timed out: {recovery}",
                    world.time,
                    run.head.frame
                );
                run.switch_to(Motion::Recover(recovery), 0, world.time)
            }
            Step::TimedOut(None) => {
                log::debug!(
                    "get-up: t {:.2} {:?} frame {} timed out: start over",
                    world.time,
                    run.motion,
                    run.head.frame
                );
                self.finish()
            }
        }
        true
    }

    fn finish(&mut self) {
        self.spare = self.running.take().map(|run| run.head);
    }

    /// The recovery motion being played, if any (for traces and tests).
    pub fn recovering(&self) -> Option<&str> {
        match &self.running.as_ref()?.motion {
            Motion::Recover(name) => Some(name),
            _ => None,
        }
    }
}

impl Run {
    /// Go on with `motion` from its frame `frame`, starting from the pose reached so far.
    fn switch_to(&mut self, motion: Motion, frame: usize, now: f64) {
        self.motion = motion;
        self.head.frame = frame;
        self.head.frame_started_s = now;
        self.head.held_since = None;
    }
}

/// The stand after a get-up (`GetUpParams::settle`): when it began and since when the body
/// has been calm.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Settling {
    since: f64,
    calm_since: Option<f64>,
}

impl Settling {
    pub fn new(now: f64) -> Self {
        Self {
            since: now,
            calm_since: None,
        }
    }

    /// One cycle: whether the robot still has to stand (false once settled or out of time).
    pub fn goes_on(&mut self, p: &SettleAfter, sensed: &Sensed, now: f64) -> bool {
        if now - self.since >= p.at_most_s {
            return false;
        }
        if !p.calm(sensed) {
            self.calm_since = None;
            return true;
        }
        now - *self.calm_since.get_or_insert(now) < p.calm_s
    }
}

impl Default for GetUp {
    fn default() -> Self {
        Self::new()
    }
}

pub(crate) enum Step {
    Playing,
    Ended,
    /// A frame's `until` did not come in time; its `on_timeout` motion, if it has one.
    TimedOut(Option<std::sync::Arc<str>>),
}

fn target_of(frame: &Keyframe, from: &[f64], model: &RobotModel, target: &mut Vec<f64>) {
    target.clear();
    target.extend_from_slice(from);
    for (joint, &angle) in &frame.pose {
        if let Some(id) = model.joint_id(joint) {
            target[id] = angle;
        }
    }
}

/// Advance `run` to `now` and write its pose: frames end after `duration_s`, or for a frame
/// with `until`, once the condition has held for `hold_s` after that.
pub(crate) fn step(
    run: &mut Playhead,
    motion: &[Keyframe],
    now: f64,
    sensed: &Sensed,
    model: &RobotModel,
    pose: &mut [f64],
) -> Step {
    loop {
        let Some(frame) = motion.get(run.frame) else {
            pose.copy_from_slice(&run.from);
            return Step::Ended;
        };
        target_of(frame, &run.from, model, &mut run.target);
        let target = &run.target;
        let t = now - run.frame_started_s;
        let done = t >= frame.duration_s
            && match frame.until {
                None => true,
                Some(c) => {
                    run.held_since = c.holds(sensed).then(|| run.held_since.unwrap_or(now));
                    // (A hair of slack: cycle times arrive rounded to 10 ms.)
                    let held = run
                        .held_since
                        .is_some_and(|since| now - since >= frame.hold_s - 1e-6);
                    let out_of_time = t >= frame.duration_s + frame.timeout_s;
                    if !held && out_of_time && !frame.timeout_goes_on {
                        pose.copy_from_slice(target);
                        run.from.copy_from_slice(target);
                        return Step::TimedOut(frame.on_timeout.clone());
                    }
                    held || out_of_time
                }
            };
        if !done {
            let s = (t / frame.duration_s).clamp(0.0, 1.0);
            let w = s * s * (3.0 - 2.0 * s);
            for ((q, a), b) in pose.iter_mut().zip(&run.from).zip(target) {
                *q = a + (b - a) * w;
            }
            return Step::Playing;
        }
        // A timed frame ends at its nominal end; a sensed one when the condition came.
        run.frame_started_s = if frame.until.is_some() {
            now
        } else {
            run.frame_started_s + frame.duration_s
        };
        run.frame += 1;
        run.from.copy_from_slice(&run.target);
        run.held_since = None;
    }
}

/// Ankle and hip strategies against the torso pitch error during a balanced frame.
fn balance(b: &GetUpBalance, a: &Attitude, lean_deg: f64, model: &RobotModel, pose: &mut [f64]) {
    let error = a.pitch_deg - lean_deg;
    let rate = a.pitch_rate_deg_s;
    let limit = |v: f64| v.clamp(-b.max_deg, b.max_deg);
    // Leaning too far forward: toes down (ankle +) and hips back (hip pitch +) push it back.
    let ankle = limit(b.ankle_per_deg * error + b.ankle_per_gyro * rate);
    let hip = limit(b.hip_per_deg * error + b.hip_per_gyro * rate);
    for (joint, offset) in [
        ("left_ankle_pitch", ankle),
        ("right_ankle_pitch", ankle),
        ("left_hip_pitch", hip),
        ("right_hip_pitch", hip),
    ] {
        if let Some(id) = model.joint_id(joint) {
            let (lo, hi) = model.joints[id].limits_deg;
            pose[id] = (pose[id] + offset).clamp(lo, hi);
        }
    }
}
