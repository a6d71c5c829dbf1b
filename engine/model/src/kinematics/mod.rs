//! Kinematics over any [`RobotModel`](crate::RobotModel): forward kinematics of the whole body,
//! serial chains with their Jacobians, numeric (damped least-squares) IK for any chain, and
//! closed-form-seeded leg IK for the Booster (T1, K1) and NAO legs.
//!
//! Conventions: every pose is an `Isometry3<f64>` in the model's body frame (x forward, y left,
//! z up, origin at the torso reference point); joint angles are in degrees, indexed by
//! [`JointId`](crate::JointId), exactly as the servers report them.

mod chain;
mod forward;
mod leg;
mod numeric;

pub use chain::Chain;
pub use forward::{BodyPoses, Kinematics};
pub use leg::{LegIk, LegKind, Side};
pub use numeric::{IkOptions, IkReport, IkTarget, NumericIk};

/// Why a kinematics request could not be served.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum KinematicsError {
    #[error("expected {expected} joint angles, got {got}")]
    AngleCount { expected: usize, got: usize },
    #[error("no joint named `{0}` in this model")]
    UnknownJoint(String),
    #[error("no frame named `{0}` in this model")]
    UnknownFrame(String),
    #[error("the target contains a non-finite number")]
    NonFiniteTarget,
    #[error("the joint angles contain a non-finite number")]
    NonFiniteAngles,
    #[error("this model has no leg of the expected shape: {0}")]
    UnsupportedLeg(String),
}
