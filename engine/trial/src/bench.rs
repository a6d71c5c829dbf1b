//! The locomotion measurements behind `libero bench walk` and the live tests.

use crate::course::Course;
use crate::episode::{start_point, Episode, Recording, Trial, TrialError};
use crate::measure::{localization_error, mean_velocity, LocalizationError};
use libero_skills::{BodyIntent, Intent, SkillParams};

/// Seconds at the start of a measurement that are left out (the walk accelerating).
pub const RAMP_S: f64 = 2.0;

/// One measured figure.
#[derive(Debug, Clone, PartialEq)]
pub struct Figure {
    /// Mean speed after the ramp, along the measured axis [m/s or deg/s].
    pub speed: f64,
    /// Seconds measured (after the ramp).
    pub seconds: f64,
    /// Distance along the axis over the measured time [m or deg].
    pub distance: f64,
    /// Seconds until the first fall, if any.
    pub fell_at: Option<f64>,
    /// The agent's own localization over the whole walk, against the ground truth.
    pub localization: Option<LocalizationError>,
}

/// `stopped_early`: the script ended before its time and goal, which it only does when the
/// agent's fall detector fired (that cycle is not recorded, so the samples may not show it).
fn figure(rec: &Recording, axis: usize, stopped_early: bool) -> Figure {
    let end = rec.samples.last().map_or(0.0, |s| s.t);
    let v = mean_velocity(rec, RAMP_S, end).unwrap_or([0.0; 3]);
    let seconds = (end - RAMP_S).max(0.0);
    Figure {
        speed: v[axis],
        seconds,
        distance: v[axis] * seconds,
        fell_at: rec.first_fall_s().or(stopped_early.then_some(end)),
        localization: localization_error(rec),
    }
}

/// Sample spacing [s]: a recording ending more than this before its time limit stopped early.
const CYCLE_S: f64 = 0.02;

/// Walk with one command until `until` says stop (or a fall).
fn walk(
    trial: &mut Trial,
    params: &SkillParams,
    command: [f64; 3],
    max_s: f64,
    until_forward_m: Option<f64>,
) -> Result<(Recording, bool), TrialError> {
    // In our half, facing +x, clear of the ball at the centre.
    let start = start_point(trial.model().server);
    let script = move |world: &libero_world::World, t: f64| {
        let fallen = world.body.posture != libero_world::Posture::Upright;
        let far = match (until_forward_m, world.truth.torso_position) {
            (Some(d), Some(p)) => p[0] - start[0] >= d,
            _ => false,
        };
        (t < max_s && !fallen && !far).then_some(Intent {
            body: BodyIntent::Walk {
                forward_m_s: command[0],
                sideways_m_s: command[1],
                turn_deg_s: command[2],
            },
            ..Default::default()
        })
    };
    let rec = trial.run(
        params,
        Episode {
            start,
            lying: None,
            settle_s: 1.0,
            script,
        },
    )?;
    let last = rec.samples.last();
    let out_of_time = last.is_some_and(|s| s.t >= max_s - 2.0 * CYCLE_S);
    let arrived = match (until_forward_m, last) {
        // The last recorded sample is one cycle short of the goal at most.
        (Some(d), Some(s)) => s.position[0] - start[0] >= d - 0.05,
        _ => false,
    };
    let stopped_early = !out_of_time && !arrived;
    Ok((rec, stopped_early))
}

/// Full-speed forward walk over `distance_m` (measured from the start, speed from after the
/// ramp), giving up after `max_s`.
pub fn forward(
    trial: &mut Trial,
    params: &SkillParams,
    distance_m: f64,
    max_s: f64,
) -> Result<Figure, TrialError> {
    let (rec, early) = walk(
        trial,
        params,
        [params.walk.max_forward_m_s, 0.0, 0.0],
        max_s,
        Some(distance_m),
    )?;
    Ok(figure(&rec, 0, early))
}

/// Full-speed sideways walk to the left.
pub fn sideways(
    trial: &mut Trial,
    params: &SkillParams,
    seconds: f64,
) -> Result<Figure, TrialError> {
    let (rec, early) = walk(
        trial,
        params,
        [0.0, params.walk.max_sideways_m_s, 0.0],
        seconds,
        None,
    )?;
    Ok(figure(&rec, 1, early))
}

/// Full-rate turn on the spot (counter-clockwise).
pub fn turning(
    trial: &mut Trial,
    params: &SkillParams,
    seconds: f64,
) -> Result<Figure, TrialError> {
    let (rec, early) = walk(
        trial,
        params,
        [0.0, 0.0, params.walk.max_turn_deg_s],
        seconds,
        None,
    )?;
    Ok(figure(&rec, 2, early))
}

/// How a random course went.
#[derive(Debug, Clone, PartialEq)]
pub struct CourseFigure {
    /// Seconds walked (the walk does not continue after a fall).
    pub walked_s: f64,
    /// Seconds until the first fall, if any.
    pub fell_at: Option<f64>,
    pub localization: Option<LocalizationError>,
}

/// A course of random commands changing every 2–5 s.
pub fn random_course(
    trial: &mut Trial,
    params: &SkillParams,
    seconds: f64,
    seed: u64,
) -> Result<CourseFigure, TrialError> {
    let w = &params.walk;
    let course = Course::random(
        seconds,
        [w.max_forward_m_s, w.max_sideways_m_s, w.max_turn_deg_s],
        seed,
    );
    let rec = trial.run(
        params,
        Episode {
            start: [-5.0, 0.0, 0.0],
            lying: None,
            settle_s: 1.0,
            script: course.script(),
        },
    )?;
    let walked = rec.samples.last().map_or(0.0, |s| s.t);
    let fell_at = rec
        .first_fall_s()
        .or((walked < seconds - 0.1).then_some(walked));
    Ok(CourseFigure {
        walked_s: walked,
        fell_at,
        localization: localization_error(&rec),
    })
}
