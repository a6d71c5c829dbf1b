//! Getting to the kicking place from anywhere around the ball, without bumping into it.
//!
//! Everything is in the robot frame (x forwards, y left, the torso origin at 0). The kicking
//! place puts the ball in front of the kicking foot with the robot facing the kick direction.
//! A straight path that would pass the ball closer than the clearance is replaced by walking
//! around the ball on the clearance circle, towards the side behind it; close to the place the
//! robot aligns with small omnidirectional steps.

use super::params::{ApproachPath, KickApproach};
use crate::walk::gait::Foot;
use crate::walk::{walk_to, Velocity, WalkParams};
use libero_world::geometry::wrap_deg;
use nalgebra::{Rotation2, Vector2};

/// What the approach wants this cycle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ApproachStep {
    /// Walk with this command.
    Walk(Velocity),
    /// Near the kicking place (within `look_within_m` and `look_within_deg`) but not within the
    /// kick's tolerances: this small-step command brings it closer.
    Align(Velocity),
    /// At the kicking place (within the tolerances).
    Ready,
}

/// The kicking place for `foot`: torso position in the robot frame and heading [deg].
pub fn kicking_place(
    ball: [f64; 2],
    direction_deg: f64,
    foot: Foot,
    a: &KickApproach,
) -> ([f64; 2], f64) {
    let d = Vector2::new(
        direction_deg.to_radians().cos(),
        direction_deg.to_radians().sin(),
    );
    let left = Vector2::new(-d.y, d.x);
    let p = Vector2::from(ball) - d * a.ball_ahead_m - left * (foot.sign() * a.ball_beside_m);
    ([p.x, p.y], direction_deg)
}

/// The foot that needs the shorter way: with the robot to the right of the line through the
/// ball along the kick direction, the ball is best kicked with the left foot, and vice versa.
pub fn natural_foot(ball: [f64; 2], direction_deg: f64) -> Foot {
    let d = Vector2::new(
        direction_deg.to_radians().cos(),
        direction_deg.to_radians().sin(),
    );
    let left = Vector2::new(-d.y, d.x);
    let robot_from_ball = -Vector2::from(ball);
    if robot_from_ball.dot(&left) < 0.0 {
        Foot::Left
    } else {
        Foot::Right
    }
}

/// Distance from `c` to the segment from `a` to `b`.
pub(crate) fn segment_distance(a: Vector2<f64>, b: Vector2<f64>, c: Vector2<f64>) -> f64 {
    let ab = b - a;
    let s = if ab.norm_squared() > 0.0 {
        ((c - a).dot(&ab) / ab.norm_squared()).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (a + ab * s - c).norm()
}

/// Angle of the arc step taken around the ball per waypoint [deg].
const ARC_STEP_DEG: f64 = 40.0;

/// How far the look zone widens once the robot has stopped in it: walking estimates jitter,
/// and a robot on its edge would otherwise start and stop walking without end.
const LOOK_ZONE_HYSTERESIS: f64 = 2.0;

/// How far the torso still travels (x, y [m], robot frame) and turns [deg] after a stop is
/// asked for while the walk executes `executed`: the walk brakes at its acceleration limits,
/// and the step under way (`a.stop_lead_steps` of one step's length) is finished first.
pub fn stopping_travel(executed: Velocity, a: &KickApproach, w: &WalkParams) -> [f64; 3] {
    let axis = |v: f64, accel: f64| {
        let braking = if accel > 0.0 {
            v * v.abs() / (2.0 * accel)
        } else {
            0.0
        };
        braking + v * w.step_period_s * a.stop_lead_steps
    };
    [
        axis(executed.forward_m_s, w.decel_forward_m_s2()),
        axis(executed.sideways_m_s, w.accel_sideways_m_s2),
        axis(executed.turn_deg_s, w.accel_turn_deg_s2),
    ]
}

/// Whether the robot, `travel` (see [`stopping_travel`]) short of where it would come to rest,
/// is within the kick's tolerances (times `scale`) of the kicking place `place` (robot frame) with heading
/// `heading` [deg].
fn within_tolerances(
    place: Vector2<f64>,
    heading: f64,
    travel: [f64; 3],
    scale: f64,
    a: &KickApproach,
) -> bool {
    // The place as seen from where the robot stops, in that rest pose's frame.
    let turned = travel[2];
    let from_rest =
        Rotation2::new(-turned.to_radians()) * (place - Vector2::new(travel[0], travel[1]));
    let heading = wrap_deg(heading - turned);
    // Errors along and across the kick direction decide readiness: along matters for the
    // contact timing, across for where the foot meets the ball.
    let d = Vector2::new(heading.to_radians().cos(), heading.to_radians().sin());
    from_rest.dot(&d).abs() <= a.ready_along_m * scale
        && from_rest.perp(&d).abs() <= a.ready_across_m * scale
        && heading.abs() <= a.ready_deg * scale
}

/// Where the robot is in its approach, besides its place relative to the ball.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Moving {
    /// The robot has stopped to look near the place (the look zone is then wider).
    pub looking: bool,
    /// How far the robot would still move if asked to stop now ([`stopping_travel`]; zeros
    /// when standing): while walking, the place counts as reached when the robot would come
    /// to rest within the tolerances, so the kick follows the walk without a look-and-correct
    /// loop.
    pub travel: [f64; 3],
    /// The tolerances are scaled by this (1: the kick's own): walking, the robot stops only
    /// well within them, so that it still is within them after the look.
    pub tolerance_scale: f64,
}

/// This cycle's approach command.
pub fn step(
    ball: [f64; 2],
    direction_deg: f64,
    foot: Foot,
    moving: Moving,
    a: &KickApproach,
    w: &WalkParams,
) -> ApproachStep {
    let Moving {
        looking,
        travel,
        tolerance_scale,
    } = moving;
    let (place, heading) = kicking_place(ball, direction_deg, foot, a);
    let b = Vector2::from(ball);
    let p = Vector2::from(place);
    let robot = Vector2::zeros();
    let heading_error = wrap_deg(heading);
    let distance = p.norm();
    // The waypoint approach aligns past the ball a little nearer than it walks round it; the
    // path approach (which comes in faster) keeps the whole clearance.
    let near_clearance = if a.path.is_some() { 1.0 } else { 0.8 };
    if distance <= a.align_within_m
        && segment_distance(robot, p, b) >= a.clearance_m * near_clearance
    {
        if within_tolerances(p, heading, travel, tolerance_scale, a) {
            return ApproachStep::Ready;
        }
        let widen = if looking { LOOK_ZONE_HYSTERESIS } else { 1.0 };
        let coarse =
            p.norm() > a.look_within_m * widen || heading_error.abs() > a.look_within_deg * widen;
        let v = p * a.align_gain_per_s;
        // On the path approach the last part is walked at the braking profile's speed, not
        // at the slow alignment speed.
        let cap = match &a.path {
            Some(path) => braking_speed(distance, path, a).max(a.align_min_speed_m_s),
            None => a.align_speed_m_s,
        };
        let scale = (v.norm() / cap).max(1.0);
        // Small position errors are walked off at the slowest speed that still moves.
        let scale = if v.norm() > 1e-9 {
            scale.min(v.norm() / a.align_min_speed_m_s)
        } else {
            scale
        };
        let v = Velocity {
            forward_m_s: v.x / scale,
            sideways_m_s: v.y / scale,
            turn_deg_s: (a.align_turn_gain_per_s * heading_error)
                .clamp(-w.max_turn_deg_s, w.max_turn_deg_s),
        };
        // Far from the tolerances, walking estimates are good enough: align on the move.
        return if coarse {
            ApproachStep::Walk(v)
        } else {
            ApproachStep::Align(v)
        };
    }
    if let Some(path) = &a.path {
        return ApproachStep::Walk(path_velocity(b, p, heading_error, a, path, w));
    }
    let v = walk_round_ball(
        b,
        p,
        heading_error,
        Clearance {
            clearance_m: a.clearance_m,
            circle_radius_m: a.circle_radius_m,
            face_travel_beyond_deg: a.face_travel_beyond_deg,
        },
        w,
    );
    let v = v.capped(Some(a.approach_speed_m_s));
    ApproachStep::Walk(Velocity {
        turn_deg_s: v
            .turn_deg_s
            .clamp(-a.approach_turn_deg_s, a.approach_turn_deg_s),
        ..v
    })
}

/// The fastest speed [m/s] from which braking at the path's rate stops within `left_m`,
/// within the approach's cap.
///
/// The walk keeps the speed of the step under way, and a new command takes a step to show:
/// the robot goes on for `lag_s` before it brakes, so the speed v must satisfy
/// v·lag + v²/(2·brake) ≤ left.
fn braking_speed(left_m: f64, path: &ApproachPath, a: &KickApproach) -> f64 {
    let (brake, lag) = (path.brake_m_s2, path.lag_s);
    (brake * (-lag + (lag * lag + 2.0 * left_m.max(0.0) / brake).sqrt())).min(a.approach_speed_m_s)
}

/// The shortest way from the robot to the kicking place round the ball (see
/// [`way_to_place`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Way {
    /// Which way to walk now (unit, robot frame).
    pub direction: Vector2<f64>,
    /// Straight on to the circle round the ball [m] (0: on it, or no need to go round) ...
    pub to_circle_m: f64,
    /// ... along the circle [m] ...
    pub round_m: f64,
    /// ... and straight on to the place [m].
    pub straight_m: f64,
}

impl Way {
    pub fn length_m(&self) -> f64 {
        self.to_circle_m + self.round_m + self.straight_m
    }
}

/// The shortest way from the robot (the origin) to `place` that keeps `clearance` from the
/// ball at `ball`. Straight when the segment passes the ball far enough; otherwise along the
/// tangent to the circle of `radius` round the ball, on round it the shorter way, then
/// straight to the place.
pub fn way_to_place(ball: Vector2<f64>, place: Vector2<f64>, clearance: f64, radius: f64) -> Way {
    let robot = Vector2::zeros();
    if segment_distance(robot, place, ball) >= clearance {
        return Way {
            direction: place.try_normalize(1e-9).unwrap_or_else(Vector2::x),
            to_circle_m: 0.0,
            round_m: 0.0,
            straight_m: place.norm(),
        };
    }
    let from = robot - ball;
    let to = place - ball;
    let distance = from.norm();
    let radial = from.try_normalize(1e-9).unwrap_or_else(|| -to.normalize());
    // Round the ball the shorter way: +1 anticlockwise.
    let arc = from.perp(&to).atan2(from.dot(&to));
    let sense = if arc >= 0.0 { 1.0 } else { -1.0 };
    let straight_m = (to.norm() - radius).abs();
    if distance > radius {
        // Along the tangent: it touches the circle `touch` round from the robot's bearing.
        let touch = (radius / distance).acos();
        let tangent_point = ball + Rotation2::new(sense * touch) * radial * radius;
        let to_tangent = tangent_point - robot;
        Way {
            direction: to_tangent.try_normalize(1e-9).unwrap_or(radial),
            to_circle_m: to_tangent.norm(),
            round_m: (arc.abs() - touch).max(0.0) * radius,
            straight_m,
        }
    } else {
        // On or inside the circle: along it, drifting out to its radius.
        let tangent = Rotation2::new(sense * std::f64::consts::FRAC_PI_2) * radial;
        let out = radial * ((radius - distance) / radius.max(1e-9));
        Way {
            direction: (tangent + out).try_normalize(1e-9).unwrap_or(tangent),
            to_circle_m: 0.0,
            round_m: arc.abs() * radius,
            straight_m,
        }
    }
}

/// The path approach's walk command towards `place` (robot frame), ending with heading
/// `heading_deg` (relative), round the ball at `ball`.
fn path_velocity(
    ball: Vector2<f64>,
    place: Vector2<f64>,
    heading_deg: f64,
    a: &KickApproach,
    path: &ApproachPath,
    w: &WalkParams,
) -> Velocity {
    // Outside the cone behind the place, the way leads to the line-up point behind it on the
    // kick line first, so that the last part is walked straight along the kick direction.
    let h = heading_deg.to_radians();
    let d = Vector2::new(h.cos(), h.sin());
    let from_place = -place;
    let along = from_place.dot(&d);
    let across = from_place.perp(&d).abs();
    let in_cone = along <= 0.0 && across <= path.cone_slope * -along + path.cone_margin_m;
    let (way, after) = if in_cone {
        (
            way_to_place(ball, place, a.clearance_m, a.circle_radius_m),
            0.0,
        )
    } else {
        let line_up = place - d * path.line_up_m;
        (
            way_to_place(ball, line_up, a.clearance_m, a.circle_radius_m),
            path.line_up_m,
        )
    };
    let left = way.length_m() + after;
    let travel_deg = way.direction.y.atan2(way.direction.x).to_degrees();
    let span = (path.face_travel_beyond_m - path.face_kick_within_m).max(1e-9);
    let blend = ((left - path.face_kick_within_m) / span).clamp(0.0, 1.0);
    let facing = wrap_deg(heading_deg + wrap_deg(travel_deg - heading_deg) * blend);
    // Stop at the place; on the circle no faster than the turn keeps up with its curve, and
    // on the way to it slow enough to get onto it.
    let mut speed = braking_speed(left, path, a);
    if way.round_m > 0.0 {
        let on_circle = a.approach_turn_deg_s.to_radians() * a.circle_radius_m;
        speed = speed.min((on_circle * on_circle + 2.0 * path.brake_m_s2 * way.to_circle_m).sqrt());
    }
    // Turned away from the way to go, turn first: walking backwards or sideways is slow, and
    // the walk's limits share one budget between turning and walking.
    let facing_travel = wrap_deg(travel_deg).to_radians().cos().max(0.0);
    let speed = speed * facing_travel.max(1.0 - blend);
    let turn = (path.turn_gain_per_s * facing).clamp(-a.approach_turn_deg_s, a.approach_turn_deg_s);
    crate::walk::clamp_command(
        Velocity {
            forward_m_s: way.direction.x * speed,
            sideways_m_s: way.direction.y * speed,
            turn_deg_s: turn,
        },
        w,
    )
}

/// How wide a berth the robot gives the ball on its way to a place beside or behind it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Clearance {
    /// Straight paths keep the torso at least this far from the ball centre [m] ...
    pub clearance_m: f64,
    /// ... otherwise the robot walks round the ball on a circle of this radius [m] ...
    pub circle_radius_m: f64,
    /// ... facing the way it walks while more than this arc is left [deg] (see
    /// `KickApproach::face_travel_beyond_deg`).
    pub face_travel_beyond_deg: f64,
}

/// The walk command towards `place` (robot frame) ending with heading `heading_deg` (relative
/// to the current one), never through the ball at `ball`: a straight path that would pass it
/// closer than the clearance becomes a walk round it on the clearance circle, towards the
/// place the shorter way.
pub fn walk_round_ball(
    ball: Vector2<f64>,
    place: Vector2<f64>,
    heading_deg: f64,
    c: Clearance,
    w: &WalkParams,
) -> Velocity {
    let (b, p) = (ball, place);
    let robot = Vector2::zeros();
    let target = if segment_distance(robot, p, b) >= c.clearance_m {
        p
    } else {
        // Around the ball: the next point on the clearance circle, turning from where the robot
        // is towards the place the shorter way.
        let from = robot - b;
        let to = p - b;
        let turn = from.perp(&to).atan2(from.dot(&to)).to_degrees();
        let step = turn.clamp(-ARC_STEP_DEG, ARC_STEP_DEG);
        let dir =
            Rotation2::new(step.to_radians()) * from.try_normalize(1e-9).unwrap_or(-to.normalize());
        let waypoint = b + dir * c.circle_radius_m;
        let heading = facing_on_the_circle(waypoint, heading_deg, turn, c.face_travel_beyond_deg);
        return walk_to::velocity_towards([waypoint.x, waypoint.y], heading, w).unwrap_or_default();
    };
    walk_to::velocity_towards([target.x, target.y], heading_deg, w).unwrap_or_default()
}

/// The heading [deg, robot frame] to hold on the way to `waypoint` on the circle round the
/// ball with `arc_left_deg` still to go: the way of travel while more than `beyond_deg` is
/// left, the final `heading_deg` with less than half of it, blended in between.
fn facing_on_the_circle(
    waypoint: Vector2<f64>,
    heading_deg: f64,
    arc_left_deg: f64,
    beyond_deg: f64,
) -> f64 {
    let travel = waypoint.y.atan2(waypoint.x).to_degrees();
    let half = beyond_deg * 0.5;
    let blend = ((arc_left_deg.abs() - half) / half.max(1e-9)).clamp(0.0, 1.0);
    wrap_deg(heading_deg + wrap_deg(travel - heading_deg) * blend)
}

#[cfg(test)]
mod tests;
