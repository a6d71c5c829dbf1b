//! The launch fit of a young track: when the ball left, how fast, along which direction.

use super::{Tracker, MAX_BALL_SPEED};
use nalgebra::Vector2;

/// A jump that started the current track.
#[derive(Debug, Clone, Copy)]
pub(super) struct Launch {
    /// The ball was last seen on the old path then, and first seen on the new one at `latest`.
    pub(super) earliest: f64,
    pub(super) latest: f64,
    /// Where the old path put the ball when the jump was seen.
    pub(super) origin: Vector2<f64>,
    /// The ball was lying at `origin` and left it: the new path starts there.
    pub(super) from_rest: bool,
}

impl Launch {
    /// The launch time: when the fitted path passes the point the ball left, clamped to the
    /// interval between the two frames (a ball placed elsewhere passes no such point).
    pub(super) fn time_on(
        &self,
        p: Vector2<f64>,
        v: Vector2<f64>,
        a: Vector2<f64>,
        now: f64,
    ) -> f64 {
        let midpoint = 0.5 * (self.earliest + self.latest);
        let Some(u) = v.try_normalize(1e-9) else {
            return midpoint;
        };
        // Along the path: s(τ) = v·τ + ½a·τ², looking for s(τ) = s_origin with τ < 0.
        let (s_origin, speed, accel) = ((self.origin - p).dot(&u), v.norm(), a.dot(&u));
        let tau = if accel.abs() < 1e-9 {
            s_origin / speed
        } else {
            let disc = speed * speed + 2.0 * accel * s_origin;
            if disc < 0.0 {
                return midpoint;
            }
            // The root nearer to now (the other is where the parabola turns back).
            (-speed + disc.sqrt()) / accel
        };
        let t = now + tau;
        if t.is_finite() {
            t.clamp(self.earliest, self.latest)
        } else {
            midpoint
        }
    }
}

/// The model fitted to a young track.
pub(super) struct LaunchFit {
    pub(super) position: Vector2<f64>,
    pub(super) velocity: Vector2<f64>,
    pub(super) launch_speed: f64,
    /// Launch point and heading [rad], the heading corrected for the curve of the path.
    pub(super) origin: Vector2<f64>,
    pub(super) heading: f64,
}

impl Tracker {
    /// Gauss-Newton fit of `s(t) = s0 + D(v_launch, t − t_launch)` to the track's observations.
    /// From rest, s is the distance from the spot the ball left, D the launch table's (the
    /// server's own slide and roll), s0 = 0 and the launch time is free (within the frames
    /// around the jump). Otherwise s is measured along the path, D is the motion model's, the
    /// launch time is the fitted guess and s0 is free.
    pub(super) fn fit_launch(
        &self,
        launch: &Launch,
        time_guess: f64,
        velocity: Vector2<f64>,
        now: f64,
    ) -> Option<LaunchFit> {
        let last = self.observations.back()?.1.xy();
        let (start, direction) = if launch.from_rest {
            (launch.origin, (last - launch.origin).try_normalize(1e-6)?)
        } else {
            (
                self.observations.front()?.1.xy(),
                velocity.try_normalize(1e-6)?,
            )
        };
        let along: arrayvec::ArrayVec<(f64, f64), { super::TRACK_CAPACITY }> = self
            .observations
            .iter()
            .take(super::TRACK_CAPACITY)
            .map(|(t, p)| {
                let d = p.xy() - start;
                (
                    *t,
                    if launch.from_rest {
                        d.norm()
                    } else {
                        d.dot(&direction)
                    },
                )
            })
            .collect();
        let ratio = self.motion.rolling_speed_ratio;
        let table = &self.params.launch_table;
        let chord_heading = direction.y.atan2(direction.x);
        let model = |theta: &nalgebra::Vector3<f64>, t: f64| {
            let (s0, v, t0) = (theta[0], theta[1].max(0.0), theta[2]);
            if launch.from_rest {
                table.distance(v, chord_heading, t - t0)
            } else {
                s0 + self.motion.advance(v, Some(v * ratio), t - t0).distance
            }
        };
        let (t_lo, t_hi) = (launch.earliest - 0.02, launch.latest);
        let free = if launch.from_rest {
            [false, true, true]
        } else {
            [true, true, false]
        };
        let first_speed = velocity.norm().max(0.1);
        let mut theta = nalgebra::Vector3::new(0.0, first_speed, time_guess.clamp(t_lo, t_hi));
        for _ in 0..10 {
            let mut normal = nalgebra::Matrix3::<f64>::zeros();
            let mut rhs = nalgebra::Vector3::<f64>::zeros();
            for &(t, s) in &along {
                let predicted = model(&theta, t);
                let mut jac = nalgebra::Vector3::zeros();
                for k in 0..3 {
                    if free[k] {
                        let mut shifted = theta;
                        shifted[k] += 1e-5;
                        jac[k] = (model(&shifted, t) - predicted) / 1e-5;
                    }
                }
                normal += jac * jac.transpose();
                rhs += jac * (s - predicted);
            }
            for k in 0..3 {
                if !free[k] {
                    normal[(k, k)] = 1.0;
                }
            }
            let step = normal.try_inverse()? * rhs;
            if !step.iter().all(|c| c.is_finite()) {
                return None;
            }
            theta += step;
            theta[1] = theta[1].max(0.0);
            theta[2] = theta[2].clamp(t_lo, t_hi);
            if step.norm() < 1e-7 {
                break;
            }
        }
        let (v0, t0) = (theta[1], theta[2]);
        // A "launch" that the model cannot explain (a ball placed by hand) is not used.
        if v0.is_nan() || v0 > MAX_BALL_SPEED || theta[0].is_nan() || theta[0].abs() > 1.0 {
            return None;
        }
        let now_state = self.motion.advance(v0, Some(v0 * ratio), now - t0);
        let origin = start + direction * theta[0];
        let heading = self.params.launch_table.launch_heading(
            v0,
            origin,
            self.observations.iter().map(|(t, p)| (t - t0, p.xy())),
            direction.y.atan2(direction.x),
        );
        Some(LaunchFit {
            position: start + direction * (theta[0] + now_state.distance),
            velocity: direction * now_state.speed,
            launch_speed: v0,
            origin,
            heading,
        })
    }
}
