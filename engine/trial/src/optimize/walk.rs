//! The walk objective: each candidate walks every one of a few [`Course`]s (several courses,
//! so it cannot fit one sequence of commands); its cost is minus the progress made the
//! commanded way, plus a heavy penalty for falling (the earlier, the heavier).

use super::{select_tunables, tunable, Objective, Tunable};
use crate::course::{progress, Course};
use crate::episode::{Episode, Trial, TrialError};
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

/// The walk tunables with these names, in the order given; an unknown name is an error that
/// lists the known ones.
pub fn select_walk_tunables(names: &[&str]) -> Result<Vec<Tunable>, String> {
    select_tunables(walk_tunables(), names, "walk")
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

/// Cost of falling at the very start, per second of course (progress is counted in seconds
/// of commanded motion, so this is twice a perfect run); a fall at the end costs half of it.
const FALL_PENALTY_PER_S: f64 = 2.0;

/// Where the robot starts each episode (in our half, well away from the ball at the centre,
/// with room for a course's forward legs).
const START: [f64; 3] = [-18.0, 0.0, 0.0];

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
