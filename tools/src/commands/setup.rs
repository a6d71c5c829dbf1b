//! Building players from the command line's choices.

use libero_agent::{LibrarySource, Player, SkillSource};
use libero_model::RobotModel;
use std::path::{Path, PathBuf};
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

/// A size field of this process's `/proc/self/status` in MB (`VmRSS` resident now, `VmHWM`
/// its peak); `None` where there is no such file or field.
pub fn proc_status_mb(field: &str) -> Option<f64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| {
        l.strip_prefix(field)
            .is_some_and(|rest| rest.starts_with(':'))
    })?;
    let kb: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb / 1024.0)
}

/// The built-in model a player with `unum` runs when the command line names `robot`: `NAO`
/// stands for the SimSpark type the team file's `robot_types` gives that number (`types`), or
/// the default mix's (goalkeeper and most field players type 0, the rest spread so a full
/// team is legal); any other name is itself.
pub fn robot_for_unum(robot: &str, unum: u32, types: Option<&[u8]>) -> String {
    if robot.eq_ignore_ascii_case("nao") {
        let index = unum.max(1) as usize - 1;
        let default = libero_agent::simspark_team_types(11);
        let t = types
            .and_then(|types| types.get(index))
            .copied()
            .unwrap_or(default[index % default.len()]);
        format!("nao_type{t}")
    } else {
        robot.to_string()
    }
}

/// The NAO type of each uniform number, when the team file (`team.ron`) names them.
pub fn team_robot_types(source: &LibrarySource) -> Option<Vec<u8>> {
    libero_strategy::strategy_of(&source.current())
        .team
        .as_ref()?
        .robot_types
        .clone()
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

/// Where a team's behavior trees and strategy files come from.
#[derive(clap::Args, Clone, Debug)]
pub struct DataArgs {
    /// Folder of behavior trees [default: the repository's behaviors/]
    #[arg(long, value_name = "DIR")]
    pub behaviors: Option<PathBuf>,
    /// Folder of formation and strategy files [default: the repository's formations/]
    #[arg(long, value_name = "DIR")]
    pub formations: Option<PathBuf>,
    /// Skill parameter file (walk, get-up, kick numbers) [default: the repository's
    /// engine/skills/params/<robot>.ron, else the built-in copy]
    #[arg(long, value_name = "FILE")]
    pub skill_params: Option<PathBuf>,
    /// Load the files once instead of reloading them on every edit.
    #[arg(long)]
    pub no_watch: bool,
}

impl DataArgs {
    /// A team folder's files: `behaviors/`, `formations/` and `t1.ron` (skill parameters)
    /// where the folder has them, else `base`'s choice (the repository's files by default).
    pub fn from_team_dir(dir: &Path, base: &DataArgs) -> Result<DataArgs, String> {
        if !dir.is_dir() {
            return Err(format!("team folder {} does not exist", dir.display()));
        }
        let sub = |name: &str| Some(dir.join(name)).filter(|p| p.exists());
        let data = DataArgs {
            behaviors: sub("behaviors").or_else(|| base.behaviors.clone()),
            formations: sub("formations").or_else(|| base.formations.clone()),
            skill_params: sub("t1.ron").or_else(|| base.skill_params.clone()),
            no_watch: base.no_watch,
        };
        if data.behaviors.is_none() && data.formations.is_none() && data.skill_params.is_none() {
            return Err(format!(
                "team folder {} has none of behaviors/, formations/, t1.ron",
                dir.display()
            ));
        }
        Ok(data)
    }

    /// Load (and, unless `--no-watch`, watch) the files; every error is reported at once.
    pub fn source(&self) -> Result<LibrarySource, Box<dyn std::error::Error>> {
        self.source_for(libero_model::ServerKind::RcssMj)
    }

    /// [`Self::source`] for players on `server`: without `--formations`, that server's field's
    /// formations.
    pub fn source_for(
        &self,
        server: libero_model::ServerKind,
    ) -> Result<LibrarySource, Box<dyn std::error::Error>> {
        let [behaviors, mut formations] = self.folders();
        if self.formations.is_none() {
            formations = libero_agent::build::default_formations_dir(server);
        }
        Ok(libero_agent::build::load_library(
            &[behaviors, formations],
            !self.no_watch,
        )?)
    }

    /// The behaviors and formations folders, the repository's where none is given.
    pub fn folders(&self) -> [PathBuf; 2] {
        let defaults = libero_agent::build::default_data_dirs();
        [
            self.behaviors
                .clone()
                .unwrap_or_else(|| defaults[0].clone()),
            self.formations
                .clone()
                .unwrap_or_else(|| defaults[1].clone()),
        ]
    }
}

impl DataArgs {
    /// The skill parameters for players of `model` (watched unless `--no-watch`). Without
    /// `--skill-params` and outside a checkout, the copy built into the binary.
    pub fn skills(&self, model: &RobotModel) -> Result<SkillSource, Box<dyn std::error::Error>> {
        let file = match &self.skill_params {
            Some(path) => path.clone(),
            None => {
                let shipped = libero_agent::build::default_skill_params_file(model);
                if !shipped.is_file() {
                    return Ok(SkillSource::Builtin);
                }
                shipped
            }
        };
        Ok(SkillSource::from_file(&file, model, !self.no_watch)?)
    }
}

/// A player that runs its behavior tree from `source` with skill parameters from `skills`.
pub fn build_player(
    model: &Arc<RobotModel>,
    team: &str,
    unum: u32,
    source: &LibrarySource,
    skills: &SkillSource,
) -> Result<Player, Box<dyn std::error::Error>> {
    Ok(libero_agent::build::tree_player(
        model, team, unum, source, skills,
    )?)
}

/// The evaluation log: one JSON line per cycle per agent.
#[derive(clap::Args, Clone, Debug, Default)]
pub struct LogArgs {
    /// Write the evaluation log (estimates and ground truth, one JSON line per cycle) to FILE;
    /// with several agents, FILE.<team>.<unum>.
    #[arg(long, value_name = "FILE")]
    pub log: Option<PathBuf>,
    /// Include each cycle's decision trace (active leaves and statuses) in the log.
    #[arg(long, requires = "log")]
    pub trace: bool,
}

impl LogArgs {
    /// Attach the log to `player`; `shared` names the file after team and number.
    pub fn attach(
        &self,
        player: &mut Player,
        team: &str,
        unum: u32,
        shared: bool,
    ) -> Result<(), Box<dyn std::error::Error>> {
        let Some(path) = &self.log else { return Ok(()) };
        let path = if shared {
            libero_world::eval_log::robot_log_path(path, team, unum)
        } else {
            path.clone()
        };
        let logger = libero_world::eval_log::EvalLogger::create(&path)
            .map_err(|e| format!("cannot create the evaluation log {}: {e}", path.display()))?;
        player.log_to(logger, self.trace);
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_nao_player_plays_the_type_its_team_file_names() {
        let types = [0, 3, 4];
        assert_eq!(robot_for_unum("NAO", 2, Some(&types)), "nao_type3");
        assert_eq!(robot_for_unum("nao", 3, Some(&types)), "nao_type4");
        // Beyond the list, and without one: the default mix.
        let default = libero_agent::simspark_team_types(11);
        assert_eq!(
            robot_for_unum("NAO", 9, Some(&types)),
            format!("nao_type{}", default[8])
        );
        assert_eq!(
            robot_for_unum("NAO", 2, None),
            format!("nao_type{}", default[1])
        );
        assert_eq!(robot_for_unum("T1", 2, Some(&types)), "T1");
    }
}
