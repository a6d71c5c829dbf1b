//! Scenario files: a named situation, written as data, run on the real server.
//!
//! A `scenarios/*.ron` file places robots of both teams (ours run their behavior trees; theirs
//! run trees too or only stand) and the ball, optionally launches the ball (a speed and
//! direction, or a speed towards a target so shots on goal are data), varies all of it per run
//! from a seed (`Range(lo, hi)` wherever a number goes), and says when a run succeeds
//! (`GoalScored`, `BallKeptOut`, `BallReached`, `BallMoved`, `NoCollision`, `All`, `Any`),
//! judged from the server's ground truth. [`load_file`] validates a file with located
//! diagnostics (the same [`Report`] as the tree and strategy files); [`run_series`] runs it
//! (`libero scenario FILE --runs N --seed S`).
//!
//! ```ron
//! // Shots on goal against our keeper alone.
//! Scenario(
//!     name: "keeper_shots",
//!     field: "fifa7vs7",
//!     ours: [Robot(unum: 1, at: (x: -26.0, y: 0.0), heading_deg: 0.0)],
//!     theirs: [],
//!     ball: Ball(
//!         at: (x: Range(-21.5, -15.5), y: Range(-5.0, 5.0)),
//!         launch: Some(Towards(target: (x: -28.0, y: Range(-1.4, 1.4)), speed_m_s: Range(6.0, 7.0))),
//!     ),
//!     time_limit_s: 8.0,
//!     success: BallKeptOut,
//! )
//! ```

mod conditions;
pub mod decode;
pub mod eval_logs;
pub mod judge;
pub mod load;
mod pass_judge;
pub mod run;
pub mod shot_judge;
pub mod spec;
pub mod summary;

#[cfg(test)]
mod load_tests;

pub use eval_logs::Logs;
pub use libero_behavior::Report;
pub use load::{is_scenario_text, load_file, load_text, validate_files};
pub use run::{Arena, RunData, RunError, Watcher, OUR_TEAM, THEIR_TEAM};
pub use spec::{Scenario, Success};
pub use summary::{RunOutcome, Summary};

use std::path::{Path, PathBuf};

/// The repository's `scenarios/` folder: under `LIBERO_HOME` if set, else under this checkout.
pub fn default_scenarios_dir() -> PathBuf {
    std::env::var_os("LIBERO_HOME")
        .map(PathBuf::from)
        .unwrap_or_else(|| Path::new(env!("CARGO_MANIFEST_DIR")).join("../.."))
        .join("scenarios")
}

/// Whether the file at `path` is a scenario file (its top value is `Scenario(...)`).
pub fn is_scenario_file(path: &Path) -> bool {
    // Bounded: a huge or binary file is no scenario, and the library then reports it.
    libero_behavior::files::read_text(path).is_ok_and(|t| is_scenario_text(&t))
}

/// Run `runs` situations drawn from `scenario` with `seed` on one server; `each` sees every
/// outcome as it comes. A run the server fails in is retried once on a fresh server; a second
/// failure ends the series early with what was run so far and the error.
pub fn run_series(
    scenario: &Scenario,
    file: &Path,
    data: &RunData,
    runs: usize,
    seed: u64,
    mut each: impl FnMut(&RunOutcome),
) -> (Summary, Option<RunError>) {
    let started = std::time::Instant::now();
    let mut summary = Summary {
        scenario: scenario.name.clone(),
        file: file.display().to_string(),
        condition: scenario.success.describe(),
        seed,
        runs: Vec::new(),
        wall_s: 0.0,
    };
    let mut arena = match Arena::start(scenario, data, Logs::Fresh) {
        Ok(a) => a,
        Err(e) => return (summary, Some(e)),
    };
    let mut error = None;
    'runs: for index in 0..runs {
        let setup = scenario.draw(seed, index, arena.ball_params());
        // A run the server fails in (rcsssmj 0.2.1 can die or stall) is run again once on a
        // fresh server with freshly connected robots.
        for attempt in 1..=2 {
            match arena.run(scenario, &setup) {
                Ok(outcome) => {
                    each(&outcome);
                    summary.runs.push(outcome);
                    continue 'runs;
                }
                Err(RunError::Interrupted) => {
                    error = Some(RunError::Interrupted);
                    break 'runs;
                }
                Err(e) if attempt == 1 => {
                    log::warn!(
                        "scenario: run {} failed ({e}); restarting the server",
                        index + 1
                    );
                    arena.stop();
                    arena = match Arena::start(scenario, data, Logs::Continue) {
                        Ok(a) => a,
                        Err(e) => {
                            summary.wall_s = started.elapsed().as_secs_f64();
                            return (summary, Some(e));
                        }
                    };
                }
                Err(e) => {
                    error = Some(e);
                    break 'runs;
                }
            }
        }
    }
    arena.stop();
    summary.wall_s = started.elapsed().as_secs_f64();
    (summary, error)
}
