//! `libero optimize <skill>`: CMA-ES over a skill's parameters against real servers, writing
//! the best values back into the parameter file; `libero evaluate`: one candidate's cost, the
//! job each evaluation is when the optimizer runs on a Ray cluster.

use super::series::Bar;
use super::CliResult;
use crate::fleet::{run_all, Bundle, Executor, ExecutorArgs, Job, Next, REPORT};
use clap::{Args, ValueEnum};
use libero_model::RobotModel;
use libero_skills::SkillParams;
use libero_trial::kick_bench::KickDirections;
use libero_trial::optimize::kick::{select_kick_tunables, KickObjective, DEFAULT_KICK_TUNABLES};
use libero_trial::optimize::{
    optimize, select_walk_tunables, write_back, write_back_for_type, Evaluator, LocalServers,
    Objective, Options, Tunable, WalkObjective, DEFAULT_WALK_TUNABLES,
};
use libero_trial::{Course, TrialError};
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::Arc;

#[derive(Clone, Copy, ValueEnum)]
pub enum Skill {
    /// The omnidirectional walk (gait geometry, timing and balance gains).
    Walk,
    /// The long kick (contact geometry, swing), kicked from around the kicking place.
    Kick,
}

impl Skill {
    fn as_arg(self) -> &'static str {
        match self {
            Skill::Walk => "walk",
            Skill::Kick => "kick",
        }
    }
}

/// The field directions of the kicks every candidate makes.
#[derive(Clone, Copy, ValueEnum)]
pub enum KickDirectionsArg {
    /// Any direction.
    AllRound,
    /// Within 25° of the +x axis, as shots at their goal go (the ball's roll curves by its
    /// direction to the field's axes).
    Shots,
}

impl KickDirectionsArg {
    fn as_arg(self) -> &'static str {
        match self {
            Self::AllRound => "all-round",
            Self::Shots => "shots",
        }
    }

    fn directions(self) -> KickDirections {
        match self {
            Self::AllRound => KickDirections::AllRound,
            Self::Shots => KickDirections::Shots,
        }
    }
}

#[derive(Clone, Copy, ValueEnum)]
pub enum CourseKind {
    /// The parameter file's speed limits straight ahead, sideways and turning, then random
    /// commands within them (25 s per seed).
    Bars,
    /// Forward, curves, sideways, turning on the spot, backwards (23 s).
    Standard,
    /// Straight ahead, rising to full speed (15 s).
    Forward,
}

impl CourseKind {
    fn as_arg(self) -> &'static str {
        match self {
            CourseKind::Bars => "bars",
            CourseKind::Standard => "standard",
            CourseKind::Forward => "forward",
        }
    }
}

/// What one evaluation measures: the skill, the start file, the courses or kicks.
#[derive(Args)]
pub struct ObjectiveArgs {
    pub skill: Skill,
    /// The robot: T1 (on rcssservermj) or a NAO type, nao_type0…4 (on SimSpark).
    #[arg(long, default_value = "T1")]
    pub robot: String,
    /// The parameter file to start from (and, for `optimize`, to write the best back to);
    /// default: the robot's shipped one (`engine/skills/params/t1.ron`, `nao.ron`).
    #[arg(long)]
    pub params: Option<PathBuf>,
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    #[arg(long, value_enum, default_value_t = CourseKind::Bars)]
    pub course: CourseKind,
    /// Seeds of the courses every candidate walks (`bars`: sides and random commands; one
    /// course per seed, costs summed, so no candidate wins by fitting one sequence).
    #[arg(long, value_delimiter = ',', default_value = "1,2")]
    pub course_seeds: Vec<u64>,
    /// Kicks every candidate makes (`kick`; more kicks, less luck, slower generations).
    #[arg(long, default_value_t = 6)]
    pub kicks: usize,
    /// The field directions of those kicks (`kick`).
    #[arg(long, value_enum, default_value_t = KickDirectionsArg::AllRound)]
    pub directions: KickDirectionsArg,
    /// The parameters searched (default: the skill's usual set; `walk`: names as in the
    /// parameter file's walk section, `kick`: `long.strike_height_m` and the like).
    #[arg(long, value_delimiter = ',')]
    pub tunables: Vec<String>,
}

#[derive(Args)]
pub struct OptimizeArgs {
    #[command(flatten)]
    pub objective: ObjectiveArgs,
    #[arg(long, default_value_t = 20)]
    pub generations: usize,
    /// Candidates per generation (default: CMA-ES's 4 + 3·ln n).
    #[arg(long)]
    pub population: Option<usize>,
    /// Initial step size as a fraction of each parameter's range.
    #[arg(long, default_value_t = 0.1)]
    pub sigma: f64,
    /// Stop after the generation that ends past this many minutes of wall time.
    #[arg(long)]
    pub budget_min: Option<f64>,
    /// Search and report, but leave the parameter file as it is.
    #[arg(long)]
    pub dry_run: bool,
    /// Save the search after every generation to this file; run the same command again and
    /// it continues from there (a file from another search is refused).
    #[arg(long, value_name = "FILE")]
    pub checkpoint: Option<PathBuf>,
    #[command(flatten)]
    pub executor: ExecutorArgs,
}

/// `libero evaluate`: one candidate's cost on a fresh server, as a JSON report.
#[derive(Args)]
pub struct EvaluateArgs {
    #[command(flatten)]
    pub objective: ObjectiveArgs,
    /// The candidate: tunable values over the start file's (`name=value,…`).
    #[arg(long = "set", value_delimiter = ',', value_name = "NAME=VALUE")]
    pub values: Vec<String>,
    /// Write `{"cost": …}` here.
    #[arg(long, value_name = "FILE")]
    pub report: PathBuf,
}

impl ObjectiveArgs {
    fn model(&self) -> Result<Arc<RobotModel>, libero_model::ModelError> {
        RobotModel::builtin(&self.robot).map(Arc::new)
    }

    /// The parameter file searched from: `--params`, or the robot's shipped one.
    fn params_file(&self, model: &RobotModel) -> PathBuf {
        self.params.clone().unwrap_or_else(|| {
            libero_server::venv::project_root()
                .join("engine/skills/params")
                .join(SkillParams::file_name(model))
        })
    }
}

/// The robot, the start parameters and their file, the searched tunables and the objective.
struct Search {
    model: Arc<RobotModel>,
    params_file: PathBuf,
    start: SkillParams,
    tunables: Vec<Tunable>,
    objective: Box<dyn Objective>,
}

/// The search `args` describe.
fn setup(args: &ObjectiveArgs) -> Result<Search, Box<dyn std::error::Error>> {
    let model = args.model()?;
    let params_file = args.params_file(&model);
    let start = SkillParams::load(&params_file, &model)?;
    let mut names: Vec<&str> = args.tunables.iter().map(String::as_str).collect();
    let w = &start.walk;
    let limits = [w.max_forward_m_s, w.max_sideways_m_s, w.max_turn_deg_s];
    let (tunables, objective): (_, Box<dyn Objective>) = match args.skill {
        Skill::Walk => {
            if names.is_empty() {
                names = DEFAULT_WALK_TUNABLES.to_vec();
            }
            let courses = match args.course {
                CourseKind::Bars => args
                    .course_seeds
                    .iter()
                    .map(|&seed| Course::bars(limits, seed))
                    .collect(),
                CourseKind::Standard => vec![Course::standard()],
                CourseKind::Forward => vec![Course::rising(w.max_forward_m_s, 15.0)],
            };
            (
                select_walk_tunables(&names, &model)?,
                Box::new(WalkObjective { courses }),
            )
        }
        Skill::Kick => {
            if names.is_empty() {
                names = DEFAULT_KICK_TUNABLES.to_vec();
            }
            let distance = start.kick.long_kick_from_m + 5.0;
            (
                select_kick_tunables(&names)?,
                Box::new(KickObjective::at_place(
                    args.kicks,
                    args.seed,
                    distance,
                    &start,
                    args.directions.directions(),
                )),
            )
        }
    };
    Ok(Search {
        model,
        params_file,
        start,
        tunables,
        objective,
    })
}

pub fn run(args: OptimizeArgs) -> CliResult {
    let Search {
        model,
        params_file,
        start,
        tunables,
        objective,
    } = setup(&args.objective)?;
    let start_text = std::fs::read_to_string(&params_file)?;
    let options = Options {
        generations: args.generations,
        population: args.population,
        sigma: args.sigma,
        seed: args.objective.seed,
        budget: args
            .budget_min
            .map(|m| std::time::Duration::from_secs_f64(m.max(0.0) * 60.0)),
        checkpoint: args.checkpoint.clone(),
        identity: format!(
            "{} of {}; {}; start file {:016x}",
            args.objective.skill.as_arg(),
            model.name,
            objective.explain(),
            fnv1a(start_text.as_bytes())
        ),
    };
    let params_path = &params_file;
    let mut evaluator: Box<dyn Evaluator> = match &args.executor.ray {
        Some(_) => Box::new(FleetEvaluator::start(&args, params_path, &tunables)?),
        None => Box::new(LocalServers::start(
            args.executor.parallel,
            &model,
            objective.as_ref(),
        )?),
    };
    println!(
        "optimizing {} parameters of {} over {} generations on {}",
        tunables.len(),
        params_path.display(),
        options.generations,
        match &args.executor.ray {
            Some(address) => format!("the Ray cluster at {address}"),
            None => format!("{} local server(s)", args.executor.parallel),
        }
    );
    let began = std::time::Instant::now();
    let outcome = optimize(
        &start,
        &tunables,
        evaluator.as_mut(),
        &options,
        |generation, cost, mean, best| {
            let values: Vec<String> = tunables
                .iter()
                .map(|t| format!("{}={:.4}", t.name, (t.get)(best)))
                .collect();
            println!(
                "generation {generation:3}: best cost {cost:8.3}, mean {mean:8.3} ({:.0} s) best: {}",
                began.elapsed().as_secs_f64(),
                values.join(" ")
            );
        },
    )?;
    if outcome.resumed_after > 0 {
        println!(
            "continued from the checkpoint after generation {}",
            outcome.resumed_after
        );
    }
    println!(
        "{} generations of {} candidates, {} evaluations in this run, {:.0} s wall time",
        outcome.history.len(),
        outcome.population,
        outcome.evaluations,
        began.elapsed().as_secs_f64()
    );
    println!(
        "cost {:.3} → {:.3} (lower is better: {})",
        outcome.start_cost,
        outcome.best_cost,
        objective.explain()
    );
    for t in &tunables {
        println!(
            "  {:24} {:9.4} → {:9.4}",
            t.name,
            (t.get)(&start),
            (t.get)(&outcome.best)
        );
    }
    if outcome.best_cost >= outcome.start_cost {
        println!("no improvement; {} left as it is", params_path.display());
    } else if args.dry_run {
        println!("dry run: {} left as it is", params_path.display());
    } else {
        let typed = model
            .hetero_type
            .filter(|t| start.walk_by_type.contains_key(t));
        let written = match (args.objective.skill, typed) {
            (Skill::Walk, Some(t)) => {
                write_back_for_type(&start_text, t, &outcome.best, &tunables)?
            }
            _ => write_back(&start_text, &outcome.best, &tunables)?,
        };
        SkillParams::from_ron(&params_path.display().to_string(), &written, &model)?;
        std::fs::write(params_path, written)?;
        println!("wrote the best parameters to {}", params_path.display());
    }
    Ok(ExitCode::SUCCESS)
}

pub fn evaluate(args: EvaluateArgs) -> CliResult {
    let Search {
        model,
        start,
        tunables,
        objective,
        ..
    } = setup(&args.objective)?;
    let mut candidate = start;
    for pair in &args.values {
        let (name, value) = pair
            .split_once('=')
            .ok_or_else(|| format!("--set {pair}: expected NAME=VALUE"))?;
        let tunable = tunables
            .iter()
            .find(|t| t.name == name)
            .ok_or_else(|| format!("--set {name}: not one of the searched tunables"))?;
        let value: f64 = value
            .parse()
            .map_err(|_| format!("--set {pair}: {value} is not a number"))?;
        (tunable.set)(&mut candidate, value);
    }
    let mut servers = LocalServers::start(1, &model, objective.as_ref())?;
    let cost = servers.costs(std::slice::from_ref(&candidate))?[0];
    let json = serde_json::json!({ "cost": cost });
    std::fs::write(&args.report, format!("{json}\n"))
        .map_err(|e| format!("cannot write {}: {e}", args.report.display()))?;
    println!("cost {cost:.4}");
    Ok(ExitCode::SUCCESS)
}

/// Candidates as `libero evaluate` jobs on an executor (the Ray cluster), one job each.
struct FleetEvaluator {
    executor: Box<dyn Executor>,
    /// `evaluate` and the objective's arguments; each job adds its `--set`.
    base: Vec<String>,
    names: Vec<&'static str>,
    gets: Vec<fn(&SkillParams) -> f64>,
    _bundle: Bundle,
}

impl FleetEvaluator {
    fn start(
        args: &OptimizeArgs,
        params_file: &Path,
        tunables: &[Tunable],
    ) -> Result<Self, String> {
        let o = &args.objective;
        let bundle = Bundle::stage(&[(params_file, "optimize/start.ron")])?;
        let executor = args.executor.start(&bundle)?;
        println!("evaluations on {}", executor.describe());
        let seeds: Vec<String> = o.course_seeds.iter().map(u64::to_string).collect();
        let names: Vec<&'static str> = tunables.iter().map(|t| t.name).collect();
        let base = vec![
            "evaluate".into(),
            o.skill.as_arg().into(),
            "--robot".into(),
            o.robot.clone(),
            "--params".into(),
            "optimize/start.ron".into(),
            "--seed".into(),
            o.seed.to_string(),
            "--course".into(),
            o.course.as_arg().into(),
            "--course-seeds".into(),
            seeds.join(","),
            "--kicks".into(),
            o.kicks.to_string(),
            "--directions".into(),
            o.directions.as_arg().into(),
            "--tunables".into(),
            names.join(","),
            "--report".into(),
            REPORT.into(),
        ];
        Ok(Self {
            executor,
            base,
            names,
            gets: tunables.iter().map(|t| t.get).collect(),
            _bundle: bundle,
        })
    }
}

impl Evaluator for FleetEvaluator {
    fn costs(&mut self, candidates: &[SkillParams]) -> Result<Vec<f64>, TrialError> {
        let jobs: Vec<Job> = candidates
            .iter()
            .map(|p| {
                let values: Vec<String> = self
                    .names
                    .iter()
                    .zip(&self.gets)
                    .map(|(name, get)| format!("{name}={:e}", get(p)))
                    .collect();
                let mut argv = self.base.clone();
                argv.extend(["--set".into(), values.join(",")]);
                Job {
                    argv,
                    timeout_s: 900.0,
                }
            })
            .collect();
        let mut bar = Bar::new(jobs.len());
        let mut done = 0;
        let results = run_all(self.executor.as_mut(), &jobs, |_, result| {
            done += 1;
            bar.show(
                done,
                if result.is_ok() {
                    ""
                } else {
                    "a candidate failed"
                },
            );
            if result.is_ok() {
                Next::Continue
            } else {
                Next::Stop
            }
        });
        bar.finish();
        results
            .into_iter()
            .map(|r| {
                let finished = r
                    .ok_or_else(|| TrialError::Elsewhere("cancelled".into()))?
                    .map_err(TrialError::Elsewhere)?;
                finished
                    .report
                    .get("cost")
                    .and_then(|c| c.as_f64())
                    .ok_or_else(|| TrialError::Elsewhere("a report without a cost".into()))
            })
            .collect()
    }
}

/// A short stable hash of the start file, so a checkpoint is not continued from another one.
fn fnv1a(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |h, &b| {
        (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3)
    })
}
