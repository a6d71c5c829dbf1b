//! Getting up from lying: key-frame motions from the parameter file, one for lying face down
//! and one for lying on the back, started by the fall detector.

use crate::walk::params::in_range;
use libero_model::{Gains, RobotModel};
use libero_world::{Posture, World};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// One key frame: reach `pose` (joint name → deg; unlisted joints keep the previous frame's
/// angle) in `duration_s`, moving smoothly from the previous frame.
#[derive(Debug, Clone, Deserialize, Serialize, PartialEq)]
pub struct Keyframe {
    pub duration_s: f64,
    pub pose: BTreeMap<String, f64>,
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
    started_s: f64,
    /// The pose the motion starts from (the angles measured when it began).
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
                started_s: world.time,
                from: world.body.joint_angles.clone(),
            });
        }
        let run = self.running.as_ref().expect("started above");
        let motion = match run.lying {
            Lying::Front => &p.front,
            Lying::Back => &p.back,
        };
        let t = world.time - run.started_s;
        match play(motion, &run.from, t, model, pose) {
            Some(()) => true,
            None => {
                // Played out: if still lying, start over from the new posture next cycle.
                self.running = None;
                true
            }
        }
    }
}

impl Default for GetUp {
    fn default() -> Self {
        Self::new()
    }
}

/// Write the motion's pose at `t` seconds into `pose`; `None` once it has ended.
fn play(
    motion: &[Keyframe],
    from: &[f64],
    t: f64,
    model: &RobotModel,
    pose: &mut [f64],
) -> Option<()> {
    pose.copy_from_slice(from);
    if t < 0.0 {
        return Some(());
    }
    let mut previous = from.to_vec();
    let mut start = 0.0;
    for frame in motion {
        let mut target = previous.clone();
        for (joint, &angle) in &frame.pose {
            if let Some(id) = model.joint_id(joint) {
                target[id] = angle;
            }
        }
        if t < start + frame.duration_s {
            let s = ((t - start) / frame.duration_s).clamp(0.0, 1.0);
            let w = s * s * (3.0 - 2.0 * s);
            for ((q, a), b) in pose.iter_mut().zip(&previous).zip(&target) {
                *q = a + (b - a) * w;
            }
            return Some(());
        }
        start += frame.duration_s;
        previous = target;
    }
    pose.copy_from_slice(&previous);
    None
}
