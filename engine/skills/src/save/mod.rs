//! Goalkeeper saves: a sideways dive to either side (a deliberate, controlled fall that lays
//! the body's length along the goal line) and a block for balls straight at the keeper, as
//! key-frame motions from the parameter file, played by the get-up's key-frame player.
//!
//! A save runs to its end once started: neither the walk nor a new request interrupts it. The
//! dive ends with the robot lying; the fall detector and the get-up then stand it up.

#[cfg(test)]
pub(crate) mod tests;

use crate::getup::{self, Keyframe, Playhead, Sensed, Step};
use libero_model::{Gains, RobotModel};
use libero_world::World;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// Where the save goes, in the robot's own frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Deserialize, Serialize)]
pub enum DiveSide {
    /// Dive to the robot's left (+y).
    Left,
    /// Dive to the robot's right (−y).
    Right,
    /// Block a ball straight at the robot (wide, low stance).
    Centre,
}

/// Where the save stands, for the decision layer.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum SaveState {
    /// No save asked for.
    #[default]
    Idle,
    /// The save motion is playing; new requests are ignored until it has played out.
    Diving(DiveSide),
    /// The motion has played out (after a dive the robot lies: the get-up follows on its own).
    /// Stays so while the request is held; a cycle without a request goes back to `Idle`.
    Done(DiveSide),
}

/// A save's motions by dive side, ready to play: built when the parameters load, because the
/// mirrored right dive is a new list of key frames.
#[derive(Debug, Clone, Default)]
pub struct SaveMotions {
    frames: [Vec<Keyframe>; 3],
}

impl SaveMotions {
    pub fn of(&self, side: DiveSide) -> &[Keyframe] {
        let index = match side {
            DiveSide::Left => 0,
            DiveSide::Right => 1,
            DiveSide::Centre => 2,
        };
        &self.frames[index]
    }
}

/// The save motions.
#[derive(Debug, Clone, Default, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct SaveParams {
    /// Dive to the left.
    #[serde(default)]
    pub left: Vec<Keyframe>,
    /// Dive to the right; `None` plays the mirror image of `left`.
    #[serde(default)]
    pub right: Option<Vec<Keyframe>>,
    /// Block straight ahead.
    #[serde(default)]
    pub block: Vec<Keyframe>,
    /// Gains during the motions, by joint name (mirrored for a mirrored right dive); others
    /// keep the model's defaults.
    #[serde(default)]
    pub gains: BTreeMap<String, Gains>,
}

impl SaveParams {
    /// The key frames for `side` (the right dive mirrored from the left one when not given).
    /// Empty when the parameter file has no such motion (the request is then ignored).
    pub fn motion(&self, side: DiveSide) -> std::borrow::Cow<'_, [Keyframe]> {
        use std::borrow::Cow;
        match side {
            DiveSide::Left => Cow::Borrowed(&self.left),
            DiveSide::Centre => Cow::Borrowed(&self.block),
            DiveSide::Right => match &self.right {
                Some(frames) => Cow::Borrowed(frames),
                None => Cow::Owned(self.left.iter().map(mirror_frame).collect()),
            },
        }
    }

    /// The three motions as played (the mirrored right dive built now, once).
    pub fn motions(&self) -> SaveMotions {
        SaveMotions {
            frames: [DiveSide::Left, DiveSide::Right, DiveSide::Centre]
                .map(|side| self.motion(side).into_owned()),
        }
    }

    /// The gains to use while `side`'s motion plays.
    pub fn gains_for(&self, side: DiveSide) -> Vec<(String, Gains)> {
        let mirrored = side == DiveSide::Right && self.right.is_none();
        self.gains
            .iter()
            .map(|(joint, g)| {
                let joint = if mirrored {
                    mirror_joint(joint).0
                } else {
                    joint.clone()
                };
                (joint, *g)
            })
            .collect()
    }

    /// Every motion given must be valid for the robot (a file without save motions is valid:
    /// the robot then cannot save).
    pub fn validate(&self, model: &RobotModel) -> Result<(), String> {
        if !self.left.is_empty() {
            getup::validate_frames("save.left", &self.left, model, None)?;
        }
        if !self.block.is_empty() {
            getup::validate_frames("save.block", &self.block, model, None)?;
        }
        match &self.right {
            Some(frames) => getup::validate_frames("save.right", frames, model, None)?,
            None if !self.left.is_empty() => getup::validate_frames(
                "save.right (mirrored from save.left)",
                &self.motion(DiveSide::Right),
                model,
                None,
            )?,
            None => {}
        }
        for (joint, g) in &self.gains {
            model
                .joint_id(joint)
                .ok_or_else(|| format!("save.gains: `{joint}` is not a joint of {}", model.name))?;
            if self.right.is_none() && model.joint_id(&mirror_joint(joint).0).is_none() {
                return Err(format!(
                    "save.gains: `{joint}` has no mirror joint for the mirrored right dive"
                ));
            }
            crate::walk::params::in_range(&format!("save.gains.{joint}.kp"), g.kp, 0.0, 3000.0)?;
            crate::walk::params::in_range(&format!("save.gains.{joint}.kd"), g.kd, 0.0, 30.0)?;
        }
        Ok(())
    }
}

/// The mirror image of a joint about the robot's sagittal plane: `left_*` ↔ `right_*`, and
/// the angle's sign flips for joints turning about the x or z axis (roll, yaw, the waist).
/// Returns the joint name and the factor for its angle.
pub fn mirror_joint(joint: &str) -> (String, f64) {
    let name = if let Some(rest) = joint.strip_prefix("left_") {
        format!("right_{rest}")
    } else if let Some(rest) = joint.strip_prefix("right_") {
        format!("left_{rest}")
    } else {
        joint.to_string()
    };
    // The NAO's hip_yaw_pitch axes are each other's mirror image already ((0, ±0.71, −0.71)
    // reflected in the sagittal plane), so its angle keeps its sign like a pitch.
    let sign = if joint.ends_with("yaw_pitch") {
        1.0
    } else if joint.contains("roll") || joint.contains("yaw") || joint == "waist" {
        -1.0
    } else {
        1.0
    };
    (name, sign)
}

/// A key frame's mirror image: joints swapped left ↔ right, roll and yaw angles negated. IMU
/// conditions are kept (those the frames use, pitch and tilt, are symmetric).
pub fn mirror_frame(frame: &Keyframe) -> Keyframe {
    Keyframe {
        pose: frame
            .pose
            .iter()
            .map(|(joint, &angle)| {
                let (name, sign) = mirror_joint(joint);
                // −0.0 would print oddly in traces; keep zeros plain.
                (name, if angle == 0.0 { 0.0 } else { sign * angle })
            })
            .collect(),
        ..frame.clone()
    }
}

/// The first cycle's targets are those of this far into the motion [s] (one server cycle), so
/// the save moves in the cycle it is asked for.
const FIRST_STEP_S: f64 = 0.02;

/// The save skill of one agent.
#[derive(Debug, Clone, Default)]
pub struct Save {
    running: Option<(DiveSide, Playhead)>,
    /// The last dive's playhead, kept for the next one's memory.
    spare: Option<Playhead>,
    state: SaveState,
}

impl Save {
    pub fn new() -> Self {
        Self::default()
    }

    /// Make room for a robot of `joints` joints now rather than at the first dive.
    pub fn with_room(mut self, joints: usize) -> Self {
        self.spare = Some(Playhead::with_room(joints));
        self
    }

    pub fn state(&self) -> SaveState {
        self.state
    }

    pub fn is_running(&self) -> bool {
        self.running.is_some()
    }

    /// The side of the save being played.
    pub fn side(&self) -> Option<DiveSide> {
        self.running.as_ref().map(|(side, _)| *side)
    }

    /// One cycle. `requested`: this cycle's save request; `may_start`: whether a new save may
    /// start now (not while a get-up runs). Starts a requested save at once from the measured
    /// angles, plays it to its end whatever is requested meanwhile, and returns whether it
    /// wrote `pose` (false: no save running, `pose` untouched).
    pub fn update(
        &mut self,
        world: &World,
        requested: Option<DiveSide>,
        may_start: bool,
        motions: &SaveMotions,
        model: &RobotModel,
        pose: &mut [f64],
    ) -> bool {
        if self.running.is_none() {
            match (self.state, requested) {
                (_, None) => self.state = SaveState::Idle,
                // Held after the end: not a new request.
                (SaveState::Done(_), Some(_)) => {}
                (_, Some(side)) if may_start && !motions.of(side).is_empty() => {
                    // One cycle in already: the targets sent this cycle move.
                    let started = world.time - FIRST_STEP_S;
                    let head = match self.spare.take() {
                        Some(mut head) => {
                            head.restart(&world.body.joint_angles, started);
                            head
                        }
                        None => Playhead::start(&world.body.joint_angles, started),
                    };
                    self.running = Some((side, head));
                    self.state = SaveState::Diving(side);
                }
                (_, Some(_)) => {}
            }
        }
        let Some((side, head)) = self.running.as_mut() else {
            return false;
        };
        let side = *side;
        let motion = motions.of(side);
        let sensed = Sensed::from_body(&world.body);
        match getup::step(head, motion, world.time, &sensed, model, pose) {
            Step::Playing => {}
            // A sensed condition that never came ends the save where it is, too: a save
            // cannot start over.
            Step::Ended | Step::TimedOut(_) => {
                self.spare = self.running.take().map(|(_, head)| head);
                self.state = SaveState::Done(side);
            }
        }
        true
    }
}
