//! Skill parameters as RON data, checked against the robot model on load.

use crate::dribble::DribbleParams;
use crate::getup::GetUpParams;
use crate::kick::{KickMotion, KickParams, KickSpread};
use crate::save::SaveParams;
use crate::walk::WalkParams;
use libero_model::RobotModel;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// Head scanning.
#[derive(Debug, Clone, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct LookAround {
    pub yaw_amplitude_deg: f64,
    pub period_s: f64,
    pub pitch_deg: f64,
}

/// Every tunable number of the skills for one robot.
#[derive(Debug, Clone, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct SkillParams {
    /// The robot model these numbers are for.
    pub robot: String,
    /// Stand posture: joint name → angle [deg]; unlisted joints are 0.
    pub stand: BTreeMap<String, f64>,
    /// Once it has walked, a standing robot stays in the walk's posture with the walk's
    /// balance corrections (`walk.balance.rest_correction_scale`) rather than going back to
    /// `stand`: the change to the taller pose after a walk rocked the T1 toe to heel by ±5°
    /// and, after a turn or a beam, over (NOTES.md, session 15).
    #[serde(default)]
    pub stand_in_walk_posture: bool,
    pub look_around: LookAround,
    pub walk: WalkParams,
    pub get_up: GetUpParams,
    pub kick: KickParams,
    /// Walking the ball along (a file without them dribbles with the defaults).
    #[serde(default)]
    pub dribble: DribbleParams,
    /// Goalkeeper saves (dives, block); a file without them cannot save.
    #[serde(default)]
    pub save: SaveParams,
    /// Named key-frame motions played on request (`BodyIntent::Motion`), e.g. the falls a
    /// get-up trial starts from where the server cannot lay a robot down.
    #[serde(default)]
    pub motions: BTreeMap<String, Vec<crate::getup::Keyframe>>,
    /// The walk of particular heterogeneous types (SimSpark's NAO types by number), in place
    /// of `walk` for a robot of that type: a type with longer legs walks another gait.
    #[serde(default)]
    pub walk_by_type: BTreeMap<u8, WalkParams>,
    /// Get-up motions of particular heterogeneous types, in place of `get_up`'s for a robot
    /// of that type: a sit-up or a push-up that lifts one body does not lift a longer-legged
    /// one.
    #[serde(default)]
    pub get_up_by_type: BTreeMap<u8, GetUpMotions>,
    /// The kick of particular heterogeneous types, in place of `kick`'s for a robot of that
    /// type: wider hips and longer legs want another weight shift and another place.
    #[serde(default)]
    pub kick_by_type: BTreeMap<u8, KickOfType>,
}

/// A type's own kick; what is not given is `kick`'s.
#[derive(Debug, Clone, Default, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct KickOfType {
    #[serde(default)]
    pub long: Option<KickMotion>,
    #[serde(default)]
    pub short: Option<KickMotion>,
    /// Where the approach leaves the ball before the kicking foot (`approach.ball_ahead_m`,
    /// `approach.ball_beside_m`) [m].
    #[serde(default)]
    pub ball_ahead_m: Option<f64>,
    #[serde(default)]
    pub ball_beside_m: Option<f64>,
    /// What `libero bench kick --robot nao_typeN` measured of this type's long kick.
    #[serde(default)]
    pub measured: Option<KickSpread>,
}

impl KickOfType {
    /// `common` as a robot of this type kicks.
    fn applied_to(&self, common: &KickParams) -> KickParams {
        let mut kick = common.clone();
        if let Some(long) = &self.long {
            kick.long = long.clone();
        }
        if let Some(short) = &self.short {
            kick.short = short.clone();
        }
        if let Some(ahead) = self.ball_ahead_m {
            kick.approach.ball_ahead_m = ahead;
        }
        if let Some(beside) = self.ball_beside_m {
            kick.approach.ball_beside_m = beside;
        }
        if let Some(measured) = self.measured {
            kick.measured = measured;
        }
        kick
    }
}

/// A type's own get-up motions; one not given is `get_up`'s.
#[derive(Debug, Clone, Default, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct GetUpMotions {
    #[serde(default)]
    pub front: Option<Vec<crate::getup::Keyframe>>,
    #[serde(default)]
    pub back: Option<Vec<crate::getup::Keyframe>>,
    /// Play this other type's own `front` motion (one that stands both bodies), instead of a
    /// copy of its frames.
    #[serde(default)]
    pub front_of_type: Option<u8>,
    /// Play this other type's own `back` motion.
    #[serde(default)]
    pub back_of_type: Option<u8>,
    /// This type's feedback in balanced key frames, in place of `get_up.balance` (a shared
    /// motion damped for one body can want other gains for another).
    #[serde(default)]
    pub balance: Option<crate::getup::GetUpBalance>,
}

type Frames = Vec<crate::getup::Keyframe>;

/// The get-up motions of type `t` for each side that is not the common one, after following
/// `front_of_type` / `back_of_type` (one step: the named type's motion must be its own).
fn motions_of_type(
    by_type: &BTreeMap<u8, GetUpMotions>,
    t: u8,
) -> Result<[Option<&Frames>; 2], String> {
    fn side<'a>(
        by_type: &'a BTreeMap<u8, GetUpMotions>,
        t: u8,
        name: &str,
        pick: fn(&GetUpMotions) -> (&Option<Frames>, Option<u8>),
    ) -> Result<Option<&'a Frames>, String> {
        let Some(own) = by_type.get(&t) else {
            return Ok(None);
        };
        match pick(own) {
            (Some(_), Some(_)) => Err(format!(
                "get_up_by_type {t}: both `{name}` and `{name}_of_type`; give one"
            )),
            (Some(frames), None) => Ok(Some(frames)),
            (None, None) => Ok(None),
            (None, Some(other)) => by_type
                .get(&other)
                .and_then(|m| pick(m).0.as_ref())
                .map(Some)
                .ok_or_else(|| {
                    format!(
                        "get_up_by_type {t}.{name}_of_type: type {other} has no `{name}` motion of its own"
                    )
                }),
        }
    }
    Ok([
        side(by_type, t, "front", |m| (&m.front, m.front_of_type))?,
        side(by_type, t, "back", |m| (&m.back, m.back_of_type))?,
    ])
}

#[derive(Debug, thiserror::Error)]
pub enum ParamsError {
    #[error("{0}")]
    Syntax(libero_model::Located),
    #[error("{file}: {message}")]
    Invalid { file: String, message: String },
    #[error("no built-in skill parameters for robot `{0}`")]
    NoBuiltin(String),
    #[error("the skills cannot drive this robot: {0}")]
    Kinematics(#[from] libero_model::kinematics::KinematicsError),
    #[error("{0}: {1}")]
    Io(String, std::io::Error),
}

/// Shipped parameters by robot family: `NAO` serves every heterogeneous type (`NAO_type0`…).
const BUILTIN: &[(&str, &str)] = &[
    ("T1", include_str!("../params/t1.ron")),
    ("NAO", include_str!("../params/nao.ron")),
];

/// The family of a robot model name: `NAO_type3` → `NAO`.
fn family(model_name: &str) -> &str {
    model_name.split('_').next().unwrap_or(model_name)
}

impl SkillParams {
    /// The shipped parameters for a robot model.
    pub fn builtin(model: &RobotModel) -> Result<Self, ParamsError> {
        let (name, text) = BUILTIN
            .iter()
            .find(|(n, _)| n.eq_ignore_ascii_case(family(&model.name)))
            .ok_or_else(|| ParamsError::NoBuiltin(model.name.clone()))?;
        Self::from_ron(
            &format!("<builtin>/{}.ron", name.to_lowercase()),
            text,
            model,
        )
    }

    /// The shipped file name for a robot model: `t1.ron`, `nao.ron` for every NAO type.
    pub fn file_name(model: &RobotModel) -> String {
        format!("{}.ron", family(&model.name).to_lowercase())
    }

    /// Parse and check a parameter file for `model`; a walk of `walk_by_type` (a get-up of
    /// `get_up_by_type`) for the model's type takes the place of `walk` (`get_up`).
    pub fn from_ron(file: &str, text: &str, model: &RobotModel) -> Result<Self, ParamsError> {
        Ok(Self::from_ron_for_family(file, text, model)?.for_type(model))
    }

    /// Parse and check a parameter file shared by a robot family (every NAO type plays
    /// nao.ron), its per-type entries not yet applied: each player takes its own with
    /// [`SkillParams::for_type`]. Checked against `model` (the joints all types share).
    pub fn from_ron_for_family(
        file: &str,
        text: &str,
        model: &RobotModel,
    ) -> Result<Self, ParamsError> {
        let params: SkillParams =
            libero_model::location::parse_ron(file, text).map_err(ParamsError::Syntax)?;
        params.validate(model).map_err(|e| match e {
            ParamsError::Invalid { message, .. } => ParamsError::Invalid {
                file: file.into(),
                message,
            },
            other => other,
        })?;
        Ok(params)
    }

    /// These parameters as a robot of `model`'s type plays them: its `walk_by_type` entry
    /// takes the place of `walk`, its `get_up_by_type` motions and balance those of `get_up`
    /// (a robot without a type, or a type without entries, plays the common ones).
    pub fn for_type(&self, model: &RobotModel) -> Self {
        let mut params = self.clone();
        let Some(t) = model.hetero_type else {
            return params;
        };
        if let Some(walk) = self.walk_by_type.get(&t) {
            params.walk = walk.clone();
        }
        if let Some(kick) = self.kick_by_type.get(&t) {
            params.kick = kick.applied_to(&self.kick);
        }
        if let Some(balance) = self.get_up_by_type.get(&t).and_then(|m| m.balance) {
            params.get_up.balance = balance;
        }
        // A reference that leads nowhere was refused by `validate`, by name.
        if let Ok([front, back]) = motions_of_type(&self.get_up_by_type, t) {
            if let Some(front) = front {
                params.get_up.front = front.clone();
            }
            if let Some(back) = back {
                params.get_up.back = back.clone();
            }
        }
        params
    }

    /// Read and check a parameter file.
    pub fn load(path: &std::path::Path, model: &RobotModel) -> Result<Self, ParamsError> {
        let text = std::fs::read_to_string(path)
            .map_err(|e| ParamsError::Io(path.display().to_string(), e))?;
        Self::from_ron(&path.display().to_string(), &text, model)
    }

    /// The parameters as RON text (for writing tuned values back).
    pub fn to_ron(&self) -> String {
        let config = ron::ser::PrettyConfig::new()
            .depth_limit(3)
            .struct_names(true);
        ron::ser::to_string_pretty(self, config).expect("skill parameters always serialise")
    }

    /// Every check that does not need the file name; errors name the offending field.
    pub fn validate(&self, model: &RobotModel) -> Result<(), ParamsError> {
        self.stand_pose(model)?;
        let invalid = |message: String| ParamsError::Invalid {
            file: String::new(),
            message,
        };
        self.walk.validate().map_err(invalid)?;
        for (t, walk) in &self.walk_by_type {
            walk.validate()
                .map_err(|e| invalid(format!("walk_by_type {t}: {e}")))?;
        }
        let walks = std::iter::once(&self.walk).chain(self.walk_by_type.values());
        for joint in walks.flat_map(|walk| walk.leg_gains.keys()) {
            let on_both_legs = ["left", "right"]
                .iter()
                .all(|side| model.joint_id(&format!("{side}_{joint}")).is_some());
            if !on_both_legs {
                return Err(invalid(format!(
                    "walk.leg_gains: `{joint}` is not a leg joint of {} (`left_{joint}` and `right_{joint}` must exist)",
                    model.name
                )));
            }
        }
        self.get_up.validate(model).map_err(invalid)?;
        for (&t, own) in &self.get_up_by_type {
            motions_of_type(&self.get_up_by_type, t).map_err(invalid)?;
            if let Some(balance) = &own.balance {
                balance
                    .validate(&format!("get_up_by_type {t}.balance"))
                    .map_err(invalid)?;
            }
            for (side, motion) in [("front", &own.front), ("back", &own.back)] {
                if let Some(frames) = motion {
                    crate::getup::validate_frames(
                        &format!("get_up_by_type {t}.{side}"),
                        frames,
                        model,
                        Some(&self.get_up.recover),
                    )
                    .map_err(invalid)?;
                }
            }
        }
        self.dribble.validate().map_err(invalid)?;
        self.save.validate(model).map_err(invalid)?;
        for (name, frames) in &self.motions {
            crate::getup::validate_frames(&format!("motions.{name}"), frames, model, None)
                .map_err(invalid)?;
        }
        validate_kick(&self.kick, "kick", model).map_err(invalid)?;
        for (t, own) in &self.kick_by_type {
            let label = format!("kick_by_type {t}");
            validate_kick(&own.applied_to(&self.kick), &label, model).map_err(invalid)?;
        }
        Ok(())
    }

    /// The motion of `motions` called `name`.
    pub fn motion_id(&self, name: &str) -> Option<crate::MotionId> {
        let index = self.motions.keys().position(|n| n == name)?;
        u16::try_from(index).ok().map(crate::MotionId)
    }

    /// The stand pose as one angle per model joint.
    pub fn stand_pose(&self, model: &RobotModel) -> Result<Vec<f64>, ParamsError> {
        let invalid = |message: String| ParamsError::Invalid {
            file: String::new(),
            message,
        };
        if !self.robot.eq_ignore_ascii_case(family(&model.name)) {
            return Err(invalid(format!(
                "parameters are for `{}`, the robot is `{}`",
                self.robot, model.name
            )));
        }
        let mut pose = vec![0.0; model.joints.len()];
        for (name, &angle) in &self.stand {
            let id = model.joint_id(name).ok_or_else(|| {
                invalid(format!("stand: `{name}` is not a joint of {}", model.name))
            })?;
            let (lo, hi) = model.joints[id].limits_deg;
            if !(lo..=hi).contains(&angle) {
                return Err(invalid(format!(
                    "stand: {name} = {angle}° is outside its limits [{lo}, {hi}]"
                )));
            }
            pose[id] = angle;
        }
        Ok(pose)
    }
}

/// A kick's numbers, its key frames (and their mirror for the left foot) and its swing gains'
/// joints; errors start with `label` (`kick`, `kick_by_type 3`).
fn validate_kick(kick: &KickParams, label: &str, model: &RobotModel) -> Result<(), String> {
    let named = |e: String| {
        if label == "kick" {
            e
        } else {
            format!("{label}: {e}")
        }
    };
    kick.validate().map_err(named)?;
    for (name, motion) in [("short", &kick.short), ("long", &kick.long)] {
        if let Some(frames) = &motion.keyframes {
            crate::getup::validate_frames(
                &format!("{label}.{name}.keyframes"),
                frames,
                model,
                None,
            )?;
            let mirrored: Vec<_> = frames.iter().map(crate::save::mirror_frame).collect();
            crate::getup::validate_frames(
                &format!("{label}.{name}.keyframes (mirrored for the left foot)"),
                &mirrored,
                model,
                None,
            )?;
        }
        for joint in motion.swing_gains.keys() {
            if model.joint_id(&format!("left_{joint}")).is_none()
                || model.joint_id(&format!("right_{joint}")).is_none()
            {
                return Err(format!(
                    "{label}: swing_gains: `{joint}` is not a leg joint of {} (`left_{joint}` and `right_{joint}` must exist)",
                    model.name
                ));
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests;
