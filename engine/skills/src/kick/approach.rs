//! Getting to the kicking place from anywhere around the ball, without bumping into it.
//!
//! Everything is in the robot frame (x forwards, y left, the torso origin at 0). The kicking
//! place puts the ball in front of the kicking foot with the robot facing the kick direction.
//! A straight path that would pass the ball closer than the clearance is replaced by walking
//! around the ball on the clearance circle, towards the side behind it; close to the place the
//! robot aligns with small omnidirectional steps.

use super::params::KickApproach;
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
        axis(executed.forward_m_s, w.accel_forward_m_s2),
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
    if distance <= a.align_within_m && segment_distance(robot, p, b) >= a.clearance_m * 0.8 {
        if within_tolerances(p, heading, travel, tolerance_scale, a) {
            return ApproachStep::Ready;
        }
        let widen = if looking { LOOK_ZONE_HYSTERESIS } else { 1.0 };
        let coarse =
            p.norm() > a.look_within_m * widen || heading_error.abs() > a.look_within_deg * widen;
        let v = p * a.align_gain_per_s;
        let scale = (v.norm() / a.align_speed_m_s).max(1.0);
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
mod tests {
    use super::*;

    const STILL: Moving = Moving {
        looking: false,
        travel: [0.0; 3],
        tolerance_scale: 1.0,
    };
    const LOOKING: Moving = Moving {
        looking: true,
        ..STILL
    };

    fn params() -> (KickApproach, WalkParams) {
        let t1 = libero_model::RobotModel::builtin("T1").unwrap();
        let p = crate::SkillParams::builtin(&t1).unwrap();
        (p.kick.approach, p.walk)
    }

    #[test]
    fn the_kicking_place_puts_the_ball_ahead_of_the_kicking_foot() {
        let (a, _) = params();
        let (place, heading) = kicking_place([1.0, 0.0], 90.0, Foot::Right, &a);
        assert_eq!(heading, 90.0);
        // Kicking towards +y with the right foot: the robot faces +y with the ball to its
        // right (+x), so it stands below the ball and to its −x.
        assert!(
            (place[0] - (1.0 - a.ball_beside_m)).abs() < 1e-9,
            "{place:?}"
        );
        assert!((place[1] + a.ball_ahead_m).abs() < 1e-9, "{place:?}");
    }

    #[test]
    fn from_in_front_of_the_ball_the_path_goes_around_it() {
        let (a, w) = params();
        // Ball 0.6 m ahead, to be kicked back towards the robot: the place is behind the ball.
        let ApproachStep::Walk(v) = step([0.6, 0.0], 180.0, Foot::Left, STILL, &a, &w) else {
            panic!("not ready from the wrong side");
        };
        // Not straight at the ball: sideways first.
        assert!(
            v.sideways_m_s.abs() > 0.01 || v.turn_deg_s.abs() > 1.0,
            "{v:?}"
        );
        let ApproachStep::Walk(v) = step([1.0, 0.0], 0.0, Foot::Left, STILL, &a, &w) else {
            panic!("not ready 1 m away");
        };
        assert!(v.forward_m_s > 0.0, "{v:?}");
    }

    #[test]
    fn round_the_ball_it_faces_the_way_it_walks_and_turns_to_the_kick_heading_near_the_place() {
        // Travel bearing 45°, kick heading -90°: far round the arc it faces the travel, near
        // the place the kick heading, half way between them in the blend.
        let waypoint = Vector2::new(0.3, 0.3);
        assert!((facing_on_the_circle(waypoint, -90.0, 120.0, 60.0) - 45.0).abs() < 1e-9);
        assert!((facing_on_the_circle(waypoint, -90.0, -20.0, 60.0) + 90.0).abs() < 1e-9);
        assert!((facing_on_the_circle(waypoint, -90.0, 45.0, 60.0) + 22.5).abs() < 1e-9);
        // 360 (off): always the kick heading.
        assert!((facing_on_the_circle(waypoint, -90.0, 179.0, 360.0) + 90.0).abs() < 1e-9);

        // The ball beside the robot, the place on its far side: walking round it, the robot
        // turns towards the way it walks (the next point of the circle, ahead and to the
        // left, behind) with the shipped T1 numbers; without, towards the kick heading (-60°).
        let (mut a, w) = params();
        let ball = [0.0, 0.45];
        let turn = |a: &KickApproach| {
            let ApproachStep::Walk(v) = step(ball, -60.0, Foot::Left, STILL, a, &w) else {
                panic!("ready beside the ball");
            };
            v.turn_deg_s
        };
        assert!(a.face_travel_beyond_deg < 180.0);
        let facing = turn(&a);
        a.face_travel_beyond_deg = 360.0;
        let heading = turn(&a);
        assert!(facing > 5.0 && heading < -5.0, "{facing} vs {heading}");
    }

    #[test]
    fn at_the_place_it_is_ready() {
        let (a, w) = params();
        let ball = [a.ball_ahead_m, a.ball_beside_m];
        assert_eq!(
            step(ball, 0.0, Foot::Left, STILL, &a, &w),
            ApproachStep::Ready
        );
        // Slightly off: stop, look and correct; further off: align on the move.
        let slightly = 0.5 * (a.ready_deg + a.look_within_deg);
        assert!(matches!(
            step(ball, slightly, Foot::Left, STILL, &a, &w),
            ApproachStep::Align(v) if v.turn_deg_s > 0.0
        ));
        let beyond = a.look_within_deg + 2.0;
        assert!(matches!(
            step(ball, beyond, Foot::Left, STILL, &a, &w),
            ApproachStep::Walk(v) if v.turn_deg_s > 0.0
        ));
        // Once stopped to look, the same error is corrected from standing.
        assert!(matches!(
            step(ball, beyond, Foot::Left, LOOKING, &a, &w),
            ApproachStep::Align(v) if v.turn_deg_s > 0.0
        ));
        assert_eq!(natural_foot(ball, 0.0), Foot::Left);
    }
}
