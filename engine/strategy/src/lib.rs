//! The strategy layer (thesis layers "high-level skills" and "strategy"): the native nodes trees
//! call, the strategy files in `formations/` and the logic they tune — formations, the
//! goalkeeper's defense point and saves, shot and pass utility, obstacle avoidance — over the one field
//! model (`engine/model/fields/*.ron`).
//!
//! The tree engine (`libero_behavior`) stays soccer-free: this crate hands it the
//! [`vocabulary`] (every node declared next to its handler, [`natives`]) and the
//! [`StrategyFiles`] reader, and implements its `Host` with [`AgentHost`].

pub mod avoidance;
pub mod files;
pub mod goalkeeper;
pub mod natives;
pub mod pass;
pub mod roles;
pub mod shot;

pub use files::{
    parse_formation, AvoidanceParams, DefenseLine, Field, Formation, GoalkeeperParams, PassParams,
    Role, Sample, ShotParams, Situation, Strategy, StrategyFiles, TeamParams,
};
pub use natives::{catalogue, vocabulary, AgentHost, DecisionNotes, Natives, PlayerMemory};

use libero_behavior::{Library, Report};
use std::path::PathBuf;

/// The strategy of a loaded library (every library this crate loads has one).
pub fn strategy_of(library: &Library) -> &Strategy {
    static EMPTY: std::sync::OnceLock<Strategy> = std::sync::OnceLock::new();
    library
        .data::<Strategy>()
        .unwrap_or_else(|| EMPTY.get_or_init(Strategy::default))
}

/// Loads and validates trees and strategy files under `paths`.
pub fn load(paths: &[PathBuf]) -> Result<Library, Report> {
    Library::load(paths, &vocabulary(), &StrategyFiles)
}

/// What `libero validate` reports for trees and strategy files under `paths`.
pub fn validate_paths(paths: &[PathBuf]) -> Report {
    libero_behavior::validate_paths(paths, &vocabulary(), &StrategyFiles)
}
