//! The kick motion: sole placements over time, from a ball position fixed when the kick starts.
//!
//! Everything is planned in the *start frame*: level, at the torso origin and heading the robot
//! had when the kick began (it stands still then). Shifting the weight moves the torso over the
//! support foot, which in the torso frame moves every world-fixed point — both soles and the
//! ball — the other way by the same amount.

use super::params::KickMotion;
use crate::walk::gait::{Foot, SolePlacement};
use crate::walk::WalkParams;
use nalgebra::{Rotation2, Vector2};

/// One planned kick.
#[derive(Debug, Clone)]
pub struct MotionPlan {
    pub foot: Foot,
    /// Sole of the kicking foot at the top of the wind-up, at the end of the swing [start
    /// frame, m], and its yaw during the swing [deg].
    windup: [f64; 3],
    swing_end: [f64; 3],
    foot_yaw_deg: f64,
    /// Neutral sole places [m].
    neutral: [[f64; 2]; 2],
    /// The soles' height below the torso while kicking, and in the walk's stance the kick
    /// starts from and ends in [m].
    sole_z: f64,
    walk_sole_z: f64,
    walk_lean_deg: f64,
    ball_radius_m: f64,
    toe_m: f64,
    m: KickMotion,
}

/// Where the kick is in its phases.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Phase {
    Shift,
    Windup,
    Swing,
    Retract,
    Recover,
    Finished,
}

/// The soles and the torso lean at one instant of a kick.
#[derive(Debug, Clone, Copy)]
pub struct MotionFrame {
    pub phase: Phase,
    pub soles: [SolePlacement; 2],
    pub lean_deg: f64,
}

/// 0 → 1 with zero slope at both ends.
fn smooth(s: f64) -> f64 {
    let s = s.clamp(0.0, 1.0);
    s * s * (3.0 - 2.0 * s)
}

fn lerp3(a: [f64; 3], b: [f64; 3], s: f64) -> [f64; 3] {
    [0, 1, 2].map(|i| a[i] + (b[i] - a[i]) * s)
}

impl MotionPlan {
    /// Plan a kick of the ball at `ball` (start frame, m) towards `direction_deg` (start frame)
    /// with `foot`. The direction is limited to what turning the foot can do; the swing runs
    /// along it through the ball centre, as far across as the foot can reach.
    pub fn new(
        foot: Foot,
        ball: [f64; 2],
        direction_deg: f64,
        ball_radius_m: f64,
        toe_m: f64,
        m: &KickMotion,
        w: &WalkParams,
    ) -> Self {
        let neutral =
            [Foot::Left, Foot::Right].map(|f| [w.foot_x_offset_m, f.sign() * w.foot_y_offset_m]);
        let mut plan = Self {
            foot,
            windup: [0.0; 3],
            swing_end: [0.0; 3],
            foot_yaw_deg: 0.0,
            neutral,
            sole_z: -m.kick_torso_height_m.unwrap_or(w.torso_height_m),
            walk_sole_z: -w.torso_height_m,
            walk_lean_deg: w.torso_lean_deg,
            ball_radius_m,
            toe_m,
            m: m.clone(),
        };
        plan.aim(ball, direction_deg);
        plan
    }

    /// Place the wind-up and the swing for a ball at `ball` (start frame).
    fn aim(&mut self, ball: [f64; 2], direction_deg: f64) {
        let m = &self.m;
        // The body will have turned about the support foot by the contact: aim in that frame.
        let turn = self.foot.sign() * m.contact_yaw_deg;
        let pivot = Vector2::from(self.neutral[self.foot.other().index()]);
        let b = Rotation2::new(-turn.to_radians()) * (Vector2::from(ball) - pivot) + pivot;
        let yaw = (direction_deg - turn).clamp(-m.max_foot_turn_deg, m.max_foot_turn_deg);
        let d = Vector2::new(yaw.to_radians().cos(), yaw.to_radians().sin());
        let home_y = self.neutral[self.foot.index()][1];
        // The sole point that puts the toe `behind` metres behind the ball's back, on the
        // line through the ball centre along the kick, as far across as the foot reaches.
        // The stance leg gives way further than commanded once the kicking foot is off the
        // ground: aim where the ball will then be in the torso frame, not where a rigid body
        // would have it. Both that and `swing_outward_m` move the line away from the support
        // foot.
        let outward = self.foot.sign() * (m.support_sag_m + m.swing_outward_m);
        let along = |behind: f64| {
            let p = b - d * (self.ball_radius_m + self.toe_m + behind);
            let y =
                p.y.clamp(home_y - m.max_reach_across_m, home_y + m.max_reach_across_m);
            [p.x, y + outward]
        };
        let [wx, wy] = along(m.windup_back_m);
        let [ex, ey] = along(-m.follow_through_m);
        self.windup = [wx, wy, self.sole_z + m.windup_lift_m];
        self.swing_end = [ex, ey, self.sole_z + m.strike_height_m];
        self.foot_yaw_deg = yaw;
    }

    /// Total duration [s].
    pub fn duration_s(&self) -> f64 {
        let m = &self.m;
        m.shift_s + m.windup_s + m.swing_s + m.retract_s + m.recover_s
    }

    /// The soles and lean `t` seconds after the kick started.
    pub fn at(&self, t: f64) -> MotionFrame {
        let m = &self.m;
        let k = self.foot.index();
        // The stance blends from the walk's to the kick's during the shift and back during
        // the recovery, with the lean.
        let stance_z = |blend: f64| self.walk_sole_z + (self.sole_z - self.walk_sole_z) * blend;
        // Phase boundaries.
        let t1 = m.shift_s;
        let t2 = t1 + m.windup_s;
        let t3 = t2 + m.swing_s;
        let t4 = t3 + m.retract_s;
        let t5 = t4 + m.recover_s;
        let progress = |from: f64, len: f64| if len > 0.0 { (t - from) / len } else { 1.0 };
        let home = [self.neutral[k][0], self.neutral[k][1], self.sole_z];
        let (phase, kick_sole, yaw, shift, lean) = if t < t1 {
            let s = smooth(progress(0.0, m.shift_s));
            let at_home = [home[0], home[1], stance_z(s)];
            (Phase::Shift, at_home, 0.0, s, s)
        } else if t < t2 {
            let s = smooth(progress(t1, m.windup_s));
            (
                Phase::Windup,
                lerp3(home, self.windup, s),
                self.foot_yaw_deg * s,
                1.0,
                1.0,
            )
        } else if t < t3 {
            // Straight at the ball, the foot dropping to the strike height early in the swing.
            let s = progress(t2, m.swing_s).clamp(0.0, 1.0);
            let mut p = lerp3(self.windup, self.swing_end, s);
            p[2] = self.swing_end[2] + (self.windup[2] - self.swing_end[2]) * (1.0 - s).powi(2);
            (Phase::Swing, p, self.foot_yaw_deg, 1.0, 1.0)
        } else if t < t4 {
            let s = smooth(progress(t3, m.retract_s));
            let yaw = self.foot_yaw_deg * (1.0 - s);
            // Back and down at once: the swing leaves the body falling towards the kicking
            // side, and the foot must be on the ground to catch it.
            let mut p = lerp3(self.swing_end, home, s);
            p[2] += m.windup_lift_m * (std::f64::consts::PI * s).sin();
            (Phase::Retract, p, yaw, 1.0, 1.0)
        } else if t < t5 {
            let back = 1.0 - smooth(progress(t4, m.recover_s));
            let at_home = [home[0], home[1], stance_z(back)];
            (Phase::Recover, at_home, 0.0, back, back)
        } else {
            let at_home = [home[0], home[1], self.walk_sole_z];
            (Phase::Finished, at_home, 0.0, 0.0, 0.0)
        };
        // The torso moves over the support foot: world-fixed points move towards the kicking side.
        let dy = self.foot.sign() * m.weight_shift_m * shift;
        let mut soles = [0, 1].map(|i| SolePlacement {
            x: self.neutral[i][0],
            y: self.neutral[i][1] + dy,
            z: stance_z(lean),
            yaw_deg: 0.0,
        });
        soles[k] = SolePlacement {
            x: kick_sole[0],
            y: kick_sole[1] + dy,
            z: kick_sole[2],
            yaw_deg: yaw,
        };
        MotionFrame {
            phase,
            soles,
            lean_deg: self.walk_lean_deg + (m.kick_lean_deg - self.walk_lean_deg) * lean,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_swing_is_aimed_in_the_frame_the_body_turns_to_by_the_contact() {
        let t1 = libero_model::RobotModel::builtin("T1").unwrap();
        let p = crate::SkillParams::builtin(&t1).unwrap();
        let mut m = p.kick.long.clone();
        let ball = [0.36, 0.10];
        m.contact_yaw_deg = 0.0;
        let straight = MotionPlan::new(Foot::Left, ball, 0.0, 0.11, 0.12, &m, &p.walk);
        m.contact_yaw_deg = 9.0;
        let left = MotionPlan::new(Foot::Left, ball, 0.0, 0.11, 0.12, &m, &p.walk);
        let right = MotionPlan::new(Foot::Right, [0.36, -0.10], 0.0, 0.11, 0.12, &m, &p.walk);
        assert_eq!(straight.foot_yaw_deg, 0.0);
        // A left kick turns the body left: the foot is turned right against it, and the swing
        // aims at the ball as it will then lie (further right).
        assert!(
            (left.foot_yaw_deg + 9.0).abs() < 1e-9,
            "{}",
            left.foot_yaw_deg
        );
        assert!(
            (right.foot_yaw_deg - 9.0).abs() < 1e-9,
            "{}",
            right.foot_yaw_deg
        );
        assert!(left.swing_end[1] < straight.swing_end[1] - 0.01);
    }

    #[test]
    fn an_outward_swing_runs_beside_the_ball_away_from_the_support_foot() {
        let t1 = libero_model::RobotModel::builtin("T1").unwrap();
        let p = crate::SkillParams::builtin(&t1).unwrap();
        let mut m = p.kick.long.clone();
        let plan = |foot: Foot, m: &KickMotion| {
            let ball = [0.36, foot.sign() * 0.10];
            MotionPlan::new(foot, ball, 0.0, 0.11, 0.12, m, &p.walk)
        };
        m.swing_outward_m = 0.0;
        let centred = [Foot::Left, Foot::Right].map(|f| plan(f, &m));
        m.swing_outward_m = 0.02;
        let outward = [Foot::Left, Foot::Right].map(|f| plan(f, &m));
        for (c, o) in centred.iter().zip(&outward) {
            let sign = c.foot.sign();
            for (a, b) in [(c.windup, o.windup), (c.swing_end, o.swing_end)] {
                assert!((sign * (b[1] - a[1]) - 0.02).abs() < 1e-9, "{a:?} {b:?}");
                assert_eq!((a[0], a[2]), (b[0], b[2]));
            }
            assert_eq!(c.foot_yaw_deg, o.foot_yaw_deg);
        }
    }

    #[test]
    fn the_kick_stands_at_its_own_height_and_ends_at_the_walks() {
        let t1 = libero_model::RobotModel::builtin("T1").unwrap();
        let p = crate::SkillParams::builtin(&t1).unwrap();
        let mut m = p.kick.long.clone();
        let mut w = p.walk.clone();
        w.torso_height_m = 0.60;
        m.kick_torso_height_m = Some(0.62);
        let plan = MotionPlan::new(Foot::Left, [0.36, 0.10], 0.0, 0.11, 0.12, &m, &w);
        let support = |t: f64| plan.at(t).soles[Foot::Right.index()].z;
        assert!((support(0.0) + 0.60).abs() < 1e-9, "{}", support(0.0));
        let windup = m.shift_s + 0.5 * m.windup_s;
        assert_eq!(plan.at(windup).phase, Phase::Windup);
        assert!((support(windup) + 0.62).abs() < 1e-9, "{}", support(windup));
        // The wind-up lifts the kicking foot from the kick's stance, not the walk's.
        let kicking = plan.at(m.shift_s + m.windup_s - 1e-6).soles[Foot::Left.index()].z;
        assert!(
            (kicking - (-0.62 + m.windup_lift_m)).abs() < 1e-3,
            "{kicking}"
        );
        let end = plan.at(plan.duration_s() + 0.1);
        assert_eq!(end.phase, Phase::Finished);
        assert!(end.soles.iter().all(|s| (s.z + 0.60).abs() < 1e-9));
        // Unset, the kick stands at the walk's height throughout.
        m.kick_torso_height_m = None;
        let plain = MotionPlan::new(Foot::Left, [0.36, 0.10], 0.0, 0.11, 0.12, &m, &w);
        assert!((plain.at(windup).soles[1].z + 0.60).abs() < 1e-9);
    }
}
