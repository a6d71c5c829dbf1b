//! Evaluations as jobs, run here or on a Ray cluster.
//!
//! A [`Job`] is one `libero` command line that starts its own fast-mode server, plays one
//! episode, scenario run or match, and writes its figures as JSON to the path that stands for
//! [`REPORT`] in its arguments. An [`Executor`] runs jobs: [`LocalExecutor`] as child processes
//! on this machine, [`RayExecutor`] as Ray tasks through the driver in `tools/ray/`. Both run
//! the same binary on the same files (a [`Bundle`]), so a figure means the same either way.

mod bundle;
mod local;
mod ray;

pub use bundle::Bundle;
pub use local::LocalExecutor;
pub use ray::RayExecutor;

/// Stands for the report file in a job's arguments.
pub const REPORT: &str = "{report}";

/// One evaluation: `libero ARGV`, run from the bundle's folder.
#[derive(Debug, Clone)]
pub struct Job {
    pub argv: Vec<String>,
    /// Killed (and failed) after this much wall time.
    pub timeout_s: f64,
}

/// A job that ran to the end.
#[derive(Debug, Clone)]
pub struct Finished {
    /// What the command wrote to its report file.
    pub report: serde_json::Value,
    /// Where it ran (`local` or a Ray node id).
    pub node: String,
    pub wall_s: f64,
    /// CPU time of the command and its server (user + system).
    pub cpu_s: f64,
}

/// A finished job, or why it did not finish (already phrased for the user).
pub type JobResult = Result<Finished, String>;

/// Runs jobs and hands back their results as they finish, in any order.
pub trait Executor {
    /// One line for the user: where the jobs run and how many at once.
    fn describe(&self) -> String;
    /// Jobs worth having in flight at once (more only queue).
    fn parallelism(&self) -> usize;
    fn submit(&mut self, id: usize, job: &Job) -> Result<(), String>;
    /// The next finished job, waiting for it; `None` when nothing is in flight.
    fn next_done(&mut self) -> Option<(usize, JobResult)>;
    /// Stop every job in flight; their results come back as errors.
    fn cancel_all(&mut self);
}

/// Where jobs run: `--ray ADDRESS` or this machine.
#[derive(clap::Args, Clone, Debug)]
pub struct ExecutorArgs {
    /// Run the evaluations as tasks on this Ray cluster (HOST:PORT of `ray start --head`)
    /// instead of on this machine.
    #[arg(long, value_name = "ADDRESS")]
    pub ray: Option<String>,
    /// Evaluations at once on this machine (one per core is the most that helps; with
    /// `--ray` the cluster's CPUs decide).
    #[arg(long, default_value_t = 2)]
    pub parallel: usize,
    /// With `--ray`: times a task is run again elsewhere when its worker or node dies.
    #[arg(long, default_value_t = 3)]
    pub max_retries: u32,
}

impl ExecutorArgs {
    pub fn start(&self, bundle: &Bundle) -> Result<Box<dyn Executor>, String> {
        Ok(match &self.ray {
            Some(address) => Box::new(RayExecutor::start(address, bundle, self.max_retries)?),
            None => Box::new(LocalExecutor::new(bundle, self.parallel.max(1))),
        })
    }
}

/// What [`run_all`]'s callback says after each result.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Next {
    Continue,
    /// Submit nothing more and cancel what is in flight.
    Stop,
}

/// Run `jobs` with at most [`Executor::parallelism`] in flight; `on_done` hears each result
/// as it comes. Results by job index; `None` for a job never run or cancelled after a stop.
pub fn run_all(
    executor: &mut dyn Executor,
    jobs: &[Job],
    mut on_done: impl FnMut(usize, &JobResult) -> Next,
) -> Vec<Option<JobResult>> {
    let mut results: Vec<Option<JobResult>> = vec![None; jobs.len()];
    let mut next = 0;
    let mut in_flight = 0;
    let mut stopped = false;
    let width = executor.parallelism().max(1);
    loop {
        while !stopped && next < jobs.len() && in_flight < width {
            match executor.submit(next, &jobs[next]) {
                Ok(()) => in_flight += 1,
                Err(e) => {
                    let result = Err(e);
                    if on_done(next, &result) == Next::Stop {
                        stopped = true;
                    }
                    results[next] = Some(result);
                }
            }
            next += 1;
        }
        let Some((id, result)) = executor.next_done() else {
            break;
        };
        in_flight = in_flight.saturating_sub(1);
        if stopped {
            continue;
        }
        if on_done(id, &result) == Next::Stop {
            stopped = true;
            executor.cancel_all();
        }
        if let Some(slot) = results.get_mut(id) {
            *slot = Some(result);
        }
    }
    results
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::VecDeque;

    /// Finishes jobs in the order submitted; records how many were in flight at most.
    #[derive(Default)]
    struct Recorder {
        queue: VecDeque<usize>,
        most_in_flight: usize,
        cancelled: usize,
    }

    impl Executor for Recorder {
        fn describe(&self) -> String {
            "recorder".into()
        }
        fn parallelism(&self) -> usize {
            2
        }
        fn submit(&mut self, id: usize, _: &Job) -> Result<(), String> {
            self.queue.push_back(id);
            self.most_in_flight = self.most_in_flight.max(self.queue.len());
            Ok(())
        }
        fn next_done(&mut self) -> Option<(usize, JobResult)> {
            let id = self.queue.pop_front()?;
            Some((
                id,
                Ok(Finished {
                    report: serde_json::json!(id),
                    node: "here".into(),
                    wall_s: 0.0,
                    cpu_s: 0.0,
                }),
            ))
        }
        fn cancel_all(&mut self) {
            self.cancelled += self.queue.len();
            self.queue.clear();
        }
    }

    fn jobs(n: usize) -> Vec<Job> {
        (0..n)
            .map(|i| Job {
                argv: vec![i.to_string()],
                timeout_s: 1.0,
            })
            .collect()
    }

    #[test]
    fn keeps_at_most_the_parallelism_in_flight_and_runs_every_job() {
        let mut executor = Recorder::default();
        let results = run_all(&mut executor, &jobs(7), |_, _| Next::Continue);
        assert_eq!(executor.most_in_flight, 2);
        let ids: Vec<u64> = results
            .iter()
            .map(|r| {
                r.as_ref()
                    .unwrap()
                    .as_ref()
                    .unwrap()
                    .report
                    .as_u64()
                    .unwrap()
            })
            .collect();
        assert_eq!(ids, vec![0, 1, 2, 3, 4, 5, 6]);
    }

    #[test]
    fn a_stop_submits_nothing_more_and_cancels_what_is_in_flight() {
        let mut executor = Recorder::default();
        let mut heard = 0;
        let results = run_all(&mut executor, &jobs(7), |_, _| {
            heard += 1;
            if heard == 3 {
                Next::Stop
            } else {
                Next::Continue
            }
        });
        assert_eq!(heard, 3);
        assert_eq!(executor.cancelled, 1, "the fourth job was in flight");
        assert_eq!(results.iter().filter(|r| r.is_some()).count(), 3);
    }
}
