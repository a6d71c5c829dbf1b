//! Kick measurements behind `libero bench kick` and the live kick test.
//!
//! Each kick is one episode: the monitor places the robot and the ball, the robot looks for the
//! ball, then a script asks for the kick every cycle (ball and direction in the robot frame,
//! from the agent's own estimates) until the skill reports it done and the ball has stopped.
//! Distance and direction come from the server's ground truth of the ball (monitor scene graph).

use crate::cmaes::Rng;
use crate::episode::{Episode, Trial, TrialError};
use crate::kick_contact::{Contact, ContactTracer};
use libero_skills::kick::KickApproach;
use libero_skills::{BodyIntent, HeadIntent, Intent, KickState, SkillParams};
use libero_world::geometry::wrap_deg;
use libero_world::{Global, Pose, World};
use std::sync::{Arc, Mutex};

/// Where one kick starts and what it asks for.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct KickSetup {
    /// Robot torso x, y [m] and heading [deg], world frame.
    pub robot: [f64; 3],
    /// Ball x, y [m], world frame.
    pub ball: [f64; 2],
    /// Kick direction [deg], world frame.
    pub direction_deg: f64,
    /// Requested distance [m] (chooses the short or the long kick).
    pub distance_m: f64,
}

/// What happened.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct KickOutcome {
    /// The skill reached its kick motion.
    pub kicked: bool,
    /// Seconds from the kick request until the kick motion started.
    pub time_to_kick_s: Option<f64>,
    /// Ball travel from where it lay when the kick motion began to where it stopped [m].
    pub distance_m: f64,
    /// Direction of that travel minus the requested direction [deg].
    pub direction_error_deg: f64,
    /// The ball moved more than a few centimetres before the kick motion began.
    pub bumped: bool,
    pub fell: bool,
    /// Where the foot met the ball (ground truth and measured joint angles).
    pub contact: Option<Contact>,
    /// Direction of the ball's first `LAUNCH_M` of travel minus the requested direction [deg]
    /// (the rest of the difference to `direction_error_deg` is the ball curving as it rolls).
    pub launch_error_deg: Option<f64>,
    /// Where the ball truly lay in the robot's frame (x forward, y left, from the torso
    /// centre) when the kick motion began [m]: how close the approach put it to the kick's
    /// place.
    pub ball_in_robot_at_kick: Option<[f64; 2]>,
    /// The robot's own latest sighting of the ball in its frame then (at most
    /// [`ESTIMATE_FRESH_S`] old): against `ball_in_robot_at_kick`, how well it saw where the
    /// ball lay.
    pub ball_estimate_at_kick: Option<[f64; 2]>,
    /// Where the ball first lay the requested distance from where it was kicked: its offset
    /// from the requested line there [m], left positive; `None` when it stopped short. A shot
    /// is judged where it crosses the goal line and a pass where it meets its receiver; a long
    /// kick curves on beyond them, so its rest point's direction (`direction_error_deg`) says
    /// little of a shot from nearer than it rolls.
    pub miss_at_distance_m: Option<f64>,
}

/// The offset [m] of `point` from the line through `from` in the field direction
/// `direction_deg`, left of it positive: its sideways coordinate as seen from `from` facing
/// along the line.
pub fn offset_from_line(from: [f64; 2], direction_deg: f64, point: [f64; 2]) -> f64 {
    Pose::new(Global::new(from[0], from[1]), direction_deg)
        .robot(Global::new(point[0], point[1]))
        .y
}

/// Keep in `first` the first ball position more than `beyond_m` from where it lay at the
/// kick (`at_kick`).
fn note_first_beyond(
    first: &mut Option<[f64; 3]>,
    at_kick: Option<[f64; 3]>,
    ball: Option<[f64; 3]>,
    beyond_m: f64,
) {
    if let (None, Some(at), Some(b)) = (*first, at_kick, ball) {
        if (b[0] - at[0]).hypot(b[1] - at[1]) >= beyond_m {
            *first = Some(b);
        }
    }
}

/// A sighting older than this at the kick's start is not the robot's estimate then [s] (vision
/// comes every third cycle).
const ESTIMATE_FRESH_S: f64 = 0.1;

/// Seconds standing after placement, head panning, so the ball is seen and localization settles.
const LOOK_S: f64 = 1.5;
/// A ball that has not moved by more than the monitor's 5 mm resolution for this long is at rest.
const BALL_STILL_S: f64 = 1.0;
/// Ball movement before the kick that counts as bumping it [m].
const BUMP_M: f64 = 0.05;
/// The ball's launch direction is taken over this much travel [m].
const LAUNCH_M: f64 = 0.5;
/// Ball placement height (its radius: resting on the ground) [m].
/// Turning rate while searching for a ball not yet seen [deg/s].
const SEARCH_TURN_DEG_S: f64 = 40.0;
/// A ball unseen this long is searched for again [s] (the default `lost_after` of `KickTo`).
const LOST_AFTER_S: f64 = 4.0;

/// The field directions seeded kicks go in.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum KickDirections {
    /// Any direction.
    AllRound,
    /// Within [`SHOT_HALF_WIDTH_DEG`] of the +x axis, as shots at their goal go. The ball's
    /// roll curves by its direction to the field's axes, so a kick straight all round can be
    /// crooked there (session 40: a 16 m kick 0.39 m off the line 10 m out all round crossed
    /// the goal line 1-2 m outside its target in striker_alone).
    Shots,
}

/// Shots at their goal from 8-14 m out leave within this angle of the field's x axis [deg].
pub const SHOT_HALF_WIDTH_DEG: f64 = 25.0;

/// A seeded kick direction [deg] and ball spot [m]: 4 m back from the centre along the kick
/// (so 12 m kicks stay on the field), give or take 3 m along x and 2 m along y.
fn kick_spot(rng: &mut Rng, directions: KickDirections) -> (f64, [f64; 2]) {
    let direction_deg = match directions {
        KickDirections::AllRound => 360.0 * rng.uniform() - 180.0,
        KickDirections::Shots => SHOT_HALF_WIDTH_DEG * (2.0 * rng.uniform() - 1.0),
    };
    let d = direction_deg.to_radians();
    let ball = [
        -4.0 * d.cos() + 6.0 * rng.uniform() - 3.0,
        -4.0 * d.sin() + 4.0 * rng.uniform() - 2.0,
    ];
    (direction_deg, ball)
}

/// `count` kicks from all round the ball, seeded: ball spots, robot places and headings, and
/// kick directions vary; each kick stays well inside the field.
pub fn setups(
    count: usize,
    seed: u64,
    distance_m: f64,
    directions: KickDirections,
) -> Vec<KickSetup> {
    let mut rng = Rng::new(seed);
    (0..count)
        .map(|_| {
            let (direction_deg, ball) = kick_spot(&mut rng, directions);
            let bearing = std::f64::consts::TAU * rng.uniform();
            let range = 1.0 + 1.5 * rng.uniform();
            let robot = [
                ball[0] + range * bearing.cos(),
                ball[1] + range * bearing.sin(),
                360.0 * rng.uniform() - 180.0,
            ];
            KickSetup {
                robot,
                ball,
                direction_deg,
                distance_m,
            }
        })
        .collect()
}

/// `count` kicks that start at the kicking place, as an approach would end: the robot stands
/// near it within the approach's tolerances (`ready_along_m`, `ready_across_m`, `ready_deg`,
/// seeded), either foot, any field direction. Quick to run (no walking), so the kick motion
/// itself can be measured and optimised.
pub fn setups_at_place(
    count: usize,
    seed: u64,
    distance_m: f64,
    approach: &KickApproach,
    directions: KickDirections,
) -> Vec<KickSetup> {
    let mut rng = Rng::new(seed);
    (0..count)
        .map(|k| {
            let (direction_deg, ball) = kick_spot(&mut rng, directions);
            let side = if k % 2 == 0 { 1.0 } else { -1.0 };
            let mut off = |tolerance: f64| tolerance * (2.0 * rng.uniform() - 1.0);
            let along = approach.ball_ahead_m + off(approach.ready_along_m);
            let across = side * approach.ball_beside_m + off(approach.ready_across_m);
            let heading = direction_deg + off(approach.ready_deg);
            let h = heading.to_radians();
            // The ball sits `along` ahead and `across` to the side of the torso.
            let robot = [
                ball[0] - along * h.cos() + across * h.sin(),
                ball[1] - along * h.sin() - across * h.cos(),
                heading,
            ];
            KickSetup {
                robot,
                ball,
                direction_deg,
                distance_m,
            }
        })
        .collect()
}

/// Script progress, shared with the measuring side.
#[derive(Debug, Clone, Copy, Default)]
struct Progress {
    ball_start: Option<[f64; 3]>,
    kick_started_at: Option<f64>,
    ball_at_kick: Option<[f64; 3]>,
    ball_in_robot_at_kick: Option<[f64; 2]>,
    ball_estimate_at_kick: Option<[f64; 2]>,
    done_at: Option<f64>,
    ball_end: Option<[f64; 3]>,
    fell: bool,
    contact: Option<Contact>,
    launch: Option<[f64; 3]>,
    /// The ball where it first lay the requested distance from where it was kicked.
    crossing: Option<[f64; 3]>,
    /// For a kick that is not made: whether the ball was ever seen, the last kick state and
    /// where the robot was.
    ball_seen: bool,
    last_state: Option<KickState>,
    last_torso: Option<[f64; 3]>,
}

/// One kick, giving up `limit_s` after the request.
pub fn kick_once(
    trial: &mut Trial,
    params: &SkillParams,
    setup: KickSetup,
    limit_s: f64,
) -> Result<KickOutcome, TrialError> {
    let monitor = trial.monitor();
    let status = trial.skill_status();
    let progress = Arc::new(Mutex::new(Progress::default()));
    let shared = Arc::clone(&progress);
    let ball_z_m = trial.ball_rest_z_m();
    let fallen_below_m = trial.fallen_below_m();
    let place_ball = trial.ball_placement(setup.ball);
    let mut placed_at: Option<f64> = None;
    // Server time of the last placement command: sightings before it show the old spot.
    let mut placed_world_time = f64::INFINITY;
    let mut last_ball: Option<([f64; 3], f64)> = None;
    let mut tracer = ContactTracer::new(trial.model(), params.kick.toe_ahead_of_ankle_m);
    let script = move |world: &World, t: f64| -> Option<Intent> {
        let truth_ball = monitor.lock().ok().and_then(|m| m.snapshot().ball);
        let mut p = shared.lock().ok()?;
        let look = Intent {
            head: HeadIntent::LookAround {
                amplitude_deg: None,
                period_s: None,
            },
            ..Default::default()
        };
        // Place the ball (again, if the server ignored the first command).
        let at_place = truth_ball.is_some_and(|b| {
            (b[0] - setup.ball[0]).hypot(b[1] - setup.ball[1]) < 0.05 && b[2] < ball_z_m + 0.02
        });
        if placed_at.is_none_or(|at| !at_place && p.ball_start.is_none() && t - at > 0.5) {
            if let Ok(mut m) = monitor.lock() {
                if let Err(e) = m.send(&place_ball) {
                    log::error!("kick bench: cannot place the ball: {e}");
                    return None;
                }
            }
            placed_at = Some(t);
            placed_world_time = world.time;
            return Some(look);
        }
        if t < LOOK_S || (p.ball_start.is_none() && !at_place) {
            if t >= LOOK_S + 5.0 {
                log::warn!(
                    "kick bench: the ball is not where it was placed ({:?} instead of {:?}); giving up",
                    truth_ball,
                    setup.ball
                );
            }
            return (t < LOOK_S + 5.0).then_some(look);
        }
        if p.ball_start.is_none() {
            p.ball_start = truth_ball;
        }
        log::trace!(
            "t {t:6.2} kick {:?} torso {:?} roll {:.1} pitch {:.1} gyro {:.0} {:.0} ball {:?} ball est {:?} me {:?} {:.1} legs {:?}",
            status.lock().map(|s| s.kick).ok(),
            world.truth.torso_position,
            world.me.roll_deg,
            world.me.pitch_deg,
            world.body.gyro[0],
            world.body.gyro[1],
            truth_ball,
            world.ball.position,
            world.me.position,
            world.me.yaw_deg,
            world.body.joint_angles[11..].iter().map(|a| a.round()).collect::<Vec<_>>()
        );
        // The swing's jolt can fool the fall detector for a moment: a fall is the torso down.
        if world
            .truth
            .torso_position
            .is_some_and(|pos| pos[2] < fallen_below_m)
        {
            p.fell = true;
            return None;
        }
        let since_request = t - LOOK_S;
        let kick = status.lock().map(|s| s.kick).unwrap_or(KickState::Idle);
        p.last_state = Some(kick);
        p.last_torso = world.truth.torso_position;
        if kick == KickState::Kicking && p.kick_started_at.is_none() {
            p.kick_started_at = Some(since_request);
            p.ball_at_kick = truth_ball;
            p.ball_estimate_at_kick = world
                .ball_seen_relative
                .filter(|(seen_at, _)| world.time - seen_at <= ESTIMATE_FRESH_S)
                .map(|(_, b)| b);
            p.ball_in_robot_at_kick =
                truth_ball
                    .zip(world.truth_pose())
                    .map(|(b, ([x, y, _], yaw_deg))| {
                        Pose::new(Global::new(x, y), yaw_deg)
                            .robot(Global::new(b[0], b[1]))
                            .to_array()
                    });
        }
        if kick == KickState::Kicking || (kick == KickState::Done && p.contact.is_none()) {
            if let Some(tracer) = tracer.as_mut() {
                tracer.observe(world, truth_ball);
                p.contact = tracer.contact();
            }
        }
        let at_kick = p.ball_at_kick;
        note_first_beyond(&mut p.launch, at_kick, truth_ball, LAUNCH_M);
        note_first_beyond(&mut p.crossing, at_kick, truth_ball, setup.distance_m);
        if kick == KickState::Done && p.done_at.is_none() {
            p.done_at = Some(t);
        }
        if let Some(done) = p.done_at {
            // Wait for the ball to come to rest.
            if let Some(b) = truth_ball {
                match last_ball {
                    Some((before, since)) if (b[0] - before[0]).hypot(b[1] - before[1]) < 0.005 => {
                        if t - since >= BALL_STILL_S {
                            p.ball_end = Some(b);
                            return None;
                        }
                    }
                    _ => last_ball = Some((b, t)),
                }
            }
            if t - done > 15.0 {
                p.ball_end = truth_ball;
                return None;
            }
        } else if since_request > limit_s {
            return None;
        }
        // Seen since it was placed (allowing for the command's two-cycle delay)?
        let seen = world
            .ball
            .last_seen_time
            .is_some_and(|at| at > placed_world_time + 0.1);
        p.ball_seen |= seen;
        // Unseen for long, as a behavior tree's `KickTo` gives up (its `lost_after`): the
        // estimate alone may have drifted off (a chase after a phantom ball was seen).
        let lost = world
            .ball
            .last_seen_time
            .is_none_or(|at| world.time - at > LOST_AFTER_S);
        let approaching = matches!(kick, KickState::Idle | KickState::Approaching);
        if !seen || (lost && approaching) {
            // Not seen (lately): turn on the spot, head panning, until it is.
            return Some(Intent {
                body: BodyIntent::Walk {
                    forward_m_s: 0.0,
                    sideways_m_s: 0.0,
                    turn_deg_s: SEARCH_TURN_DEG_S,
                },
                ..look
            });
        }
        Some(Intent {
            body: BodyIntent::Kick {
                ball: world.ball_relative(libero_world::FRESH_BALL_SIGHTING_S),
                direction_deg: wrap_deg(setup.direction_deg - world.me.yaw_deg),
                distance_m: setup.distance_m,
            },
            ..Default::default()
        })
    };
    let rec = trial.run(
        params,
        Episode {
            start: setup.robot,
            lying: None,
            settle_s: 0.5,
            script,
        },
    )?;
    let p = *progress.lock().map_err(|_| TrialError::Empty)?;
    if p.kick_started_at.is_none() {
        log::info!(
            "kick bench: no kick: ball seen {}, last kick state {:?}, torso at {:?}, fell {}",
            p.ball_seen,
            p.last_state,
            p.last_torso,
            p.fell
        );
    }
    let mut outcome = KickOutcome {
        kicked: p.kick_started_at.is_some(),
        time_to_kick_s: p.kick_started_at,
        fell: p.fell || rec.samples.iter().any(|s| s.low),
        contact: p.contact,
        ball_in_robot_at_kick: p.ball_in_robot_at_kick,
        ball_estimate_at_kick: p.ball_estimate_at_kick,
        launch_error_deg: p.ball_at_kick.zip(p.launch).map(|(a, b)| {
            wrap_deg((b[1] - a[1]).atan2(b[0] - a[0]).to_degrees() - setup.direction_deg)
        }),
        miss_at_distance_m: p
            .ball_at_kick
            .zip(p.crossing)
            .map(|(at, b)| offset_from_line([at[0], at[1]], setup.direction_deg, [b[0], b[1]])),
        ..Default::default()
    };
    if let (Some(start), Some(at_kick)) = (p.ball_start, p.ball_at_kick) {
        outcome.bumped = (at_kick[0] - start[0]).hypot(at_kick[1] - start[1]) > BUMP_M;
    }
    // A bump during the approach moves the ball; the kick is measured from where it lay when
    // the kick motion began (bumps are counted separately).
    if let (Some(start), Some(end)) = (p.ball_at_kick.or(p.ball_start), p.ball_end) {
        let (dx, dy) = (end[0] - start[0], end[1] - start[1]);
        outcome.distance_m = dx.hypot(dy);
        outcome.direction_error_deg = wrap_deg(dy.atan2(dx).to_degrees() - setup.direction_deg);
    }
    Ok(outcome)
}

/// Figures over several kicks.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct KickSummary {
    pub kicks: usize,
    /// Kicks where the kick motion ran.
    pub kicked: usize,
    pub mean_distance_m: f64,
    pub min_distance_m: f64,
    pub mean_abs_direction_error_deg: f64,
    pub max_abs_direction_error_deg: f64,
    pub falls: usize,
    pub bumps: usize,
    pub mean_time_to_kick_s: f64,
    /// Kicks that rolled the requested distance, and their mean |offset| from the requested
    /// line there [m] ([`KickOutcome::miss_at_distance_m`]).
    pub reached_distance: usize,
    pub mean_abs_miss_m: f64,
}

impl KickSummary {
    /// Means over every setup: a kick that never happened counts as 0 m and 180° off.
    pub fn of(outcomes: &[KickOutcome]) -> Self {
        let n = outcomes.len().max(1) as f64;
        let error = |o: &KickOutcome| {
            if o.kicked {
                o.direction_error_deg.abs()
            } else {
                180.0
            }
        };
        let times: Vec<f64> = outcomes.iter().filter_map(|o| o.time_to_kick_s).collect();
        let misses: Vec<f64> = outcomes
            .iter()
            .filter_map(|o| o.miss_at_distance_m.map(f64::abs))
            .collect();
        Self {
            kicks: outcomes.len(),
            kicked: outcomes.iter().filter(|o| o.kicked).count(),
            mean_distance_m: outcomes.iter().map(|o| o.distance_m).sum::<f64>() / n,
            min_distance_m: outcomes
                .iter()
                .map(|o| o.distance_m)
                .fold(f64::INFINITY, f64::min),
            mean_abs_direction_error_deg: outcomes.iter().map(error).sum::<f64>() / n,
            max_abs_direction_error_deg: outcomes.iter().map(error).fold(0.0, f64::max),
            falls: outcomes.iter().filter(|o| o.fell).count(),
            bumps: outcomes.iter().filter(|o| o.bumped).count(),
            mean_time_to_kick_s: times.iter().sum::<f64>() / times.len().max(1) as f64,
            reached_distance: misses.len(),
            mean_abs_miss_m: misses.iter().sum::<f64>() / misses.len().max(1) as f64,
        }
    }
}

/// Time allowed from the request to the kick motion [s].
pub const KICK_LIMIT_S: f64 = 40.0;

/// `count` seeded kicks asking for `distance_m`; each outcome is also logged.
pub fn kicks(
    trial: &mut Trial,
    params: &SkillParams,
    count: usize,
    seed: u64,
    distance_m: f64,
) -> Result<(Vec<KickOutcome>, KickSummary), TrialError> {
    let mut outcomes = Vec::with_capacity(count);
    for (i, setup) in setups(count, seed, distance_m, KickDirections::AllRound)
        .into_iter()
        .enumerate()
    {
        let o = kick_once(trial, params, setup, KICK_LIMIT_S)?;
        log::info!(
            "kick {i:2}: robot ({:6.2}, {:6.2}, {:6.1}°) ball ({:6.2}, {:6.2}) towards {:6.1}°: \
             {:5.2} m, error {:+6.1}°, kicked {}, after {:.1} s, bumped {}, fell {}, ball in the \
             robot frame at the kick {:?} (its estimate {:?})",
            setup.robot[0],
            setup.robot[1],
            setup.robot[2],
            setup.ball[0],
            setup.ball[1],
            setup.direction_deg,
            o.distance_m,
            o.direction_error_deg,
            o.kicked,
            o.time_to_kick_s.unwrap_or(f64::NAN),
            o.bumped,
            o.fell,
            o.ball_in_robot_at_kick
                .map(|[x, y]| format!("({x:.4}, {y:.4})"))
                .unwrap_or_default(),
            o.ball_estimate_at_kick
                .map(|[x, y]| format!("({x:.4}, {y:.4})"))
                .unwrap_or_default()
        );
        outcomes.push(o);
    }
    let summary = KickSummary::of(&outcomes);
    Ok((outcomes, summary))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shot_setups_go_towards_their_goal_and_all_round_ones_anywhere() {
        let approach = SkillParams::builtin(&libero_model::RobotModel::builtin("T1").unwrap())
            .unwrap()
            .kick
            .approach;
        let shots = setups(40, 3, 10.0, KickDirections::Shots);
        let at_place = setups_at_place(40, 3, 10.0, &approach, KickDirections::Shots);
        for s in shots.iter().chain(&at_place) {
            assert!(s.direction_deg.abs() <= SHOT_HALF_WIDTH_DEG, "{s:?}");
        }
        let round = setups(40, 3, 10.0, KickDirections::AllRound);
        assert!(round.iter().any(|s| s.direction_deg.abs() > 90.0));
    }

    #[test]
    fn a_point_left_of_the_asked_line_is_off_it_by_a_positive_distance() {
        // Along +x from (1, 1): a point 2 m on and 0.5 m to the left.
        assert!((offset_from_line([1.0, 1.0], 0.0, [3.0, 1.5]) - 0.5).abs() < 1e-12);
        // Towards -y (-90°): "left" is +x.
        assert!((offset_from_line([0.0, 0.0], -90.0, [0.3, -4.0]) - 0.3).abs() < 1e-12);
        // Along the diagonal, a point on it is on the line.
        assert!(offset_from_line([-2.0, 1.0], 45.0, [1.0, 4.0]).abs() < 1e-12);
        // Right of a line towards 180°: a point at larger y.
        assert!(offset_from_line([0.0, 0.0], 180.0, [-3.0, 1.0]) < 0.0);
    }
}
