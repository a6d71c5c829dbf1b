//! Whole-body forward kinematics with a precomputed tree and caller-owned output buffers.

use super::KinematicsError;
use crate::robot::{JointId, RobotModel};
use nalgebra::{Isometry3, Translation3, Unit, UnitQuaternion, Vector3};

/// The fixed geometry of one joint, ready for composition.
#[derive(Debug, Clone)]
pub(crate) struct JointGeometry {
    /// `None` = mounted on the torso.
    pub parent: Option<JointId>,
    /// Parent joint frame → this joint's frame at zero angle.
    pub mount: Isometry3<f64>,
    pub axis: Unit<Vector3<f64>>,
    pub limits_rad: (f64, f64),
}

impl JointGeometry {
    /// Parent joint frame → this joint's frame at `angle_rad`.
    #[inline]
    pub fn local(&self, angle_rad: f64) -> Isometry3<f64> {
        let mut pose = self.mount;
        pose.rotation *= UnitQuaternion::from_axis_angle(&self.axis, angle_rad);
        pose
    }
}

#[derive(Debug, Clone)]
struct FrameGeometry {
    name: String,
    parent: Option<JointId>,
    offset: Isometry3<f64>,
}

/// A robot model prepared for forward kinematics. Build once per model; every call after that is
/// allocation-free when given a [`BodyPoses`] buffer made by [`Kinematics::new_poses`].
#[derive(Debug, Clone)]
pub struct Kinematics {
    pub(crate) joints: Vec<JointGeometry>,
    joint_names: Vec<String>,
    frames: Vec<FrameGeometry>,
}

/// Poses of every joint frame and named frame for one set of joint angles.
#[derive(Debug, Clone, Default)]
pub struct BodyPoses {
    to_parent: Vec<Isometry3<f64>>,
    to_torso: Vec<Isometry3<f64>>,
    frames: Vec<Isometry3<f64>>,
}

impl BodyPoses {
    /// Pose of `joint`'s frame (after its rotation) in its parent joint's frame (or the torso's).
    pub fn joint_in_parent(&self, joint: JointId) -> Option<&Isometry3<f64>> {
        self.to_parent.get(joint)
    }

    /// Pose of `joint`'s frame (after its rotation) in the torso frame.
    pub fn joint_in_torso(&self, joint: JointId) -> Option<&Isometry3<f64>> {
        self.to_torso.get(joint)
    }

    /// Pose of the named frame with index `frame` (see [`Kinematics::frame_id`]) in the torso frame.
    pub fn frame_in_torso(&self, frame: usize) -> Option<&Isometry3<f64>> {
        self.frames.get(frame)
    }

    /// All joint poses in the torso frame, indexed by `JointId`.
    pub fn joints_in_torso(&self) -> &[Isometry3<f64>] {
        &self.to_torso
    }
}

pub(crate) fn isometry(origin: &[f64; 3], rotation: &[f64; 4]) -> Isometry3<f64> {
    let [w, x, y, z] = *rotation;
    let q = nalgebra::Quaternion::new(w, x, y, z);
    Isometry3::from_parts(
        Translation3::new(origin[0], origin[1], origin[2]),
        UnitQuaternion::from_quaternion(q),
    )
}

impl Kinematics {
    /// Prepare `model` (already validated: parents precede children, axes are unit vectors).
    pub fn new(model: &RobotModel) -> Self {
        let joint_index = |name: &Option<String>| name.as_deref().and_then(|n| model.joint_id(n));
        let joints = model
            .joints
            .iter()
            .map(|j| JointGeometry {
                parent: joint_index(&j.parent),
                mount: isometry(&j.origin, &j.rotation),
                axis: Unit::new_normalize(Vector3::from(j.axis)),
                limits_rad: (j.limits_deg.0.to_radians(), j.limits_deg.1.to_radians()),
            })
            .collect();
        let frames = model
            .frames
            .iter()
            .map(|f| FrameGeometry {
                name: f.name.clone(),
                parent: joint_index(&f.parent),
                offset: isometry(&f.origin, &f.rotation),
            })
            .collect();
        Self {
            joints,
            joint_names: model.joints.iter().map(|j| j.name.clone()).collect(),
            frames,
        }
    }

    /// Number of joints (the length every angle slice must have).
    pub fn joint_count(&self) -> usize {
        self.joints.len()
    }

    /// Index of a named frame (`camera`, `left_sole`, ...), for [`BodyPoses::frame_in_torso`].
    pub fn frame_id(&self, name: &str) -> Option<usize> {
        self.frames.iter().position(|f| f.name == name)
    }

    pub(crate) fn frame_parent_and_offset(
        &self,
        frame: usize,
    ) -> (Option<JointId>, Isometry3<f64>) {
        let f = &self.frames[frame];
        (f.parent, f.offset)
    }

    pub(crate) fn joint_name(&self, joint: JointId) -> &str {
        &self.joint_names[joint]
    }

    /// A buffer sized for this model.
    pub fn new_poses(&self) -> BodyPoses {
        let identity = Isometry3::identity();
        BodyPoses {
            to_parent: vec![identity; self.joints.len()],
            to_torso: vec![identity; self.joints.len()],
            frames: vec![identity; self.frames.len()],
        }
    }

    /// Fill `out` with the poses for `angles_deg` (one angle per joint, `JointId` order).
    pub fn forward(&self, angles_deg: &[f64], out: &mut BodyPoses) -> Result<(), KinematicsError> {
        if angles_deg.len() != self.joints.len() {
            return Err(KinematicsError::AngleCount {
                expected: self.joints.len(),
                got: angles_deg.len(),
            });
        }
        if out.to_torso.len() != self.joints.len() || out.frames.len() != self.frames.len() {
            *out = self.new_poses();
        }
        for (i, joint) in self.joints.iter().enumerate() {
            let local = joint.local(angles_deg[i].to_radians());
            out.to_parent[i] = local;
            // Parents precede children (validated on load), so the parent's pose is already final.
            out.to_torso[i] = match joint.parent {
                Some(p) => out.to_torso[p] * local,
                None => local,
            };
        }
        for (k, frame) in self.frames.iter().enumerate() {
            out.frames[k] = match frame.parent {
                Some(p) => out.to_torso[p] * frame.offset,
                None => frame.offset,
            };
        }
        Ok(())
    }

    /// Pose of one named frame in the torso frame, walking only its own chain.
    pub fn frame_pose(
        &self,
        frame: &str,
        angles_deg: &[f64],
    ) -> Result<Isometry3<f64>, KinematicsError> {
        let id = self
            .frame_id(frame)
            .ok_or_else(|| KinematicsError::UnknownFrame(frame.to_string()))?;
        if angles_deg.len() != self.joints.len() {
            return Err(KinematicsError::AngleCount {
                expected: self.joints.len(),
                got: angles_deg.len(),
            });
        }
        let (parent, offset) = self.frame_parent_and_offset(id);
        Ok(self.joint_pose_in_torso(parent, angles_deg) * offset)
    }

    /// Pose of `joint` (or the torso for `None`) in the torso frame; `angles_deg` must be full length.
    pub(crate) fn joint_pose_in_torso(
        &self,
        joint: Option<JointId>,
        angles_deg: &[f64],
    ) -> Isometry3<f64> {
        let mut pose = Isometry3::identity();
        let mut current = joint;
        while let Some(j) = current {
            pose = self.joints[j].local(angles_deg[j].to_radians()) * pose;
            current = self.joints[j].parent;
        }
        pose
    }
}
