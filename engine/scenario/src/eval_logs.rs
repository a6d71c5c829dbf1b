//! The robots' evaluation logs of a series (`libero scenario --log PREFIX`): one file per
//! robot, `PREFIX.TEAM.UNUM`.

use crate::run::RunError;
use libero_world::eval_log::{robot_log_path, EvalLogger};
use std::path::Path;

/// Whether an arena's robots start their evaluation logs afresh or write on at their end (a
/// server restarted within a series: the runs before it stay in the logs).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Logs {
    Fresh,
    Continue,
}

impl Logs {
    /// The log of robot `unum` of `team` under `prefix`.
    pub fn open(self, prefix: &Path, team: &str, unum: u32) -> Result<EvalLogger, RunError> {
        let path = robot_log_path(prefix, team, unum);
        let logger = match self {
            Logs::Fresh => EvalLogger::create(&path),
            Logs::Continue => EvalLogger::append(&path),
        };
        logger.map_err(|e| {
            RunError::Setup(format!(
                "cannot create the evaluation log {}: {e}",
                path.display()
            ))
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::Write;

    #[test]
    fn a_restarted_arena_writes_on_at_the_end_of_each_robots_log() {
        let dir = std::env::temp_dir().join(format!("libero-logs-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let prefix = dir.join("log");
        let write = |logs: Logs, line: &str| {
            let mut out = logs.open(&prefix, "Libero", 7).unwrap().into_inner();
            writeln!(out, "{line}").unwrap();
            out.flush().unwrap();
        };
        write(Logs::Fresh, "first server");
        write(Logs::Continue, "second server");
        let path = robot_log_path(&prefix, "Libero", 7);
        assert_eq!(
            std::fs::read_to_string(&path).unwrap(),
            "first server\nsecond server\n"
        );
        write(Logs::Fresh, "a new series");
        assert_eq!(std::fs::read_to_string(&path).unwrap(), "a new series\n");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
