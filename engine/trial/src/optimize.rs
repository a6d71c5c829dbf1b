//! `libero optimize walk`: CMA-ES over the walk's parameters against the real server.
//!
//! Each candidate walks every one of a few [`Course`]s on a fast-mode server (several courses,
//! so it cannot fit one sequence of commands); its cost is minus the progress made the
//! commanded way, plus a heavy penalty for falling (the earlier, the heavier). Several servers
//! evaluate a generation in parallel. Parameters are searched in coordinates
//! normalised to their allowed range, so one step size fits all.

use crate::cmaes::CmaEs;
use crate::course::{progress, Course};
use crate::episode::{Episode, Trial, TrialError};
use libero_skills::SkillParams;
use std::sync::Mutex;

/// One searched number: its name in the parameter file, its range, and how to reach it.
pub struct Tunable {
    pub name: &'static str,
    pub lo: f64,
    pub hi: f64,
    pub get: fn(&SkillParams) -> f64,
    pub set: fn(&mut SkillParams, f64),
}

macro_rules! tunable {
    ($name:ident, $lo:expr, $hi:expr, $($path:ident).+) => {
        Tunable {
            name: stringify!($name),
            lo: $lo,
            hi: $hi,
            get: |p| p.$($path).+,
            set: |p, v| p.$($path).+ = v,
        }
    };
}

/// The walk numbers the optimiser searches by default: the few that decide how fast and how
/// steadily the gait goes (cadence, clearance, weight shift, where the feet land, lean, ankle
/// damping). Fewer dimensions let a run of an hour on one server actually converge.
pub const DEFAULT_WALK_TUNABLES: [&str; 7] = [
    "step_period_s",
    "step_height_m",
    "sway_m",
    "foot_x_offset_m",
    "torso_lean_deg",
    "ankle_pitch_per_gyro",
    "ankle_roll_per_gyro",
];

/// The walk tunables with these names, in the order given; an unknown name is an error that
/// lists the known ones.
pub fn select_walk_tunables(names: &[&str]) -> Result<Vec<Tunable>, String> {
    let mut all = walk_tunables();
    names
        .iter()
        .map(|name| {
            let at = all.iter().position(|t| t.name == *name).ok_or_else(|| {
                let known: Vec<&str> = walk_tunables().iter().map(|t| t.name).collect();
                format!("no walk tunable `{name}` (known: {})", known.join(", "))
            })?;
            Ok(all.remove(at))
        })
        .collect()
}

/// Every walk number the optimiser can search.
pub fn walk_tunables() -> Vec<Tunable> {
    vec![
        tunable!(step_period_s, 0.2, 0.5, walk.step_period_s),
        tunable!(torso_height_m, 0.5, 0.65, walk.torso_height_m),
        tunable!(torso_lean_deg, -5.0, 15.0, walk.torso_lean_deg),
        tunable!(foot_x_offset_m, 0.0, 0.12, walk.foot_x_offset_m),
        tunable!(foot_y_offset_m, 0.08, 0.14, walk.foot_y_offset_m),
        tunable!(step_height_m, 0.01, 0.08, walk.step_height_m),
        tunable!(sway_m, 0.0, 0.06, walk.sway_m),
        tunable!(sway_phase_lead, 0.0, 0.4, walk.sway_phase_lead),
        tunable!(arm_swing_deg_per_m, -200.0, 200.0, walk.arm_swing_deg_per_m),
        tunable!(
            ankle_pitch_per_gyro,
            -0.3,
            0.3,
            walk.balance.ankle_pitch_per_gyro
        ),
        tunable!(
            ankle_pitch_per_tilt,
            -1.5,
            1.5,
            walk.balance.ankle_pitch_per_tilt
        ),
        tunable!(
            hip_pitch_per_gyro,
            -0.3,
            0.3,
            walk.balance.hip_pitch_per_gyro
        ),
        tunable!(
            ankle_roll_per_gyro,
            -0.3,
            0.3,
            walk.balance.ankle_roll_per_gyro
        ),
        tunable!(hip_roll_per_gyro, -0.3, 0.3, walk.balance.hip_roll_per_gyro),
    ]
}

/// How to run the search.
#[derive(Debug, Clone)]
pub struct Options {
    pub generations: usize,
    /// Candidates per generation (`None`: CMA-ES default).
    pub population: Option<usize>,
    /// Servers evaluating in parallel.
    pub servers: usize,
    /// Initial step size in normalised units (1 = the whole range).
    pub sigma: f64,
    pub seed: u64,
    /// Stop after the generation that ends past this much wall time (the server's speed
    /// depends on the machine's load, so a budget in generations alone can run far over).
    pub budget: Option<std::time::Duration>,
    /// Every candidate walks all of these; its cost is the sum.
    pub courses: Vec<Course>,
}

/// Cost of falling at the very start, per second of course (progress is counted in seconds
/// of commanded motion, so this is twice a perfect run); a fall at the end costs half of it.
const FALL_PENALTY_PER_S: f64 = 2.0;

/// Where the robot starts each episode (in our half, well away from the ball at the centre,
/// with room for a course's forward legs).
const START: [f64; 3] = [-18.0, 0.0, 0.0];

/// The result of a search.
pub struct Outcome {
    pub best: SkillParams,
    pub best_cost: f64,
    pub start_cost: f64,
    /// Candidates per generation.
    pub population: usize,
    /// Parameter sets evaluated, the start included.
    pub evaluations: usize,
    /// (generation, best cost so far, mean cost of the generation)
    pub history: Vec<(usize, f64, f64)>,
}

/// Cost of `params` over all `courses`.
pub fn evaluate_courses(
    trial: &mut Trial,
    params: &SkillParams,
    courses: &[Course],
) -> Result<f64, TrialError> {
    courses.iter().map(|c| evaluate(trial, params, c)).sum()
}

/// Cost of `params` on `course`: −progress, plus the fall penalty if it fell.
pub fn evaluate(
    trial: &mut Trial,
    params: &SkillParams,
    course: &Course,
) -> Result<f64, TrialError> {
    let rec = trial.run(
        params,
        Episode {
            start: START,
            lying: None,
            settle_s: 1.0,
            script: course.script(),
        },
    )?;
    let mut cost = -progress(course, &rec);
    if let Some(t) = rec.first_fall_s().or_else(|| {
        // The script stops at the agent's own fall detection; a short recording is a fall too.
        (rec.samples.last().map_or(0.0, |s| s.t) < course.duration_s() - 0.1)
            .then(|| rec.samples.last().map_or(0.0, |s| s.t))
    }) {
        let duration = course.duration_s();
        cost += FALL_PENALTY_PER_S * duration * (1.0 - 0.5 * t / duration);
    }
    Ok(cost)
}

fn to_normalised(params: &SkillParams, tunables: &[Tunable]) -> Vec<f64> {
    tunables
        .iter()
        .map(|t| ((t.get)(params) - t.lo) / (t.hi - t.lo))
        .collect()
}

fn from_normalised(base: &SkillParams, x: &[f64], tunables: &[Tunable]) -> SkillParams {
    let mut p = base.clone();
    for (t, v) in tunables.iter().zip(x) {
        (t.set)(&mut p, t.lo + v.clamp(0.0, 1.0) * (t.hi - t.lo));
    }
    p
}

/// Distance outside the unit box, added to the cost so the search stays inside the ranges.
fn box_penalty(x: &[f64]) -> f64 {
    x.iter().map(|v| (v - v.clamp(0.0, 1.0)).abs()).sum::<f64>() * 10.0
}

/// Run CMA-ES from `start`; `report` hears about each finished generation: its number, the
/// best cost so far, the generation's mean cost and the best parameters so far (so a run that
/// is cut short still tells what it found).
pub fn optimize(
    start: &SkillParams,
    tunables: &[Tunable],
    options: &Options,
    mut report: impl FnMut(usize, f64, f64, &SkillParams),
) -> Result<Outcome, TrialError> {
    let began = std::time::Instant::now();
    let mut trials = (0..options.servers.max(1))
        .map(|_| Trial::start())
        .collect::<Result<Vec<_>, _>>()?;
    let start_cost = evaluate_courses(&mut trials[0], start, &options.courses)?;
    let mut best = (start_cost, start.clone());
    let mut es = CmaEs::new(
        to_normalised(start, tunables),
        options.sigma,
        options.population,
        options.seed,
    );
    let mut history = Vec::new();
    for generation in 1..=options.generations {
        let xs = es.ask();
        let costs = evaluate_all(&mut trials, start, &xs, tunables, &options.courses)?;
        es.tell(&xs, &costs);
        let mean = costs.iter().sum::<f64>() / costs.len() as f64;
        for (x, &c) in xs.iter().zip(&costs) {
            if c < best.0 {
                best = (c, from_normalised(start, x, tunables));
            }
        }
        history.push((generation, best.0, mean));
        report(generation, best.0, mean, &best.1);
        if options.budget.is_some_and(|b| began.elapsed() > b) {
            break;
        }
    }
    Ok(Outcome {
        best: best.1,
        best_cost: best.0,
        start_cost,
        population: es.population_size(),
        evaluations: 1 + es.population_size() * history.len(),
        history,
    })
}

fn evaluate_all(
    trials: &mut [Trial],
    base: &SkillParams,
    xs: &[Vec<f64>],
    tunables: &[Tunable],
    courses: &[Course],
) -> Result<Vec<f64>, TrialError> {
    let next = Mutex::new(0usize);
    let costs = Mutex::new(vec![f64::INFINITY; xs.len()]);
    let failure: Mutex<Option<TrialError>> = Mutex::new(None);
    std::thread::scope(|scope| {
        for trial in trials.iter_mut() {
            let (next, costs, failure) = (&next, &costs, &failure);
            scope.spawn(move || loop {
                let i = {
                    let mut n = next.lock().expect("index lock");
                    let i = *n;
                    *n += 1;
                    i
                };
                let Some(x) = xs.get(i) else { break };
                let params = from_normalised(base, x, tunables);
                match evaluate_courses(trial, &params, courses) {
                    Ok(c) => costs.lock().expect("cost lock")[i] = c + box_penalty(x),
                    Err(e) => {
                        *failure.lock().expect("failure lock") = Some(e);
                        break;
                    }
                }
            });
        }
    });
    if let Some(e) = failure.into_inner().expect("failure lock") {
        return Err(e);
    }
    Ok(costs.into_inner().expect("cost lock"))
}

/// Replace the values of `tunables` in the RON text of a parameter file by those of `best`,
/// keeping every comment and the layout. Each tunable's name occurs once in the file.
pub fn write_back(text: &str, best: &SkillParams, tunables: &[Tunable]) -> Result<String, String> {
    let mut out = text.to_string();
    for t in tunables {
        let key = format!("{}:", t.name);
        let hits: Vec<usize> = out.match_indices(&key).map(|(i, _)| i).collect();
        let &[at] = hits.as_slice() else {
            return Err(format!(
                "`{}` occurs {} times in the file, expected once",
                t.name,
                hits.len()
            ));
        };
        let value_start = at + key.len();
        let rest = &out[value_start..];
        let skip = rest.len() - rest.trim_start().len();
        let number_len = rest[skip..]
            .find(|c: char| !(c.is_ascii_digit() || matches!(c, '-' | '+' | '.' | 'e' | 'E')))
            .unwrap_or(rest.len() - skip);
        let value = (t.get)(best);
        let formatted = format!("{:.4}", value);
        out.replace_range(
            value_start + skip..value_start + skip + number_len,
            &formatted,
        );
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn write_back_changes_only_the_tuned_numbers() {
        let model = libero_model::RobotModel::builtin("T1").unwrap();
        let text = include_str!("../../skills/params/t1.ron");
        let mut p = SkillParams::builtin(&model).unwrap();
        p.walk.step_period_s = 0.3125;
        p.walk.balance.ankle_pitch_per_gyro = -0.05;
        let written = write_back(text, &p, &walk_tunables()).unwrap();
        let again = SkillParams::from_ron("w.ron", &written, &model).unwrap();
        assert_eq!(again.walk.step_period_s, 0.3125);
        assert_eq!(again.walk.balance.ankle_pitch_per_gyro, -0.05);
        assert_eq!(written.lines().count(), text.lines().count());
        assert!(written.contains("// Omnidirectional walk"));
    }

    #[test]
    fn selects_tunables_by_name_and_names_the_known_ones_on_a_typo() {
        let picked = select_walk_tunables(&DEFAULT_WALK_TUNABLES).unwrap();
        let names: Vec<&str> = picked.iter().map(|t| t.name).collect();
        assert_eq!(names, DEFAULT_WALK_TUNABLES);
        let err = select_walk_tunables(&["step_period"]).err().unwrap();
        assert!(err.contains("step_period_s"), "{err}");
    }
}
