//! The ball: field position from vision, velocity and acceleration by a least-squares fit over
//! a short window, and predictions from the motion model ([`crate::ball_motion`]).
//!
//! Observations that fit the current trajectory extend its *track*; one that does not (a kick,
//! a referee placing the ball, our own relocalization) starts a new one. A new track that starts
//! from a jump is assumed to be a launch without spin: the ball slides until its speed has dropped
//! to `rolling_speed_ratio` × launch speed, then rolls. Its stop point comes from the launch
//! table ([`crate::ball_launch`]): the server's ball curves. Finished roll-outs tune the drag
//! factor of the straight-line model used for everything else.

use crate::ball_motion::BallMotion;
use crate::params::BallParams;
use launch_fit::Launch;
use nalgebra::{Vector2, Vector3};
use std::collections::VecDeque;

/// Observations kept per track (a little more than 2 s of vision at 25 Hz).
pub(crate) const TRACK_CAPACITY: usize = 64;
/// Faster than any kick [m/s]: a launch fit beyond it explains nothing.
const MAX_BALL_SPEED: f64 = 15.0;
/// Points needed before a track's fit says anything about launch speed or rest.
const LAUNCH_WINDOW_MIN_POINTS: usize = 3;

/// The agent's belief about the ball (global field frame).
#[derive(Debug, Clone, serde::Serialize)]
pub struct BallEstimate {
    /// Position on the ground [m], predicted forward to the current cycle when not in view.
    pub position: [f64; 2],
    /// Height of the ball centre [m] (0.11 when on the ground).
    pub height: f64,
    /// [m/s]
    pub velocity: [f64; 2],
    /// Fitted acceleration [m/s²].
    pub acceleration: [f64; 2],
    /// Where it will come to rest.
    pub predicted_stop: [f64; 2],
    /// Simulation time it was last seen (`None`: never).
    pub last_seen_time: Option<f64>,
    /// Time of a teammate's sighting we took because it was newer than our own (`None`:
    /// none since our own).
    pub heard_time: Option<f64>,
    /// Seen in the current cycle's vision.
    pub seen_now: bool,
    /// Still sliding after a launch (decelerates faster than rolling).
    pub sliding: bool,
    /// Learned multiplier of the rolling resistance.
    pub drag_factor: f64,
    #[serde(skip)]
    tracker: Tracker,
}

#[derive(Debug, Clone)]
struct Tracker {
    params: BallParams,
    motion: BallMotion,
    observations: VecDeque<(f64, Vector3<f64>)>,
    /// The fitted state at `fit_time`: what predictions start from.
    fit_time: f64,
    fit_position: Vector2<f64>,
    fit_velocity: Vector2<f64>,
    /// How the current track started, if it started with a jump (`None`: first sight).
    launch: Option<Launch>,
    launch_speed: Option<f64>,
    /// The launch of the current track as fitted: (launch point, heading [rad], speed).
    launched: Option<(Vector2<f64>, f64, f64)>,
    /// Set once the track has been seen rolling: (position, speed) at that moment.
    rolling_start: Option<(Vector2<f64>, f64)>,
    learned_from_track: bool,
    drag_factor: f64,
    /// Where the ball lies while at rest.
    rest_position: Option<Vector2<f64>>,
    /// Whether the window's points show the fitted motion beyond their own scatter; otherwise
    /// the estimate is published at rest at `window_mean`.
    motion_supported: bool,
    window_mean: Vector2<f64>,
    /// The track holds a teammate's sighting only: the next own sighting starts afresh.
    heard_track: bool,
    /// Where the ball last left a spot it lay at, kept while it rolls on: a teammate's report
    /// restarts the track (and forgets its launch), but not where the roll came from.
    roll_origin: Option<Vector2<f64>>,
}

impl BallEstimate {
    pub fn new(params: &BallParams) -> Self {
        Self {
            position: [0.0; 2],
            height: 0.11,
            velocity: [0.0; 2],
            acceleration: [0.0; 2],
            predicted_stop: [0.0; 2],
            last_seen_time: None,
            heard_time: None,
            seen_now: false,
            sliding: false,
            drag_factor: 1.0,
            tracker: Tracker {
                params: params.clone(),
                motion: BallMotion::new(params, 1.0, 0.0),
                drag_factor: 1.0,
                observations: VecDeque::with_capacity(TRACK_CAPACITY),
                fit_time: 0.0,
                fit_position: Vector2::zeros(),
                fit_velocity: Vector2::zeros(),
                launch: None,
                launch_speed: None,
                launched: None,
                rolling_start: None,
                learned_from_track: false,
                rest_position: None,
                motion_supported: false,
                window_mean: Vector2::zeros(),
                heard_track: false,
                roll_origin: None,
            },
        }
    }

    /// The motion model with the current drag factor.
    pub fn motion(&self) -> &BallMotion {
        &self.tracker.motion
    }

    /// Seconds since the ball was last seen (infinite if never).
    /// Own sightings and teammates' newer ones alike.
    pub fn age(&self, now: f64) -> f64 {
        let latest = match (self.last_seen_time, self.heard_time) {
            (Some(a), Some(b)) => Some(a.max(b)),
            (a, b) => a.or(b),
        };
        latest.map_or(f64::INFINITY, |t| now - t)
    }

    /// A teammate saw the ball at `position` at `sighting_time` (communication). Taken when it
    /// is newer than our own sighting by more than `newer_by_s`, as a ball at rest there (the
    /// message carries no velocity); heard and seen points never share a fit, so the next own
    /// sighting starts a fresh track. Returns whether it was taken.
    pub fn hear(
        &mut self,
        now: f64,
        sighting_time: f64,
        position: [f64; 2],
        newer_by_s: f64,
    ) -> bool {
        if !position.iter().all(|c| c.is_finite()) || !sighting_time.is_finite() {
            return false;
        }
        let own = self.last_seen_time.unwrap_or(f64::NEG_INFINITY);
        let heard = self.heard_time.unwrap_or(f64::NEG_INFINITY);
        if sighting_time <= own + newer_by_s || sighting_time <= heard || sighting_time > now {
            return false;
        }
        let t = &mut self.tracker;
        t.reset_track();
        t.launch = None;
        t.observations
            .push_back((sighting_time, Vector3::new(position[0], position[1], 0.11)));
        t.fit(sighting_time);
        t.heard_track = true;
        self.heard_time = Some(sighting_time);
        self.publish(now);
        true
    }

    /// One cycle: `seen` is the ball's field position from this cycle's vision, if any.
    pub fn update(&mut self, time: f64, seen: Option<Vector3<f64>>) {
        self.seen_now = false;
        if let Some(p) = seen.filter(|p| p.iter().all(|c| c.is_finite())) {
            self.observe(time, p);
            self.seen_now = true;
            self.last_seen_time = Some(time);
            self.height = p.z;
        }
        self.publish(time);
    }

    fn observe(&mut self, time: f64, p: Vector3<f64>) {
        self.heard_time = None;
        let t = &mut self.tracker;
        if t.heard_track {
            t.reset_track();
            t.observations.clear();
            t.heard_track = false;
        }
        let last = t.observations.back().copied();
        let predicted = last.map(|_| t.predict_from_fit(time - t.fit_time));
        // A ball at rest is watched more closely: its first movement dates the launch.
        let jumped = match t.rest_position {
            Some(rest) => (p.xy() - rest).norm() > t.params.start_gate,
            // One point predicts nothing yet (its velocity is unknown).
            None if t.observations.len() < 2 => false,
            None => predicted.is_some_and(|q| (q - p.xy()).norm() > t.params.new_track_gate),
        };
        let at_rest = t.rest_position.is_some();
        if jumped || last.is_none() {
            let mut carried = arrayvec::ArrayVec::<_, TRACK_CAPACITY>::new();
            t.launch = match (last, predicted) {
                (Some(_), Some(_)) if jumped && at_rest => {
                    // The frames that had already moved a little belong to the new path.
                    let origin = t.rest_position.unwrap_or_default();
                    while t.observations.len() > 1 {
                        let Some(&(tb, pb)) = t.observations.back() else {
                            break;
                        };
                        if (pb.xy() - origin).norm() <= t.params.start_gate / 3.0 {
                            break;
                        }
                        carried.push((tb, pb));
                        t.observations.pop_back();
                    }
                    let earliest = t.observations.back().map_or(time, |(tb, _)| *tb);
                    let latest = carried.last().map_or(time, |(tb, _)| *tb);
                    Some(Launch {
                        earliest,
                        latest,
                        origin,
                        from_rest: true,
                    })
                }
                // Seen just before: the jump happened between the two frames.
                (Some((before, _)), Some(origin)) if jumped && time - before < 0.2 => {
                    Some(Launch {
                        earliest: before,
                        latest: time,
                        origin,
                        from_rest: false,
                    })
                }
                _ => None,
            };
            // Faster than any kick: the ball was placed, not kicked.
            let teleported = t.launch.is_some_and(|l| {
                let dt = (time - l.earliest).max(1e-3);
                (p.xy() - l.origin).norm() / dt > t.params.max_launch_speed_m_s
            });
            if teleported {
                t.launch = None;
                carried.clear();
            }
            // A jump with no new launch from rest (a touch on the way, a placement) is not
            // the roll that left the old spot; a jump after a teammate's report is the same
            // roll seen again.
            match t.launch {
                Some(l) if l.from_rest => t.roll_origin = Some(l.origin),
                Some(_) => t.roll_origin = None,
                None if teleported => t.roll_origin = None,
                None => {}
            }
            t.reset_track();
            t.observations.extend(carried.into_iter().rev());
        }
        if t.observations.len() == TRACK_CAPACITY {
            t.observations.pop_front();
        }
        t.observations.push_back((time, p));
        t.fit(time);
        self.learn_from_rollout();
    }

    /// When a track that was seen rolling comes to rest, compare how far it rolled with the
    /// model and move the drag factor towards the observed value.
    fn learn_from_rollout(&mut self) {
        let t = &mut self.tracker;
        let Some((start, speed)) = t.rolling_start else {
            return;
        };
        let at_rest = t.fit_velocity.norm() < t.params.rest_speed;
        if !at_rest || t.learned_from_track || speed < 0.5 {
            return;
        }
        t.learned_from_track = true;
        let rolled = (t.fit_position - start).norm();
        let predicted = t.motion.stop_distance(speed, None);
        if rolled < 0.3 || !(predicted.is_finite() && predicted > 0.0) {
            return;
        }
        // Rolling distance is roughly inversely proportional to the resistance.
        let ratio = (predicted / rolled).clamp(0.5, 2.0);
        let (lo, hi) = t.params.drag_factor_bounds;
        let factor = (self.drag_factor * ratio.powf(t.params.drag_learning_rate)).clamp(lo, hi);
        self.drag_factor = factor;
        t.drag_factor = factor;
    }

    fn publish(&mut self, time: f64) {
        let t = &self.tracker;
        if t.observations.is_empty() {
            return;
        }
        // Jitter of a ball at rest (our own pose and camera shaking while walking) fits
        // velocities of up to 1.4 m/s from a few points; carried on while the ball is out of
        // sight, they sent the robot after a ball metres from the real one.
        if !t.motion_supported {
            self.position = t.window_mean.into();
            self.velocity = [0.0; 2];
            self.acceleration = [0.0; 2];
            self.sliding = false;
            self.predicted_stop = self.position;
            return;
        }
        let dt = time - t.fit_time;
        let position = t.predict_from_fit(dt);
        let direction = t.fit_velocity.try_normalize(1e-9).unwrap_or_default();
        let speed = t.fit_velocity.norm();
        let rolls_below = t.rolls_below();
        let progress = t.motion.advance(speed, rolls_below, dt);
        let remaining = t
            .motion
            .stop_distance(progress.speed, t.rolls_below_at(progress.speed));
        self.position = [position.x, position.y];
        self.velocity = (direction * progress.speed).into();
        let decel = t
            .motion
            .deceleration(progress.speed, self.sliding_at(progress.speed));
        self.acceleration = if progress.speed > 0.0 {
            (-direction * decel).into()
        } else {
            [0.0; 2]
        };
        self.sliding = self.sliding_at(progress.speed);
        // A launch seen from its start stops where the server's physics takes it (curved path).
        let stop = match t.launched {
            Some((origin, heading, v0)) if progress.speed > 0.0 => {
                origin + t.params.launch_table.stop_offset(v0, heading)
            }
            _ => position + direction * remaining,
        };
        self.predicted_stop = stop.into();
    }

    fn sliding_at(&self, speed: f64) -> bool {
        self.tracker.rolls_below_at(speed).is_some()
    }

    /// Where the rolling ball was kicked from, when the track saw it leave a spot where it
    /// lay (a pass or a shot from rest); `None` for a ball at rest or first seen rolling.
    pub fn launched_from(&self) -> Option<[f64; 2]> {
        let rolling = self.velocity != [0.0; 2];
        self.tracker
            .roll_origin
            .filter(|_| rolling)
            .map(|o| [o.x, o.y])
    }

    /// Position after `dt` more seconds.
    pub fn predict_position(&self, dt: f64) -> [f64; 2] {
        let (origin, direction, speed, roll) = self.kinematic_state();
        let d = self.tracker.motion.advance(speed, roll, dt).distance;
        (origin + direction * d).into()
    }

    /// Where and when (seconds from now) the ball path crosses the line through `point` along
    /// `direction`, before it stops; `None` if it does not.
    pub fn line_crossing(&self, point: [f64; 2], direction: [f64; 2]) -> Option<(f64, [f64; 2])> {
        let (origin, heading, speed, roll) = self.kinematic_state();
        let (q, d) = (Vector2::from(point), Vector2::from(direction));
        // Solve origin + heading·s = q + d·u for s.
        let denom = heading.x * d.y - heading.y * d.x;
        if denom.abs() < 1e-12 || speed <= 0.0 {
            return None;
        }
        let w = q - origin;
        let s = (w.x * d.y - w.y * d.x) / denom;
        let time = self.tracker.motion.time_to_cover(speed, roll, s)?;
        (s >= 0.0).then(|| (time, (origin + heading * s).into()))
    }

    /// (position now, unit heading, speed, rolls_below) of the current prediction.
    fn kinematic_state(&self) -> (Vector2<f64>, Vector2<f64>, f64, Option<f64>) {
        let v = Vector2::from(self.velocity);
        let speed = v.norm();
        let heading = v.try_normalize(1e-9).unwrap_or_default();
        (
            Vector2::from(self.position),
            heading,
            speed,
            self.tracker.rolls_below_at(speed),
        )
    }
}

impl Tracker {
    /// The speed below which the current track rolls, if it is still sliding.
    fn rolls_below(&self) -> Option<f64> {
        self.launch_speed
            .map(|v| v * self.motion.rolling_speed_ratio)
            .filter(|_| self.rolling_start.is_none())
    }

    fn rolls_below_at(&self, speed: f64) -> Option<f64> {
        self.rolls_below().filter(|r| *r < speed)
    }

    fn predict_from_fit(&self, dt: f64) -> Vector2<f64> {
        let speed = self.fit_velocity.norm();
        let heading = self.fit_velocity.try_normalize(1e-9).unwrap_or_default();
        let d = self.motion.advance(speed, self.rolls_below(), dt).distance;
        self.fit_position + heading * d
    }

    /// Least-squares fit of position, velocity and acceleration at `now` over the window.
    /// Forget the current track (its points and what was fitted from them).
    fn reset_track(&mut self) {
        self.observations.clear();
        self.launch_speed = None;
        self.launched = None;
        self.rest_position = None;
        self.rolling_start = None;
        self.learned_from_track = false;
    }

    fn fit(&mut self, now: f64) {
        let window = self.params.fit_window_s + 1e-6;
        let points: arrayvec::ArrayVec<(f64, Vector2<f64>), TRACK_CAPACITY> = self
            .observations
            .iter()
            .take(TRACK_CAPACITY)
            .filter(|(t, _)| now - t <= window)
            .map(|(t, p)| (t - now, p.xy()))
            .collect();
        let (position, velocity, acceleration) = fit_polynomial(&points);
        // Friction depends on the direction of travel; the path of a young track from rest
        // is best given by where it left.
        let heading_vector = match self.launch {
            Some(l) if l.from_rest => self
                .observations
                .back()
                .map_or(velocity, |(_, p)| p.xy() - l.origin),
            _ => velocity,
        };
        if heading_vector.norm() > 1e-6 {
            let heading = heading_vector.y.atan2(heading_vector.x);
            self.motion = BallMotion::new(&self.params, self.drag_factor, heading);
        }
        self.fit_time = now;
        self.fit_position = position;
        self.fit_velocity = if velocity.norm() < self.params.rest_speed {
            Vector2::zeros()
        } else {
            velocity
        };
        // Shortly after a launch the path crosses from sliding to rolling, which a polynomial
        // cannot follow: fit the motion model itself (launch speed and time) instead.
        if let Some(launch) = self.launch {
            let young = now - launch.latest <= self.params.launch_fit_s;
            if young && self.observations.len() >= LAUNCH_WINDOW_MIN_POINTS {
                let guess = launch.time_on(position, velocity, acceleration, now);
                if let Some(fit) = self.fit_launch(&launch, guess, velocity, now) {
                    self.fit_position = fit.position;
                    self.fit_velocity = fit.velocity;
                    self.launch_speed = Some(fit.launch_speed);
                    self.launched = Some((fit.origin, fit.heading, fit.launch_speed));
                }
            } else if self.launch_speed.is_none() {
                self.launch_speed = Some(self.fit_velocity.norm());
            }
        }
        // At rest when the fit says so, or when the window's points do not move even though a
        // jump started a launch fit: the jump was our own relocalization (moving the ball as
        // seen from our pose estimate), and a real launch must find the ball at rest again.
        let settled = points.len() >= LAUNCH_WINDOW_MIN_POINTS
            && (self.fit_velocity.norm() == 0.0 || velocity.norm() < self.params.rest_speed);
        self.window_mean =
            points.iter().map(|(_, p)| p).sum::<Vector2<f64>>() / points.len().max(1) as f64;
        if settled {
            self.roll_origin = None;
            if self.launched.is_some() {
                self.launch = None;
                self.launched = None;
                self.launch_speed = None;
            }
            self.fit_velocity = Vector2::zeros();
            // Where it lies: the mean of the window, following the slow drift of our own pose
            // estimate (a stale rest point would make noise look like a start).
            self.rest_position = Some(self.window_mean);
        }
        self.motion_supported = self.fit_velocity.norm() > 0.0
            && moves_beyond_scatter(
                &points,
                self.params.scatter_floor_m,
                self.params.motion_significance,
            );
        let speed = self.fit_velocity.norm();
        let position = self.fit_position;
        // Rolling once the speed is down to the rolling speed, or when a track that did not
        // start with a visible launch decelerates like a rolling ball.
        if self.rolling_start.is_none() && speed > 0.0 && points.len() >= 4 {
            let along = -acceleration.dot(&self.fit_velocity) / speed;
            let threshold = 0.5
                * (self.motion.deceleration(speed, true) + self.motion.deceleration(speed, false));
            let launched_rolling = self.rolls_below().is_some_and(|r| speed <= r);
            let decelerates_like_rolling = self.launch.is_none() && along < threshold;
            if launched_rolling || decelerates_like_rolling {
                self.rolling_start = Some((position, speed));
            }
        }
    }
}

/// Whether the points move more than their scatter explains: the velocity of a straight line
/// fitted to them over its standard error (both axes; the scatter about the line, at least
/// `scatter_floor`), above `significance`. Fewer than four points never do.
fn moves_beyond_scatter(
    points: &[(f64, Vector2<f64>)],
    scatter_floor: f64,
    significance: f64,
) -> bool {
    let n = points.len();
    if n < 4 {
        return false;
    }
    let count = n as f64;
    let mean_t = points.iter().map(|(t, _)| t).sum::<f64>() / count;
    let mean_p = points.iter().map(|(_, p)| p).sum::<Vector2<f64>>() / count;
    let spread_t: f64 = points.iter().map(|(t, _)| (t - mean_t).powi(2)).sum();
    if spread_t <= 0.0 {
        return false;
    }
    let slope = points
        .iter()
        .map(|(t, p)| (p - mean_p) * (t - mean_t))
        .sum::<Vector2<f64>>()
        / spread_t;
    let residual: f64 = points
        .iter()
        .map(|(t, p)| (p - mean_p - slope * (t - mean_t)).norm_squared())
        .sum();
    let scatter = (residual / (2.0 * (count - 2.0))).sqrt().max(scatter_floor);
    slope.norm() * spread_t.sqrt() / scatter > significance
}

/// Fit `p(τ) = p0 + v·τ + ½a·τ²` to (τ, p) points (τ ≤ 0); falls back to a line with two
/// points and to the point itself with one.
fn fit_polynomial(points: &[(f64, Vector2<f64>)]) -> (Vector2<f64>, Vector2<f64>, Vector2<f64>) {
    let zero = Vector2::zeros();
    match points {
        [] => (zero, zero, zero),
        [(_, p)] => (*p, zero, zero),
        _ => {
            let span = points.last().unwrap().0 - points[0].0;
            let quadratic = points.len() >= 4 && span > 0.1;
            let n = if quadratic { 3 } else { 2 };
            let mut normal = nalgebra::Matrix3::<f64>::zeros();
            let mut rhs = nalgebra::Matrix3x2::<f64>::zeros();
            for (tau, p) in points {
                let basis = [1.0, *tau, 0.5 * tau * tau];
                for i in 0..n {
                    for j in 0..n {
                        normal[(i, j)] += basis[i] * basis[j];
                    }
                    rhs[(i, 0)] += basis[i] * p.x;
                    rhs[(i, 1)] += basis[i] * p.y;
                }
            }
            if !quadratic {
                normal[(2, 2)] = 1.0;
            }
            match normal.try_inverse() {
                Some(inverse) => {
                    let c = inverse * rhs;
                    let row = |i: usize| Vector2::new(c[(i, 0)], c[(i, 1)]);
                    let (p, v, a) = (row(0), row(1), row(2));
                    if p.iter()
                        .chain(v.iter())
                        .chain(a.iter())
                        .all(|x| x.is_finite())
                    {
                        (p, v, a)
                    } else {
                        (points.last().unwrap().1, zero, zero)
                    }
                }
                None => (points.last().unwrap().1, zero, zero),
            }
        }
    }
}

#[path = "ball_launch_fit.rs"]
mod launch_fit;

#[path = "ball_interception.rs"]
mod interception;

#[cfg(test)]
#[path = "ball_tests.rs"]
mod tests;
