//! A serial chain of joints ending in a tip frame, evaluated with its geometric Jacobian.

use super::forward::Kinematics;
use super::KinematicsError;
use crate::robot::JointId;
use nalgebra::{Isometry3, Vector3};

/// Longest chain supported; keeps evaluation on the stack (the longest real chain is a T1 leg
/// from the torso: waist + 6 leg joints).
pub const MAX_CHAIN_JOINTS: usize = 8;

/// Joints from `first` down to a tip frame. Joints above `first` are the chain's base: they are read
/// from the angle vector but never changed by IK on this chain.
#[derive(Debug, Clone)]
pub struct Chain {
    /// Parent of the first joint (`None` = torso).
    base: Option<JointId>,
    joints: Vec<JointId>,
    /// Last joint's frame → tip.
    tip: Isometry3<f64>,
}

/// Tip pose plus, for each chain joint, its world axis and axis point (torso frame).
pub(crate) struct ChainState {
    pub tip: Isometry3<f64>,
    pub axes: [Vector3<f64>; MAX_CHAIN_JOINTS],
    pub points: [Vector3<f64>; MAX_CHAIN_JOINTS],
}

impl Chain {
    /// The chain from `first_joint` down to the named frame (`camera`, `left_sole`, ...).
    /// `first_joint = None` starts at the torso, so every joint above the frame moves.
    pub fn to_frame(
        kin: &Kinematics,
        first_joint: Option<&str>,
        frame: &str,
    ) -> Result<Self, KinematicsError> {
        let id = kin
            .frame_id(frame)
            .ok_or_else(|| KinematicsError::UnknownFrame(frame.to_string()))?;
        let (parent, offset) = kin.frame_parent_and_offset(id);
        Self::build(kin, first_joint, parent, offset)
    }

    /// The chain from `first_joint` down to the frame of `last_joint` itself.
    pub fn to_joint(
        kin: &Kinematics,
        first_joint: Option<&str>,
        last_joint: &str,
    ) -> Result<Self, KinematicsError> {
        let last = (0..kin.joint_count())
            .find(|&j| kin.joint_name(j) == last_joint)
            .ok_or_else(|| KinematicsError::UnknownJoint(last_joint.to_string()))?;
        Self::build(kin, first_joint, Some(last), Isometry3::identity())
    }

    fn build(
        kin: &Kinematics,
        first_joint: Option<&str>,
        last: Option<JointId>,
        tip: Isometry3<f64>,
    ) -> Result<Self, KinematicsError> {
        let mut joints = Vec::new();
        let mut current = last;
        let mut found_first = first_joint.is_none();
        while let Some(j) = current {
            joints.push(j);
            current = kin.joints[j].parent;
            if Some(kin.joint_name(j)) == first_joint {
                found_first = true;
                break;
            }
        }
        if !found_first {
            let name = first_joint.unwrap_or_default();
            return Err(KinematicsError::UnknownJoint(format!(
                "{name} (not above the chain's tip)"
            )));
        }
        if joints.len() > MAX_CHAIN_JOINTS {
            return Err(KinematicsError::UnknownJoint(format!(
                "chain of {} joints is longer than {MAX_CHAIN_JOINTS}",
                joints.len()
            )));
        }
        joints.reverse();
        Ok(Self {
            base: current,
            joints,
            tip,
        })
    }

    /// The moving joints, root first.
    pub fn joints(&self) -> &[JointId] {
        &self.joints
    }

    /// Pose of the tip in the torso frame. `angles_deg` is the whole-body angle vector.
    pub fn tip_pose(
        &self,
        kin: &Kinematics,
        angles_deg: &[f64],
    ) -> Result<Isometry3<f64>, KinematicsError> {
        check_len(kin, angles_deg)?;
        Ok(self.evaluate(kin, angles_deg).tip)
    }

    /// Base pose in the torso frame (depends only on joints above the chain).
    pub(crate) fn base_pose(&self, kin: &Kinematics, angles_deg: &[f64]) -> Isometry3<f64> {
        kin.joint_pose_in_torso(self.base, angles_deg)
    }

    /// Tip pose and joint axes, given a correct-length angle vector.
    pub(crate) fn evaluate(&self, kin: &Kinematics, angles_deg: &[f64]) -> ChainState {
        self.evaluate_from(kin, self.base_pose(kin, angles_deg), angles_deg)
    }

    pub(crate) fn evaluate_from(
        &self,
        kin: &Kinematics,
        base: Isometry3<f64>,
        angles_deg: &[f64],
    ) -> ChainState {
        let mut state = ChainState {
            tip: base,
            axes: [Vector3::zeros(); MAX_CHAIN_JOINTS],
            points: [Vector3::zeros(); MAX_CHAIN_JOINTS],
        };
        let mut pose = base;
        for (k, &j) in self.joints.iter().enumerate() {
            let geometry = &kin.joints[j];
            pose *= geometry.local(angles_deg[j].to_radians());
            state.axes[k] = pose.rotation * geometry.axis.into_inner();
            state.points[k] = pose.translation.vector;
        }
        state.tip = pose * self.tip;
        state
    }
}

pub(crate) fn check_len(kin: &Kinematics, angles_deg: &[f64]) -> Result<(), KinematicsError> {
    if angles_deg.len() == kin.joint_count() {
        Ok(())
    } else {
        Err(KinematicsError::AngleCount {
            expected: kin.joint_count(),
            got: angles_deg.len(),
        })
    }
}
