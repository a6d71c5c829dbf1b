//! Evaluation logs read for the view: an index of each log's lines by time (the lines stay on
//! disk and are read when a frame is asked for, so a long log costs a few bytes a line).

use libero_agent::{AgentView, TreeShape};
use serde::Deserialize;
use std::collections::HashMap;
use std::fs::File;
use std::io::{BufRead, BufReader, Read, Seek, SeekFrom};
use std::path::{Path, PathBuf};

/// One agent's log.
struct LogIndex {
    path: PathBuf,
    /// (time, byte offset, length) of each line that reads as a record.
    lines: Vec<(f64, u64, u32)>,
}

/// The logs of one match (any number of agents), on one timeline.
pub struct Replay {
    logs: Vec<LogIndex>,
    /// Every time any log has a line for, ascending: the timeline's steps.
    times: Vec<f64>,
    shapes: HashMap<(String, u32, u64), TreeShape>,
}

#[derive(Deserialize)]
struct Head {
    time: f64,
    #[serde(default)]
    team: String,
    #[serde(default)]
    unum: u32,
    #[serde(default)]
    tree_shape: Option<TreeShape>,
}

/// The longest line read (a record with a decision is a few kB).
const MAX_LINE_BYTES: usize = 1 << 20;

impl Replay {
    /// Index the logs; a line that is not a record is skipped (and counted in the error when
    /// a log has none at all).
    pub fn open(paths: &[PathBuf]) -> Result<Replay, String> {
        let mut logs = Vec::new();
        let mut times = Vec::new();
        let mut shapes = HashMap::new();
        for path in paths {
            let file =
                File::open(path).map_err(|e| format!("cannot open {}: {e}", path.display()))?;
            let mut reader = BufReader::new(file);
            let mut lines = Vec::new();
            let mut offset = 0u64;
            let mut line = String::new();
            let mut skipped = 0usize;
            loop {
                line.clear();
                let n = reader
                    .by_ref()
                    .take(MAX_LINE_BYTES as u64)
                    .read_line(&mut line)
                    .map_err(|e| format!("{}: {e}", path.display()))?;
                if n == 0 {
                    break;
                }
                match serde_json::from_str::<Head>(&line) {
                    Ok(head) => {
                        lines.push((head.time, offset, n as u32));
                        times.push(head.time);
                        if let Some(shape) = head.tree_shape {
                            shapes.insert((head.team, head.unum, shape.generation), shape);
                        }
                    }
                    Err(_) => skipped += 1,
                }
                offset += n as u64;
            }
            if lines.is_empty() {
                return Err(format!(
                    "{}: no evaluation-log records ({skipped} lines that are not)",
                    path.display()
                ));
            }
            lines.sort_by(|a, b| a.0.total_cmp(&b.0));
            logs.push(LogIndex {
                path: path.clone(),
                lines,
            });
        }
        times.sort_by(f64::total_cmp);
        times.dedup_by(|a, b| (*a - *b).abs() < 1e-6);
        Ok(Replay {
            logs,
            times,
            shapes,
        })
    }

    /// Steps on the timeline.
    pub fn len(&self) -> usize {
        self.times.len()
    }

    pub fn is_empty(&self) -> bool {
        self.times.is_empty()
    }

    pub fn time(&self, step: usize) -> Option<f64> {
        self.times.get(step).copied()
    }

    /// Each agent's record at `step`: its latest line at or before that time.
    pub fn agents_at(&self, step: usize) -> Vec<AgentView> {
        let Some(t) = self.time(step) else {
            return Vec::new();
        };
        self.logs
            .iter()
            .filter_map(|log| {
                let k = log.lines.partition_point(|(time, ..)| *time <= t + 1e-6);
                let (_, offset, len) = *log.lines.get(k.checked_sub(1)?)?;
                read_line(&log.path, offset, len)
            })
            .collect()
    }

    /// The tree shape a log carried for an agent and generation.
    pub fn shape(&self, team: &str, unum: u32, generation: u64) -> Option<&TreeShape> {
        self.shapes.get(&(team.to_string(), unum, generation))
    }
}

fn read_line(path: &Path, offset: u64, len: u32) -> Option<AgentView> {
    let mut file = File::open(path).ok()?;
    file.seek(SeekFrom::Start(offset)).ok()?;
    let mut buffer = vec![0; len as usize];
    file.read_exact(&mut buffer).ok()?;
    serde_json::from_slice(&buffer).ok()
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::Write;

    fn line(time: f64, unum: u32, x: f64) -> String {
        format!(
            r#"{{"time":{time},"cycle":1,"team":"T","unum":{unum},"side":"Left","play_mode":"PlayOn","me":{{"position":[{x},0.5],"yaw_deg":10.0}},"ball":null,"players":[],"truth":null}}"#
        )
    }

    #[test]
    fn the_timeline_merges_logs_and_each_step_shows_each_agents_latest_line() {
        let dir = tempfile::tempdir().unwrap();
        let a = dir.path().join("a.jsonl");
        let b = dir.path().join("b.jsonl");
        let mut fa = File::create(&a).unwrap();
        for (t, x) in [(0.0, 1.0), (0.02, 2.0), (0.04, 3.0)] {
            writeln!(fa, "{}", line(t, 1, x)).unwrap();
        }
        writeln!(fa, "not a record").unwrap();
        let mut fb = File::create(&b).unwrap();
        for (t, x) in [(0.02, -1.0), (0.06, -2.0)] {
            writeln!(fb, "{}", line(t, 2, x)).unwrap();
        }
        let replay = Replay::open(&[a, b]).unwrap();
        assert_eq!(replay.len(), 4);
        let xs = |step| -> Vec<(u32, f64)> {
            replay
                .agents_at(step)
                .iter()
                .map(|v| (v.unum, v.me.position[0]))
                .collect()
        };
        assert_eq!(xs(0), vec![(1, 1.0)], "agent 2 has no line yet");
        assert_eq!(xs(1), vec![(1, 2.0), (2, -1.0)]);
        assert_eq!(xs(3), vec![(1, 3.0), (2, -2.0)]);
        assert!(replay.agents_at(9).is_empty());
    }
}
