//! Jobs as Ray tasks, through the driver module `tools/ray/libero_ray.py` (built in).

use super::{Bundle, Executor, Finished, Job, JobResult};
use serde::Deserialize;
use std::collections::HashSet;
use std::io::{BufRead, BufReader, Write};
use std::process::{Child, ChildStdin, Command, Stdio};
use std::sync::mpsc::{self, Receiver};
use std::time::Duration;

const DRIVER: &str = include_str!("../../ray/libero_ray.py");

/// How long the driver may take to join the cluster and check every node (it ships the
/// bundle to each).
const READY_TIMEOUT: Duration = Duration::from_secs(600);

#[derive(Debug, Deserialize)]
#[serde(tag = "event", rename_all = "snake_case")]
enum Event {
    Ready {
        nodes: Vec<NodeFacts>,
        ray: String,
    },
    Refused {
        error: String,
    },
    Done {
        id: usize,
        ok: bool,
        #[serde(default)]
        report: serde_json::Value,
        #[serde(default)]
        error: Option<String>,
        #[serde(default)]
        node: Option<String>,
        #[serde(default)]
        wall_s: f64,
        #[serde(default)]
        cpu_s: f64,
    },
}

/// A cluster node as the driver found it.
#[derive(Debug, Clone, Deserialize)]
pub struct NodeFacts {
    pub node: String,
    pub host: String,
    pub platform: String,
    pub cpus: f64,
}

/// The Ray side: a Python driver process joined to the cluster, fed jobs as JSON lines.
pub struct RayExecutor {
    address: String,
    driver: Child,
    stdin: Option<ChildStdin>,
    events: Receiver<Event>,
    in_flight: HashSet<usize>,
    nodes: Vec<NodeFacts>,
    ray_version: String,
    log_path: std::path::PathBuf,
}

impl RayExecutor {
    /// Join the cluster at `address`; every node is checked (Ray and rcsssmj versions, the
    /// bundled binary runs there) before any job is taken.
    pub fn start(address: &str, bundle: &Bundle, max_retries: u32) -> Result<Self, String> {
        let install = libero_server::ensure_ray_installed().map_err(|e| e.to_string())?;
        let script = bundle.scratch().join("libero_ray.py");
        std::fs::write(&script, DRIVER).map_err(|e| format!("{}: {e}", script.display()))?;
        let log_path = bundle.scratch().join("ray-driver.log");
        let log = std::fs::File::create(&log_path).map_err(|e| e.to_string())?;
        let mut command = Command::new(install.python());
        // The driver dies with this process (killed or not), and Ray then stops its tasks:
        // nothing is left running on the cluster for a driver nobody reads.
        libero_server::process::die_with_parent(&mut command);
        let mut driver = command
            .arg(&script)
            .args(["--address", address, "--bundle"])
            .arg(bundle.root())
            .args([
                "--libero-version",
                &version_line(),
                "--rcsssmj",
                libero_server::RCSSSMJ_VERSION,
                "--max-retries",
                &max_retries.to_string(),
            ])
            .env("RAY_DISABLE_USAGE_STATS", "1")
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(log)
            .spawn()
            .map_err(|e| format!("cannot start the Ray driver: {e}"))?;
        let stdout = driver.stdout.take().expect("piped stdout");
        let stdin = driver.stdin.take();
        let (tx, events) = mpsc::channel();
        std::thread::spawn(move || {
            for line in BufReader::new(stdout).lines() {
                let Ok(line) = line else { break };
                match serde_json::from_str::<Event>(&line) {
                    Ok(event) => {
                        if tx.send(event).is_err() {
                            break;
                        }
                    }
                    Err(e) => log::warn!("ray driver: unreadable line ({e}): {line}"),
                }
            }
        });
        let mut executor = Self {
            address: address.to_string(),
            driver,
            stdin,
            events,
            in_flight: HashSet::new(),
            nodes: Vec::new(),
            ray_version: String::new(),
            log_path,
        };
        match executor.events.recv_timeout(READY_TIMEOUT) {
            Ok(Event::Ready { nodes, ray }) => {
                executor.nodes = nodes;
                executor.ray_version = ray;
                Ok(executor)
            }
            Ok(Event::Refused { error }) => Err(format!("the Ray cluster is refused: {error}")),
            Ok(Event::Done { .. }) => Err("the Ray driver answered out of turn".into()),
            Err(_) => Err(format!(
                "the Ray driver did not get ready: {}",
                executor.log_tail()
            )),
        }
    }

    fn log_tail(&self) -> String {
        let text = std::fs::read_to_string(&self.log_path).unwrap_or_default();
        let lines: Vec<&str> = text.lines().rev().take(10).collect();
        lines.into_iter().rev().collect::<Vec<_>>().join("\n")
    }

    fn send(&mut self, line: serde_json::Value) -> Result<(), String> {
        let stdin = self
            .stdin
            .as_mut()
            .ok_or_else(|| "the Ray driver is closed".to_string())?;
        writeln!(stdin, "{line}")
            .and_then(|()| stdin.flush())
            .map_err(|e| format!("the Ray driver stopped: {e}\n{}", self.log_tail()))
    }
}

/// What `libero --version` prints, which the driver compares on every node.
fn version_line() -> String {
    format!("libero {}", env!("CARGO_PKG_VERSION"))
}

impl Executor for RayExecutor {
    fn describe(&self) -> String {
        let nodes: Vec<String> = self
            .nodes
            .iter()
            .map(|n| {
                format!(
                    "{} {} ({}, {} CPU)",
                    n.host,
                    &n.node[..n.node.len().min(8)],
                    n.platform,
                    n.cpus
                )
            })
            .collect();
        format!(
            "Ray {} at {}, {} node(s): {}",
            self.ray_version,
            self.address,
            self.nodes.len(),
            nodes.join(", ")
        )
    }

    fn parallelism(&self) -> usize {
        (self.nodes.iter().map(|n| n.cpus).sum::<f64>().floor() as usize).max(1)
    }

    fn submit(&mut self, id: usize, job: &Job) -> Result<(), String> {
        self.send(serde_json::json!({
            "op": "job", "id": id, "argv": job.argv, "timeout_s": job.timeout_s,
        }))?;
        self.in_flight.insert(id);
        Ok(())
    }

    fn next_done(&mut self) -> Option<(usize, JobResult)> {
        if self.in_flight.is_empty() {
            return None;
        }
        loop {
            let Ok(event) = self.events.recv() else {
                // The driver is gone: every job in flight is lost.
                let id = *self.in_flight.iter().next()?;
                self.in_flight.remove(&id);
                return Some((
                    id,
                    Err(format!("the Ray driver stopped\n{}", self.log_tail())),
                ));
            };
            if let Event::Done {
                id,
                ok,
                report,
                error,
                node,
                wall_s,
                cpu_s,
            } = event
            {
                if !self.in_flight.remove(&id) {
                    continue;
                }
                let node = node.unwrap_or_else(|| "?".into());
                let result = if ok {
                    Ok(Finished {
                        report,
                        node,
                        wall_s,
                        cpu_s,
                    })
                } else {
                    Err(format!(
                        "on node {}: {}",
                        &node[..node.len().min(8)],
                        error.unwrap_or_default()
                    ))
                };
                return Some((id, result));
            }
        }
    }

    fn cancel_all(&mut self) {
        let _ = self.send(serde_json::json!({"op": "cancel"}));
    }
}

impl Drop for RayExecutor {
    fn drop(&mut self) {
        if !self.in_flight.is_empty() {
            self.cancel_all();
        }
        // End of input: the driver finishes what is in flight (cancelled) and leaves.
        self.stdin = None;
        for _ in 0..100 {
            if matches!(self.driver.try_wait(), Ok(Some(_))) {
                return;
            }
            std::thread::sleep(Duration::from_millis(100));
        }
        let _ = self.driver.kill();
        let _ = self.driver.wait();
    }
}
