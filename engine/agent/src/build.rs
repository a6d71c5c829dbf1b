//! Assembling a player from data: robot model, skill parameters, decision source.

use crate::decide::{Decider, LibrarySource, StandAndBeam, TreeDecider};
use crate::player::Player;
use crate::skill_source::SkillSource;
use crate::stats::AgentStats;
use libero_behavior::{LiveLibrary, ReloadOptions};
use libero_model::RobotModel;
use libero_skills::{SkillParams, Skills};
use libero_strategy::{vocabulary, Natives, StrategyFiles};
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// Why a player could not be assembled.
#[derive(Debug, thiserror::Error)]
pub enum BuildError {
    #[error(transparent)]
    Params(#[from] libero_skills::ParamsError),
    #[error("the behavior files have errors:\n{0}")]
    Behavior(String),
}

/// Own-frame kick-off position of a player (own goal at −x), used when no formation is loaded.
pub fn fallback_kickoff_pose(unum: u32) -> [f64; 3] {
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

/// A player that beams to its kick-off place and stands, with the model's built-in skill
/// parameters.
pub fn standing_player(
    model: &Arc<RobotModel>,
    team: &str,
    unum: u32,
) -> Result<Player, BuildError> {
    let decider = Box::new(StandAndBeam {
        beam_pose: fallback_kickoff_pose(unum),
    });
    player_with(model, team, unum, decider, &SkillSource::Builtin)
}

/// A player with skill parameters from `skills` and `decider`.
pub fn player_with(
    model: &Arc<RobotModel>,
    team: &str,
    unum: u32,
    decider: Box<dyn Decider>,
    skills: &SkillSource,
) -> Result<Player, BuildError> {
    let engine = Skills::new(model, skills.initial(model)?)?;
    let mut player = Player::new(
        Arc::clone(model),
        engine,
        decider,
        team,
        unum,
        Arc::new(AgentStats::default()),
    );
    player.follow_skill_params(skills.clone());
    Ok(player)
}

/// The repository's skill parameter file for a robot (`engine/skills/params/t1.ron` for the
/// T1, `nao.ron` for every NAO type): under `LIBERO_HOME` if set, else under this checkout.
pub fn default_skill_params_file(model: &RobotModel) -> PathBuf {
    repository_root()
        .join("engine/skills/params")
        .join(SkillParams::file_name(model))
}

fn repository_root() -> PathBuf {
    std::env::var_os("LIBERO_HOME")
        .map(PathBuf::from)
        .unwrap_or_else(|| Path::new(env!("CARGO_MANIFEST_DIR")).join("../.."))
}

/// The repository's data folders (`behaviors/`, `formations/`): under `LIBERO_HOME` if set,
/// else under the checkout this crate was built from.
pub fn default_data_dirs() -> Vec<PathBuf> {
    vec![
        repository_root().join("behaviors"),
        default_formations_dir(libero_model::ServerKind::RcssMj),
    ]
}

/// The repository's formations for a server's field: `formations/` on rcssservermj (7 a side),
/// `formations/simspark/` on SimSpark (11 a side, its own team file). The trees are the same.
pub fn default_formations_dir(server: libero_model::ServerKind) -> PathBuf {
    let formations = repository_root().join("formations");
    match server {
        libero_model::ServerKind::RcssMj => formations,
        libero_model::ServerKind::SimSpark => formations.join("simspark"),
    }
}

/// Load the behavior and strategy files of `dirs`; with `watch`, keep watching them and swap in
/// every good edit while the team plays.
pub fn load_library(dirs: &[PathBuf], watch: bool) -> Result<LibrarySource, BuildError> {
    if watch {
        let vocabulary = vocabulary();
        let live = LiveLibrary::start(
            dirs.to_vec(),
            Arc::new(vocabulary),
            Arc::new(StrategyFiles),
            ReloadOptions::default(),
        )
        .map_err(|report| BuildError::Behavior(report.render_text()))?;
        Ok(LibrarySource::Live(Arc::new(live)))
    } else {
        let library = libero_strategy::load(dirs)
            .map_err(|report| BuildError::Behavior(report.render_text()))?;
        Ok(LibrarySource::Fixed(Arc::new(library)))
    }
}

/// A player whose decisions come from its behavior tree in `source` and whose skill
/// parameters come from `skills`.
pub fn tree_player(
    model: &Arc<RobotModel>,
    team: &str,
    unum: u32,
    source: &LibrarySource,
    skills: &SkillSource,
) -> Result<Player, BuildError> {
    let natives = Natives::new();
    let decider = Box::new(TreeDecider::new(source.clone(), natives, unum));
    player_with(model, team, unum, decider, skills)
}
