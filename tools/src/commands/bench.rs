//! `libero bench walk|getup`: locomotion measurements on a real server started by the command.

use super::CliResult;
use clap::{Args, ValueEnum};
use libero_model::RobotModel;
use libero_skills::getup::Lying;
use libero_skills::SkillParams;
use libero_trial::getup_bench::{self, GET_UP_LIMIT_S};
use libero_trial::{bench, kick_bench, kick_step_bench, Trial};
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Clone, Copy, ValueEnum)]
pub enum Measure {
    /// Forward over 20 m, sideways, turning on the spot, 5 minutes of random commands.
    Walk,
    /// 20 get-ups from lying face down and 20 from the back, each placed with another heading,
    /// roll and position; then one walk after a get-up.
    #[value(name = "getup")]
    GetUp,
    /// 20 long and 20 short kicks from all round the ball (5 each with `--short`), and 20
    /// dribbles with the walk's kick step when the skill file has one.
    Kick,
    /// CPU per agent-cycle: `--players` of our agents and as many that only answer, in one
    /// run (`--duration` s of play, 10 with `--short`); the ratio, the server's CPU per cycle
    /// and the peak RSS.
    Cycle,
    /// What the field view costs: agent CPU per cycle with the view off and on (a viewer
    /// connected), in alternating phases of one run (`--duration` s of play, 20 with `--short`).
    View,
}

#[derive(Args)]
pub struct BenchArgs {
    pub what: Measure,
    /// The robot: T1 (on rcssservermj) or a NAO type, nao_type0…4 (on SimSpark)
    /// [default: T1, or nao_type0 with `--server simspark`].
    #[arg(long)]
    pub robot: Option<String>,
    /// The server; the robot's own by default (a NAO type plays on SimSpark).
    #[arg(long)]
    pub server: Option<libero_model::ServerKind>,
    /// A skill parameter file instead of the built-in one.
    #[arg(long)]
    pub params: Option<PathBuf>,
    /// The CI version: 10 m forward, 10 s sideways and turning, 60 s of random commands;
    /// 3 get-ups from each side; 5 kicks of each kind.
    #[arg(long)]
    pub short: bool,
    /// Seed of the random course, the get-up placements or the kick setups.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// `cycle`: agents per kind.
    #[arg(long, default_value_t = 7)]
    pub players: u32,
    /// `cycle`: play time measured [s].
    #[arg(long, default_value_t = 60.0)]
    pub duration: f64,
    /// `cycle`: the trees, strategy and skill files our agents run.
    #[command(flatten)]
    pub data: super::setup::DataArgs,
}

pub fn run(args: BenchArgs) -> CliResult {
    use libero_model::ServerKind;
    let robot = match (&args.robot, args.server) {
        (Some(robot), _) => robot.clone(),
        (None, Some(ServerKind::SimSpark)) => "nao_type0".to_string(),
        (None, _) => "T1".to_string(),
    };
    let model = RobotModel::builtin(&robot)?;
    if args.server.is_some_and(|server| server != model.server) {
        return Err(format!("{robot} does not play on that server (--server, --robot)").into());
    }
    let simspark = model.server == ServerKind::SimSpark;
    if simspark && !matches!(args.what, Measure::Walk | Measure::GetUp | Measure::Kick) {
        return Err(format!(
            "only `libero bench walk`, `getup` and `kick` run on SimSpark so far (robot {robot})"
        )
        .into());
    }
    let params = match &args.params {
        Some(path) => SkillParams::load(path, &model)?,
        None => SkillParams::builtin(&model)?,
    };
    match args.what {
        Measure::Walk => bench_walk(&params, &args, model),
        Measure::GetUp => bench_get_up(&params, &args, model),
        Measure::Kick => bench_kick(&params, &args, model),
        Measure::Cycle => {
            let play_s = if args.short { 10.0 } else { args.duration };
            super::bench_cycle::bench_cycle(args.players.clamp(1, 7), play_s, &args.data)
        }
        Measure::View => {
            let (play_s, phases) = if args.short {
                (20.0, 4)
            } else {
                (args.duration, 10)
            };
            super::bench_view::bench_view(args.players.clamp(1, 7), play_s, phases, &args.data)
        }
    }
}

fn fall_note(fell_at: Option<f64>) -> String {
    fell_at.map_or_else(|| "no fall".to_string(), |t| format!("FELL at {t:.1} s"))
}

fn bench_walk(params: &SkillParams, args: &BenchArgs, model: RobotModel) -> CliResult {
    let (distance, seconds, course_s) = if args.short {
        (10.0, 10.0, 60.0)
    } else {
        (20.0, 20.0, 300.0)
    };
    let mut trial = Trial::start_on(std::sync::Arc::new(model))?;
    let f = bench::forward(&mut trial, params, distance, distance / 0.2)?;
    println!(
        "forward {:.2} m/s ({:.1} m in {:.1} s after a {:.0} s start, {})",
        f.speed,
        f.distance,
        f.seconds,
        bench::RAMP_S,
        fall_note(f.fell_at)
    );
    let s = bench::sideways(&mut trial, params, seconds)?;
    println!("sideways {:.2} m/s ({})", s.speed, fall_note(s.fell_at));
    let t = bench::turning(&mut trial, params, seconds)?;
    println!("turn {:.0} deg/s ({})", t.speed, fall_note(t.fell_at));
    let c = bench::random_course(&mut trial, params, course_s, args.seed)?;
    println!(
        "course {:.0} s of random commands: {} falls ({:.0} s walked{})",
        course_s,
        usize::from(c.fell_at.is_some()),
        c.walked_s,
        c.fell_at
            .map_or(String::new(), |t| format!(", fell at {t:.1} s"))
    );
    for (what, e) in [("forward", &f.localization), ("course", &c.localization)] {
        if let Some(e) = e {
            println!(
                "localization while walking ({what}): median {:.3} m, 90 % {:.3} m, max {:.3} m \
                 over {} cycles ({:.0} % of the walk unlocalized)",
                e.median_m,
                e.p90_m,
                e.max_m,
                e.samples,
                100.0 * e.unlocalized_share
            );
        }
    }
    Ok(ExitCode::SUCCESS)
}

fn bench_get_up(params: &SkillParams, args: &BenchArgs, model: RobotModel) -> CliResult {
    let runs = if args.short { 3 } else { 20 };
    let mut trial = Trial::start_on(std::sync::Arc::new(model))?;
    for (name, side) in [("front", Lying::Front), ("back", Lying::Back)] {
        let mut done = Vec::new();
        for placement in getup_bench::varied_placements(side, runs, args.seed) {
            let run = getup_bench::get_up(&mut trial, params, placement, GET_UP_LIMIT_S)?;
            log::info!(
                "getup {name}: heading {:.0} deg, roll {:.0} deg: stood at {:?}",
                placement.start[2],
                placement.lying.roll_deg,
                run.stood_at
            );
            if !run.succeeded() {
                // The ground truth of a miss, to tell a stalled roll from a failed pop.
                for s in run.recording.samples.iter().step_by(5) {
                    log::info!(
                        "  t {:5.2} z {:5.3} tilt {:5.1} pitch {:6.1} roll {:6.1} {:?}",
                        s.t,
                        s.position[2],
                        s.tilt_deg,
                        s.pitch_deg,
                        s.roll_deg,
                        s.posture
                    );
                }
            }
            done.push(run);
        }
        let s = getup_bench::summarize(&done);
        let time = |t: Option<f64>| t.map_or_else(|| "-".to_string(), |t| format!("{t:.1} s"));
        println!(
            "getup {name} {}/{} successes, mean {}, worst {} (standing within {GET_UP_LIMIT_S:.0} s, held {:.1} s)",
            s.successes,
            s.runs,
            time(s.mean_s),
            time(s.worst_s),
            getup_bench::STANDING_HOLD_S
        );
    }
    let placement = getup_bench::varied_placements(Lying::Front, 1, args.seed)[0];
    let walk = getup_bench::walk_after_get_up(
        &mut trial,
        params,
        placement,
        WALK_AFTER_S,
        params.walk.max_forward_m_s * 0.6,
        WALK_S,
    )?;
    println!(
        "getup then walk: stood at {}, walked {:.2} m in {WALK_S:.0} s ({})",
        walk.stood_at
            .map_or_else(|| "never".to_string(), |t| format!("{t:.1} s")),
        walk.walked_m,
        if walk.fell { "FELL" } else { "no fall" }
    );
    Ok(ExitCode::SUCCESS)
}

/// The walk after a get-up starts this long after the placement (the get-up is over by then).
const WALK_AFTER_S: f64 = GET_UP_LIMIT_S + 0.5;
const WALK_S: f64 = 4.0;
/// Distances asked for: beyond `long_kick_from_m` for the long kick, below it for the short one.
const LONG_KICK_REQUEST_M: f64 = 8.0;
const SHORT_KICK_REQUEST_M: f64 = 1.5;

fn bench_kick(params: &SkillParams, args: &BenchArgs, model: RobotModel) -> CliResult {
    let count = if args.short { 5 } else { 20 };
    let mut trial = Trial::start_on(std::sync::Arc::new(model))?;
    for (name, distance, seed) in [
        ("long", LONG_KICK_REQUEST_M, args.seed),
        ("short", SHORT_KICK_REQUEST_M, args.seed.wrapping_add(1000)),
    ] {
        let (_, s) = kick_bench::kicks(&mut trial, params, count, seed, distance)?;
        println!(
            "kick {name} {} kicks: mean distance {:.1} m (min {:.1}), mean |direction error| {:.1}° \
             (max {:.1}°), {} rolled the {distance} m asked, {:.2} m off the line there (mean \
             |offset|), {} falls, {} bumped, {} not kicked, mean time to kick {:.1} s",
            s.kicks,
            s.mean_distance_m,
            s.min_distance_m,
            s.mean_abs_direction_error_deg,
            s.max_abs_direction_error_deg,
            s.reached_distance,
            s.mean_abs_miss_m,
            s.falls,
            s.bumps,
            s.kicks - s.kicked,
            s.mean_time_to_kick_s
        );
    }
    if params.walk.kick_step.is_some() {
        let (_, s) = kick_step_bench::dribbles(&mut trial, params, count, args.seed)?;
        println!(
            "kick step {} dribbles: {} kick steps made, first one's roll {:.1} m (min {:.1}), \
             mean |direction error| {:.1}° (max {:.1}°), {} falls, mean time to it {:.1} s",
            s.dribbles,
            s.kicked,
            s.mean_roll_m,
            s.min_roll_m,
            s.mean_abs_direction_error_deg,
            s.max_abs_direction_error_deg,
            s.falls,
            s.mean_time_to_kick_s
        );
    }
    Ok(ExitCode::SUCCESS)
}
