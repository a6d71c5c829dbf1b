//! The dribble's kick step on the real server: a robot standing behind a ball dribbles it along
//! a field direction with kick steps allowed; the ground truth says when the first kick step
//! began, where the ball was then (in the robot's frame), how far and in which direction it
//! rolled, and whether the robot fell.

use crate::episode::{Episode, Trial, TrialError};
use libero_skills::{BodyIntent, HeadIntent, Intent, SkillParams};
use libero_world::geometry::wrap_deg;
use libero_world::World;
use std::sync::{Arc, Mutex};

/// Where the robot starts and where the ball lies (world frame), and the dribble's direction.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct KickStepSetup {
    /// x, y [m], heading [deg].
    pub robot: [f64; 3],
    pub ball: [f64; 2],
    pub direction_deg: f64,
}

/// What the ground truth shows of one dribble with kick steps.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct KickStepOutcome {
    /// Kick steps begun.
    pub kick_steps: u32,
    /// Seconds from the dribble's start to the first kick step.
    pub first_after_s: Option<f64>,
    /// The ball in the robot's frame (x ahead, y left) [m] when the first kick step began.
    pub ball_in_robot: Option<[f64; 2]>,
    /// How far the ball went in the `ROLL_S` after the first kick step began [m] ...
    pub roll_m: f64,
    /// ... and its direction against the dribble's [deg].
    pub direction_error_deg: f64,
    pub fell: bool,
}

/// Seconds after a kick step's start over which its roll is measured: a 7 m roll is over.
pub const ROLL_S: f64 = 2.5;
/// Looking at the ball before the dribble starts [s].
const LOOK_S: f64 = 1.0;

#[derive(Default)]
struct Progress {
    steps: u32,
    first: Option<(f64, [f64; 2], Option<[f64; 2]>)>,
    ball_after: Option<[f64; 2]>,
    fell: bool,
}

/// One dribble from `setup`: `limit_s` seconds for the first kick step, then `ROLL_S` for
/// its roll.
pub fn kick_step_once(
    trial: &mut Trial,
    params: &SkillParams,
    setup: KickStepSetup,
    limit_s: f64,
) -> Result<KickStepOutcome, TrialError> {
    let monitor = trial.monitor();
    let status = trial.skill_status();
    let progress = Arc::new(Mutex::new(Progress::default()));
    let shared = Arc::clone(&progress);
    let fallen_below_m = trial.fallen_below_m();
    let place_ball = trial.ball_placement(setup.ball);
    let mut placed = false;
    let script = move |world: &World, t: f64| -> Option<Intent> {
        let truth = monitor.lock().ok().and_then(|m| m.snapshot().ball);
        let mut p = shared.lock().ok()?;
        if !placed {
            placed = true;
            if let Ok(mut m) = monitor.lock() {
                if let Err(e) = m.send(&place_ball) {
                    log::error!("kick step bench: cannot place the ball: {e}");
                    return None;
                }
            }
        }
        if world
            .truth
            .torso_position
            .is_some_and(|pos| pos[2] < fallen_below_m)
        {
            p.fell = true;
            return None;
        }
        if t < LOOK_S {
            return Some(Intent {
                head: HeadIntent::LookAt { target: [1.0, 0.0] },
                ..Default::default()
            });
        }
        let steps = status.lock().map(|s| s.kick_steps).unwrap_or(0);
        if steps > p.steps && p.first.is_none() {
            let relative = truth.zip(world.truth_pose()).map(|(b, ([x, y, _], yaw))| {
                let (c, s) = (yaw.to_radians().cos(), yaw.to_radians().sin());
                let (dx, dy) = (b[0] - x, b[1] - y);
                [c * dx + s * dy, -s * dx + c * dy]
            });
            p.first = truth.map(|b| (t, [b[0], b[1]], relative));
        }
        p.steps = steps;
        if let Some((at, _, _)) = p.first {
            if t - at >= ROLL_S {
                p.ball_after = truth.map(|b| [b[0], b[1]]);
                return None;
            }
        }
        if p.first.is_none() && t > LOOK_S + limit_s {
            return None;
        }
        Some(Intent {
            body: BodyIntent::Dribble {
                ball: world.ball_relative(libero_world::FRESH_BALL_SIGHTING_S),
                direction_deg: wrap_deg(setup.direction_deg - world.me.yaw_deg),
                kick_steps: true,
            },
            ..Default::default()
        })
    };
    trial.run(
        params,
        Episode {
            start: setup.robot,
            lying: None,
            settle_s: 0.5,
            script,
        },
    )?;
    let p = progress.lock().map_err(|_| TrialError::Empty)?;
    let mut outcome = KickStepOutcome {
        kick_steps: p.steps,
        fell: p.fell,
        ..Default::default()
    };
    if let Some((at, from, relative)) = p.first {
        outcome.first_after_s = Some(at - LOOK_S);
        outcome.ball_in_robot = relative;
        if let Some(to) = p.ball_after {
            let (dx, dy) = (to[0] - from[0], to[1] - from[1]);
            outcome.roll_m = dx.hypot(dy);
            outcome.direction_error_deg = wrap_deg(dy.atan2(dx).to_degrees() - setup.direction_deg);
        }
    }
    Ok(outcome)
}

/// `count` setups along +x: the robot 0.6-1.4 m behind the ball and up to 0.15 m to either
/// side of its line, one row per setup.
pub fn setups(count: usize, seed: u64) -> Vec<KickStepSetup> {
    let mut rng = crate::cmaes::Rng::new(seed);
    (0..count)
        .map(|i| {
            let y = -3.0 + 0.5 * i as f64;
            let behind = 0.6 + 0.8 * rng.uniform();
            let side = 0.3 * rng.uniform() - 0.15;
            KickStepSetup {
                robot: [-6.0, y, 0.0],
                ball: [-6.0 + behind, y + side],
                direction_deg: 0.0,
            }
        })
        .collect()
}

/// Figures over several dribbles with kick steps.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct KickStepSummary {
    pub dribbles: usize,
    /// Dribbles in which a kick step was made.
    pub kicked: usize,
    /// Over those: the first kick step's roll, its direction error and the time to it.
    pub mean_roll_m: f64,
    pub min_roll_m: f64,
    pub mean_abs_direction_error_deg: f64,
    pub max_abs_direction_error_deg: f64,
    pub mean_time_to_kick_s: f64,
    pub falls: usize,
}

impl KickStepSummary {
    pub fn of(outcomes: &[KickStepOutcome]) -> Self {
        let kicked: Vec<_> = outcomes
            .iter()
            .filter(|o| o.first_after_s.is_some())
            .collect();
        let n = kicked.len().max(1) as f64;
        let mean =
            |f: &dyn Fn(&KickStepOutcome) -> f64| kicked.iter().map(|o| f(o)).sum::<f64>() / n;
        Self {
            dribbles: outcomes.len(),
            kicked: kicked.len(),
            mean_roll_m: mean(&|o| o.roll_m),
            min_roll_m: kicked
                .iter()
                .map(|o| o.roll_m)
                .fold(f64::INFINITY, f64::min),
            mean_abs_direction_error_deg: mean(&|o| o.direction_error_deg.abs()),
            max_abs_direction_error_deg: kicked
                .iter()
                .map(|o| o.direction_error_deg.abs())
                .fold(0.0, f64::max),
            mean_time_to_kick_s: mean(&|o| o.first_after_s.unwrap_or(0.0)),
            falls: outcomes.iter().filter(|o| o.fell).count(),
        }
    }
}

/// Seconds a bench dribble may take to its first kick step.
pub const KICK_STEP_LIMIT_S: f64 = 10.0;

/// `count` dribbles from [`setups`]; each outcome and the summary.
pub fn dribbles(
    trial: &mut Trial,
    params: &SkillParams,
    count: usize,
    seed: u64,
) -> Result<(Vec<KickStepOutcome>, KickStepSummary), TrialError> {
    let mut outcomes = Vec::with_capacity(count);
    for setup in setups(count, seed) {
        let o = kick_step_once(trial, params, setup, KICK_STEP_LIMIT_S)?;
        log::info!("kick step bench: {setup:?}: {o:?}");
        outcomes.push(o);
    }
    let summary = KickStepSummary::of(&outcomes);
    Ok((outcomes, summary))
}
