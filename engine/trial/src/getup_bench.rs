//! The get-up measurements behind `libero bench getup` and the live tests: the robot is
//! placed lying, its own fall detector starts the get-up, and the ground truth shows whether
//! and when it stood.

use crate::cmaes::Rng;
use crate::episode::{Episode, LyingPlacement, Recording, Sample, Trial, TrialError};
use libero_skills::getup::Lying;
use libero_skills::{BodyIntent, Intent, SkillParams};
use libero_world::World;

/// Where and how a lying robot is placed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Placement {
    pub lying: LyingPlacement,
    /// World x, y [m] and heading [deg] of the torso before it is tipped over.
    pub start: [f64; 3],
}

/// Standing: the torso high (`Sample::tall`) with its long axis at most this far from the
/// vertical [deg].
pub const STANDING_TILT_DEG: f64 = 20.0;
/// Standing must last this long to count [s].
pub const STANDING_HOLD_S: f64 = 1.5;
/// A get-up must stand within this time of the placement to count [s].
pub const GET_UP_LIMIT_S: f64 = 5.0;

/// Largest roll about the long axis at placement [deg].
const MAX_ROLL_DEG: f64 = 18.0;
/// Placement area: our half, clear of the centre circle, the goal and the lines' ends [m].
const X_RANGE_M: (f64, f64) = (-13.0, -4.0);
const Y_RANGE_M: (f64, f64) = (-6.0, 6.0);

/// `n` placements lying on `side`: headings spread evenly over the full turn (with a random
/// offset), rolls up to ±18° and positions drawn from `seed`. Sync mode is deterministic, so
/// repeating one placement would measure one run `n` times.
pub fn varied_placements(side: Lying, n: usize, seed: u64) -> Vec<Placement> {
    let mut rng = Rng::new(seed);
    let offset = rng.uniform() * 360.0;
    let between = |rng: &mut Rng, (lo, hi): (f64, f64)| lo + (hi - lo) * rng.uniform();
    (0..n)
        .map(|k| {
            let heading = (offset + 360.0 * k as f64 / n as f64) % 360.0 - 180.0;
            Placement {
                lying: LyingPlacement {
                    side,
                    roll_deg: between(&mut rng, (-MAX_ROLL_DEG, MAX_ROLL_DEG)),
                },
                start: [
                    between(&mut rng, X_RANGE_M),
                    between(&mut rng, Y_RANGE_M),
                    heading,
                ],
            }
        })
        .collect()
}

/// Whether a sample shows the robot standing: torso high and upright.
pub fn standing(s: &Sample) -> bool {
    s.tall && s.tilt_deg <= STANDING_TILT_DEG
}

/// When the robot first stood and then kept standing for `hold_s` (the recording must cover
/// the hold).
pub fn stood_up_at(rec: &Recording, hold_s: f64) -> Option<f64> {
    let mut since: Option<f64> = None;
    for s in &rec.samples {
        if standing(s) {
            let start = *since.get_or_insert(s.t);
            if s.t - start >= hold_s {
                return Some(start);
            }
        } else {
            since = None;
        }
    }
    None
}

/// One get-up.
#[derive(Debug, Clone)]
pub struct GetUpRun {
    pub placement: Placement,
    /// Seconds from the placement until the robot stood for good (see [`stood_up_at`]), if it
    /// did within the episode.
    pub stood_at: Option<f64>,
    pub recording: Recording,
}

impl GetUpRun {
    /// Stood within [`GET_UP_LIMIT_S`] and stayed standing for [`STANDING_HOLD_S`].
    pub fn succeeded(&self) -> bool {
        self.stood_at.is_some_and(|t| t < GET_UP_LIMIT_S)
    }
}

/// Place the robot lying and only ask it to stand: the get-up must come from its own fall
/// detector. Records `limit_s` plus the hold.
pub fn get_up(
    trial: &mut Trial,
    params: &SkillParams,
    placement: Placement,
    limit_s: f64,
) -> Result<GetUpRun, TrialError> {
    let episode_s = limit_s + STANDING_HOLD_S + 0.1;
    let script = move |_: &World, t: f64| (t < episode_s).then(Intent::default);
    let recording = trial.run(
        params,
        Episode {
            start: placement.start,
            lying: Some(placement.lying),
            settle_s: 0.0,
            script,
        },
    )?;
    Ok(GetUpRun {
        placement,
        stood_at: stood_up_at(&recording, STANDING_HOLD_S),
        recording,
    })
}

/// Success count and times of a series of get-ups.
#[derive(Debug, Clone, PartialEq)]
pub struct GetUpSummary {
    pub runs: usize,
    pub successes: usize,
    /// Over the successful runs [s].
    pub mean_s: Option<f64>,
    pub worst_s: Option<f64>,
}

pub fn summarize(runs: &[GetUpRun]) -> GetUpSummary {
    let times: Vec<f64> = runs
        .iter()
        .filter(|r| r.succeeded())
        .filter_map(|r| r.stood_at)
        .collect();
    GetUpSummary {
        runs: runs.len(),
        successes: times.len(),
        mean_s: (!times.is_empty()).then(|| times.iter().sum::<f64>() / times.len() as f64),
        worst_s: times.iter().copied().reduce(f64::max),
    }
}

/// What happened when the robot was asked to walk after getting up.
#[derive(Debug, Clone, PartialEq)]
pub struct WalkAfterGetUp {
    /// Seconds from the placement until it stood for good.
    pub stood_at: Option<f64>,
    /// Metres walked (along its heading) after the walk command started.
    pub walked_m: f64,
    /// The robot fell (ground truth or its own detector) after the walk command started.
    pub fell: bool,
}

/// Get up from `placement`, then walk forward at `speed_m_s` for `walk_s` seconds, starting at
/// `walk_at_s` after the placement (the get-up must be over by then).
pub fn walk_after_get_up(
    trial: &mut Trial,
    params: &SkillParams,
    placement: Placement,
    walk_at_s: f64,
    speed_m_s: f64,
    walk_s: f64,
) -> Result<WalkAfterGetUp, TrialError> {
    let end_s = walk_at_s + walk_s;
    let script = move |_: &World, t: f64| {
        (t < end_s).then(|| Intent {
            body: if t < walk_at_s {
                BodyIntent::Stand
            } else {
                BodyIntent::Walk {
                    forward_m_s: speed_m_s,
                    sideways_m_s: 0.0,
                    turn_deg_s: 0.0,
                }
            },
            ..Default::default()
        })
    };
    let rec = trial.run(
        params,
        Episode {
            start: placement.start,
            lying: Some(placement.lying),
            settle_s: 0.0,
            script,
        },
    )?;
    let walking: Vec<&Sample> = rec.samples.iter().filter(|s| s.t >= walk_at_s).collect();
    let walked_m = match (walking.first(), walking.last()) {
        (Some(a), Some(b)) => {
            let heading = a.yaw_deg.to_radians();
            let (dx, dy) = (b.position[0] - a.position[0], b.position[1] - a.position[1]);
            dx * heading.cos() + dy * heading.sin()
        }
        _ => 0.0,
    };
    let fell = walking.is_empty()
        || walking.iter().any(|s| s.fallen())
        || walking.last().is_some_and(|s| s.t < end_s - 0.1);
    Ok(WalkAfterGetUp {
        stood_at: stood_up_at(&rec, STANDING_HOLD_S),
        walked_m,
        fell,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use libero_world::Posture;

    fn at(t: f64, z: f64, tilt: f64) -> Sample {
        Sample {
            t,
            position: [0.0, 0.0, z],
            yaw_deg: 0.0,
            pitch_deg: 0.0,
            roll_deg: 0.0,
            tilt_deg: tilt,
            posture: Posture::Upright,
            low: z < crate::episode::FALLEN_TORSO_Z_M,
            tall: z >= 0.6,
            estimate: None,
        }
    }

    fn recording(samples: Vec<Sample>) -> Recording {
        Recording {
            samples,
            intents: Vec::new(),
        }
    }

    #[test]
    fn standing_counts_only_when_held() {
        let mut samples: Vec<Sample> = (0..100)
            .map(|k| {
                let t = k as f64 * 0.02;
                at(t, if t < 0.5 { 0.2 } else { 0.65 }, 5.0)
            })
            .collect();
        let rec = recording(samples.clone());
        assert_eq!(stood_up_at(&rec, 1.0), Some(0.5));
        // Falling again before the hold is over does not count.
        samples[60] = at(1.2, 0.3, 80.0);
        let rec = recording(samples);
        assert_eq!(stood_up_at(&rec, 1.0), None);
        // High but tilted is not standing.
        let rec = recording((0..100).map(|k| at(k as f64 * 0.02, 0.65, 40.0)).collect());
        assert_eq!(stood_up_at(&rec, 0.5), None);
    }

    #[test]
    fn placements_cover_the_turn_and_vary() {
        let p = varied_placements(Lying::Back, 20, 3);
        assert_eq!(p.len(), 20);
        let mut headings: Vec<f64> = p.iter().map(|p| p.start[2]).collect();
        headings.sort_by(f64::total_cmp);
        for pair in headings.windows(2) {
            assert!((pair[1] - pair[0] - 18.0).abs() < 1e-9, "{headings:?}");
        }
        assert!(p.iter().all(|p| p.lying.roll_deg.abs() <= MAX_ROLL_DEG));
        assert!(p.iter().all(|p| p.lying.side == Lying::Back));
        let rolls: Vec<f64> = p.iter().map(|p| p.lying.roll_deg).collect();
        assert!(rolls.iter().any(|&r| r > 5.0) && rolls.iter().any(|&r| r < -5.0));
        assert_ne!(p[0].start[0], p[1].start[0]);
    }

    #[test]
    fn summary_counts_only_in_time_successes() {
        let placement = varied_placements(Lying::Front, 1, 1)[0];
        let run = |stood_at| GetUpRun {
            placement,
            stood_at,
            recording: Recording::default(),
        };
        let s = summarize(&[run(Some(3.0)), run(Some(4.0)), run(None), run(Some(6.0))]);
        assert_eq!(s.runs, 4);
        assert_eq!(s.successes, 2);
        assert_eq!(s.mean_s, Some(3.5));
        assert_eq!(s.worst_s, Some(4.0));
    }
}
