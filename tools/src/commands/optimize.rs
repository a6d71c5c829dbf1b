//! `libero optimize <skill>`: CMA-ES over a skill's parameters against real servers, writing
//! the best values back into the parameter file.

use super::CliResult;
use clap::{Args, ValueEnum};
use libero_model::RobotModel;
use libero_skills::SkillParams;
use libero_trial::optimize::{optimize, walk_tunables, write_back, Options};
use libero_trial::Course;
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Clone, Copy, ValueEnum)]
pub enum Skill {
    /// The omnidirectional walk (gait geometry, timing and balance gains).
    Walk,
}

#[derive(Clone, Copy, ValueEnum)]
pub enum CourseKind {
    /// Forward, curves, sideways, turning on the spot, backwards (24 s).
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
    #[arg(long, value_enum, default_value_t = CourseKind::Standard)]
    pub course: CourseKind,
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
    let tunables = match args.skill {
        Skill::Walk => walk_tunables(),
    };
    let course = match args.course {
        CourseKind::Standard => Course::standard(),
        CourseKind::Forward => Course::rising(start.walk.max_forward_m_s, 15.0),
    };
    let options = Options {
        generations: args.generations,
        population: args.population,
        servers: args.servers,
        sigma: args.sigma,
        seed: args.seed,
        course,
    };
    println!(
        "optimizing {} parameters of {} over {} generations on {} server(s)",
        tunables.len(),
        args.params.display(),
        options.generations,
        options.servers
    );
    let outcome = optimize(&start, &tunables, &options, |generation, best, mean| {
        println!("generation {generation:3}: best cost {best:8.3}, mean {mean:8.3}");
    })?;
    println!(
        "cost {:.3} → {:.3} (lower is better: minus metres made good, +20 for an early fall)",
        outcome.start_cost, outcome.best_cost
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
