//! Jobs as child processes on this machine.

use super::{Bundle, Executor, Finished, Job, JobResult, REPORT};
use std::collections::{HashMap, VecDeque};
use std::os::unix::process::CommandExt;
use std::path::PathBuf;
use std::process::{Command, Stdio};
use std::sync::mpsc::{self, Receiver, RecvTimeoutError, Sender};
use std::time::{Duration, Instant};

/// Runs each job as `libero ARGV` from the bundle's folder, `parallel` at a time; each job
/// is its own process group, so a timeout or a cancel stops its server too.
pub struct LocalExecutor {
    root: PathBuf,
    venv: PathBuf,
    scratch: PathBuf,
    parallel: usize,
    queue: VecDeque<(usize, Job)>,
    running: HashMap<usize, Running>,
    done_tx: Sender<(usize, JobResult)>,
    done_rx: Receiver<(usize, JobResult)>,
}

struct Running {
    pid: i32,
    deadline: Instant,
    killed: Option<&'static str>,
}

impl LocalExecutor {
    pub fn new(bundle: &Bundle, parallel: usize) -> Self {
        let (done_tx, done_rx) = mpsc::channel();
        Self {
            root: bundle.root().to_path_buf(),
            // The bundle has no virtualenv of its own: jobs use this one.
            venv: libero_server::venv::venv_path(),
            scratch: bundle.scratch().to_path_buf(),
            parallel,
            queue: VecDeque::new(),
            running: HashMap::new(),
            done_tx,
            done_rx,
        }
    }

    fn start_queued(&mut self) {
        while self.running.len() < self.parallel {
            let Some((id, job)) = self.queue.pop_front() else {
                return;
            };
            match self.spawn(id, &job) {
                Ok(pid) => {
                    self.running.insert(
                        id,
                        Running {
                            pid,
                            deadline: Instant::now() + Duration::from_secs_f64(job.timeout_s),
                            killed: None,
                        },
                    );
                }
                Err(e) => {
                    let _ = self.done_tx.send((id, Err(e)));
                }
            }
        }
    }

    fn spawn(&self, id: usize, job: &Job) -> Result<i32, String> {
        let dir = self.scratch.join(format!("job-{id}"));
        std::fs::create_dir_all(&dir).map_err(|e| format!("{}: {e}", dir.display()))?;
        let report = dir.join("report.json");
        let output = dir.join("output.txt");
        let log =
            std::fs::File::create(&output).map_err(|e| format!("{}: {e}", output.display()))?;
        let log2 = log.try_clone().map_err(|e| e.to_string())?;
        let argv: Vec<String> = job
            .argv
            .iter()
            .map(|a| a.replace(REPORT, &report.display().to_string()))
            .collect();
        let mut command = Command::new(self.root.join("libero"));
        // A job (and through it its server) dies with this process. The executor is driven
        // from one thread, which lives as long as the series or the optimizer.
        libero_server::process::die_with_parent(&mut command);
        let child = command
            .args(&argv)
            .current_dir(&self.root)
            .env("LIBERO_HOME", &self.root)
            .env("LIBERO_VENV", &self.venv)
            .stdin(Stdio::null())
            .stdout(log)
            .stderr(log2)
            .process_group(0)
            .spawn()
            .map_err(|e| format!("cannot start libero {}: {e}", argv.join(" ")))?;
        let pid = child.id() as i32;
        // The child is reaped by wait4 below (for its rusage), never by `Child::wait`.
        drop(child);
        let done = self.done_tx.clone();
        std::thread::spawn(move || {
            let began = Instant::now();
            let (status, cpu_s) = wait_with_usage(pid);
            let wall_s = began.elapsed().as_secs_f64();
            let result = match status {
                Ok(0) => read_report(&report, &output).map(|report| Finished {
                    report,
                    node: "local".into(),
                    wall_s,
                    cpu_s,
                }),
                Ok(code) => Err(format!("exit status {code}\n{}", tail(&output))),
                Err(e) => Err(e),
            };
            let _ = std::fs::remove_dir_all(report.parent().unwrap_or(&report));
            let _ = done.send((id, result));
        });
        Ok(pid)
    }

    fn kill(running: &mut Running, why: &'static str) {
        if running.killed.is_none() {
            running.killed = Some(why);
            // SAFETY: kill(2) on the job's own process group.
            unsafe {
                libc::kill(-running.pid, libc::SIGKILL);
            }
        }
    }
}

impl Executor for LocalExecutor {
    fn describe(&self) -> String {
        format!("this machine, {} at a time", self.parallel)
    }

    fn parallelism(&self) -> usize {
        self.parallel
    }

    fn submit(&mut self, id: usize, job: &Job) -> Result<(), String> {
        self.queue.push_back((id, job.clone()));
        self.start_queued();
        Ok(())
    }

    fn next_done(&mut self) -> Option<(usize, JobResult)> {
        loop {
            if self.running.is_empty() && self.queue.is_empty() {
                // A spawn failure is already in the channel.
                return self.done_rx.try_recv().ok();
            }
            match self.done_rx.recv_timeout(Duration::from_millis(200)) {
                Ok((id, result)) => {
                    let killed = self.running.remove(&id).and_then(|r| r.killed);
                    self.start_queued();
                    let result = match killed {
                        Some(why) => Err(why.to_string()),
                        None => result,
                    };
                    return Some((id, result));
                }
                Err(RecvTimeoutError::Timeout) => {
                    let now = Instant::now();
                    for running in self.running.values_mut() {
                        if now > running.deadline {
                            Self::kill(running, "timed out");
                        }
                    }
                }
                Err(RecvTimeoutError::Disconnected) => return None,
            }
        }
    }

    fn cancel_all(&mut self) {
        for (id, _) in self.queue.drain(..) {
            let _ = self.done_tx.send((id, Err("cancelled".into())));
        }
        for running in self.running.values_mut() {
            Self::kill(running, "cancelled");
        }
    }
}

impl Drop for LocalExecutor {
    fn drop(&mut self) {
        for running in self.running.values_mut() {
            Self::kill(running, "cancelled");
        }
    }
}

/// Wait for `pid` and read its CPU time (its own and its waited-for children's: the server).
fn wait_with_usage(pid: i32) -> (Result<i32, String>, f64) {
    let mut status = 0;
    // SAFETY: a zeroed rusage is a valid out-parameter for wait4.
    let mut usage: libc::rusage = unsafe { std::mem::zeroed() };
    loop {
        // SAFETY: wait4 on our own child, with valid pointers.
        let got = unsafe { libc::wait4(pid, &mut status, 0, &mut usage) };
        if got == pid {
            break;
        }
        let e = std::io::Error::last_os_error();
        if e.kind() != std::io::ErrorKind::Interrupted {
            return (Err(format!("cannot wait for the job: {e}")), 0.0);
        }
    }
    let seconds = |t: libc::timeval| t.tv_sec as f64 + t.tv_usec as f64 * 1e-6;
    let cpu = seconds(usage.ru_utime) + seconds(usage.ru_stime);
    let code = if libc::WIFEXITED(status) {
        Ok(libc::WEXITSTATUS(status))
    } else {
        Err(format!("killed by signal {}", libc::WTERMSIG(status)))
    };
    (code, cpu)
}

fn read_report(
    report: &std::path::Path,
    output: &std::path::Path,
) -> Result<serde_json::Value, String> {
    let text = std::fs::read_to_string(report)
        .map_err(|e| format!("the job wrote no report ({e})\n{}", tail(output)))?;
    serde_json::from_str(&text).map_err(|e| format!("the job's report is not JSON: {e}"))
}

/// The last lines of a job's output, for an error message.
fn tail(output: &std::path::Path) -> String {
    let text = std::fs::read_to_string(output).unwrap_or_default();
    let lines: Vec<&str> = text.lines().rev().take(12).collect();
    lines.into_iter().rev().collect::<Vec<_>>().join("\n")
}
