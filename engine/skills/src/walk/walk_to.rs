//! Walking to a pose given relative to the robot: a proportional controller on distance and
//! heading that faces the target when far away and walks omnidirectionally when near.

use super::params::WalkParams;
use super::Velocity;

/// The command that brings the robot to `target` = (x, y) [m] in its own frame (x forwards,
/// y left) with final heading `heading_deg` relative to its current heading; `None` once there.
pub fn velocity_towards(target: [f64; 2], heading_deg: f64, p: &WalkParams) -> Option<Velocity> {
    let t = &p.walk_to;
    let [x, y] = target;
    let distance = x.hypot(y);
    if distance < t.arrive_m && heading_deg.abs() < t.arrive_deg {
        return None;
    }
    velocity(target, heading_deg, p)
}

/// As [`velocity_towards`] for a robot standing still: `None` until the target is beyond
/// `restart_m` or `restart_deg`.
pub fn velocity_from_rest(target: [f64; 2], heading_deg: f64, p: &WalkParams) -> Option<Velocity> {
    let t = &p.walk_to;
    if target[0].hypot(target[1]) < t.restart_m && heading_deg.abs() < t.restart_deg {
        return None;
    }
    velocity_towards(target, heading_deg, p)
}

fn velocity(target: [f64; 2], heading_deg: f64, p: &WalkParams) -> Option<Velocity> {
    let t = &p.walk_to;
    let [x, y] = target;
    let distance = x.hypot(y);
    let bearing_deg = y.atan2(x).to_degrees();
    let (forward, sideways, turn_error_deg) = if distance > t.face_target_beyond_m {
        // Far: turn to face the target and walk forwards, slowing down while badly turned.
        let alignment = bearing_deg.to_radians().cos().max(0.0);
        (t.gain_per_s * distance * alignment, 0.0, bearing_deg)
    } else {
        (t.gain_per_s * x, t.gain_per_s * y, heading_deg)
    };
    Some(
        Velocity {
            forward_m_s: forward,
            sideways_m_s: sideways,
            turn_deg_s: (t.turn_gain_per_s * turn_error_deg)
                .clamp(-p.max_turn_deg_s, p.max_turn_deg_s),
        }
        .within_limits(p),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_standing_robot_ignores_a_target_wobbling_within_the_restart_band() {
        let model = libero_model::RobotModel::builtin("T1").unwrap();
        let p = crate::SkillParams::builtin(&model).unwrap().walk;
        let t = &p.walk_to;
        // Walking, anything beyond the arrival tolerance is walked to.
        let wobble = [t.arrive_m * 2.0, 0.0];
        assert!(velocity_towards(wobble, 0.0, &p).is_some());
        // Standing, the same wobble (and a few degrees of heading) leave the robot standing.
        assert!(velocity_from_rest(wobble, t.arrive_deg * 1.5, &p).is_none());
        // Beyond the band it walks again.
        assert!(velocity_from_rest([t.restart_m * 1.1, 0.0], 0.0, &p).is_some());
        assert!(velocity_from_rest([0.0, 0.0], t.restart_deg * 1.1, &p).is_some());
    }
}
