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

    pub fn duration_s(&self) -> f64 {
        self.legs.iter().map(|l| l.duration_s).sum()
    }

    /// The command at `t` seconds; `None` past the end.
    pub fn at(&self, t: f64) -> Option<Leg> {
        let mut start = 0.0;
        for l in &self.legs {
            if t < start + l.duration_s {
                return Some(*l);
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

/// Metres of heading change that count like one metre of travel.
const DEG_PER_METRE: f64 = 200.0;

/// How far the robot moved the way it was told: travel along each cycle's commanded direction
/// [m] plus turning in the commanded sense (200° count as 1 m), minus sideways drift.
pub fn progress(course: &Course, rec: &Recording) -> f64 {
    let mut total = 0.0;
    for w in rec.samples.windows(2) {
        let (a, b) = (&w[0], &w[1]);
        let Some(l) = course.at(a.t) else { break };
        let yaw = a.yaw_deg.to_radians();
        let (dx, dy) = (b.position[0] - a.position[0], b.position[1] - a.position[1]);
        let local = [
            dx * yaw.cos() + dy * yaw.sin(),
            -dx * yaw.sin() + dy * yaw.cos(),
        ];
        let speed = l.forward_m_s.hypot(l.sideways_m_s);
        if speed > 1e-6 {
            let dir = [l.forward_m_s / speed, l.sideways_m_s / speed];
            let along = local[0] * dir[0] + local[1] * dir[1];
            let across = -local[0] * dir[1] + local[1] * dir[0];
            total += along - 0.5 * across.abs();
        } else {
            total -= 0.5 * local[0].hypot(local[1]);
        }
        let mut turned = b.yaw_deg - a.yaw_deg;
        if turned > 180.0 {
            turned -= 360.0;
        } else if turned < -180.0 {
            turned += 360.0;
        }
        if l.turn_deg_s.abs() > 1e-6 {
            total += turned * l.turn_deg_s.signum() / DEG_PER_METRE;
        } else {
            total -= turned.abs() / DEG_PER_METRE;
        }
    }
    total
}
