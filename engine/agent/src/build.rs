//! Assembling a player from data: robot model, skill parameters, decision source.

use crate::decide::StandAndBeam;
use crate::player::Player;
use crate::stats::AgentStats;
use libero_model::RobotModel;
use libero_skills::{SkillParams, Skills};
use std::sync::Arc;

/// Why a player could not be assembled.
#[derive(Debug, thiserror::Error)]
pub enum BuildError {
    #[error(transparent)]
    Params(#[from] libero_skills::ParamsError),
}

/// Own-frame kick-off position of a player (own goal at −x), used when no formation is loaded.
pub fn fallback_kickoff_pose(unum: u32) -> [f64; 3] {
    let table = [[-25.0, 0.0], [-15.0, 6.0], [-15.0, -6.0], [-9.0, 0.0], [-5.0, 8.0], [-5.0, -8.0], [-2.0, 0.0]];
    let [x, y] = table[(unum.saturating_sub(1) as usize) % table.len()];
    [x, y, 0.0]
}

/// A player that beams to its kick-off place and stands, with the model's built-in skill
/// parameters.
pub fn standing_player(model: &Arc<RobotModel>, team: &str, unum: u32) -> Result<Player, BuildError> {
    let skills = Skills::new(model, SkillParams::builtin(model)?)?;
    let decider = Box::new(StandAndBeam { beam_pose: fallback_kickoff_pose(unum) });
    Ok(Player::new(Arc::clone(model), skills, decider, team, unum, Arc::new(AgentStats::default())))
}
