//! `libero optimize <skill>`: CMA-ES over a skill's parameters against real servers, writing
//! the best values back into the parameter file.

use super::CliResult;
use clap::{Args, ValueEnum};
use libero_model::RobotModel;
use libero_skills::SkillParams;
use libero_trial::optimize::kick::{select_kick_tunables, KickObjective, DEFAULT_KICK_TUNABLES};
use libero_trial::optimize::{
    optimize, select_walk_tunables, write_back, Objective, Options, WalkObjective,
    DEFAULT_WALK_TUNABLES,
};
use libero_trial::Course;
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Clone, Copy, ValueEnum)]
pub enum Skill {
    /// The omnidirectional walk (gait geometry, timing and balance gains).
    Walk,
    /// The long kick (contact geometry, swing), kicked from around the kicking place.
    Kick,
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

#[derive(Args)]
pub struct OptimizeArgs {
    pub skill: Skill,
    /// The parameter file to start from and write the best parameters back to.
    #[arg(long, default_value_os_t = default_params_file())]
    pub params: PathBuf,
    #[arg(long, default_value_t = 20)]
    pub generations: usize,
    /// Candidates per generation (default: CMA-ES's 4 + 3·ln n).
    #[arg(long)]
    pub population: Option<usize>,
    /// Servers evaluating in parallel (one per core is the most that helps).
    #[arg(long, default_value_t = 2)]
    pub servers: usize,
    /// Initial step size as a fraction of each parameter's range.
    #[arg(long, default_value_t = 0.1)]
    pub sigma: f64,
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Stop after the generation that ends past this many minutes of wall time.
    #[arg(long)]
    pub budget_min: Option<f64>,
    #[arg(long, value_enum, default_value_t = CourseKind::Bars)]
    pub course: CourseKind,
    /// Seeds of the courses every candidate walks (`bars`: sides and random commands; one
    /// course per seed, costs summed, so no candidate wins by fitting one sequence).
    #[arg(long, value_delimiter = ',', default_value = "1,2")]
    pub course_seeds: Vec<u64>,
    /// Kicks every candidate makes (`kick`; more kicks, less luck, slower generations).
    #[arg(long, default_value_t = 6)]
    pub kicks: usize,
    /// The parameters searched (default: the skill's usual set; `walk`: names as in the
    /// parameter file's walk section, `kick`: `long.strike_height_m` and the like).
    #[arg(long, value_delimiter = ',')]
    pub tunables: Vec<String>,
    /// Search and report, but leave the parameter file as it is.
    #[arg(long)]
    pub dry_run: bool,
}

fn default_params_file() -> PathBuf {
    libero_server::venv::project_root().join("engine/skills/params/t1.ron")
}

pub fn run(args: OptimizeArgs) -> CliResult {
    let model = RobotModel::builtin("T1")?;
    let start = SkillParams::load(&args.params, &model)?;
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
                select_walk_tunables(&names)?,
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
                    args.kicks, args.seed, distance, &start,
                )),
            )
        }
    };
    let options = Options {
        generations: args.generations,
        population: args.population,
        servers: args.servers,
        sigma: args.sigma,
        seed: args.seed,
        budget: args
            .budget_min
            .map(|m| std::time::Duration::from_secs_f64(m.max(0.0) * 60.0)),
    };
    println!(
        "optimizing {} parameters of {} over {} generations on {} server(s)",
        tunables.len(),
        args.params.display(),
        options.generations,
        options.servers
    );
    let began = std::time::Instant::now();
    let outcome = optimize(
        &start,
        &tunables,
        objective.as_ref(),
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
    println!(
        "{} generations of {} candidates, {} evaluations, {:.0} s wall time",
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
        println!("no improvement; {} left as it is", args.params.display());
    } else if args.dry_run {
        println!("dry run: {} left as it is", args.params.display());
    } else {
        let text = std::fs::read_to_string(&args.params)?;
        let written = write_back(&text, &outcome.best, &tunables)?;
        SkillParams::from_ron(&args.params.display().to_string(), &written, &model)?;
        std::fs::write(&args.params, written)?;
        println!("wrote the best parameters to {}", args.params.display());
    }
    Ok(ExitCode::SUCCESS)
}
