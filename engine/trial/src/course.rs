//! Walk courses: timed sequences of velocity commands, and how well a recording followed one.

use crate::cmaes::Rng;
use crate::episode::Recording;
use libero_skills::{BodyIntent, Intent};

/// One leg of a course: walk with this command for `duration_s`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Leg {
    pub duration_s: f64,
    pub forward_m_s: f64,
    pub sideways_m_s: f64,
    pub turn_deg_s: f64,
}

/// A sequence of commands.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Course {
    pub legs: Vec<Leg>,
}

const fn leg(duration_s: f64, forward_m_s: f64, sideways_m_s: f64, turn_deg_s: f64) -> Leg {
    Leg {
        duration_s,
        forward_m_s,
        sideways_m_s,
        turn_deg_s,
    }
}

impl Course {
    /// Straight ahead at `speed` for `seconds`.
    pub fn straight(speed: f64, seconds: f64) -> Self {
        Self {
            legs: vec![leg(seconds, speed, 0.0, 0.0)],
        }
    }

    /// Rising to `speed` straight ahead: a third of the time at 40 %, a third at 70 %, the
    /// rest at full speed (the optimiser's forward course: gradual, so early candidates that
    /// only manage slow walking still score).
    pub fn rising(speed: f64, seconds: f64) -> Self {
        let third = seconds / 3.0;
        Self {
            legs: vec![
                leg(third, 0.4 * speed, 0.0, 0.0),
                leg(third, 0.7 * speed, 0.0, 0.0),
                leg(seconds - 2.0 * third, speed, 0.0, 0.0),
            ],
        }
    }

    /// The optimiser's standard course: forward at rising speeds, curves, sideways, turning on
    /// the spot and backwards, with changes mid-walk.
    pub fn standard() -> Self {
        Self {
            legs: vec![
                leg(3.0, 0.3, 0.0, 0.0),
                leg(6.0, 0.6, 0.0, 0.0),
                leg(3.0, 0.4, 0.0, 30.0),
                leg(3.0, 0.0, 0.25, 0.0),
                leg(3.0, 0.0, 0.0, -60.0),
                leg(3.0, 0.3, -0.15, 0.0),
                leg(2.0, -0.2, 0.0, 0.0),
            ],
        }
    }

    /// Random commands within the limits, each held for 2–5 s (the 5-minute stability test).
    pub fn random(seconds: f64, limits: [f64; 3], seed: u64) -> Self {
        let mut rng = Rng::new(seed);
        let mut legs = Vec::new();
        let mut total = 0.0;
        while total < seconds {
            let d = (2.0 + 3.0 * rng.uniform()).min(seconds - total).max(0.02);
            let mut c = || 2.0 * rng.uniform() - 1.0;
            let (f, s, w) = (c(), c(), c());
            legs.push(leg(d, f * limits[0], s * limits[1], w * limits[2]));
            total += d;
        }
        Self { legs }
    }

    /// The optimiser's course for the speed bars: a short start, then `limits` (forward m/s,
    /// sideways m/s, turn deg/s) held straight ahead, sideways and turning on the spot (sides
    /// chosen by `seed`), then random commands within the limits. Asking for the limits, which
    /// lie above the bars, is what makes the executed speed reach the bars.
    pub fn bars(limits: [f64; 3], seed: u64) -> Self {
        let mut rng = Rng::new(seed.wrapping_mul(7919));
        let mut side = || if rng.uniform() < 0.5 { -1.0 } else { 1.0 };
        let (s, w) = (side(), side());
        let mut legs = vec![
            leg(2.0, 0.5 * limits[0], 0.0, 0.0),
            leg(7.0, limits[0], 0.0, 0.0),
            leg(5.0, 0.0, s * limits[1], 0.0),
            leg(3.0, 0.0, 0.0, w * limits[2]),
        ];
        legs.extend(Self::random(8.0, limits, seed).legs);
        Self { legs }
    }

    pub fn duration_s(&self) -> f64 {
        self.legs.iter().map(|l| l.duration_s).sum()
    }

    /// The command at `t` seconds; `None` past the end.
    pub fn at(&self, t: f64) -> Option<Leg> {
        self.leg_index(t).map(|i| self.legs[i])
    }

    /// Which leg is walked at `t` seconds; `None` past the end.
    pub fn leg_index(&self, t: f64) -> Option<usize> {
        let mut start = 0.0;
        for (i, l) in self.legs.iter().enumerate() {
            if t < start + l.duration_s {
                return Some(i);
            }
            start += l.duration_s;
        }
        None
    }

    /// A script for [`crate::Episode`] that follows the course and ends early at a fall.
    pub fn script(
        &self,
    ) -> impl FnMut(&libero_world::World, f64) -> Option<Intent> + Clone + Send + 'static {
        let course = self.clone();
        move |world, t| {
            if world.body.posture != libero_world::Posture::Upright {
                return None;
            }
            let l = course.at(t)?;
            Some(Intent {
                body: BodyIntent::Walk {
                    forward_m_s: l.forward_m_s,
                    sideways_m_s: l.sideways_m_s,
                    turn_deg_s: l.turn_deg_s,
                },
                ..Default::default()
            })
        }
    }
}

/// Speeds below these count as these when progress is scaled by the command (so a tiny
/// random command does not turn a millimetre into a big score).
const MIN_SPEED_M_S: f64 = 0.1;
const MIN_TURN_DEG_S: f64 = 10.0;

/// How well the robot moved the way it was told, in seconds of commanded motion achieved.
/// Per leg of the course: the travel along the commanded direction divided by the commanded
/// speed, plus the turn in the commanded sense divided by the commanded rate, minus half the
/// net sideways drift and unwanted turn (scaled the same way). Travel is summed cycle by cycle
/// in the robot's frame, so curves count; drift is taken net over the leg, so the sway of
/// every step does not count as drift. A robot that does exactly what it is told scores about
/// the course's duration (twice that on legs that both walk and turn); slow, slipping or
/// drifting walks score less, and sideways and turning count as much as forward.
pub fn progress(course: &Course, rec: &Recording) -> f64 {
    let mut total = 0.0;
    // Travel in the robot's frame (forward, left) [m] and turn [deg] in the current leg.
    let mut moved = ([0.0, 0.0], 0.0);
    let mut current: Option<usize> = None;
    for w in rec.samples.windows(2) {
        let (a, b) = (&w[0], &w[1]);
        let Some(index) = course.leg_index(a.t) else {
            break;
        };
        if current != Some(index) {
            if let Some(done) = current {
                total += leg_score(&course.legs[done], moved);
            }
            current = Some(index);
            moved = ([0.0, 0.0], 0.0);
        }
        let yaw = a.yaw_deg.to_radians();
        let (dx, dy) = (b.position[0] - a.position[0], b.position[1] - a.position[1]);
        moved.0[0] += dx * yaw.cos() + dy * yaw.sin();
        moved.0[1] += -dx * yaw.sin() + dy * yaw.cos();
        let mut turned = b.yaw_deg - a.yaw_deg;
        if turned > 180.0 {
            turned -= 360.0;
        } else if turned < -180.0 {
            turned += 360.0;
        }
        moved.1 += turned;
    }
    if let Some(done) = current {
        total += leg_score(&course.legs[done], moved);
    }
    total
}

/// One leg's part of [`progress`] from its travel ([forward, left] m) and turn [deg].
fn leg_score(l: &Leg, (travel, turned): ([f64; 2], f64)) -> f64 {
    let speed = l.forward_m_s.hypot(l.sideways_m_s);
    let mut score = if speed > 1e-6 {
        let dir = [l.forward_m_s / speed, l.sideways_m_s / speed];
        let along = travel[0] * dir[0] + travel[1] * dir[1];
        let across = -travel[0] * dir[1] + travel[1] * dir[0];
        (along - 0.5 * across.abs()) / speed.max(MIN_SPEED_M_S)
    } else {
        -0.5 * travel[0].hypot(travel[1]) / MIN_SPEED_M_S
    };
    score += if l.turn_deg_s.abs() > 1e-6 {
        turned * l.turn_deg_s.signum() / l.turn_deg_s.abs().max(MIN_TURN_DEG_S)
    } else {
        -0.5 * turned.abs() / MIN_TURN_DEG_S
    };
    score
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::episode::Sample;

    /// A recording of a robot that moves by `velocity(t)` (forward m/s, left m/s, deg/s in its
    /// own frame), sampled every 20 ms.
    fn follow(seconds: f64, velocity: impl Fn(f64) -> [f64; 3]) -> Recording {
        let (mut x, mut y, mut yaw) = (0.0f64, 0.0f64, 0.0f64);
        let mut samples = Vec::new();
        let dt = 0.02;
        for i in 0..=(seconds / dt).round() as usize {
            let t = i as f64 * dt;
            samples.push(Sample {
                t,
                position: [x, y, 0.6],
                yaw_deg: yaw,
                pitch_deg: 0.0,
                roll_deg: 0.0,
                tilt_deg: 0.0,
                posture: libero_world::Posture::Upright,
                low: false,
                tall: true,
                estimate: None,
            });
            let [f, s, w] = velocity(t);
            let r = yaw.to_radians();
            x += (f * r.cos() - s * r.sin()) * dt;
            y += (f * r.sin() + s * r.cos()) * dt;
            yaw += w * dt;
        }
        Recording {
            samples,
            intents: Vec::new(),
        }
    }

    #[test]
    fn progress_counts_seconds_of_commanded_motion_in_every_direction() {
        let course = Course {
            legs: vec![
                leg(4.0, 0.5, 0.0, 0.0),
                leg(4.0, 0.0, 0.2, 0.0),
                leg(4.0, 0.0, 0.0, 45.0),
            ],
        };
        let exact = follow(12.0, |t| {
            course
                .at(t)
                .map_or([0.0; 3], |l| [l.forward_m_s, l.sideways_m_s, l.turn_deg_s])
        });
        assert!(
            (progress(&course, &exact) - 12.0).abs() < 0.1,
            "{}",
            progress(&course, &exact)
        );
        // Half the speed everywhere: half the score, sideways and turning included.
        let half = follow(12.0, |t| {
            course.at(t).map_or([0.0; 3], |l| {
                [
                    l.forward_m_s / 2.0,
                    l.sideways_m_s / 2.0,
                    l.turn_deg_s / 2.0,
                ]
            })
        });
        assert!((progress(&course, &half) - 6.0).abs() < 0.1);
        // Standing still scores nothing; drifting while told to turn on the spot costs.
        assert!(progress(&course, &follow(12.0, |_| [0.0; 3])).abs() < 1e-9);
        let drift = follow(12.0, |t| match course.leg_index(t) {
            Some(2) => [0.1, 0.0, 45.0],
            _ => [0.0; 3],
        });
        assert!(progress(&course, &drift) < 4.0 - 0.1);
    }

    #[test]
    fn a_sway_that_averages_out_is_not_drift() {
        let course = Course::straight(0.5, 4.0);
        let swaying = follow(4.0, |t| {
            [0.5, 0.2 * (std::f64::consts::TAU * t / 0.7).cos(), 0.0]
        });
        assert!((progress(&course, &swaying) - 4.0).abs() < 0.15);
    }

    #[test]
    fn bars_course_asks_for_the_limits_and_differs_by_seed() {
        let limits = [0.6, 0.25, 60.0];
        let a = Course::bars(limits, 1);
        assert!(a
            .legs
            .iter()
            .any(|l| l.forward_m_s == 0.6 && l.duration_s >= 5.0));
        assert!(a.legs.iter().any(|l| l.sideways_m_s.abs() == 0.25));
        assert!(a.legs.iter().any(|l| l.turn_deg_s.abs() == 60.0));
        for l in &a.legs {
            assert!(l.forward_m_s.abs() <= 0.6 && l.sideways_m_s.abs() <= 0.25);
        }
        assert_ne!(a, Course::bars(limits, 2));
        assert!((a.duration_s() - 25.0).abs() < 1e-9);
    }
}
