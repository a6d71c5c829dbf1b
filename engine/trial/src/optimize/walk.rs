//! The walk objective: each candidate walks every one of a few [`Course`]s (several courses,
//! so it cannot fit one sequence of commands); its cost is minus the progress made the
//! commanded way, plus a heavy penalty for falling (the earlier, the heavier).

use super::{select_tunables, tunable, Objective, Tunable};
use crate::course::{progress, Course};
use crate::episode::{Episode, Trial, TrialError};
use libero_model::{RobotModel, ServerKind};
use libero_skills::SkillParams;

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

/// The walk tunables with these names, in the order given, with ranges for `model`; an
/// unknown name is an error that lists the known ones.
pub fn select_walk_tunables(names: &[&str], model: &RobotModel) -> Result<Vec<Tunable>, String> {
    select_tunables(walk_tunables(model), names, "walk")
}

/// The standing torso height the ranges below are written for (the T1's) [m].
const REFERENCE_HEIGHT_M: f64 = 0.6735;

/// Every walk number the optimiser can search, with ranges for `model`: written for a robot
/// standing [`REFERENCE_HEIGHT_M`] tall, lengths scale with the model's standing height and
/// times and speeds with its square root (a pendulum's: the same gait at the same Froude
/// number), so the NAO (0.385 m) searches steps of 0.15-0.38 s and a 0.29-0.37 m torso.
pub fn walk_tunables(model: &RobotModel) -> Vec<Tunable> {
    let length = model.standing_torso_height / REFERENCE_HEIGHT_M;
    let time = length.sqrt();
    let scaled = |t: Tunable, by: f64| Tunable {
        lo: t.lo * by,
        hi: t.hi * by,
        ..t
    };
    vec![
        scaled(tunable!(step_period_s, 0.2, 0.5, walk.step_period_s), time),
        scaled(
            tunable!(torso_height_m, 0.5, 0.65, walk.torso_height_m),
            length,
        ),
        tunable!(torso_lean_deg, -5.0, 15.0, walk.torso_lean_deg),
        scaled(
            tunable!(foot_x_offset_m, 0.0, 0.12, walk.foot_x_offset_m),
            length,
        ),
        scaled(
            tunable!(foot_y_offset_m, 0.08, 0.14, walk.foot_y_offset_m),
            length,
        ),
        scaled(
            tunable!(step_height_m, 0.01, 0.08, walk.step_height_m),
            length,
        ),
        scaled(tunable!(sway_m, 0.0, 0.06, walk.sway_m), length),
        tunable!(sway_phase_lead, 0.0, 0.4, walk.sway_phase_lead),
        tunable!(arm_swing_deg_per_m, -400.0, 400.0, walk.arm_swing_deg_per_m),
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

/// Cost of falling at the very start, per second of course (progress is counted in seconds
/// of commanded motion, so this is twice a perfect run); a fall at the end costs half of it.
const FALL_PENALTY_PER_S: f64 = 2.0;

/// Where the robot starts each episode: in our half, well away from the ball at the centre,
/// with room for a course's forward legs (SimSpark's field is 30 m long, rcssservermj's 55 m).
fn start_on(server: ServerKind) -> [f64; 3] {
    match server {
        ServerKind::RcssMj => [-18.0, 0.0, 0.0],
        ServerKind::SimSpark => crate::episode::start_point(server),
    }
}

/// Every candidate walks all of these courses; its cost is the sum.
pub struct WalkObjective {
    pub courses: Vec<Course>,
}

impl Objective for WalkObjective {
    fn cost(&self, trial: &mut Trial, params: &SkillParams) -> Result<f64, TrialError> {
        self.courses
            .iter()
            .map(|c| evaluate(trial, params, c))
            .sum()
    }

    fn explain(&self) -> String {
        let seconds: f64 = self.courses.iter().map(Course::duration_s).sum();
        format!(
            "minus seconds of commanded motion achieved over {seconds:.0} s of courses; a fall adds \
             {FALL_PENALTY_PER_S} per course second, half that at the very end"
        )
    }
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
            start: start_on(trial.model().server),
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranges_scale_with_the_robot_lengths_directly_and_times_by_the_root() {
        let range = |model: &str, name: &str| {
            let model = RobotModel::builtin(model).unwrap();
            let t = walk_tunables(&model)
                .into_iter()
                .find(|t| t.name == name)
                .unwrap();
            (t.lo, t.hi)
        };
        assert_eq!(range("T1", "torso_height_m"), (0.5, 0.65));
        let (lo, hi) = range("nao_type0", "torso_height_m");
        let k = 0.385 / REFERENCE_HEIGHT_M;
        assert!((lo - 0.5 * k).abs() < 1e-9 && (hi - 0.65 * k).abs() < 1e-9);
        let (lo, _) = range("nao_type0", "step_period_s");
        assert!((lo - 0.2 * k.sqrt()).abs() < 1e-9, "{lo}");
        // Angles and gains do not scale.
        assert_eq!(range("nao_type0", "torso_lean_deg"), (-5.0, 15.0));
        // Every NAO range lies inside what its parameter file may hold.
        let model = RobotModel::builtin("nao_type0").unwrap();
        let mut params = SkillParams::builtin(&model).unwrap();
        for t in walk_tunables(&model) {
            for v in [t.lo, t.hi] {
                (t.set)(&mut params, v);
                params
                    .validate(&model)
                    .unwrap_or_else(|e| panic!("{} = {v}: {e}", t.name));
            }
            (t.set)(&mut params, (t.lo + t.hi) / 2.0);
        }
    }
}
