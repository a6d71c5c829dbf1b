//! `libero series`: many matches (or scenario runs) as jobs, here or on a Ray cluster, and
//! what they say: wins, draws and losses, the mean goal difference with its interval, and a
//! sequential test that stops the series once the answer is clear.

mod stats;

use super::CliResult;
use crate::fleet::{run_all, Bundle, ExecutorArgs, Finished, Job, JobResult, Next, REPORT};
use clap::Args;
use serde::Serialize;
use stats::{mean_with_interval, rate_with_interval, sign_test_p, Estimate, Sprt, Verdict};
use std::io::{IsTerminal, Write};
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

#[derive(Args)]
pub struct SeriesArgs {
    /// The home team's folder (`behaviors/`, `formations/`, `t1.ron`, each optional)
    /// [default: this repository's files]
    #[arg(long, value_name = "DIR")]
    pub home: Option<PathBuf>,
    /// The away team's folder, like `--home` [default: the home team's files]
    #[arg(long, value_name = "DIR", conflicts_with = "away_cmd")]
    pub away: Option<PathBuf>,
    /// An external away team, run as `CMD <host> <port>` from the bundle's folder on the
    /// worker (ship its files with `--away-files`).
    #[arg(long, value_name = "CMD")]
    pub away_cmd: Option<String>,
    /// A folder shipped to every worker as `external/` (an external team's binary and start
    /// script: `--away-cmd external/start.sh`).
    #[arg(long, value_name = "DIR", requires = "away_cmd")]
    pub away_files: Option<PathBuf>,
    /// Halves to play (the home team alternates between the left and the right side).
    #[arg(long, default_value_t = 20)]
    pub matches: usize,
    /// Play time of each half [s] (a whole ssim half is 300).
    #[arg(long, default_value_t = 300.0)]
    pub half_s: f64,
    /// Players per team.
    #[arg(long, default_value_t = 7)]
    pub players: u32,
    /// Runs of this scenario file instead of matches (the home team's files play it).
    #[arg(long, value_name = "FILE", conflicts_with_all = ["away", "away_cmd"])]
    pub scenario: Option<PathBuf>,
    /// Scenario runs (with `--scenario`).
    #[arg(long, default_value_t = 20)]
    pub runs: usize,
    /// First seed of the scenario runs (run i draws with seed + i).
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Chance of calling a difference that is not there (the sequential test).
    #[arg(long, default_value_t = 0.05)]
    pub alpha: f64,
    /// Chance of missing a difference of `--effect`.
    #[arg(long, default_value_t = 0.1)]
    pub beta: f64,
    /// The difference worth finding: the better team's share of decisive matches.
    #[arg(long, default_value_t = 0.75)]
    pub effect: f64,
    /// Once a match ends past this many minutes of wall time, start no more and stop those
    /// still playing (the report holds what finished).
    #[arg(long, value_name = "MINUTES")]
    pub budget_min: Option<f64>,
    /// Play every match even once the sequential test has decided.
    #[arg(long)]
    pub no_early_stop: bool,
    /// Write the figures and every match as JSON.
    #[arg(long, value_name = "FILE")]
    pub report: Option<PathBuf>,
    #[command(flatten)]
    pub executor: ExecutorArgs,
}

/// One match as the series keeps it.
#[derive(Debug, Clone, Serialize)]
pub struct MatchResult {
    pub index: usize,
    pub home_side: &'static str,
    /// `[home, away]`.
    pub score: [u64; 2],
    pub node: String,
    pub wall_s: f64,
    pub cpu_s: f64,
}

#[derive(Debug, Serialize)]
struct MatchSeriesReport {
    executor: String,
    half_s: f64,
    players: u32,
    planned: usize,
    played: usize,
    failed: Vec<String>,
    wins: u32,
    draws: u32,
    losses: u32,
    goal_difference: Estimate,
    goals_home: Estimate,
    goals_away: Estimate,
    sprt: Sprt,
    verdict: Verdict,
    stopped_early: bool,
    /// The fixed-sample sign test over all decisive matches (meaningful when the series ran
    /// its planned length).
    sign_test_p: f64,
    wall_s: f64,
    cpu_s_per_match: Estimate,
    matches: Vec<MatchResult>,
}

#[derive(Debug, Clone, Serialize)]
struct RunResult {
    index: usize,
    seed: u64,
    success: bool,
    time_s: Option<f64>,
    node: String,
    wall_s: f64,
    cpu_s: f64,
}

#[derive(Debug, Serialize)]
struct ScenarioSeriesReport {
    executor: String,
    scenario: String,
    planned: usize,
    played: usize,
    failed: Vec<String>,
    successes: u32,
    success_rate: Estimate,
    wall_s: f64,
    cpu_s_per_run: Estimate,
    runs: Vec<RunResult>,
}

pub fn run(args: SeriesArgs) -> CliResult {
    let sprt = Sprt {
        alpha: args.alpha,
        beta: args.beta,
        effect: args.effect,
    };
    sprt.validate()?;
    let mut extra: Vec<(PathBuf, &str)> = Vec::new();
    if let Some(dir) = &args.home {
        extra.push((dir.clone(), "teams/home"));
    }
    if let Some(dir) = &args.away {
        extra.push((dir.clone(), "teams/away"));
    }
    if let Some(dir) = &args.away_files {
        extra.push((dir.clone(), "external"));
    }
    if let Some(file) = &args.scenario {
        extra.push((file.clone(), "series/scenario.ron"));
    }
    for (path, _) in &extra {
        if !path.exists() {
            return Err(format!("{} does not exist", path.display()).into());
        }
    }
    let extra_refs: Vec<(&std::path::Path, &str)> =
        extra.iter().map(|(p, n)| (p.as_path(), *n)).collect();
    let bundle = Bundle::stage(&extra_refs)?;
    let mut executor = args.executor.start(&bundle)?;
    println!("series on {}", executor.describe());
    if args.scenario.is_some() {
        scenario_series(&args, executor.as_mut())
    } else {
        match_series(&args, sprt, executor.as_mut())
    }
}

fn team_data_args(dir: &Option<PathBuf>, name: &str) -> Vec<String> {
    let Some(dir) = dir else { return Vec::new() };
    let mut argv = Vec::new();
    for (sub, flag) in [
        ("behaviors", "--behaviors"),
        ("formations", "--formations"),
        ("t1.ron", "--skill-params"),
    ] {
        if dir.join(sub).exists() {
            argv.push(flag.to_string());
            argv.push(format!("teams/{name}/{sub}"));
        }
    }
    argv
}

fn match_jobs(args: &SeriesArgs) -> Vec<Job> {
    (0..args.matches)
        .map(|i| {
            let mut argv: Vec<String> = [
                "match",
                "--players",
                &args.players.to_string(),
                "--duration",
                &args.half_s.to_string(),
                "--report",
                REPORT,
                "--home-name",
                "Home",
                "--away-name",
                "Away",
            ]
            .map(String::from)
            .to_vec();
            if args.home.is_some() {
                argv.extend(["--home".into(), "teams/home".into()]);
            }
            if args.away.is_some() {
                argv.extend(["--away".into(), "teams/away".into()]);
            }
            if let Some(cmd) = &args.away_cmd {
                argv.extend(["--away-cmd".into(), cmd.clone()]);
            }
            if i % 2 == 1 {
                argv.push("--home-right".into());
            }
            argv.push("--no-watch".into());
            Job {
                argv,
                // Fast mode runs a 7 v 7 half at about real time on two loaded cores.
                timeout_s: 180.0 + 6.0 * args.half_s,
            }
        })
        .collect()
}

fn match_series(
    args: &SeriesArgs,
    sprt: Sprt,
    executor: &mut dyn crate::fleet::Executor,
) -> CliResult {
    let jobs = match_jobs(args);
    let began = Instant::now();
    let mut matches: Vec<MatchResult> = Vec::new();
    let mut failed = Vec::new();
    let mut verdict = Verdict::Undecided;
    let mut progress = Bar::new(jobs.len());
    let _ = run_all(executor, &jobs, |index, result| {
        match read_match(index, result) {
            Ok(m) => matches.push(m),
            Err(e) => failed.push(format!("match {}: {e}", index + 1)),
        }
        let (w, _, l) = outcome_counts(&matches);
        verdict = sprt.verdict(w, l);
        progress.show(
            matches.len() + failed.len(),
            &format!(
                "W{w} L{l} D{} | {}",
                matches.len() as u32 - w - l,
                short(verdict)
            ),
        );
        let over_budget = args
            .budget_min
            .is_some_and(|m| began.elapsed().as_secs_f64() > m * 60.0);
        if (verdict.decided() && !args.no_early_stop) || over_budget {
            Next::Stop
        } else {
            Next::Continue
        }
    });
    progress.finish();
    matches.sort_by_key(|m| m.index);
    let (wins, draws, losses) = outcome_counts(&matches);
    let failed_count = failed.len();
    let diff: Vec<f64> = matches
        .iter()
        .map(|m| m.score[0] as f64 - m.score[1] as f64)
        .collect();
    let home: Vec<f64> = matches.iter().map(|m| m.score[0] as f64).collect();
    let away: Vec<f64> = matches.iter().map(|m| m.score[1] as f64).collect();
    let cpu: Vec<f64> = matches.iter().map(|m| m.cpu_s).collect();
    let report = MatchSeriesReport {
        executor: executor.describe(),
        half_s: args.half_s,
        players: args.players,
        planned: jobs.len(),
        played: matches.len(),
        failed,
        wins,
        draws,
        losses,
        goal_difference: mean_with_interval(&diff),
        goals_home: mean_with_interval(&home),
        goals_away: mean_with_interval(&away),
        sprt,
        verdict,
        stopped_early: matches.len() + failed_count < jobs.len(),
        sign_test_p: sign_test_p(wins, losses),
        wall_s: began.elapsed().as_secs_f64(),
        cpu_s_per_match: mean_with_interval(&cpu),
        matches,
    };
    println!(
        "{} of {} halves of {:.0} s ({} v {}) in {:.0} s wall time{}",
        report.played,
        report.planned,
        report.half_s,
        report.players,
        report.players,
        report.wall_s,
        if report.stopped_early {
            ", stopped early"
        } else {
            ""
        }
    );
    println!(
        "home: {} won, {} drawn, {} lost; goals {} : {}",
        wins,
        draws,
        losses,
        show(&report.goals_home),
        show(&report.goals_away)
    );
    println!("goal difference {}", show(&report.goal_difference));
    println!("sequential test: {}", verdict.describe(&sprt));
    println!(
        "sign test over all decisive halves: p = {:.4}",
        report.sign_test_p
    );
    println!("CPU per half {} s", show(&report.cpu_s_per_match));
    finish(&report.failed, &args.report, &report)
}

fn scenario_series(args: &SeriesArgs, executor: &mut dyn crate::fleet::Executor) -> CliResult {
    let file = args.scenario.as_ref().expect("scenario mode");
    let jobs: Vec<Job> = (0..args.runs)
        .map(|i| {
            let mut argv: Vec<String> = ["scenario", "series/scenario.ron", "--runs", "1"]
                .map(String::from)
                .to_vec();
            argv.extend([
                "--seed".into(),
                (args.seed + i as u64).to_string(),
                "--report".into(),
                REPORT.into(),
                "--no-watch".into(),
            ]);
            argv.extend(team_data_args(&args.home, "home"));
            Job {
                argv,
                timeout_s: 600.0,
            }
        })
        .collect();
    let began = Instant::now();
    let mut runs: Vec<RunResult> = Vec::new();
    let mut failed = Vec::new();
    let mut progress = Bar::new(jobs.len());
    let _ = run_all(executor, &jobs, |index, result| {
        match read_run(index, args.seed + index as u64, result) {
            Ok(r) => runs.push(r),
            Err(e) => failed.push(format!("run {}: {e}", index + 1)),
        }
        let ok = runs.iter().filter(|r| r.success).count();
        progress.show(runs.len() + failed.len(), &format!("{ok} succeeded"));
        Next::Continue
    });
    progress.finish();
    runs.sort_by_key(|r| r.index);
    let successes = runs.iter().filter(|r| r.success).count() as u32;
    let cpu: Vec<f64> = runs.iter().map(|r| r.cpu_s).collect();
    let report = ScenarioSeriesReport {
        executor: executor.describe(),
        scenario: file.display().to_string(),
        planned: jobs.len(),
        played: runs.len(),
        failed,
        successes,
        success_rate: rate_with_interval(successes, runs.len() as u32),
        wall_s: began.elapsed().as_secs_f64(),
        cpu_s_per_run: mean_with_interval(&cpu),
        runs,
    };
    let rate = &report.success_rate;
    println!(
        "{}: {} of {} runs succeeded: {:.0} % (95 % interval {:.0}–{:.0} %), {:.0} s wall time",
        report.scenario,
        successes,
        report.played,
        rate.mean * 100.0,
        rate.low.unwrap_or(f64::NAN) * 100.0,
        rate.high.unwrap_or(f64::NAN) * 100.0,
        report.wall_s
    );
    finish(&report.failed, &args.report, &report)
}

fn read_match(index: usize, result: &JobResult) -> Result<MatchResult, String> {
    let done: &Finished = result.as_ref().map_err(Clone::clone)?;
    let score = done
        .report
        .get("score")
        .and_then(|s| s.as_array())
        .filter(|s| s.len() == 2)
        .and_then(|s| Some([s[0].as_u64()?, s[1].as_u64()?]))
        .ok_or("the match report has no score")?;
    Ok(MatchResult {
        index,
        home_side: if index.is_multiple_of(2) {
            "left"
        } else {
            "right"
        },
        score,
        node: done.node.clone(),
        wall_s: done.wall_s,
        cpu_s: done.cpu_s,
    })
}

fn read_run(index: usize, seed: u64, result: &JobResult) -> Result<RunResult, String> {
    let done: &Finished = result.as_ref().map_err(Clone::clone)?;
    let run = done
        .report
        .get("per_run")
        .and_then(|r| r.get(0))
        .ok_or("the scenario report has no run")?;
    Ok(RunResult {
        index,
        seed,
        success: run
            .get("success")
            .and_then(|s| s.as_bool())
            .unwrap_or(false),
        time_s: run.get("time_s").and_then(|t| t.as_f64()),
        node: done.node.clone(),
        wall_s: done.wall_s,
        cpu_s: done.cpu_s,
    })
}

fn outcome_counts(matches: &[MatchResult]) -> (u32, u32, u32) {
    let wins = matches.iter().filter(|m| m.score[0] > m.score[1]).count() as u32;
    let losses = matches.iter().filter(|m| m.score[0] < m.score[1]).count() as u32;
    (wins, matches.len() as u32 - wins - losses, losses)
}

fn short(v: Verdict) -> &'static str {
    match v {
        Verdict::HomeBetter => "home better",
        Verdict::AwayBetter => "away better",
        Verdict::NoDifference => "no difference",
        Verdict::Undecided => "undecided",
    }
}

fn show(e: &Estimate) -> String {
    match (e.low, e.high) {
        (Some(lo), Some(hi)) => format!("{:.2} (95 % interval {lo:.2} to {hi:.2})", e.mean),
        _ => format!("{:.2}", e.mean),
    }
}

fn first_line(s: &str) -> &str {
    s.lines().next().unwrap_or(s)
}

/// The failures listed, the report written; failure if any job failed.
fn finish(failed: &[String], path: &Option<PathBuf>, report: &impl Serialize) -> CliResult {
    for f in failed {
        println!("failed: {}", first_line(f));
    }
    write_report(path, report)?;
    Ok(if failed.is_empty() {
        ExitCode::SUCCESS
    } else {
        ExitCode::FAILURE
    })
}

fn write_report(path: &Option<PathBuf>, report: &impl Serialize) -> Result<(), String> {
    let Some(path) = path else { return Ok(()) };
    let json = serde_json::to_string_pretty(report).map_err(|e| e.to_string())?;
    std::fs::write(path, json + "\n")
        .map_err(|e| format!("cannot write the report {}: {e}", path.display()))?;
    println!("report written to {}", path.display());
    Ok(())
}

/// Jobs done out of planned: a bar redrawn in place on a terminal, a line per job otherwise.
pub struct Bar {
    total: usize,
    terminal: bool,
    began: Instant,
}

impl Bar {
    pub fn new(total: usize) -> Self {
        Self {
            total,
            terminal: std::io::stdout().is_terminal(),
            began: Instant::now(),
        }
    }

    pub fn show(&mut self, done: usize, note: &str) {
        let filled = (done * 30).checked_div(self.total).unwrap_or(30).min(30);
        let line = format!(
            "[{}{}] {done}/{} {:5.0} s  {note}",
            "#".repeat(filled),
            ".".repeat(30 - filled),
            self.total,
            self.began.elapsed().as_secs_f64()
        );
        let mut out = std::io::stdout().lock();
        if self.terminal {
            let _ = write!(out, "\r{line:<90}");
            let _ = out.flush();
        } else {
            let _ = writeln!(out, "{line}");
        }
    }

    pub fn finish(&self) {
        if self.terminal {
            println!();
        }
    }
}
