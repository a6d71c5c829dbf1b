//! Getting up from lying: key-frame motions from the parameter file, one for lying face down
//! and one for lying on the back, started by the fall detector.

use crate::walk::balance::Attitude;
use crate::walk::params::in_range;
use libero_model::{Gains, RobotModel};
use libero_world::{BodyState, Posture, World};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// One key frame: reach `pose` (joint name → deg; unlisted joints keep the previous frame's
/// angle) in `duration_s`, moving smoothly from the previous frame.
#[derive(Debug, Clone, Deserialize, Serialize, PartialEq)]
pub struct Keyframe {
    pub duration_s: f64,
    pub pose: BTreeMap<String, f64>,
    /// Hold the pose after `duration_s` until the IMU reports this, so the next frame starts
    /// from a sensed state rather than a moment in time (the dynamic phases are chaotic in
    /// time). Not met within `timeout_s` more: the motion gives up and starts over.
    #[serde(default)]
    pub until: Option<Condition>,
    #[serde(default = "default_timeout_s")]
    pub timeout_s: f64,
    /// Torso pitch [deg, + nose down] this frame should end at; when given, the ankles and
    /// hips push against the measured deviation (`get_up.balance`) during the frame.
    #[serde(default)]
    pub balance_pitch_deg: Option<f64>,
}

fn default_timeout_s() -> f64 {
    1.0
}

/// A state of the torso read from the agent's own IMU (accelerometer-derived attitude).
#[derive(Debug, Clone, Copy, Deserialize, Serialize, PartialEq)]
pub enum Condition {
    /// Torso pitch above this [deg, + nose down].
    TorsoPitchAbove(f64),
    /// Torso pitch below this [deg].
    TorsoPitchBelow(f64),
    /// Torso within this many degrees of vertical (pitch and roll).
    UprightWithin(f64),
    /// The torso's front within `within_deg` of pointing straight down (lying face down, not
    /// on a side: there gravity has almost no x and z part and the pitch angle is noise), and
    /// turning slower than `rate_below_deg_s`: a roll that is still going, or rocking back,
    /// is not a start for the face-down motion.
    FaceDown {
        within_deg: f64,
        rate_below_deg_s: f64,
    },
}

/// What the `until` conditions read, all from the agent's own IMU.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Sensed {
    pub attitude: Attitude,
    /// Angle between the torso's front (+x) and straight down [deg]: 0 face down, 90 on a
    /// side, upright or head down, 180 on the back.
    pub from_face_down_deg: f64,
    /// Magnitude of the gyro's rate [deg/s].
    pub rate_deg_s: f64,
}

impl Sensed {
    pub fn from_body(body: &BodyState) -> Self {
        let [gx, gy, gz] = body.gravity;
        let norm = (gx * gx + gy * gy + gz * gz).sqrt();
        // The specific force points up: face down it points along the torso's −x.
        let from_face_down_deg = if norm > 1e-6 {
            (-gx / norm).clamp(-1.0, 1.0).acos().to_degrees()
        } else {
            90.0
        };
        let [wx, wy, wz] = body.gyro;
        Self {
            attitude: Attitude::from_body(body),
            from_face_down_deg,
            rate_deg_s: (wx * wx + wy * wy + wz * wz).sqrt(),
        }
    }
}

impl Condition {
    pub fn holds(self, s: &Sensed) -> bool {
        let a = &s.attitude;
        match self {
            Condition::TorsoPitchAbove(deg) => a.pitch_deg > deg,
            Condition::TorsoPitchBelow(deg) => a.pitch_deg < deg,
            Condition::UprightWithin(deg) => a.pitch_deg.abs() < deg && a.roll_deg.abs() < deg,
            Condition::FaceDown {
                within_deg,
                rate_below_deg_s,
            } => s.from_face_down_deg < within_deg && s.rate_deg_s < rate_below_deg_s,
        }
    }

    fn validate(self, at: &str) -> Result<(), String> {
        match self {
            Condition::TorsoPitchAbove(d) | Condition::TorsoPitchBelow(d) => {
                in_range(&format!("{at}.until"), d, -180.0, 180.0)
            }
            Condition::UprightWithin(d) => in_range(&format!("{at}.until"), d, 0.0, 90.0),
            Condition::FaceDown {
                within_deg,
                rate_below_deg_s,
            } => {
                in_range(&format!("{at}.until.within_deg"), within_deg, 0.0, 90.0)?;
                in_range(
                    &format!("{at}.until.rate_below_deg_s"),
                    rate_below_deg_s,
                    0.0,
                    1000.0,
                )
            }
        }
    }
}

/// Balance feedback in key frames with `balance_pitch_deg`: offsets added to both ankle and
/// hip pitch targets [deg per deg of pitch error, deg per deg/s of pitch rate].
#[derive(Debug, Clone, Copy, Deserialize, Serialize, PartialEq)]
pub struct GetUpBalance {
    pub ankle_per_deg: f64,
    pub ankle_per_gyro: f64,
    pub hip_per_deg: f64,
    pub hip_per_gyro: f64,
    pub max_deg: f64,
}

impl Default for GetUpBalance {
    fn default() -> Self {
        Self {
            ankle_per_deg: 0.0,
            ankle_per_gyro: 0.0,
            hip_per_deg: 0.0,
            hip_per_gyro: 0.0,
            max_deg: 0.0,
        }
    }
}

/// The get-up motions.
#[derive(Debug, Clone, Deserialize, Serialize, PartialEq)]
pub struct GetUpParams {
    /// Lying face down.
    pub front: Vec<Keyframe>,
    /// Lying on the back.
    pub back: Vec<Keyframe>,
    /// Gains during the motions, by joint name; others keep the model's defaults.
    pub gains: BTreeMap<String, Gains>,
    /// Wait this long lying still before starting, so the body has come to rest [s].
    pub rest_s: f64,
    #[serde(default)]
    pub balance: GetUpBalance,
    /// When set, the back motion (a roll onto the front) runs straight on into the front
    /// motion from this key frame, without the hand-off through the fall detector: the
    /// roll's last frames then take the place of the front motion's opening frames, whose
    /// time is saved.
    #[serde(default)]
    pub back_then_front_from: Option<usize>,
}

impl GetUpParams {
    pub fn validate(&self, model: &RobotModel) -> Result<(), String> {
        for (name, motion) in [("front", &self.front), ("back", &self.back)] {
            if motion.is_empty() {
                return Err(format!("get_up.{name}: the motion has no key frames"));
            }
            for (k, frame) in motion.iter().enumerate() {
                let at = format!("get_up.{name}[{k}]");
                in_range(&format!("{at}.duration_s"), frame.duration_s, 0.02, 5.0)?;
                in_range(&format!("{at}.timeout_s"), frame.timeout_s, 0.0, 5.0)?;
                if let Some(c) = frame.until {
                    c.validate(&at)?;
                }
                if let Some(pitch) = frame.balance_pitch_deg {
                    in_range(&format!("{at}.balance_pitch_deg"), pitch, -90.0, 90.0)?;
                }
                for (joint, &angle) in &frame.pose {
                    let id = model.joint_id(joint).ok_or_else(|| {
                        format!("{at}.pose: `{joint}` is not a joint of {}", model.name)
                    })?;
                    let (lo, hi) = model.joints[id].limits_deg;
                    in_range(&format!("{at}.pose.{joint}"), angle, lo, hi)?;
                }
            }
        }
        for (joint, g) in &self.gains {
            model.joint_id(joint).ok_or_else(|| {
                format!("get_up.gains: `{joint}` is not a joint of {}", model.name)
            })?;
            in_range(&format!("get_up.gains.{joint}.kp"), g.kp, 0.0, 3000.0)?;
            in_range(&format!("get_up.gains.{joint}.kd"), g.kd, 0.0, 30.0)?;
        }
        let b = &self.balance;
        for (name, v) in [
            ("ankle_per_deg", b.ankle_per_deg),
            ("ankle_per_gyro", b.ankle_per_gyro),
            ("hip_per_deg", b.hip_per_deg),
            ("hip_per_gyro", b.hip_per_gyro),
        ] {
            in_range(&format!("get_up.balance.{name}"), v, -5.0, 5.0)?;
        }
        in_range("get_up.balance.max_deg", b.max_deg, 0.0, 45.0)?;
        if let Some(k) = self.back_then_front_from {
            if k >= self.front.len() {
                return Err(format!(
                    "get_up.back_then_front_from: {k} is past the front motion's {} key frames",
                    self.front.len()
                ));
            }
        }
        in_range("get_up.rest_s", self.rest_s, 0.0, 3.0)
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Lying {
    Front,
    Back,
}

/// A get-up in progress.
#[derive(Debug, Clone)]
pub struct GetUp {
    running: Option<Run>,
    /// Since when the fall detector has reported lying without a break [s].
    lying_since: Option<f64>,
}

#[derive(Debug, Clone)]
struct Run {
    lying: Lying,
    /// The key frame being played, when it started, and the pose it starts from (the
    /// measured angles for the first frame, the previous frame's target after that).
    frame: usize,
    frame_started_s: f64,
    from: Vec<f64>,
}

impl GetUp {
    pub fn new() -> Self {
        Self {
            running: None,
            lying_since: None,
        }
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
            let settled = self
                .lying_since
                .is_some_and(|since| world.time - since >= p.rest_s);
            let Some(lying) = lying.filter(|_| settled || requested) else {
                return false;
            };
            self.running = Some(Run {
                lying,
                frame: 0,
                frame_started_s: world.time,
                from: world.body.joint_angles.clone(),
            });
        }
        let run = self.running.as_mut().expect("started above");
        let motion = match run.lying {
            Lying::Front => &p.front,
            Lying::Back => &p.back,
        };
        let sensed = Sensed::from_body(&world.body);
        match step(run, motion, world.time, &sensed, model, pose) {
            Step::Playing => {
                if let Some(lean) = motion.get(run.frame).and_then(|f| f.balance_pitch_deg) {
                    balance(&p.balance, &sensed.attitude, lean, model, pose);
                }
            }
            Step::Ended => match (run.lying, p.back_then_front_from) {
                // The roll is over (its last frame waited for face down): on into the
                // front motion, from the pose the roll ended in.
                (Lying::Back, Some(k)) => {
                    run.lying = Lying::Front;
                    run.frame = k;
                    run.frame_started_s = world.time;
                }
                _ => self.running = None,
            },
            // A sensed condition never came: if still lying, start over from the new
            // posture next cycle.
            Step::GaveUp => self.running = None,
        }
        true
    }
}

impl Default for GetUp {
    fn default() -> Self {
        Self::new()
    }
}

enum Step {
    Playing,
    Ended,
    GaveUp,
}

fn target_of(frame: &Keyframe, from: &[f64], model: &RobotModel) -> Vec<f64> {
    let mut target = from.to_vec();
    for (joint, &angle) in &frame.pose {
        if let Some(id) = model.joint_id(joint) {
            target[id] = angle;
        }
    }
    target
}

/// Advance `run` to `now` and write its pose: frames end after `duration_s`, or for a frame
/// with `until`, once the condition holds after that.
fn step(
    run: &mut Run,
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
        let target = target_of(frame, &run.from, model);
        let t = now - run.frame_started_s;
        let done = t >= frame.duration_s
            && match frame.until {
                None => true,
                Some(c) if c.holds(sensed) => true,
                Some(_) if t >= frame.duration_s + frame.timeout_s => {
                    pose.copy_from_slice(&target);
                    return Step::GaveUp;
                }
                Some(_) => false,
            };
        if !done {
            let s = (t / frame.duration_s).clamp(0.0, 1.0);
            let w = s * s * (3.0 - 2.0 * s);
            for ((q, a), b) in pose.iter_mut().zip(&run.from).zip(&target) {
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
        run.from = target;
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
    for side in ["left", "right"] {
        for (joint, offset) in [("ankle_pitch", ankle), ("hip_pitch", hip)] {
            if let Some(id) = model.joint_id(&format!("{side}_{joint}")) {
                let (lo, hi) = model.joints[id].limits_deg;
                pose[id] = (pose[id] + offset).clamp(lo, hi);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn frame(duration_s: f64, knee: f64, until: Option<Condition>) -> Keyframe {
        Keyframe {
            duration_s,
            pose: BTreeMap::from([("left_knee".to_string(), knee)]),
            until,
            timeout_s: 0.5,
            balance_pitch_deg: None,
        }
    }

    fn start(model: &RobotModel) -> Run {
        Run {
            lying: Lying::Front,
            frame: 0,
            frame_started_s: 0.0,
            from: vec![0.0; model.joints.len()],
        }
    }

    fn pitched(deg: f64) -> Sensed {
        Sensed {
            attitude: Attitude {
                pitch_deg: deg,
                ..Attitude::default()
            },
            from_face_down_deg: 90.0,
            rate_deg_s: 0.0,
        }
    }

    #[test]
    fn a_sensed_frame_holds_until_its_condition_then_moves_on() {
        let model = RobotModel::builtin("T1").unwrap();
        let knee = model.joint_id("left_knee").unwrap();
        let motion = [
            frame(0.2, 90.0, Some(Condition::TorsoPitchBelow(30.0))),
            frame(0.2, 10.0, None),
        ];
        let mut run = start(&model);
        let mut pose = vec![0.0; model.joints.len()];
        let lying = pitched(80.0);
        assert!(matches!(
            step(&mut run, &motion, 0.1, &lying, &model, &mut pose),
            Step::Playing
        ));
        assert!((pose[knee] - 45.0).abs() < 1e-9, "halfway: {}", pose[knee]);
        // Past the duration but still lying: hold the target.
        step(&mut run, &motion, 0.4, &lying, &model, &mut pose);
        assert_eq!((run.frame, pose[knee]), (0, 90.0));
        // The torso has come up: the next frame starts now, from the held target.
        step(&mut run, &motion, 0.5, &pitched(20.0), &model, &mut pose);
        assert_eq!((run.frame, pose[knee]), (1, 90.0));
        step(&mut run, &motion, 0.6, &pitched(20.0), &model, &mut pose);
        assert!((pose[knee] - 50.0).abs() < 1e-9, "halfway: {}", pose[knee]);
        assert!(matches!(
            step(&mut run, &motion, 0.8, &pitched(20.0), &model, &mut pose),
            Step::Ended
        ));
    }

    #[test]
    fn a_condition_that_never_comes_gives_up() {
        let model = RobotModel::builtin("T1").unwrap();
        let motion = [frame(0.2, 90.0, Some(Condition::UprightWithin(20.0)))];
        let mut run = start(&model);
        let mut pose = vec![0.0; model.joints.len()];
        let lying = pitched(80.0);
        assert!(matches!(
            step(&mut run, &motion, 0.69, &lying, &model, &mut pose),
            Step::Playing
        ));
        assert!(matches!(
            step(&mut run, &motion, 0.71, &lying, &model, &mut pose),
            Step::GaveUp
        ));
    }

    #[test]
    fn balance_pushes_back_against_a_forward_lean() {
        let model = RobotModel::builtin("T1").unwrap();
        let b = GetUpBalance {
            ankle_per_deg: 0.5,
            ankle_per_gyro: 0.0,
            hip_per_deg: 0.2,
            hip_per_gyro: 0.0,
            max_deg: 4.0,
        };
        let mut pose = vec![0.0; model.joints.len()];
        balance(&b, &pitched(15.0).attitude, 5.0, &model, &mut pose);
        let at = |n: &str| pose[model.joint_id(n).unwrap()];
        assert_eq!(at("right_ankle_pitch"), 4.0, "clamped to max_deg");
        assert!((at("left_hip_pitch") - 2.0).abs() < 1e-9);
    }

    #[test]
    fn face_down_is_told_from_lying_on_a_side() {
        let model = RobotModel::builtin("T1").unwrap();
        let mut body = BodyState::new(&model);
        let sensed = |body: &BodyState| Sensed::from_body(body);
        body.gravity = [-9.81, 0.0, 0.0];
        assert!(sensed(&body).from_face_down_deg < 1e-9);
        // On the right side, slightly nose down: pitch reads far above 60° ...
        body.gravity = [-0.5, 9.8, 0.1];
        let side = sensed(&body);
        assert!(side.attitude.pitch_deg > 60.0, "{side:?}");
        assert!(Condition::TorsoPitchAbove(60.0).holds(&side));
        // ... but the torso's front is nearly level: not face down.
        let face_down = Condition::FaceDown {
            within_deg: 35.0,
            rate_below_deg_s: 40.0,
        };
        assert!(!face_down.holds(&side), "{side:?}");
        // Face down with 20° of roll towards the side still counts ...
        let roll = 20f64.to_radians();
        body.gravity = [-9.81 * roll.cos(), 9.81 * roll.sin(), 0.0];
        assert!(face_down.holds(&sensed(&body)));
        // ... unless the body is still rolling.
        body.gyro = [50.0, 10.0, 0.0];
        assert!(!face_down.holds(&sensed(&body)));
        // On the back: as far from face down as can be.
        body.gravity = [9.81, 0.0, 0.0];
        assert!((sensed(&body).from_face_down_deg - 180.0).abs() < 1e-9);
    }

    #[test]
    fn the_back_motion_runs_on_into_the_front_motion_when_asked() {
        let model = RobotModel::builtin("T1").unwrap();
        let knee = model.joint_id("left_knee").unwrap();
        let mut p = crate::SkillParams::builtin(&model).unwrap().get_up;
        p.rest_s = 0.0;
        p.back = vec![frame(0.1, 20.0, None)];
        p.front = vec![frame(0.1, 50.0, None), frame(0.2, 80.0, None)];
        p.back_then_front_from = Some(1);
        let mut world = World::new(&model, "t", 1);
        world.body.gravity = [9.81, 0.0, 0.0];
        world.body.posture = Posture::FallenBack;
        let mut getup = GetUp::new();
        let mut pose = vec![0.0; model.joints.len()];
        let mut at = |t: f64, getup: &mut GetUp, pose: &mut Vec<f64>| {
            world.time = t;
            assert!(getup.update(&world, false, &p, &model, pose));
            pose[knee]
        };
        at(0.0, &mut getup, &mut pose);
        assert_eq!(
            at(0.1, &mut getup, &mut pose),
            20.0,
            "the roll has played out"
        );
        // Still lying on the back as far as the detector knows, yet the front motion goes
        // on from its frame 1 (80°), skipping frame 0 (50°).
        assert!(
            (at(0.2, &mut getup, &mut pose) - 50.0).abs() < 1e-9,
            "halfway 20 → 80"
        );
        assert_eq!(at(0.3, &mut getup, &mut pose), 80.0);
        p.back_then_front_from = Some(2);
        assert!(p
            .validate(&model)
            .unwrap_err()
            .contains("back_then_front_from"));
    }

    #[test]
    fn validation_names_a_bad_condition() {
        let model = RobotModel::builtin("T1").unwrap();
        let mut p = crate::SkillParams::builtin(&model).unwrap().get_up;
        p.back[0].until = Some(Condition::UprightWithin(120.0));
        let err = p.validate(&model).unwrap_err();
        assert!(err.contains("get_up.back[0].until"), "{err}");
    }
}
