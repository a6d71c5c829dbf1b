//! The get-up motions as data: key frames, the IMU conditions a frame can wait for, and their
//! validation.

use crate::walk::balance::Attitude;
use crate::walk::params::in_range;
use libero_model::{Gains, RobotModel};
use libero_world::BodyState;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// One key frame: reach `pose` (joint name → deg; unlisted joints keep the previous frame's
/// angle) in `duration_s`, moving smoothly from the previous frame.
#[derive(Debug, Clone, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Keyframe {
    pub duration_s: f64,
    pub pose: BTreeMap<String, f64>,
    /// Hold the pose after `duration_s` until the IMU reports this, so the next frame starts
    /// from a sensed state rather than a moment in time (the dynamic phases are chaotic in
    /// time). Not met within `timeout_s` more: the motion gives up and starts over, or plays
    /// `on_timeout` instead.
    #[serde(default)]
    pub until: Option<Condition>,
    #[serde(default = "default_timeout_s")]
    pub timeout_s: f64,
    /// How long `until` must hold without a break before the frame ends [s]. The
    /// accelerometer reads every jolt of a body in contact as tilt: one cycle's reading can
    /// fake a condition the torso is 10–15° short of.
    #[serde(default)]
    pub hold_s: f64,
    /// A motion of `get_up.recover` to play when `until` has not come within `timeout_s`,
    /// from the pose held then (e.g. a slow rise from a squat the pop left leaning forward),
    /// instead of starting over from the ground.
    #[serde(default)]
    /// Shared: a timeout during play hands the name on without copying it.
    pub on_timeout: Option<std::sync::Arc<str>>,
    /// When `until` has not come within `timeout_s`, go on with the next frame instead of
    /// starting over: for a wait that helps when it can come but is not needed (lying flat
    /// before the tuck: a robot left in a pike by a failed try lies flat first, one with its
    /// body rolled a little starts anyway).
    #[serde(default)]
    pub timeout_goes_on: bool,
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
#[serde(deny_unknown_fields)]
pub struct GetUpBalance {
    pub ankle_per_deg: f64,
    pub ankle_per_gyro: f64,
    pub hip_per_deg: f64,
    pub hip_per_gyro: f64,
    pub max_deg: f64,
}

impl GetUpBalance {
    pub fn validate(&self, at: &str) -> Result<(), String> {
        for (name, v) in [
            ("ankle_per_deg", self.ankle_per_deg),
            ("ankle_per_gyro", self.ankle_per_gyro),
            ("hip_per_deg", self.hip_per_deg),
            ("hip_per_gyro", self.hip_per_gyro),
        ] {
            in_range(&format!("{at}.{name}"), v, -5.0, 5.0)?;
        }
        in_range(&format!("{at}.max_deg"), self.max_deg, 0.0, 45.0)
    }
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

/// Waiting for a lying body to stop moving before a get-up starts.
#[derive(Debug, Clone, Copy, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct RestUntilStill {
    /// Still: the gyro's rate below this [deg/s] ...
    pub rate_below_deg_s: f64,
    /// ... or lying this long, still or not [s].
    pub at_most_s: f64,
}

/// Standing still after a get-up until the torso is upright and calm.
#[derive(Debug, Clone, Copy, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct SettleAfter {
    /// Settled: pitch and roll within this of upright [deg] ...
    pub upright_within_deg: f64,
    /// ... the gyro's rate below this [deg/s] ...
    pub rate_below_deg_s: f64,
    /// ... both for this long [s];
    pub calm_s: f64,
    /// or this long after the motion ended, settled or not [s].
    pub at_most_s: f64,
}

impl SettleAfter {
    /// Whether the body read by `sensed` counts as settled.
    pub fn calm(&self, sensed: &Sensed) -> bool {
        sensed.attitude.pitch_deg.abs() < self.upright_within_deg
            && sensed.attitude.roll_deg.abs() < self.upright_within_deg
            && sensed.rate_deg_s < self.rate_below_deg_s
    }
}

/// The get-up motions.
#[derive(Debug, Clone, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct GetUpParams {
    /// Lying face down.
    pub front: Vec<Keyframe>,
    /// Lying on the back.
    pub back: Vec<Keyframe>,
    /// Gains during the motions, by joint name; others keep the model's defaults.
    pub gains: BTreeMap<String, Gains>,
    /// Wait this long lying before starting, so the body has come to rest [s].
    pub rest_s: f64,
    /// ... and, when set, until the torso turns slower than this (a fall in a match often
    /// ends in a roll or a rocking on the back that goes on for a second; a motion started
    /// then lands in a pose its frames do not expect).
    #[serde(default)]
    pub rest_until_still: Option<RestUntilStill>,
    /// After a get-up, stand until the body has settled before walking again (a walk started
    /// the moment the motion ended, the torso still 13-16 deg forward, fell again within
    /// 1-1.5 s several times a run in striker_alone).
    #[serde(default)]
    pub settle: Option<SettleAfter>,
    #[serde(default)]
    pub balance: GetUpBalance,
    /// When set, the back motion (a roll onto the front) runs straight on into the front
    /// motion from this key frame, without the hand-off through the fall detector: the
    /// roll's last frames then take the place of the front motion's opening frames, whose
    /// time is saved.
    #[serde(default)]
    pub back_then_front_from: Option<usize>,
    /// Named motions a key frame's `on_timeout` switches to. When one has played out, the
    /// get-up is over (the fall detector starts a new one if the body is down again).
    #[serde(default)]
    pub recover: BTreeMap<String, Vec<Keyframe>>,
}

impl GetUpParams {
    pub fn validate(&self, model: &RobotModel) -> Result<(), String> {
        let named = [
            ("front".to_string(), &self.front),
            ("back".to_string(), &self.back),
        ];
        let recover = self
            .recover
            .iter()
            .map(|(n, m)| (format!("recover.{n}"), m));
        for (name, motion) in named.into_iter().chain(recover) {
            validate_frames(
                &format!("get_up.{name}"),
                motion,
                model,
                Some(&self.recover),
            )?;
        }
        for (joint, g) in &self.gains {
            model.joint_id(joint).ok_or_else(|| {
                format!("get_up.gains: `{joint}` is not a joint of {}", model.name)
            })?;
            in_range(&format!("get_up.gains.{joint}.kp"), g.kp, 0.0, 3000.0)?;
            in_range(&format!("get_up.gains.{joint}.kd"), g.kd, 0.0, 30.0)?;
        }
        self.balance.validate("get_up.balance")?;
        if let Some(k) = self.back_then_front_from {
            if k >= self.front.len() {
                return Err(format!(
                    "get_up.back_then_front_from: {k} is past the front motion's {} key frames",
                    self.front.len()
                ));
            }
        }
        if let Some(r) = self.rest_until_still {
            in_range(
                "get_up.rest_until_still.rate_below_deg_s",
                r.rate_below_deg_s,
                0.0,
                1000.0,
            )?;
            in_range(
                "get_up.rest_until_still.at_most_s",
                r.at_most_s,
                self.rest_s,
                10.0,
            )?;
        }
        if let Some(st) = self.settle {
            in_range(
                "get_up.settle.upright_within_deg",
                st.upright_within_deg,
                0.0,
                45.0,
            )?;
            in_range(
                "get_up.settle.rate_below_deg_s",
                st.rate_below_deg_s,
                0.0,
                1000.0,
            )?;
            in_range("get_up.settle.calm_s", st.calm_s, 0.0, st.at_most_s)?;
            in_range("get_up.settle.at_most_s", st.at_most_s, 0.0, 5.0)?;
        }
        in_range("get_up.rest_s", self.rest_s, 0.0, 3.0)
    }
}

/// Check one key-frame motion; `at` names it in errors (`get_up.front`). `recover`: the named
/// motions an `on_timeout` may switch to (`None`: the skill has none, `on_timeout` is refused).
pub(crate) fn validate_frames(
    at: &str,
    motion: &[Keyframe],
    model: &RobotModel,
    recover: Option<&BTreeMap<String, Vec<Keyframe>>>,
) -> Result<(), String> {
    if motion.is_empty() {
        return Err(format!("{at}: the motion has no key frames"));
    }
    for (k, frame) in motion.iter().enumerate() {
        let at = format!("{at}[{k}]");
        in_range(&format!("{at}.duration_s"), frame.duration_s, 0.02, 5.0)?;
        in_range(&format!("{at}.timeout_s"), frame.timeout_s, 0.0, 5.0)?;
        in_range(&format!("{at}.hold_s"), frame.hold_s, 0.0, 1.0)?;
        if let Some(next) = &frame.on_timeout {
            if frame.until.is_none() {
                return Err(format!(
                    "{at}.on_timeout: the frame has no `until` to time out on"
                ));
            }
            let Some(recover) = recover else {
                return Err(format!(
                    "{at}.on_timeout: this motion has no recovery motions to switch to"
                ));
            };
            if !recover.contains_key(&**next) {
                let known: Vec<&str> = recover.keys().map(String::as_str).collect();
                return Err(format!(
                    "{at}.on_timeout: no motion `{next}` in get_up.recover (it has: {})",
                    if known.is_empty() {
                        "none".to_string()
                    } else {
                        known.join(", ")
                    }
                ));
            }
        }
        if frame.timeout_goes_on && (frame.until.is_none() || frame.on_timeout.is_some()) {
            return Err(format!(
                "{at}.timeout_goes_on: needs an `until` to time out on and no `on_timeout`"
            ));
        }
        if let Some(c) = frame.until {
            c.validate(&at)?;
        }
        if let Some(pitch) = frame.balance_pitch_deg {
            in_range(&format!("{at}.balance_pitch_deg"), pitch, -90.0, 90.0)?;
        }
        for (joint, &angle) in &frame.pose {
            let id = model
                .joint_id(joint)
                .ok_or_else(|| format!("{at}.pose: `{joint}` is not a joint of {}", model.name))?;
            let (lo, hi) = model.joints[id].limits_deg;
            in_range(&format!("{at}.pose.{joint}"), angle, lo, hi)?;
        }
    }
    Ok(())
}
