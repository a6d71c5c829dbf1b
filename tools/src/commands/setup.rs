//! Building players from the command line's choices.

use libero_agent::{AgentStats, Player, StandAndBeam};
use libero_model::RobotModel;
use libero_skills::{SkillParams, Skills};
use std::path::PathBuf;
use std::sync::atomic::AtomicBool;
use std::sync::Arc;

/// A shutdown flag set by Ctrl-C (first press: stop cleanly).
pub fn ctrl_c_flag() -> Arc<AtomicBool> {
    let flag = Arc::new(AtomicBool::new(false));
    let f = Arc::clone(&flag);
    if let Err(e) = ctrlc::set_handler(move || f.store(true, std::sync::atomic::Ordering::Relaxed))
    {
        log::warn!("Ctrl-C handler not installed: {e}");
    }
    flag
}

/// A robot model by built-in name or from a RON file.
pub fn load_robot(
    name: &str,
    file: Option<&PathBuf>,
) -> Result<Arc<RobotModel>, Box<dyn std::error::Error>> {
    let model = match file {
        Some(path) => RobotModel::load(path)?,
        None => RobotModel::builtin(name)?,
    };
    Ok(Arc::new(model))
}

/// Own-frame kick-off position of a player (own goal at −x), spread over the own half.
fn kickoff_pose(unum: u32) -> [f64; 3] {
    // Replaced by the formation files once the strategy layer is wired in.
    let table = [
        [-25.0, 0.0],
        [-15.0, 6.0],
        [-15.0, -6.0],
        [-9.0, 0.0],
        [-5.0, 8.0],
        [-5.0, -8.0],
        [-2.0, 0.0],
    ];
    let [x, y] = table[(unum.saturating_sub(1) as usize) % table.len()];
    [x, y, 0.0]
}

/// A player with the standard pipeline.
pub fn build_player(
    model: &Arc<RobotModel>,
    team: &str,
    unum: u32,
) -> Result<Player, Box<dyn std::error::Error>> {
    let params = SkillParams::builtin(model)?;
    let skills = Skills::new(model, params)?;
    let decider = Box::new(StandAndBeam {
        beam_pose: kickoff_pose(unum),
    });
    Ok(Player::new(
        Arc::clone(model),
        skills,
        decider,
        team,
        unum,
        Arc::new(AgentStats::default()),
    ))
}
