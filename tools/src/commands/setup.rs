//! Building players from the command line's choices.

use libero_agent::Player;
use libero_model::RobotModel;
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

/// A player with the standard pipeline.
pub fn build_player(model: &Arc<RobotModel>, team: &str, unum: u32) -> Result<Player, Box<dyn std::error::Error>> {
    Ok(libero_agent::build::standing_player(model, team, unum)?)
}
