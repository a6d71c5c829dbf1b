//! Dribbling (thesis 6.3): walking the ball towards a target without stopping.
//!
//! Robot frame throughout (x forwards, y left, torso origin at 0). The robot first lines up
//! behind the ball on the line along the dribble direction — walking round the ball when it is
//! on the wrong side — and then walks on through it: each step's foot pushes the ball ahead,
//! the robot steers sideways so the ball stays in front of the middle of its feet, and turns
//! with the line when the direction changes. Lined up, nothing slows it down near the ball.

use crate::kick::approach::{walk_round_ball, Clearance};
use crate::walk::gait::Foot;
use crate::walk::params::{in_range, Check};
use crate::walk::{Velocity, WalkParams};
use libero_world::geometry::wrap_deg;
use nalgebra::Vector2;
use serde::{Deserialize, Serialize};

/// The dribble's numbers (`dribble:` in the skill parameter file).
#[derive(Debug, Clone, Copy, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct DribbleParams {
    /// Lined up, the torso is this far behind the ball centre [m] ...
    pub behind_m: f64,
    /// ... and this far to the side of the ball's line, so the ball is in front of one foot
    /// [m]: with the ball between the feet the robot stepped onto it and fell.
    pub ball_beside_m: f64,
    /// Pushing starts when the robot is behind the ball (at least `min_behind_m` [m]), within
    /// `capture_across_m` [m] of the line or `capture_cone_deg` [deg] of it as seen from the
    /// ball (far behind, a wider offset closes on the way), and faces the line within
    /// `capture_deg` [deg] ...
    pub min_behind_m: f64,
    pub capture_across_m: f64,
    pub capture_cone_deg: f64,
    pub capture_deg: f64,
    /// ... and stops beyond these (across [m], heading [deg]), or once the robot is no longer
    /// behind the ball.
    pub release_across_m: f64,
    pub release_deg: f64,
    /// Forward speed while pushing [m/s] ...
    pub push_speed_m_s: f64,
    /// ... and while catching up with a ball more than `catch_up_beyond_m` [m] ahead.
    pub catch_up_speed_m_s: f64,
    pub catch_up_beyond_m: f64,
    /// Sideways correction per metre off the line [1/s] and turn per degree of heading error
    /// [1/s] while pushing, the turn at most `push_turn_deg_s`.
    pub across_gain_per_s: f64,
    /// ... the sideways correction at most `push_sideways_m_s` [m/s] (stepping sideways into
    /// the ball at speed tripped the robot over it).
    pub push_sideways_m_s: f64,
    pub turn_gain_per_s: f64,
    pub push_turn_deg_s: f64,
    /// Lining up: speed cap [m/s], turn cap [deg/s], and the berth given to the ball (straight
    /// paths keep `clearance_m` from it, else the robot walks round it on `circle_radius_m`).
    pub line_up_speed_m_s: f64,
    pub line_up_turn_deg_s: f64,
    pub clearance_m: f64,
    pub circle_radius_m: f64,
    /// As the kick approach's `face_travel_beyond_deg`: walking round the ball, face the way
    /// of travel while more than this arc is left [deg]; 360: always the line's heading.
    #[serde(default = "crate::walk::face_travel_off")]
    pub face_travel_beyond_deg: f64,
    /// When to kick the ball on with a kick step of the walk (`walk.kick_step`) instead of
    /// walking it on (`None`: never).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub kick: Option<DribbleKickParams>,
}

/// Where the ball must be for a dribble's kick step: ahead of the torso between
/// `ahead_min_m` and `ahead_max_m` [m] when the step begins, within `across_m` [m] of the
/// kicking foot's line, the robot facing the dribble's line within `heading_deg` [deg].
#[derive(Debug, Clone, Copy, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct DribbleKickParams {
    pub ahead_min_m: f64,
    pub ahead_max_m: f64,
    pub across_m: f64,
    pub heading_deg: f64,
    /// The kicked ball goes straight on when it lies this far inside the kicking foot's
    /// neutral line (towards the other foot) [m]; the strike shifts the foot across by the
    /// difference.
    pub ball_inside_m: f64,
}

impl Default for DribbleParams {
    fn default() -> Self {
        Self {
            behind_m: 0.3,
            ball_beside_m: 0.1,
            min_behind_m: 0.15,
            capture_across_m: 0.08,
            capture_cone_deg: 12.0,
            capture_deg: 15.0,
            release_across_m: 0.2,
            release_deg: 40.0,
            push_speed_m_s: 0.4,
            catch_up_speed_m_s: 0.55,
            catch_up_beyond_m: 0.8,
            across_gain_per_s: 1.5,
            push_sideways_m_s: 0.1,
            turn_gain_per_s: 1.5,
            push_turn_deg_s: 30.0,
            line_up_speed_m_s: 0.45,
            line_up_turn_deg_s: 40.0,
            clearance_m: 0.3,
            circle_radius_m: 0.45,
            face_travel_beyond_deg: crate::walk::face_travel_off(),
            kick: None,
        }
    }
}

impl DribbleParams {
    pub fn validate(&self) -> Check {
        let p = |name: &str| format!("dribble.{name}");
        in_range(&p("behind_m"), self.behind_m, 0.05, 2.0)?;
        in_range(&p("ball_beside_m"), self.ball_beside_m, 0.0, 0.5)?;
        in_range(&p("min_behind_m"), self.min_behind_m, 0.0, self.behind_m)?;
        in_range(&p("capture_across_m"), self.capture_across_m, 0.0, 1.0)?;
        in_range(&p("capture_cone_deg"), self.capture_cone_deg, 0.0, 60.0)?;
        in_range(&p("capture_deg"), self.capture_deg, 0.0, 90.0)?;
        in_range(
            &p("release_across_m"),
            self.release_across_m,
            self.capture_across_m,
            2.0,
        )?;
        in_range(&p("release_deg"), self.release_deg, self.capture_deg, 180.0)?;
        in_range(&p("push_speed_m_s"), self.push_speed_m_s, 0.01, 2.0)?;
        in_range(&p("catch_up_speed_m_s"), self.catch_up_speed_m_s, 0.01, 2.0)?;
        in_range(&p("catch_up_beyond_m"), self.catch_up_beyond_m, 0.0, 10.0)?;
        in_range(&p("across_gain_per_s"), self.across_gain_per_s, 0.0, 20.0)?;
        in_range(&p("push_sideways_m_s"), self.push_sideways_m_s, 0.0, 2.0)?;
        in_range(&p("turn_gain_per_s"), self.turn_gain_per_s, 0.0, 20.0)?;
        in_range(&p("push_turn_deg_s"), self.push_turn_deg_s, 0.0, 360.0)?;
        in_range(&p("line_up_speed_m_s"), self.line_up_speed_m_s, 0.01, 2.0)?;
        in_range(
            &p("line_up_turn_deg_s"),
            self.line_up_turn_deg_s,
            1.0,
            360.0,
        )?;
        in_range(&p("clearance_m"), self.clearance_m, 0.05, self.behind_m)?;
        in_range(
            &p("face_travel_beyond_deg"),
            self.face_travel_beyond_deg,
            0.0,
            360.0,
        )?;
        if let Some(k) = &self.kick {
            in_range(&p("kick.ahead_min_m"), k.ahead_min_m, 0.0, 1.0)?;
            in_range(&p("kick.ahead_max_m"), k.ahead_max_m, k.ahead_min_m, 1.0)?;
            in_range(&p("kick.across_m"), k.across_m, 0.0, 0.3)?;
            in_range(&p("kick.heading_deg"), k.heading_deg, 0.0, 45.0)?;
            in_range(&p("kick.ball_inside_m"), k.ball_inside_m, -0.1, 0.1)?;
        }
        in_range(
            &p("circle_radius_m"),
            self.circle_radius_m,
            self.clearance_m,
            3.0,
        )
    }
}

/// Where a dribble stands.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum DribbleState {
    /// No dribble asked for.
    #[default]
    Idle,
    /// Getting behind the ball on the dribble line.
    LiningUp,
    /// Walking the ball along the line.
    Pushing,
}

/// The dribble skill: the pushing/lining-up hysteresis and the foot in use are kept between
/// cycles.
#[derive(Debug, Clone, Default)]
pub struct Dribble {
    state: DribbleState,
    /// +1: the robot keeps to the left of the ball's line (the ball before its right foot),
    /// −1: to the right.
    side: f64,
    /// The foot to kick the ball on with this cycle, if it is in place for a kick step, and
    /// the strike's shift across [m].
    kick_foot: Option<(Foot, f64)>,
}

impl Dribble {
    pub fn state(&self) -> DribbleState {
        self.state
    }

    pub fn reset(&mut self) {
        self.state = DribbleState::Idle;
        self.kick_foot = None;
    }

    /// The foot whose next step should kick the ball on and the strike's shift across (set
    /// by the last update).
    pub fn kick_foot(&self) -> Option<(Foot, f64)> {
        self.kick_foot
    }

    /// This cycle's walk command for dribbling the ball at `ball` towards `direction_deg`
    /// (both robot frame).
    pub fn update(
        &mut self,
        ball: [f64; 2],
        direction_deg: f64,
        p: &DribbleParams,
        w: &WalkParams,
    ) -> Velocity {
        let b = Vector2::from(ball);
        let theta = wrap_deg(direction_deg);
        let d = Vector2::new(theta.to_radians().cos(), theta.to_radians().sin());
        let left = Vector2::new(-d.y, d.x);
        // Where the robot is relative to the ball, along the line and across it.
        let along = (-b).dot(&d);
        let across = (-b).dot(&left);
        let behind = -along;
        let pushing = self.state == DribbleState::Pushing;
        if !pushing || self.side == 0.0 {
            // The foot nearer the line: the robot stays on the side it is on.
            self.side = if across >= 0.0 { 1.0 } else { -1.0 };
        }
        // How far the robot is from where it should be across the line.
        let off = across - self.side * p.ball_beside_m;
        log::trace!(
            "dribble: ball ({:.2}, {:.2}) dir {theta:.0}° behind {behind:.2} across {across:.2} {:?}",
            b.x,
            b.y,
            self.state
        );
        let keeps = if pushing {
            behind >= 0.0 && off.abs() <= p.release_across_m && theta.abs() <= p.release_deg
        } else {
            let cone = p.capture_cone_deg.to_radians().tan() * behind;
            behind >= p.min_behind_m
                && off.abs() <= p.capture_across_m.max(cone)
                && theta.abs() <= p.capture_deg
        };
        self.kick_foot = None;
        if keeps {
            self.state = DribbleState::Pushing;
            let foot = if self.side > 0.0 {
                Foot::Right
            } else {
                Foot::Left
            };
            let foot_y = foot.sign() * w.foot_y_offset_m;
            self.kick_foot = p
                .kick
                .filter(|k| {
                    (k.ahead_min_m..=k.ahead_max_m).contains(&b.x)
                        && (b.y - foot_y).abs() <= k.across_m
                        && theta.abs() <= k.heading_deg
                })
                .map(|k| (foot, b.y - (foot_y - foot.sign() * k.ball_inside_m)));
            let ahead = behind - p.behind_m;
            let speed = if ahead > p.catch_up_beyond_m {
                p.catch_up_speed_m_s
            } else {
                p.push_speed_m_s
            };
            // Along the line, closing on it sideways; the turn keeps the feet square to it.
            let correction =
                (off * p.across_gain_per_s).clamp(-p.push_sideways_m_s, p.push_sideways_m_s);
            let v = d * speed - left * correction;
            return Velocity {
                forward_m_s: v.x,
                sideways_m_s: v.y,
                turn_deg_s: (p.turn_gain_per_s * theta)
                    .clamp(-p.push_turn_deg_s, p.push_turn_deg_s),
            }
            .within_limits(w);
        }
        self.state = DribbleState::LiningUp;
        let place = b - d * p.behind_m + left * (self.side * p.ball_beside_m);
        let v = walk_round_ball(
            b,
            place,
            theta,
            Clearance {
                clearance_m: p.clearance_m,
                circle_radius_m: p.circle_radius_m,
                face_travel_beyond_deg: p.face_travel_beyond_deg,
            },
            w,
        )
        .capped(Some(p.line_up_speed_m_s));
        Velocity {
            turn_deg_s: v
                .turn_deg_s
                .clamp(-p.line_up_turn_deg_s, p.line_up_turn_deg_s),
            ..v
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn walk() -> WalkParams {
        let t1 = libero_model::RobotModel::builtin("T1").unwrap();
        crate::SkillParams::builtin(&t1).unwrap().walk
    }

    #[test]
    fn lined_up_behind_the_ball_it_walks_on_through_it() {
        let (p, w) = (DribbleParams::default(), walk());
        let mut d = Dribble::default();
        // Ball straight ahead before the right foot, to be taken straight on: push at the push
        // speed, no turn.
        let v = d.update([p.behind_m, -p.ball_beside_m], 0.0, &p, &w);
        assert_eq!(d.state(), DribbleState::Pushing);
        assert!((v.forward_m_s - p.push_speed_m_s).abs() < 1e-9, "{v:?}");
        assert!(v.sideways_m_s.abs() < 1e-9 && v.turn_deg_s.abs() < 1e-9);
        // Right at the ball (it has not rolled away yet): still pushing, not slowing down.
        let v = d.update([0.18, -p.ball_beside_m], 0.0, &p, &w);
        assert_eq!(d.state(), DribbleState::Pushing);
        assert!((v.forward_m_s - p.push_speed_m_s).abs() < 1e-9, "{v:?}");
        // The ball rolled far ahead: catch up faster.
        let v = d.update([2.0, -p.ball_beside_m], 0.0, &p, &w);
        assert!((v.forward_m_s - p.catch_up_speed_m_s).abs() < 1e-9, "{v:?}");
    }

    #[test]
    fn pushing_steers_back_onto_the_line_and_turns_with_it() {
        let (p, w) = (DribbleParams::default(), walk());
        let mut d = Dribble::default();
        // Ball ahead and a little to the left of its place before the left foot: step left.
        let v = d.update([0.4, p.ball_beside_m + 0.05], 0.0, &p, &w);
        assert_eq!(d.state(), DribbleState::Pushing);
        assert!(v.sideways_m_s > 0.0, "{v:?}");
        // The line turned left by 10°: turn left.
        let v = d.update([0.4, p.ball_beside_m], 10.0, &p, &w);
        assert!(v.turn_deg_s > 0.0, "{v:?}");
    }

    #[test]
    fn from_the_wrong_side_it_lines_up_round_the_ball_first() {
        let (p, w) = (DribbleParams::default(), walk());
        let mut d = Dribble::default();
        // The ball is ahead but is to be dribbled back towards the robot.
        let v = d.update([0.6, 0.0], 180.0, &p, &w);
        assert_eq!(d.state(), DribbleState::LiningUp);
        // Not straight at the ball: round it.
        assert!(
            v.sideways_m_s.abs() > 0.01 || v.turn_deg_s.abs() > 1.0,
            "{v:?}"
        );
        // Far off to the side of the line: lining up, not pushing.
        let v = d.update([0.5, 1.0], 0.0, &p, &w);
        assert_eq!(d.state(), DribbleState::LiningUp);
        assert!(v.sideways_m_s > 0.0 || v.turn_deg_s > 0.0, "{v:?}");
    }

    #[test]
    fn pushing_stops_once_the_robot_is_past_the_ball_or_off_the_line() {
        let (p, w) = (DribbleParams::default(), walk());
        let mut d = Dribble::default();
        let beside = p.ball_beside_m;
        d.update([0.4, beside], 0.0, &p, &w);
        assert_eq!(d.state(), DribbleState::Pushing);
        // Inside the release band: keeps pushing.
        d.update([0.4, beside + 0.15], 0.0, &p, &w);
        assert_eq!(d.state(), DribbleState::Pushing);
        // The ball slipped out to the side.
        d.update([0.2, beside + 0.3], 0.0, &p, &w);
        assert_eq!(d.state(), DribbleState::LiningUp);
        // Lined up again, then the ball ends up behind the robot.
        d.update([0.4, beside], 0.0, &p, &w);
        d.update([-0.05, beside], 0.0, &p, &w);
        assert_eq!(d.state(), DribbleState::LiningUp);
    }

    #[test]
    fn a_ball_in_place_before_a_foot_asks_for_that_foots_kick_step() {
        let w = walk();
        let k = DribbleKickParams {
            ahead_min_m: 0.24,
            ahead_max_m: 0.36,
            across_m: 0.04,
            heading_deg: 10.0,
            ball_inside_m: 0.05,
        };
        let p = DribbleParams {
            kick: Some(k),
            ..DribbleParams::default()
        };
        let mut d = Dribble::default();
        // The robot left of the line: the ball before its right foot, 0.3 m ahead.
        let right = -w.foot_y_offset_m;
        d.update([0.3, right], 0.0, &p, &w);
        let (foot, across) = d.kick_foot().expect("in place");
        assert_eq!(foot, Foot::Right);
        // The strike moves the foot out by `ball_inside_m`: the ball ends up inside it.
        assert!((across + k.ball_inside_m).abs() < 1e-12, "{across}");
        // Too far ahead, too near, off the foot's line, or the line turned: no kick step.
        for (ball, direction) in [
            ([0.5, right], 0.0),
            ([0.2, right], 0.0),
            ([0.3, right + 0.06], 0.0),
            ([0.3, right], 15.0),
        ] {
            d.update(ball, direction, &p, &w);
            assert_eq!(d.kick_foot(), None, "{ball:?} {direction}");
        }
        // Without `kick` in the file, never.
        let mut plain = Dribble::default();
        plain.update([0.3, right], 0.0, &DribbleParams::default(), &w);
        assert_eq!(plain.kick_foot(), None);
    }

    #[test]
    fn the_shipped_numbers_are_valid() {
        DribbleParams::default().validate().unwrap();
    }
}
