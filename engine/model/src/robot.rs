//! Robot model schema: joints as the server names them, limits, gains and geometry.

use crate::data::{self, DataFile};
use crate::location::{Located, SourceLocation};
use serde::{Deserialize, Serialize};
use std::collections::HashSet;
use std::path::Path;

/// Which simulator a robot model belongs to (and so which wire dialect it speaks).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum ServerKind {
    /// rcssservermj (MuJoCo): position/velocity/torque motor commands in degrees.
    RcssMj,
    /// SimSpark rcssserver3d: joint velocity effectors in rad/s.
    SimSpark,
}

impl ServerKind {
    /// The built-in field this server plays on by default (`engine/model/fields/`).
    pub fn default_field(self) -> &'static str {
        match self {
            ServerKind::RcssMj => "fifa7vs7",
            ServerKind::SimSpark => "simspark",
        }
    }
}

impl std::str::FromStr for ServerKind {
    type Err = String;
    /// `rcssservermj` (also `mj`) or `simspark` (also `rcssserver3d`), as the command line names them.
    fn from_str(s: &str) -> Result<Self, String> {
        match s.to_ascii_lowercase().as_str() {
            "rcssservermj" | "mj" | "rcsssmj" => Ok(ServerKind::RcssMj),
            "simspark" | "rcssserver3d" => Ok(ServerKind::SimSpark),
            other => Err(format!(
                "unknown server `{other}`: use `rcssservermj` or `simspark`"
            )),
        }
    }
}

/// Position and damping gains for a joint motor (rcssservermj `kp`, `kd`).
///
/// SimSpark has no motor gains (velocity effectors only); there `kp` is the dimensionless gain `g`
/// of the client-side servo `v = g·(θ* − θ̂)/Δt` (simspark.md §8.2) and `kd` is 0.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Gains {
    /// N·m/rad
    pub kp: f64,
    /// N·m·s/rad
    pub kd: f64,
}

/// Index of a joint within its robot model (the order of `RobotModel::joints`).
pub type JointId = usize;

/// One actuated hinge joint.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Joint {
    /// Our name for the joint, e.g. `left_hip_pitch`.
    pub name: String,
    /// The effector/actuator name the server accepts, e.g. `lle1`.
    pub effector: String,
    /// The perceptor name the server reports the angle under, e.g. `q_llj1` or `llj1`.
    pub perceptor: String,
    /// The joint this one is mounted on; `None` means the torso.
    #[serde(default)]
    pub parent: Option<String>,
    /// Position of this joint's axis point in the parent joint's frame at zero pose [m].
    ///
    /// Every model is expressed in one body convention, whatever its simulator uses: x forward,
    /// y left, z up, origin at the torso reference point (rcssservermj: the `torso` site; SimSpark:
    /// the torso centre; SimSpark's own x-right/y-forward numbers are converted once, in the data).
    #[serde(default)]
    pub origin: [f64; 3],
    /// Fixed rotation of this joint's frame relative to the parent joint's frame at zero pose, as a
    /// quaternion `(w, x, y, z)` (MuJoCo's `quat` order); identity when the frames are parallel.
    #[serde(default = "identity_rotation")]
    pub rotation: [f64; 4],
    /// Rotation axis in the joint's own frame (unit vector).
    pub axis: [f64; 3],
    /// Lower and upper angle limits [deg].
    pub limits_deg: (f64, f64),
    /// Largest torque the motor delivers [N·m].
    pub max_torque: f64,
    /// Largest joint speed the server allows [deg/s], where it has one.
    #[serde(default)]
    pub max_speed_deg: Option<f64>,
    /// Gains used when a skill does not say otherwise.
    pub gains: Gains,
}

/// A named point of interest fixed to a joint's link (camera, soles, vision markers).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Frame {
    pub name: String,
    /// The joint whose link carries this frame; `None` means the torso.
    #[serde(default)]
    pub parent: Option<String>,
    /// Position in the parent joint's frame [m].
    pub origin: [f64; 3],
    /// Orientation relative to the parent joint's frame, quaternion `(w, x, y, z)`.
    #[serde(default = "identity_rotation")]
    pub rotation: [f64; 4],
    /// The part name under which the server's vision reports this frame's origin when the
    /// robot sees itself (SimSpark: `lfoot`, the foot box's centre): a point whose place in
    /// the camera frame the robot knows from its joints, so what the camera adds can be told.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub seen_as: Option<String>,
}

fn identity_rotation() -> [f64; 4] {
    [1.0, 0.0, 0.0, 0.0]
}

fn is_unit_quaternion(q: &[f64; 4]) -> bool {
    let norm = q.iter().map(|v| v * v).sum::<f64>().sqrt();
    q.iter().all(|v| v.is_finite()) && (norm - 1.0).abs() < 1e-3
}

/// A complete robot description.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RobotModel {
    /// Model name as sent in `init` (rcssservermj) or as known to SimSpark, e.g. `T1`, `NAO`.
    pub name: String,
    pub server: ServerKind,
    /// SimSpark scene file, e.g. `rsg/agent/nao/nao_hetero.rsg`.
    #[serde(default)]
    pub scene: Option<String>,
    /// SimSpark heterogeneous robot type (0–4).
    #[serde(default)]
    pub hetero_type: Option<u8>,
    /// Total mass [kg].
    pub mass: f64,
    /// Torso origin height when standing straight on flat ground [m].
    pub standing_torso_height: f64,
    pub joints: Vec<Joint>,
    #[serde(default)]
    pub frames: Vec<Frame>,
}

/// Why a robot model could not be used.
pub type ModelError = crate::data::DataError;

/// The robot models shipped with Libero, by file name.
const BUILTIN: &[(&str, &str)] = &[
    ("T1", include_str!("../robots/t1.ron")),
    ("K1", include_str!("../robots/k1.ron")),
    ("NAO_type0", include_str!("../robots/nao_type0.ron")),
    ("NAO_type1", include_str!("../robots/nao_type1.ron")),
    ("NAO_type2", include_str!("../robots/nao_type2.ron")),
    ("NAO_type3", include_str!("../robots/nao_type3.ron")),
    ("NAO_type4", include_str!("../robots/nao_type4.ron")),
];

impl RobotModel {
    /// Names of the shipped robot models.
    pub fn builtin_names() -> Vec<&'static str> {
        data::builtin_names::<Self>()
    }

    /// A shipped robot model by name (case-insensitive), parsed and validated.
    pub fn builtin(name: &str) -> Result<Self, ModelError> {
        data::builtin(name)
    }

    /// Load and validate a robot model file.
    pub fn load(path: &Path) -> Result<Self, ModelError> {
        data::load(path)
    }

    /// Parse and validate RON text; `file` names the source in error messages.
    pub fn from_ron(file: &str, text: &str) -> Result<Self, ModelError> {
        data::from_ron(file, text)
    }

    /// Every semantic problem of the model, located in `text` where possible.
    fn problems(&self, file: &str, text: &str) -> Vec<Located> {
        let mut errors = Vec::new();
        let mut report = |needle: &str, message: String| {
            errors.push(Located {
                file: file.to_string(),
                at: SourceLocation::of_first(text, needle).unwrap_or_default(),
                message,
            })
        };
        if self.joints.is_empty() {
            report("joints", "a robot model needs at least one joint".into());
        }
        let mut names = HashSet::new();
        let mut effectors = HashSet::new();
        let mut perceptors = HashSet::new();
        for joint in &self.joints {
            let here = format!("\"{}\"", joint.name);
            if !names.insert(joint.name.as_str()) {
                report(&here, format!("joint `{}` is defined twice", joint.name));
            }
            if !effectors.insert(joint.effector.as_str()) {
                report(
                    &here,
                    format!("effector `{}` is used twice", joint.effector),
                );
            }
            if !perceptors.insert(joint.perceptor.as_str()) {
                report(
                    &here,
                    format!("perceptor `{}` is used twice", joint.perceptor),
                );
            }
            if !is_wire_atom(&joint.effector) || !is_wire_atom(&joint.perceptor) {
                report(
                    &here,
                    format!(
                        "joint `{}`: effector and perceptor names must be plain atoms (letters, digits, `_`)",
                        joint.name
                    ),
                );
            }
            let (lo, hi) = joint.limits_deg;
            if !(lo.is_finite() && hi.is_finite() && lo < hi) {
                report(
                    &here,
                    format!("joint `{}`: limits_deg must be finite with lower < upper, got ({lo}, {hi})", joint.name),
                );
            }
            let norm = joint.axis.iter().map(|a| a * a).sum::<f64>().sqrt();
            if !(norm - 1.0).abs().lt(&1e-6) {
                report(
                    &here,
                    format!(
                        "joint `{}`: axis must be a unit vector (length is {norm})",
                        joint.name
                    ),
                );
            }
            if !(joint.max_torque.is_finite() && joint.max_torque > 0.0) {
                report(
                    &here,
                    format!("joint `{}`: max_torque must be positive", joint.name),
                );
            }
            if !(joint.gains.kp >= 0.0
                && joint.gains.kd >= 0.0
                && joint.gains.kp.is_finite()
                && joint.gains.kd.is_finite())
            {
                report(
                    &here,
                    format!(
                        "joint `{}`: gains must be finite and non-negative",
                        joint.name
                    ),
                );
            }
            if !is_unit_quaternion(&joint.rotation) {
                report(
                    &here,
                    format!(
                        "joint `{}`: rotation must be a unit quaternion (w, x, y, z)",
                        joint.name
                    ),
                );
            }
            if joint.origin.iter().any(|v| !v.is_finite()) {
                report(
                    &here,
                    format!("joint `{}`: origin must be finite", joint.name),
                );
            }
        }
        let known: HashSet<&str> = self.joints.iter().map(|j| j.name.as_str()).collect();
        for (i, joint) in self.joints.iter().enumerate() {
            if let Some(parent) = &joint.parent {
                let earlier = self.joints[..i].iter().any(|j| &j.name == parent);
                if !earlier {
                    let hint = if known.contains(parent.as_str()) {
                        "it must be listed before its children"
                    } else {
                        "no joint has that name"
                    };
                    report(
                        &format!("\"{}\"", joint.name),
                        format!(
                            "joint `{}`: parent `{parent}` is not usable: {hint}",
                            joint.name
                        ),
                    );
                }
            }
        }
        let mut frame_names = HashSet::new();
        for frame in &self.frames {
            let here = format!("\"{}\"", frame.name);
            if !frame_names.insert(frame.name.as_str()) {
                report(&here, format!("frame `{}` is defined twice", frame.name));
            }
            if !is_unit_quaternion(&frame.rotation) || frame.origin.iter().any(|v| !v.is_finite()) {
                report(
                    &here,
                    format!(
                        "frame `{}`: origin must be finite and rotation a unit quaternion",
                        frame.name
                    ),
                );
            }
            if let Some(parent) = &frame.parent {
                if !known.contains(parent.as_str()) {
                    report(
                        &here,
                        format!(
                            "frame `{}`: parent joint `{parent}` does not exist",
                            frame.name
                        ),
                    );
                }
            }
        }
        if self.server == ServerKind::SimSpark && self.scene.is_none() {
            report("server", "a SimSpark robot needs a `scene` path".into());
        }
        if !(self.standing_torso_height > 0.0 && self.mass > 0.0) {
            report(
                "mass",
                "mass and standing_torso_height must be positive".into(),
            );
        }
        errors
    }

    /// The joint with our name `name`.
    pub fn joint_id(&self, name: &str) -> Option<JointId> {
        self.joints.iter().position(|j| j.name == name)
    }

    /// The joint the server reports under `perceptor`.
    pub fn joint_by_perceptor(&self, perceptor: &str) -> Option<JointId> {
        self.joints.iter().position(|j| j.perceptor == perceptor)
    }

    /// The named frame (camera, soles, ...).
    pub fn frame(&self, name: &str) -> Option<&Frame> {
        self.frames.iter().find(|f| f.name == name)
    }

    /// `angle` clamped into the joint's limits.
    pub fn clamp_deg(&self, joint: JointId, angle: f64) -> f64 {
        let (lo, hi) = self.joints[joint].limits_deg;
        angle.clamp(lo, hi)
    }
}

/// True when `name` can be sent to a server as one atom without any escaping.
fn is_wire_atom(name: &str) -> bool {
    !name.is_empty() && name.bytes().all(|b| b.is_ascii_alphanumeric() || b == b'_')
}

impl DataFile for RobotModel {
    const KIND: &'static str = "robot model";
    const BUILTIN: &'static [(&'static str, &'static str)] = BUILTIN;

    fn problems(&self, file: &str, text: &str) -> Vec<Located> {
        RobotModel::problems(self, file, text)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_builtin_model_loads() {
        for name in RobotModel::builtin_names() {
            let model = RobotModel::builtin(name).unwrap_or_else(|e| panic!("{name}: {e}"));
            assert!(!model.joints.is_empty());
        }
    }

    #[test]
    fn t1_has_the_servers_23_actuators_in_message_order() {
        let t1 = RobotModel::builtin("t1").unwrap();
        let effectors: Vec<&str> = t1.joints.iter().map(|j| j.effector.as_str()).collect();
        assert_eq!(
            effectors,
            [
                "he1", "he2", "lae1", "lae2", "lae3", "lae4", "rae1", "rae2", "rae3", "rae4",
                "te1", "lle1", "lle2", "lle3", "lle4", "lle5", "lle6", "rle1", "rle2", "rle3",
                "rle4", "rle5", "rle6"
            ]
        );
        assert_eq!(t1.joint_by_perceptor("q_rlj6"), Some(22));
    }

    #[test]
    fn semantic_errors_are_located_and_all_reported() {
        let text = include_str!("../robots/t1.ron");
        let broken = text
            .replacen("effector: \"he2\"", "effector: \"he1\"", 1)
            .replacen("limits_deg: (-90.0, 90.0)", "limits_deg: (90.0, -90.0)", 1);
        let Err(ModelError::Invalid(errors)) = RobotModel::from_ron("t1.ron", &broken) else {
            panic!("broken model accepted");
        };
        assert_eq!(errors.len(), 2, "{errors:?}");
        assert!(errors.iter().all(|e| e.at.line > 1));
        assert!(errors
            .iter()
            .any(|e| e.message.contains("effector `he1` is used twice")));
        assert!(errors.iter().any(|e| e.message.contains("lower < upper")));
    }

    #[test]
    fn syntax_errors_carry_a_position() {
        let Err(ModelError::Invalid(errors)) =
            RobotModel::from_ron("x.ron", "RobotModel(\n  name: 3,\n)")
        else {
            panic!("accepted");
        };
        assert_eq!(errors[0].at.line, 2);
    }
}
