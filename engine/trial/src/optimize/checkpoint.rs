//! The optimizer's state after each generation, so a killed run continues where it stopped.
//!
//! A checkpoint holds the CMA-ES state (mean, step size, covariance, paths, generation and the
//! sampler's seed state), the best point so far and the history. It names the search that
//! wrote it (tunables and ranges, population, step size, seed, objective, start file), and
//! only that search takes it up: another is refused rather than silently mixed in.

use super::{Options, Tunable};
use crate::cmaes::CmaEs;
use crate::episode::TrialError;
use serde::{Deserialize, Serialize};
use std::path::Path;

#[derive(Serialize, Deserialize)]
pub struct Checkpoint {
    pub identity: String,
    pub start_cost: f64,
    pub best_cost: f64,
    /// The best point in normalised coordinates.
    pub best_x: Vec<f64>,
    pub history: Vec<(usize, f64, f64)>,
    pub es: CmaEs,
}

/// What makes two runs the same search.
pub fn identity(tunables: &[Tunable], options: &Options) -> String {
    let names: Vec<String> = tunables
        .iter()
        .map(|t| format!("{}[{}..{}]", t.name, t.lo, t.hi))
        .collect();
    format!(
        "tunables {}; population {:?}; sigma {}; seed {}; {}",
        names.join(","),
        options.population,
        options.sigma,
        options.seed,
        options.identity
    )
}

fn error(path: &Path, detail: impl Into<String>) -> TrialError {
    TrialError::Checkpoint {
        path: path.display().to_string(),
        detail: detail.into(),
    }
}

/// The checkpoint at `path` if there is one; an error if it is unreadable or from another
/// search.
pub fn load(path: &Path, identity: &str) -> Result<Option<Checkpoint>, TrialError> {
    let text = match std::fs::read_to_string(path) {
        Ok(text) => text,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(None),
        Err(e) => return Err(error(path, e.to_string())),
    };
    let saved: Checkpoint = serde_json::from_str(&text).map_err(|e| {
        error(
            path,
            format!("not a checkpoint ({e}); remove it to start over"),
        )
    })?;
    if saved.identity != identity {
        return Err(error(
            path,
            format!(
                "written by another search; remove it to start over\n  it: {}\n  this run: {identity}",
                saved.identity
            ),
        ));
    }
    Ok(Some(saved))
}

/// Write by rename, so a run killed while writing leaves the previous checkpoint whole.
pub fn save(path: &Path, checkpoint: &Checkpoint) -> Result<(), TrialError> {
    let json = serde_json::to_string(checkpoint).map_err(|e| error(path, e.to_string()))?;
    let partial = path.with_extension("partial");
    std::fs::write(&partial, json)
        .and_then(|()| std::fs::rename(&partial, path))
        .map_err(|e| error(path, e.to_string()))
}

#[cfg(test)]
mod tests {
    use super::super::*;
    use super::*;

    /// Costs by a formula: the distance of two walk numbers from a target.
    struct Formula;

    impl Evaluator for Formula {
        fn costs(&mut self, candidates: &[SkillParams]) -> Result<Vec<f64>, TrialError> {
            Ok(candidates
                .iter()
                .map(|p| {
                    (p.walk.step_period_s - 0.31).powi(2) + (p.walk.step_height_m - 0.05).powi(2)
                })
                .collect())
        }
    }

    fn options(generations: usize, checkpoint: &Path) -> Options {
        Options {
            generations,
            population: Some(6),
            sigma: 0.2,
            seed: 3,
            budget: None,
            checkpoint: Some(checkpoint.to_path_buf()),
            identity: "formula".into(),
        }
    }

    #[test]
    fn a_run_cut_short_and_resumed_ends_where_an_uncut_run_ends() {
        let model = libero_model::RobotModel::builtin("T1").unwrap();
        let start = SkillParams::builtin(&model).unwrap();
        let tunables = select_walk_tunables(
            &["step_period_s", "step_height_m"],
            &libero_model::RobotModel::builtin("T1").unwrap(),
        )
        .unwrap();
        let dir = tempfile::tempdir().unwrap();
        let whole = dir.path().join("whole.json");
        let uncut = optimize(
            &start,
            &tunables,
            &mut Formula,
            &options(8, &whole),
            |_, _, _, _| {},
        )
        .unwrap();
        let cut = dir.path().join("cut.json");
        let first = optimize(
            &start,
            &tunables,
            &mut Formula,
            &options(3, &cut),
            |_, _, _, _| {},
        )
        .unwrap();
        assert_eq!(first.history.len(), 3);
        let resumed = optimize(
            &start,
            &tunables,
            &mut Formula,
            &options(8, &cut),
            |_, _, _, _| {},
        )
        .unwrap();
        assert_eq!(resumed.resumed_after, 3);
        assert_eq!(
            resumed.evaluations,
            5 * 6,
            "only the five generations left ran"
        );
        assert_eq!(resumed.history, uncut.history);
        assert_eq!(resumed.best_cost, uncut.best_cost);
        // Another search does not take the checkpoint up.
        let mut other = options(8, &cut);
        other.seed = 4;
        let refused = optimize(&start, &tunables, &mut Formula, &other, |_, _, _, _| {});
        assert!(matches!(refused, Err(TrialError::Checkpoint { .. })));
    }
}
