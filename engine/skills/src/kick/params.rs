//! The kick's tunable numbers, as they appear in the `kick:` section of the skill parameter file.
//! Key names differ from the walk's (the optimizer finds walk keys by name in the file).

use crate::walk::params::{in_range, Check};
use libero_model::Gains;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// Everything about kicking: where to stand, how to get there, and the two kick motions.
#[derive(Debug, Clone, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct KickParams {
    /// Requests of at least this distance get the long kick, shorter ones the short kick [m].
    pub long_kick_from_m: f64,
    /// Ball radius [m].
    pub ball_radius_m: f64,
    /// Toe tip ahead of the ankle (the IK's sole point) [m].
    pub toe_ahead_of_ankle_m: f64,
    pub approach: KickApproach,
    pub short: KickMotion,
    pub long: KickMotion,
    /// What `libero bench kick` measured of the long kick; decisions weigh a kick's chances
    /// with it (the shot utility).
    #[serde(default)]
    pub measured: KickSpread,
}

/// The long kick's measured outcome spread.
#[derive(Debug, Clone, Copy, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct KickSpread {
    /// Standard deviation of the direction error [deg].
    pub direction_sd_deg: f64,
    /// Mean distance the ball travels along a field axis [m] ...
    pub distance_m: f64,
    /// ... and its standard deviation [m].
    pub distance_sd_m: f64,
    /// How much farther a kick along a field diagonal rolls [m]; in between by sin²(2θ) of
    /// the angle θ to the nearest axis. rcssservermj's ball rolls farther on the diagonals (its
    /// friction cone, which also curves a kick off an axis). The world model's `LaunchTable`
    /// says the same of spin-free monitor launches, by more (10.8 m along an axis is 14.6 m on
    /// the diagonal there, +3.8); a kicked ball does less, as it curves less (`curve_share`),
    /// so this is the kick's own measured figure rather than the table's.
    #[serde(default)]
    pub diagonal_extra_m: f64,
}

impl KickSpread {
    /// The mean distance of a kick along `(x, y)` (any length, a field-aligned frame: global
    /// or a team's own, which differ by 180°) [m].
    pub fn distance_along(&self, x: f64, y: f64) -> f64 {
        let r2 = x * x + y * y;
        if r2 <= 0.0 {
            return self.distance_m;
        }
        let sin_2theta = 2.0 * x * y / r2;
        self.distance_m + self.diagonal_extra_m * sin_2theta * sin_2theta
    }
}

impl Default for KickSpread {
    /// Unmeasured: a wide spread, so nothing is trusted that has not been measured.
    fn default() -> Self {
        Self {
            direction_sd_deg: 8.0,
            distance_m: 6.0,
            distance_sd_m: 2.0,
            diagonal_extra_m: 0.0,
        }
    }
}

/// The path approach: along the shortest way to the kicking place that keeps `clearance_m`
/// from the ball (straight, or along the tangent to the circle round it and on round it), at
/// the speed from which braking at `brake_m_s2` still stops at the place, facing the way of
/// travel far out and the kick heading near the place.
#[derive(Debug, Clone, Copy, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct ApproachPath {
    /// The deceleration the speed profile plans with [m/s²]: at `s` metres of path left the
    /// robot walks at most √(2·brake·s) (and at most `approach_speed_m_s`).
    pub brake_m_s2: f64,
    /// How long the robot goes on at its speed before braking takes hold [s] (the step under
    /// way is finished at its length; the next is shorter).
    pub lag_s: f64,
    /// With more than this much path left the robot faces the way it walks [m] ...
    pub face_travel_beyond_m: f64,
    /// ... with less than this the kick heading [m]; blended in between.
    pub face_kick_within_m: f64,
    /// Turn per degree of heading error [1/s] (capped at `approach_turn_deg_s`).
    pub turn_gain_per_s: f64,
    /// Outside the cone behind the kicking place (half-width `cone_margin_m` plus
    /// `cone_slope` per metre behind it) the robot first walks to the line-up point,
    /// `line_up_m` behind the place on the kick line [m].
    pub line_up_m: f64,
    pub cone_slope: f64,
    pub cone_margin_m: f64,
}

/// Getting to the kicking place behind the ball.
#[derive(Debug, Clone, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct KickApproach {
    /// At the kicking place the ball centre is this far ahead of the torso origin [m] ...
    pub ball_ahead_m: f64,
    /// ... and this far to the side of the kicking foot [m].
    pub ball_beside_m: f64,
    /// A beamed robot lands in the stand pose, its torso this much further forward over its
    /// feet than in the walk's posture that the kick starts from [m]: a set-play taker is
    /// beamed this much nearer the ball, so that the posture change leaves it at the kicking
    /// place instead of a step behind it. Absent: 0.
    #[serde(default)]
    pub beam_nearer_m: f64,
    /// Paths to the kicking place keep the torso at least this far from the ball centre [m];
    /// otherwise the robot walks around the ball on a circle of this radius.
    pub clearance_m: f64,
    /// Radius of the circle walked around the ball [m] (torso to ball centre): wider than the
    /// clearance, since turning and side-stepping feet reach out beyond the torso.
    pub circle_radius_m: f64,
    /// Walking round the ball with more than this arc still to go [deg], the robot faces the
    /// way it walks (forwards is about twice as fast as sideways or backwards); with less
    /// than half of it left it turns to the kick heading, and in between it blends the two.
    /// 360 (the default): always the kick heading.
    #[serde(default = "crate::walk::face_travel_off")]
    pub face_travel_beyond_deg: f64,
    /// Speed cap while walking to the kicking place [m/s].
    pub approach_speed_m_s: f64,
    /// The path approach (absent: the robot walks to waypoints round the ball and aligns at
    /// `align_speed_m_s` near the place).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub path: Option<ApproachPath>,
    /// Fastest turn while walking there [deg/s]: the walk's fastest turn on top of walking
    /// fast, with the command changing every cycle, can tip the robot over.
    pub approach_turn_deg_s: f64,
    /// Closer than this to the kicking place the robot aligns with small steps [m].
    pub align_within_m: f64,
    /// Alignment: speed per metre of position error [1/s], turn per degree of heading error
    /// [1/s], and speed cap [m/s].
    pub align_gain_per_s: f64,
    pub align_turn_gain_per_s: f64,
    pub align_speed_m_s: f64,
    /// Slowest alignment walk [m/s]: slower commands barely move the robot (the first steps of
    /// a walk sway more than they travel), so small errors are walked off at this speed.
    pub align_min_speed_m_s: f64,
    /// Within these errors of the kicking place the robot stops, looks and corrects in short
    /// walks; beyond them it aligns on the move (stopping to look at every step is slow).
    pub look_within_m: f64,
    pub look_within_deg: f64,
    /// The kick starts when the robot has stopped within these errors of the kicking place:
    /// along the kick direction [m], across it [m], heading [deg].
    pub ready_along_m: f64,
    pub ready_across_m: f64,
    pub ready_deg: f64,
    /// Near the place: how long to stand still and look before judging the errors [s], and
    /// how long each correction walk lasts [s].
    pub look_s: f64,
    /// The look ends early, after `steady_look_s` [s], when every ball position asked for
    /// since the robot stopped lies within `steady_m` [m] (per axis) of each other: a ball in
    /// view with a steady estimate needs no longer look.
    pub steady_look_s: f64,
    pub steady_m: f64,
    /// While walking, the kicking place counts as reached when the robot would come to rest
    /// within the tolerances if asked to stop now: braking at the walk's acceleration limits
    /// plus this many steps' length at the executed speed (the step under way is finished).
    pub stop_lead_steps: f64,
    /// Walking (on the move or in a correction), the robot stops for the kick only within
    /// this fraction of the tolerances: it still is within them after the stop and the look.
    pub stop_within: f64,
    /// Before the kick starts (and before the errors are judged) the torso rates must have
    /// stayed below `calm_rate_deg_s` for this long [s].
    pub calm_s: f64,
    /// After this many looks at the kicking place that found it not ready, the robot steps
    /// back for `retreat_s` (at `align_speed_m_s`) and approaches afresh.
    pub looks_before_retreat: u32,
    pub retreat_s: f64,
    pub correction_s: f64,
    /// Standing still means also a torso roll and pitch rate below this [deg/s]: the look
    /// (and so the kick) waits until the sway from the last steps has died down.
    pub calm_rate_deg_s: f64,
    /// The head looks at the ball while approaching, pitched down at most this far (and this
    /// far during the kick motion) [deg].
    pub look_down_deg: f64,
    /// Height of the camera above the ground while walking [m], for pitching the head at the
    /// ball.
    pub eye_height_m: f64,
}

/// One kick motion, in phases: shift the weight onto the support leg, lift and wind up the
/// kicking foot, swing it through the ball, bring it back, and shift the weight back.
/// With `keyframes`, those key frames are played instead (the phases' numbers then only
/// describe nothing the kick uses but `roll_out_m` and the gains).
#[derive(Debug, Clone, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct KickMotion {
    /// Key frames of a kick with the right foot, played from the measured angles instead of
    /// the IK-placed swing (the left foot plays their mirror image): for a robot whose legs
    /// cannot swing through the ball along a planned line (the NAO's nearly straight legs,
    /// NOTES.md session 20). Absent: the IK kick.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub keyframes: Option<Vec<crate::getup::Keyframe>>,
    /// Where the key-frame kick sends the ball, relative to the robot's heading, for the
    /// right foot [deg] (mirrored for the left): the approach faces off by as much.
    #[serde(default)]
    pub keyframe_aim_deg: f64,
    /// Phase durations [s].
    pub shift_s: f64,
    pub windup_s: f64,
    pub swing_s: f64,
    pub retract_s: f64,
    pub recover_s: f64,
    /// Torso shift over the support foot [m].
    pub weight_shift_m: f64,
    /// How much further than `weight_shift_m` the torso ends up over the support foot, the
    /// stance leg and foot giving way under the body's weight (measured) [m].
    pub support_sag_m: f64,
    /// How far the whole body has turned about the support foot by the time the foot meets
    /// the ball [deg], towards the kicking foot's side (measured: the swing's reaction spins
    /// the support foot on the ground). The swing is aimed in the frame the body will then have.
    pub contact_yaw_deg: f64,
    /// How far this kick's ball usually travels [m] (measured). The ball's path curves (on
    /// rcssservermj towards the field's diagonals, see `LaunchTable`); the kick is aimed off so
    /// a ball travelling this far comes to rest on the requested line. 0: aim straight.
    pub roll_out_m: f64,
    /// How much of the table's curve this kick's ball shows (measured: 1 is a ball launched
    /// by the monitor, sliding before it rolls). A long-kicked T1 ball curved about half as
    /// much: aimed for the whole curve, shots from the side crossed the goal line 1-1.9 m
    /// outside their target; aimed straight, 0.8-1.5 m inside (NOTES.md, session 29).
    #[serde(default = "whole_curve")]
    pub curve_share: f64,
    /// Torso lean while kicking [deg], + forwards.
    pub kick_lean_deg: f64,
    /// Torso height over the soles while kicking [m], reached during the weight shift and
    /// left during the recovery as the lean is; unset: the walk's. The swing's torques were
    /// tuned at one height: a faster gait that walks lower (more knee bend) must not move the
    /// kick's stance with it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub kick_torso_height_m: Option<f64>,
    /// How much of the torso's measured tilt the kicking foot allows for while it comes back
    /// down (0: placed as if the torso were upright, 1: placed on the level ground below a
    /// tilted torso). A body left leaning over the support foot after the swing is pushed
    /// back by the kicking foot reaching the ground instead of hanging in the air.
    pub landing_tilt_gain: f64,
    /// Height of the kicking sole during the wind-up [m].
    pub windup_lift_m: f64,
    /// How far behind the ball's back the toe is pulled during the wind-up [m].
    pub windup_back_m: f64,
    /// The swing aims the toe this far past the ball's back [m].
    pub follow_through_m: f64,
    /// Height of the kicking sole when it meets the ball [m].
    pub strike_height_m: f64,
    /// Largest lateral shift of the kicking foot towards the ball from its neutral place [m].
    pub max_reach_across_m: f64,
    /// The swing's line runs this far outside the ball's centre, away from the support foot
    /// [m]: where the toe meets the ball across its face steers the launch.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub swing_outward_m: f64,
    /// Largest direction correction made by turning the kicking foot [deg].
    pub max_foot_turn_deg: f64,
    /// Gyro damping on the stance ankle: pitch and roll correction per deg/s of the torso's
    /// pitch and roll rate [deg per deg/s], at most `stance_max_correction_deg`.
    pub stance_pitch_per_gyro: f64,
    pub stance_roll_per_gyro: f64,
    pub stance_max_correction_deg: f64,
    /// Motor gains of the kicking leg's joints during the swing (`hip_pitch`, …); unlisted
    /// joints keep the walk's leg gains. Shared: a kick's plan copies its motion, and that
    /// copy happens during play.
    pub swing_gains: std::sync::Arc<BTreeMap<String, Gains>>,
}

/// kd beyond which the server's explicit Euler integration goes unstable on the T1's legs
/// (rcssservermj.md §3.1; hip pitch ≈ 31).
const MAX_KD: f64 = 30.0;
const MAX_KP: f64 = 3000.0;

/// The key-frame kicks as played, per foot (the left foot's mirrored from the right's once,
/// when the parameters load: a kick during play copies nothing).
#[derive(Debug, Clone, Default)]
pub struct KickFrames {
    /// `[left, right]` of the short kick, then of the long one; empty without key frames.
    short: [Vec<crate::getup::Keyframe>; 2],
    long: [Vec<crate::getup::Keyframe>; 2],
}

impl KickFrames {
    pub fn of(k: &KickParams) -> Self {
        let both = |m: &KickMotion| match &m.keyframes {
            Some(right) => [
                right.iter().map(crate::save::mirror_frame).collect(),
                right.clone(),
            ],
            None => [Vec::new(), Vec::new()],
        };
        Self {
            short: both(&k.short),
            long: both(&k.long),
        }
    }

    /// The key frames of the long or short kick with `foot`; empty for an IK kick.
    pub fn get(&self, long: bool, foot: crate::walk::gait::Foot) -> &[crate::getup::Keyframe] {
        let both = if long { &self.long } else { &self.short };
        &both[foot.index()]
    }
}

impl KickParams {
    pub fn validate(&self) -> Check {
        let k = "kick";
        in_range(
            &format!("{k}.long_kick_from_m"),
            self.long_kick_from_m,
            0.0,
            50.0,
        )?;
        in_range(&format!("{k}.ball_radius_m"), self.ball_radius_m, 0.01, 0.3)?;
        in_range(
            &format!("{k}.toe_ahead_of_ankle_m"),
            self.toe_ahead_of_ankle_m,
            0.0,
            0.3,
        )?;
        let a = &self.approach;
        let p = |name: &str| format!("{k}.approach.{name}");
        in_range(&p("ball_ahead_m"), a.ball_ahead_m, 0.05, 1.0)?;
        in_range(&p("ball_beside_m"), a.ball_beside_m, 0.0, 0.3)?;
        in_range(
            &p("beam_nearer_m"),
            a.beam_nearer_m,
            0.0,
            0.5 * a.ball_ahead_m,
        )?;
        in_range(&p("clearance_m"), a.clearance_m, 0.1, 2.0)?;
        in_range(&p("circle_radius_m"), a.circle_radius_m, a.clearance_m, 3.0)?;
        in_range(
            &p("face_travel_beyond_deg"),
            a.face_travel_beyond_deg,
            0.0,
            360.0,
        )?;
        in_range(&p("approach_speed_m_s"), a.approach_speed_m_s, 0.01, 2.0)?;
        in_range(&p("approach_turn_deg_s"), a.approach_turn_deg_s, 1.0, 360.0)?;
        if let Some(path) = &a.path {
            in_range(&p("path.brake_m_s2"), path.brake_m_s2, 0.01, 10.0)?;
            in_range(&p("path.lag_s"), path.lag_s, 0.0, 2.0)?;
            in_range(
                &p("path.face_kick_within_m"),
                path.face_kick_within_m,
                0.0,
                10.0,
            )?;
            in_range(
                &p("path.face_travel_beyond_m"),
                path.face_travel_beyond_m,
                path.face_kick_within_m,
                20.0,
            )?;
            in_range(&p("path.turn_gain_per_s"), path.turn_gain_per_s, 0.01, 20.0)?;
            in_range(&p("path.line_up_m"), path.line_up_m, 0.0, 5.0)?;
            in_range(&p("path.cone_slope"), path.cone_slope, 0.0, 10.0)?;
            in_range(&p("path.cone_margin_m"), path.cone_margin_m, 0.0, 1.0)?;
        }
        in_range(&p("align_within_m"), a.align_within_m, 0.01, 2.0)?;
        in_range(&p("align_gain_per_s"), a.align_gain_per_s, 0.01, 10.0)?;
        in_range(
            &p("align_turn_gain_per_s"),
            a.align_turn_gain_per_s,
            0.01,
            10.0,
        )?;
        in_range(&p("align_speed_m_s"), a.align_speed_m_s, 0.005, 1.0)?;
        in_range(
            &p("align_min_speed_m_s"),
            a.align_min_speed_m_s,
            0.0,
            a.align_speed_m_s,
        )?;
        in_range(&p("look_within_m"), a.look_within_m, 0.0, 1.0)?;
        in_range(&p("look_within_deg"), a.look_within_deg, 0.0, 90.0)?;
        in_range(&p("ready_along_m"), a.ready_along_m, 0.001, 0.5)?;
        in_range(&p("ready_across_m"), a.ready_across_m, 0.001, 0.5)?;
        in_range(&p("ready_deg"), a.ready_deg, 0.1, 45.0)?;
        in_range(&p("look_s"), a.look_s, 0.0, 5.0)?;
        in_range(&p("steady_look_s"), a.steady_look_s, 0.0, a.look_s)?;
        in_range(&p("steady_m"), a.steady_m, 0.0, 0.5)?;
        in_range(&p("stop_lead_steps"), a.stop_lead_steps, 0.0, 5.0)?;
        in_range(&p("stop_within"), a.stop_within, 0.1, 1.0)?;
        in_range(&p("calm_s"), a.calm_s, 0.0, 5.0)?;
        in_range(
            &p("looks_before_retreat"),
            f64::from(a.looks_before_retreat),
            1.0,
            100.0,
        )?;
        in_range(&p("retreat_s"), a.retreat_s, 0.0, 10.0)?;
        in_range(&p("correction_s"), a.correction_s, 0.05, 5.0)?;
        in_range(&p("calm_rate_deg_s"), a.calm_rate_deg_s, 0.1, 100.0)?;
        in_range(&p("look_down_deg"), a.look_down_deg, -90.0, 90.0)?;
        in_range(&p("eye_height_m"), a.eye_height_m, 0.1, 3.0)?;
        // A path ending at the kicking place must be able to keep the clearance.
        let place_distance = a.ball_ahead_m.hypot(a.ball_beside_m);
        if a.clearance_m >= place_distance {
            return Err(format!(
                "{k}.approach.clearance_m = {} must be less than the kicking place's distance from the ball ({place_distance:.3} m)",
                a.clearance_m
            ));
        }
        self.short.validate(&format!("{k}.short"))?;
        self.long.validate(&format!("{k}.long"))
    }
}

impl KickMotion {
    fn validate(&self, m: &str) -> Check {
        let p = |name: &str| format!("{m}.{name}");
        for (name, v) in [
            ("shift_s", self.shift_s),
            ("windup_s", self.windup_s),
            ("retract_s", self.retract_s),
            ("recover_s", self.recover_s),
        ] {
            in_range(&p(name), v, 0.0, 5.0)?;
        }
        in_range(&p("swing_s"), self.swing_s, 0.02, 2.0)?;
        in_range(&p("weight_shift_m"), self.weight_shift_m, 0.0, 0.2)?;
        in_range(&p("support_sag_m"), self.support_sag_m, 0.0, 0.2)?;
        in_range(&p("contact_yaw_deg"), self.contact_yaw_deg, -30.0, 30.0)?;
        in_range(&p("roll_out_m"), self.roll_out_m, 0.0, 40.0)?;
        in_range(&p("curve_share"), self.curve_share, 0.0, 2.0)?;
        in_range(&p("kick_lean_deg"), self.kick_lean_deg, -20.0, 30.0)?;
        if let Some(h) = self.kick_torso_height_m {
            in_range(&p("kick_torso_height_m"), h, 0.1, 1.0)?;
        }
        in_range(&p("landing_tilt_gain"), self.landing_tilt_gain, 0.0, 1.5)?;
        in_range(&p("windup_lift_m"), self.windup_lift_m, 0.0, 0.3)?;
        in_range(&p("windup_back_m"), self.windup_back_m, 0.0, 0.5)?;
        in_range(&p("follow_through_m"), self.follow_through_m, 0.0, 0.5)?;
        in_range(&p("strike_height_m"), self.strike_height_m, 0.0, 0.3)?;
        in_range(&p("max_reach_across_m"), self.max_reach_across_m, 0.0, 0.2)?;
        in_range(&p("swing_outward_m"), self.swing_outward_m, -0.05, 0.05)?;
        in_range(&p("max_foot_turn_deg"), self.max_foot_turn_deg, 0.0, 45.0)?;
        in_range(
            &p("stance_pitch_per_gyro"),
            self.stance_pitch_per_gyro,
            -5.0,
            5.0,
        )?;
        in_range(
            &p("stance_roll_per_gyro"),
            self.stance_roll_per_gyro,
            -5.0,
            5.0,
        )?;
        in_range(
            &p("stance_max_correction_deg"),
            self.stance_max_correction_deg,
            0.0,
            30.0,
        )?;
        for (joint, g) in self.swing_gains.iter() {
            in_range(&p(&format!("swing_gains.{joint}.kp")), g.kp, 0.0, MAX_KP)?;
            in_range(&p(&format!("swing_gains.{joint}.kd")), g.kd, 0.0, MAX_KD)?;
        }
        Ok(())
    }
}

fn whole_curve() -> f64 {
    1.0
}

fn is_zero(v: &f64) -> bool {
    *v == 0.0
}
