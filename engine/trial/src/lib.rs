//! Skill trials on a real server, for benchmarks, tests and the optimizer.
//!
//! A [`Trial`] owns one headless rcssservermj (`--sync --no-realtime`) and its monitor. Each
//! [`Trial::run`] connects a fresh player whose decisions come from a script, places the robot
//! with the monitor, lets it settle, runs the script and records the server's ground truth.
//! Ground truth is used here only to *measure*; the skills never see it.

pub mod bench;
pub mod cmaes;
pub mod course;
pub mod episode;
pub mod getup_bench;
pub mod kick_bench;
pub mod kick_contact;
pub mod kick_step_bench;
pub mod measure;
pub mod optimize;
pub mod save_bench;
mod scripted;

pub use course::Course;
pub use episode::{Episode, LyingPlacement, Recording, Sample, Trial, TrialError};
