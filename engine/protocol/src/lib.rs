//! The wire: bytes → frames → S-expressions → typed percepts, and actions → bytes.
//!
//! Both servers speak the same framing and S-expression syntax; they differ in which items a
//! percept holds and how joints are commanded. [`percept`] reads both dialects into one type;
//! [`action`] writes each dialect's commands, taking actuator names only from a robot model.

pub mod action;
pub mod cursor;
pub mod frame;
pub mod percept;
pub mod sexp;

pub use action::{ActionWriter, MotorCommand};
pub use frame::{encode_frame, is_timeout, FrameError, FrameReader};
pub use percept::{parse_percept, parse_percept_str, Percept, PerceptError, Polar};
