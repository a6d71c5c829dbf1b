//! `libero optimize <skill>`: CMA-ES over a skill's parameters against the real server.
//!
//! An [`Objective`] says what a parameter set costs on a fast-mode server: [`walk`] walks a few
//! courses, [`kick`] kicks from a few places. Several servers evaluate a generation in
//! parallel. Parameters are searched in coordinates normalised to their allowed range, so one
//! step size fits all, and the best are written back into the parameter file in place.

pub mod checkpoint;
pub mod kick;
pub mod walk;

use crate::cmaes::CmaEs;
use crate::episode::{Trial, TrialError};
use libero_model::RobotModel;
use libero_skills::SkillParams;
use std::sync::{Arc, Mutex};

pub use walk::{select_walk_tunables, walk_tunables, WalkObjective, DEFAULT_WALK_TUNABLES};

/// What a parameter set costs (lower is better), measured on a server.
pub trait Objective: Sync {
    fn cost(&self, trial: &mut Trial, params: &SkillParams) -> Result<f64, TrialError>;
    /// One line saying what the cost means, for the report.
    fn explain(&self) -> String;
}

/// One searched number: its name on the command line, where it is in the parameter file
/// (field names from the top, dot-separated), its range, and how to reach it.
pub struct Tunable {
    pub name: &'static str,
    pub path: &'static str,
    pub lo: f64,
    pub hi: f64,
    pub get: fn(&SkillParams) -> f64,
    pub set: fn(&mut SkillParams, f64),
}

macro_rules! tunable {
    ($name:ident, $lo:expr, $hi:expr, $($path:ident).+) => {
        $crate::optimize::Tunable {
            name: stringify!($name),
            path: stringify!($($path).+),
            lo: $lo,
            hi: $hi,
            get: |p| p.$($path).+,
            set: |p, v| p.$($path).+ = v,
        }
    };
    ($name:literal, $lo:expr, $hi:expr, $($path:ident).+) => {
        $crate::optimize::Tunable {
            name: $name,
            path: stringify!($($path).+),
            lo: $lo,
            hi: $hi,
            get: |p| p.$($path).+,
            set: |p, v| p.$($path).+ = v,
        }
    };
}
pub(crate) use tunable;

/// The tunables of `all` with these names, in the order given; an unknown name is an error
/// that lists the known ones.
pub fn select_tunables(
    all: Vec<Tunable>,
    names: &[&str],
    skill: &str,
) -> Result<Vec<Tunable>, String> {
    let known: Vec<&str> = all.iter().map(|t| t.name).collect();
    let known = known.join(", ");
    let mut all = all;
    names
        .iter()
        .map(|name| {
            let at = all
                .iter()
                .position(|t| t.name == *name)
                .ok_or_else(|| format!("no {skill} tunable `{name}` (known: {known})"))?;
            Ok(all.remove(at))
        })
        .collect()
}

/// How to run the search.
#[derive(Debug, Clone)]
pub struct Options {
    pub generations: usize,
    /// Candidates per generation (`None`: CMA-ES default).
    pub population: Option<usize>,
    /// Initial step size in normalised units (1 = the whole range).
    pub sigma: f64,
    pub seed: u64,
    /// Stop after the generation that ends past this much wall time (the server's speed
    /// depends on the machine's load, so a budget in generations alone can run far over).
    pub budget: Option<std::time::Duration>,
    /// Written after every generation; a run that finds one from the same search continues
    /// from it (see [`checkpoint`]).
    pub checkpoint: Option<std::path::PathBuf>,
    /// What else makes two runs the same search (the objective, the start file's text), so a
    /// checkpoint is only taken up by the search that wrote it.
    pub identity: String,
}

/// The result of a search.
pub struct Outcome {
    pub best: SkillParams,
    pub best_cost: f64,
    pub start_cost: f64,
    /// Candidates per generation.
    pub population: usize,
    /// Parameter sets evaluated in this run, the start included unless resumed.
    pub evaluations: usize,
    /// (generation, best cost so far, mean cost of the generation), resumed ones included.
    pub history: Vec<(usize, f64, f64)>,
    /// The generation a checkpoint let this run start after (0: from the start).
    pub resumed_after: usize,
}

/// Where candidates are evaluated: [`LocalServers`] on this machine, or elsewhere (the
/// `libero` program's Ray executor).
pub trait Evaluator {
    /// The costs of `candidates`, in order (lower is better).
    fn costs(&mut self, candidates: &[SkillParams]) -> Result<Vec<f64>, TrialError>;
}

/// Fast-mode servers on this machine, each evaluating candidates in turn on its own thread.
pub struct LocalServers<'a> {
    trials: Vec<Trial>,
    objective: &'a dyn Objective,
}

impl<'a> LocalServers<'a> {
    /// `servers` fast-mode servers of `model`'s kind, each with an agent of that robot.
    pub fn start(
        servers: usize,
        model: &Arc<RobotModel>,
        objective: &'a dyn Objective,
    ) -> Result<Self, TrialError> {
        let trials = (0..servers.max(1))
            .map(|_| Trial::start_on(Arc::clone(model)))
            .collect::<Result<Vec<_>, _>>()?;
        Ok(Self { trials, objective })
    }
}

impl Evaluator for LocalServers<'_> {
    fn costs(&mut self, candidates: &[SkillParams]) -> Result<Vec<f64>, TrialError> {
        let objective = self.objective;
        let next = Mutex::new(0usize);
        let costs = Mutex::new(vec![f64::INFINITY; candidates.len()]);
        let failure: Mutex<Option<TrialError>> = Mutex::new(None);
        std::thread::scope(|scope| {
            for trial in self.trials.iter_mut() {
                let (next, costs, failure) = (&next, &costs, &failure);
                scope.spawn(move || loop {
                    let i = {
                        let mut n = next.lock().expect("index lock");
                        let i = *n;
                        *n += 1;
                        i
                    };
                    let Some(params) = candidates.get(i) else {
                        break;
                    };
                    match objective.cost(trial, params) {
                        Ok(c) => costs.lock().expect("cost lock")[i] = c,
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
    evaluator: &mut dyn Evaluator,
    options: &Options,
    mut report: impl FnMut(usize, f64, f64, &SkillParams),
) -> Result<Outcome, TrialError> {
    let began = std::time::Instant::now();
    let identity = checkpoint::identity(tunables, options);
    let resumed = match &options.checkpoint {
        Some(path) => checkpoint::load(path, &identity)?,
        None => None,
    };
    let mut evaluations = 0;
    let (mut es, start_cost, mut best, mut history) = match resumed {
        Some(saved) => {
            let best = from_normalised(start, &saved.best_x, tunables);
            (
                saved.es,
                saved.start_cost,
                (saved.best_cost, best),
                saved.history,
            )
        }
        None => {
            let start_cost = evaluator.costs(std::slice::from_ref(start))?[0];
            evaluations += 1;
            let es = CmaEs::new(
                to_normalised(start, tunables),
                options.sigma,
                options.population,
                options.seed,
            );
            (es, start_cost, (start_cost, start.clone()), Vec::new())
        }
    };
    let resumed_after = es.generation();
    let mut best_x = to_normalised(&best.1, tunables);
    for generation in resumed_after + 1..=options.generations {
        let xs = es.ask();
        let candidates: Vec<SkillParams> = xs
            .iter()
            .map(|x| from_normalised(start, x, tunables))
            .collect();
        let raw = evaluator.costs(&candidates)?;
        evaluations += candidates.len();
        let costs: Vec<f64> = raw
            .iter()
            .zip(&xs)
            .map(|(c, x)| c + box_penalty(x))
            .collect();
        es.tell(&xs, &costs);
        let mean = costs.iter().sum::<f64>() / costs.len() as f64;
        for ((x, candidate), &c) in xs.iter().zip(candidates).zip(&costs) {
            if c < best.0 {
                best = (c, candidate);
                best_x = x.clone();
            }
        }
        history.push((generation, best.0, mean));
        if let Some(path) = &options.checkpoint {
            checkpoint::save(
                path,
                &checkpoint::Checkpoint {
                    identity: identity.clone(),
                    start_cost,
                    best_cost: best.0,
                    best_x: best_x.clone(),
                    history: history.clone(),
                    es: es.clone(),
                },
            )?;
        }
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
        evaluations,
        history,
        resumed_after,
    })
}

/// Replace the values of `tunables` in the RON text of a parameter file by those of `best`,
/// keeping every comment and the layout. Each tunable is found by its path: every field name in
/// turn, each the first occurrence (outside comments) after the one before.
pub fn write_back(text: &str, best: &SkillParams, tunables: &[Tunable]) -> Result<String, String> {
    write_back_from(text, 0, None, best, tunables)
}

/// As [`write_back`], for a robot whose walk is its type's entry of `walk_by_type`: the walk
/// numbers are written into that entry, not into `walk`.
pub fn write_back_for_type(
    text: &str,
    hetero_type: u8,
    best: &SkillParams,
    tunables: &[Tunable],
) -> Result<String, String> {
    let map = find_field(text, 0, "walk_by_type")
        .ok_or("the file has no `walk_by_type` to write the type's walk into")?;
    let entry = find_field(text, map, &hetero_type.to_string())
        .ok_or_else(|| format!("`walk_by_type` has no entry for type {hetero_type}"))?;
    write_back_from(text, entry, Some("walk"), best, tunables)
}

/// Write the tunables found from byte `from` on; with `within`, paths starting with that
/// field start at `from` without it (the field is the map entry `from` points into).
fn write_back_from(
    text: &str,
    from: usize,
    within: Option<&str>,
    best: &SkillParams,
    tunables: &[Tunable],
) -> Result<String, String> {
    let mut out = text.to_string();
    for t in tunables {
        let mut fields: Vec<&str> = t.path.split('.').map(str::trim).collect();
        let mut at = 0;
        if within.is_some_and(|w| fields.first() == Some(&w)) {
            fields.remove(0);
            at = from;
        }
        for field in fields {
            at = find_field(&out, at, field)
                .ok_or_else(|| format!("`{}` ({}) is not in the file", t.name, t.path))?;
        }
        let value_start = at;
        let rest = &out[value_start..];
        let skip = rest.len() - rest.trim_start().len();
        let number_len = rest[skip..]
            .find(|c: char| !(c.is_ascii_digit() || matches!(c, '-' | '+' | '.' | 'e' | 'E')))
            .unwrap_or(rest.len() - skip);
        if number_len == 0 {
            return Err(format!(
                "`{}` ({}) is not a number in the file",
                t.name, t.path
            ));
        }
        let formatted = format!("{:.4}", (t.get)(best));
        out.replace_range(
            value_start + skip..value_start + skip + number_len,
            &formatted,
        );
    }
    Ok(out)
}

/// The position just after `field:` at or after `from`, skipping comments and longer names
/// that end in `field`.
fn find_field(text: &str, from: usize, field: &str) -> Option<usize> {
    let key = format!("{field}:");
    let mut search = from;
    while let Some(i) = text[search..].find(&key).map(|i| i + search) {
        let line_start = text[..i].rfind('\n').map_or(0, |n| n + 1);
        let in_comment = text[line_start..i].contains("//");
        let joined = text[..i]
            .chars()
            .next_back()
            .is_some_and(|c| c.is_alphanumeric() || c == '_');
        if !in_comment && !joined {
            return Some(i + key.len());
        }
        search = i + key.len();
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    fn t1() -> RobotModel {
        RobotModel::builtin("T1").unwrap()
    }

    #[test]
    fn write_back_changes_only_the_tuned_numbers() {
        let model = libero_model::RobotModel::builtin("T1").unwrap();
        let text = include_str!("../../../skills/params/t1.ron");
        let mut p = SkillParams::builtin(&model).unwrap();
        p.walk.step_period_s = 0.3125;
        p.walk.balance.ankle_pitch_per_gyro = -0.05;
        let written = write_back(text, &p, &walk_tunables(&t1())).unwrap();
        let again = SkillParams::from_ron("w.ron", &written, &model).unwrap();
        assert_eq!(again.walk.step_period_s, 0.3125);
        assert_eq!(again.walk.balance.ankle_pitch_per_gyro, -0.05);
        assert_eq!(written.lines().count(), text.lines().count());
        assert!(written.contains("// Omnidirectional walk"));
    }

    #[test]
    fn a_types_walk_is_written_into_its_walk_by_type_entry() {
        let model = RobotModel::builtin("nao_type3").unwrap();
        let shipped = include_str!("../../../skills/params/nao.ron");
        let mut walk = SkillParams::builtin(&model).unwrap().walk;
        walk.step_period_s = 0.25;
        let entry = format!(
            "    walk_by_type: {{ 1: {}, 3: {} }},\n)",
            ron::to_string(&walk).unwrap(),
            ron::to_string(&walk).unwrap()
        );
        // The shipped file with its own `walk_by_type` replaced by entries for types 1 and 3.
        let cut = shipped
            .find("    walk_by_type:")
            .unwrap_or_else(|| shipped.trim_end().strip_suffix(')').unwrap().len());
        let text = shipped[..cut].to_string() + &entry;
        let mut best = SkillParams::from_ron("t.ron", &text, &model).unwrap();
        assert_eq!(best.walk.step_period_s, 0.25, "type 3 walks its own walk");
        best.walk.step_period_s = 0.1875;
        let tunables = select_walk_tunables(&["step_period_s"], &model).unwrap();
        let written = write_back_for_type(&text, 3, &best, &tunables).unwrap();
        let again = SkillParams::from_ron("w.ron", &written, &model).unwrap();
        assert_eq!(again.walk.step_period_s, 0.1875);
        assert_eq!(
            again.walk_by_type[&1].step_period_s, 0.25,
            "type 1 untouched"
        );
        let type0 = RobotModel::builtin("nao_type0").unwrap();
        let plain = SkillParams::from_ron("w.ron", &written, &type0).unwrap();
        assert_eq!(
            plain.walk.step_period_s,
            SkillParams::builtin(&type0).unwrap().walk.step_period_s,
            "the family's walk untouched"
        );
    }

    #[test]
    fn write_back_finds_a_field_by_its_path_among_equal_names() {
        let model = libero_model::RobotModel::builtin("T1").unwrap();
        let text = include_str!("../../../skills/params/t1.ron");
        let mut p = SkillParams::builtin(&model).unwrap();
        // `strike_height_m` is in both the short and the long kick.
        p.kick.long.strike_height_m = 0.1234;
        let written = write_back(text, &p, &kick::kick_tunables()).unwrap();
        let again = SkillParams::from_ron("k.ron", &written, &model).unwrap();
        assert_eq!(again.kick.long.strike_height_m, 0.1234);
        let short = SkillParams::builtin(&model)
            .unwrap()
            .kick
            .short
            .strike_height_m;
        assert_eq!(again.kick.short.strike_height_m, short);
        assert_eq!(written.lines().count(), text.lines().count());
    }

    #[test]
    fn selects_tunables_by_name_and_names_the_known_ones_on_a_typo() {
        let picked = select_walk_tunables(&DEFAULT_WALK_TUNABLES, &t1()).unwrap();
        let names: Vec<&str> = picked.iter().map(|t| t.name).collect();
        assert_eq!(names, DEFAULT_WALK_TUNABLES);
        let err = select_walk_tunables(&["step_period"], &t1()).err().unwrap();
        assert!(err.contains("step_period_s"), "{err}");
    }
}
