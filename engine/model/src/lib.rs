//! Robot models and field geometry, described as RON data and validated on load.
//!
//! Everything the engine knows about a body (joint names on the wire, limits, gains,
//! kinematic geometry) comes from here, so that the rest of the engine never spells an
//! actuator name of its own.

pub mod data;
pub mod field;
pub mod kinematics;
pub mod location;
pub mod robot;
pub mod team_types;

pub use field::{FieldError, FieldGeometry, Landmark};
pub use location::{Located, SourceLocation};
pub use robot::{Gains, Joint, JointId, ModelError, RobotModel, ServerKind};
