//! How a free ball slows down on the ground, in closed form.
//!
//! Deceleration = constant + quadratic_drag·v² along a straight line. The constant is the
//! sliding friction while a ball launched without spin slides, and the (learned) rolling
//! resistance once it rolls; the switch happens at `rolling_speed_ratio` × launch speed.
//! Each phase has closed-form speed, distance and time, so predictions cost no integration.

use crate::params::{BallParams, DirectionalFriction};

/// One phase: deceleration `constant + quadratic·v²`.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Phase {
    constant: f64,
    quadratic: f64,
}

/// Below this the quadratic term is ignored (the formulas divide by it).
const NEGLIGIBLE_DRAG: f64 = 1e-9;

impl Phase {
    fn angle(&self, v: f64) -> f64 {
        (v * (self.quadratic / self.constant).sqrt()).atan()
    }

    fn rate(&self) -> f64 {
        (self.constant * self.quadratic).sqrt()
    }

    /// Time to slow from `v0` to `v1` (≤ v0).
    fn time_between(&self, v0: f64, v1: f64) -> f64 {
        if self.quadratic < NEGLIGIBLE_DRAG {
            return (v0 - v1) / self.constant;
        }
        (self.angle(v0) - self.angle(v1)) / self.rate()
    }

    /// Distance covered while slowing from `v0` to `v1`.
    fn distance_between(&self, v0: f64, v1: f64) -> f64 {
        let (c, q) = (self.constant, self.quadratic);
        if q < NEGLIGIBLE_DRAG {
            return (v0 * v0 - v1 * v1) / (2.0 * c);
        }
        ((c + q * v0 * v0) / (c + q * v1 * v1)).ln() / (2.0 * q)
    }

    /// Speed after covering `s` from `v0` (0 if it stops first).
    fn speed_after_distance(&self, v0: f64, s: f64) -> f64 {
        let (c, q) = (self.constant, self.quadratic);
        let v_sq = if q < NEGLIGIBLE_DRAG {
            v0 * v0 - 2.0 * c * s
        } else {
            ((c + q * v0 * v0) * (-2.0 * q * s).exp() - c) / q
        };
        v_sq.max(0.0).sqrt()
    }

    /// (distance, speed) after `t` from `v0`, stopping at zero speed.
    fn advance(&self, v0: f64, t: f64) -> (f64, f64) {
        let stop = self.time_between(v0, 0.0);
        if t >= stop {
            return (self.distance_between(v0, 0.0), 0.0);
        }
        let (c, q) = (self.constant, self.quadratic);
        if q < NEGLIGIBLE_DRAG {
            return (v0 * t - 0.5 * c * t * t, v0 - c * t);
        }
        let (a0, a) = (self.angle(v0), self.angle(v0) - self.rate() * t);
        ((a.cos() / a0.cos()).ln() / q, a.tan() * (c / q).sqrt())
    }
}

/// The table entry for `heading`, linearly interpolated in the angle to the nearest field axis.
fn friction_towards(table: &[DirectionalFriction], heading: f64) -> DirectionalFriction {
    let folded = heading.to_degrees().rem_euclid(90.0);
    let angle = if folded > 45.0 { 90.0 - folded } else { folded };
    let first = table[0];
    let Some(i) = table.iter().position(|f| f.angle_deg >= angle) else {
        return *table.last().unwrap_or(&first);
    };
    if i == 0 {
        return first;
    }
    let (a, b) = (table[i - 1], table[i]);
    let w = (angle - a.angle_deg) / (b.angle_deg - a.angle_deg);
    let mix = |x: f64, y: f64| x + w * (y - x);
    DirectionalFriction {
        angle_deg: angle,
        sliding: mix(a.sliding, b.sliding),
        rolling: mix(a.rolling, b.rolling),
        quadratic_drag: mix(a.quadratic_drag, b.quadratic_drag),
    }
}

/// The ball's straight-line slow-down, from the tunable parameters and the learned drag factor.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BallMotion {
    sliding: Phase,
    rolling: Phase,
    pub rolling_speed_ratio: f64,
}

/// Where the motion is along its line after some time.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Progress {
    /// Distance from the starting point [m].
    pub distance: f64,
    /// Speed [m/s].
    pub speed: f64,
}

impl BallMotion {
    /// The model for a ball travelling along `heading` [rad, field frame]; `drag_factor`
    /// multiplies the rolling resistance (learned from roll-outs).
    pub fn new(params: &BallParams, drag_factor: f64, heading: f64) -> Self {
        let f = friction_towards(&params.friction_by_direction, heading);
        Self {
            sliding: Phase {
                constant: f.sliding,
                quadratic: f.quadratic_drag,
            },
            rolling: Phase {
                constant: f.rolling * drag_factor,
                quadratic: f.quadratic_drag,
            },
            rolling_speed_ratio: params.rolling_speed_ratio,
        }
    }

    /// Deceleration [m/s²] at speed `v` while sliding or rolling.
    pub fn deceleration(&self, v: f64, sliding: bool) -> f64 {
        let phase = if sliding { self.sliding } else { self.rolling };
        phase.constant + phase.quadratic * v * v
    }

    /// The speed at which a sliding ball starts rolling (`None`: it already rolls), clamped so
    /// that a ball slower than that is treated as rolling.
    fn roll_speed(v: f64, rolls_below: Option<f64>) -> Option<f64> {
        rolls_below.filter(|r| *r < v)
    }

    /// Total distance to a stop from speed `v`; `rolls_below` = the speed at which a sliding
    /// ball starts rolling.
    pub fn stop_distance(&self, v: f64, rolls_below: Option<f64>) -> f64 {
        let v = v.max(0.0);
        match Self::roll_speed(v, rolls_below) {
            Some(r) => self.sliding.distance_between(v, r) + self.rolling.distance_between(r, 0.0),
            None => self.rolling.distance_between(v, 0.0),
        }
    }

    /// Time to a stop from speed `v`.
    pub fn stop_time(&self, v: f64, rolls_below: Option<f64>) -> f64 {
        let v = v.max(0.0);
        match Self::roll_speed(v, rolls_below) {
            Some(r) => self.sliding.time_between(v, r) + self.rolling.time_between(r, 0.0),
            None => self.rolling.time_between(v, 0.0),
        }
    }

    /// Distance and speed after `t` seconds.
    pub fn advance(&self, v: f64, rolls_below: Option<f64>, t: f64) -> Progress {
        let (v, t) = (v.max(0.0), t.max(0.0));
        let (distance, speed) = match Self::roll_speed(v, rolls_below) {
            Some(r) => {
                let slide_time = self.sliding.time_between(v, r);
                if t <= slide_time {
                    self.sliding.advance(v, t)
                } else {
                    let (d, s) = self.rolling.advance(r, t - slide_time);
                    (self.sliding.distance_between(v, r) + d, s)
                }
            }
            None => self.rolling.advance(v, t),
        };
        Progress { distance, speed }
    }

    /// When the ball has covered `s` metres, or `None` if it stops first.
    pub fn time_to_cover(&self, v: f64, rolls_below: Option<f64>, s: f64) -> Option<f64> {
        let v = v.max(0.0);
        if s < 0.0 || s >= self.stop_distance(v, rolls_below) {
            return (s <= 0.0).then_some(0.0);
        }
        Some(match Self::roll_speed(v, rolls_below) {
            Some(r) => {
                let slide = self.sliding.distance_between(v, r);
                if s <= slide {
                    let v1 = self.sliding.speed_after_distance(v, s);
                    self.sliding.time_between(v, v1)
                } else {
                    let v1 = self.rolling.speed_after_distance(r, s - slide);
                    self.sliding.time_between(v, r) + self.rolling.time_between(r, v1)
                }
            }
            None => {
                let v1 = self.rolling.speed_after_distance(v, s);
                self.rolling.time_between(v, v1)
            }
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::params::WorldParams;

    fn motion() -> BallMotion {
        BallMotion::new(&WorldParams::builtin().ball, 1.0, 0.0)
    }

    /// Euler integration of the same model, to check the closed forms.
    fn integrate(m: &BallMotion, v0: f64, rolls_below: Option<f64>, t_end: f64) -> (f64, f64) {
        let (mut v, mut x, dt) = (v0, 0.0, 1e-5);
        let mut t = 0.0;
        while t < t_end && v > 0.0 {
            let sliding = rolls_below.is_some_and(|r| v > r);
            let a = m.deceleration(v, sliding);
            x += v * dt;
            v = (v - a * dt).max(0.0);
            t += dt;
        }
        (x, v)
    }

    #[test]
    fn closed_forms_agree_with_integration() {
        let m = motion();
        for &(v0, roll) in &[(8.0, Some(5.7)), (3.0, None), (1.0, Some(0.7)), (0.2, None)] {
            for &t in &[0.1, 0.5, 1.5, 4.0, 20.0] {
                let p = m.advance(v0, roll, t);
                let (x, v) = integrate(&m, v0, roll, t);
                assert!((p.distance - x).abs() < 2e-3, "v0 {v0} t {t}: {p:?} vs {x}");
                assert!((p.speed - v).abs() < 2e-3, "v0 {v0} t {t}: {p:?} vs {v}");
            }
            let stop = m.stop_distance(v0, roll);
            let (x, _) = integrate(&m, v0, roll, 100.0);
            assert!((stop - x).abs() < 2e-3);
            let half = m.time_to_cover(v0, roll, stop / 2.0).unwrap();
            assert!((m.advance(v0, roll, half).distance - stop / 2.0).abs() < 1e-6);
            assert_eq!(m.time_to_cover(v0, roll, stop + 0.1), None);
        }
    }

    #[test]
    fn stop_distances_match_the_simulated_server_ball() {
        // MuJoCo runs of the server's ball (world.xml) launched at v0 without spin.
        let params = WorldParams::builtin().ball;
        for &(v0, deg, simulated) in &[
            (1.0, 0.0, 0.5645),
            (4.0, 90.0, 6.911),
            (8.0, 180.0, 18.08),
            (4.0, 45.0, 9.44),
            (8.0, -45.0, 23.85),
            (8.0, 30.0, 21.73),
        ] {
            let m = BallMotion::new(&params, 1.0, f64::to_radians(deg));
            let predicted = m.stop_distance(v0, Some(v0 * m.rolling_speed_ratio));
            assert!(
                (predicted - simulated).abs() < 0.04 * simulated,
                "{v0}: {predicted} vs {simulated}"
            );
        }
    }

    #[test]
    fn no_drag_means_constant_deceleration() {
        let mut p = WorldParams::builtin().ball;
        p.friction_by_direction.truncate(1);
        p.friction_by_direction[0].quadratic_drag = 0.0;
        let m = BallMotion::new(&p, 1.0, 0.3);
        let d = m.stop_distance(2.0, None);
        assert!((d - 4.0 / (2.0 * p.friction_by_direction[0].rolling)).abs() < 1e-9);
        assert!(m.advance(2.0, None, 100.0).speed == 0.0);
    }
}
