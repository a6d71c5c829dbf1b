//! The walk's tunable numbers, as they appear in the skill parameter file.

use libero_model::Gains;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// Gait geometry, timing, command limits and the balance loop of the omnidirectional walk.
#[derive(Debug, Clone, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct WalkParams {
    /// Duration of one step (one foot's swing) [s].
    pub step_period_s: f64,
    /// Height of the torso origin above the soles while walking [m]; lower = more knee bend.
    pub torso_height_m: f64,
    /// Forward lean of the torso while walking [deg].
    pub torso_lean_deg: f64,
    /// Neutral sole position ahead of the torso origin, in the level walk frame [m].
    pub foot_x_offset_m: f64,
    /// Neutral lateral distance of each sole from the torso's mid-plane [m].
    pub foot_y_offset_m: f64,
    /// Peak height of the swing foot above the ground [m].
    pub step_height_m: f64,
    /// Lateral shift of the torso towards the support foot at mid-step [m].
    pub sway_m: f64,
    /// Fraction of a step by which the sway leads the foot pattern (makes up for the server's
    /// action delay and the body's lag) [0..0.5].
    pub sway_phase_lead: f64,
    /// Time to blend from the current posture into the walk posture before the first step [s].
    pub settle_s: f64,
    /// Share of `step_height_m` the walk's first step (the weight shift onto the support leg)
    /// lifts its foot by [0..1] (absent from a file: 0, a shift without lift). A T1 shifting
    /// without lift rolled 10° onto the first swing leg's side and yawed up to 15° before
    /// stepping on; lifting 0.4 of a step halves the roll (NOTES.md, session 20).
    #[serde(default)]
    pub start_lift_scale: f64,
    pub max_forward_m_s: f64,
    pub max_backward_m_s: f64,
    pub max_sideways_m_s: f64,
    pub max_turn_deg_s: f64,
    /// How fast the executed command may follow the requested one [m/s², m/s², deg/s²].
    pub accel_forward_m_s2: f64,
    /// Slowing down forwards or backwards, this instead [m/s²] (absent: `accel_forward_m_s2`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub decel_forward_m_s2: Option<f64>,
    pub accel_sideways_m_s2: f64,
    pub accel_turn_deg_s2: f64,
    /// Arm swing in opposition to the legs, per metre of foot offset [deg/m].
    pub arm_swing_deg_per_m: f64,
    /// Motor gains of both legs while walking, by leg joint (`hip_pitch`, …); joints not
    /// listed keep the model's defaults. Position tracking needs far stiffer legs than
    /// standing: with the defaults the body's lateral sway resonates near the step frequency.
    pub leg_gains: BTreeMap<String, Gains>,
    pub balance: BalanceParams,
    pub walk_to: WalkToParams,
    /// The kick step a dribble may ask for (`None`: the walk has none).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub kick_step: Option<super::kick_step::KickStepParams>,
}

/// The IMU feedback loop. Torso pitch/roll come from the low-passed accelerometer, rates from
/// the gyro; both are in the torso frame.
#[derive(Debug, Clone, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct BalanceParams {
    /// Ankle pitch correction per deg/s of pitch rate [deg per deg/s] (ankle strategy).
    pub ankle_pitch_per_gyro: f64,
    /// Ankle pitch correction per degree of pitch error [deg/deg].
    pub ankle_pitch_per_tilt: f64,
    /// Hip pitch correction per deg/s of pitch rate (hip strategy).
    pub hip_pitch_per_gyro: f64,
    /// Ankle roll correction per deg/s of roll rate.
    pub ankle_roll_per_gyro: f64,
    /// Hip roll correction per deg/s of roll rate.
    pub hip_roll_per_gyro: f64,
    /// Foot placement shift per degree of pitch error [m/deg] (capture-step style).
    pub step_x_per_tilt_m: f64,
    /// Coming to a stop (no command, none left to execute), the closing steps take no
    /// capture step while the pitch error is below this [deg]: the steps of a few millimetres
    /// it asks for keep the feet from coming together, and the stop goes on for seconds.
    /// 0: capture steps always (absent from a file: 0).
    #[serde(default)]
    pub stop_capture_min_deg: f64,
    /// Standing in the walk's posture (stopped, or settling before the first step), this
    /// fraction of the walking corrections damps the body's sway (0: none; absent: 0).
    #[serde(default)]
    pub rest_correction_scale: f64,
    /// The torso leans into the walk's acceleration: this many degrees further forward per
    /// m/s² of speeding up (back when slowing down), followed with a lag of one step period,
    /// so the body is over the feet the gait's speed change needs (0: a fixed lean; absent: 0).
    #[serde(default)]
    pub lean_per_accel_deg: f64,
    /// Largest correction any joint gets from the loop [deg].
    pub max_correction_deg: f64,
}

/// Turning a target pose into walk commands.
#[derive(Debug, Clone, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct WalkToParams {
    /// Forward speed per metre of distance to the target [1/s].
    pub gain_per_s: f64,
    /// Turn rate per degree of heading error [1/s].
    pub turn_gain_per_s: f64,
    /// Beyond this distance the robot first faces the target and walks forwards [m].
    pub face_target_beyond_m: f64,
    /// Close enough in position [m] and heading [deg] to stop.
    pub arrive_m: f64,
    pub arrive_deg: f64,
    /// Standing, the robot walks again only once the target is this far [m] or this much
    /// turned [deg]: a target wobbling by a few centimetres (a self-estimate, a ball being
    /// watched) otherwise starts and stops the walk every few cycles, and those starts are
    /// where robots holding a position fall.
    pub restart_m: f64,
    pub restart_deg: f64,
}

/// Stiffness and damping beyond which the server's explicit Euler integration (h = 5 ms)
/// goes unstable on the T1's legs (rcssservermj.md §3.1: kp·h² + 2·kd·h < 4·m_eff; the hip
/// pitch allows kd ≈ 31, the ankles only ≈ 4.3 at low kp).
const MAX_KP: f64 = 3000.0;
const MAX_KD: f64 = 30.0;

/// One located complaint about a parameter.
pub(crate) type Check = Result<(), String>;

pub(crate) fn in_range(path: &str, value: f64, lo: f64, hi: f64) -> Check {
    if value.is_finite() && (lo..=hi).contains(&value) {
        Ok(())
    } else {
        Err(format!("{path} = {value} is outside [{lo}, {hi}]"))
    }
}

impl WalkParams {
    /// How fast a forward or backward speed may come down [m/s²].
    pub fn decel_forward_m_s2(&self) -> f64 {
        self.decel_forward_m_s2.unwrap_or(self.accel_forward_m_s2)
    }

    /// Every field within physically sensible bounds for a humanoid from the NAO's size (0.385 m
    /// standing torso height) to the T1's (0.67 m).
    pub fn validate(&self) -> Check {
        let w = "walk";
        in_range(&format!("{w}.step_period_s"), self.step_period_s, 0.1, 1.0)?;
        in_range(
            &format!("{w}.torso_height_m"),
            self.torso_height_m,
            0.2,
            0.7,
        )?;
        in_range(
            &format!("{w}.torso_lean_deg"),
            self.torso_lean_deg,
            -20.0,
            30.0,
        )?;
        in_range(
            &format!("{w}.foot_x_offset_m"),
            self.foot_x_offset_m,
            -0.15,
            0.15,
        )?;
        in_range(
            &format!("{w}.foot_y_offset_m"),
            self.foot_y_offset_m,
            0.03,
            0.2,
        )?;
        in_range(&format!("{w}.step_height_m"), self.step_height_m, 0.0, 0.15)?;
        in_range(&format!("{w}.sway_m"), self.sway_m, 0.0, 0.1)?;
        in_range(
            &format!("{w}.sway_phase_lead"),
            self.sway_phase_lead,
            0.0,
            0.5,
        )?;
        in_range(&format!("{w}.settle_s"), self.settle_s, 0.0, 3.0)?;
        in_range(
            &format!("{w}.start_lift_scale"),
            self.start_lift_scale,
            0.0,
            1.0,
        )?;
        in_range(
            &format!("{w}.max_forward_m_s"),
            self.max_forward_m_s,
            0.0,
            2.0,
        )?;
        in_range(
            &format!("{w}.max_backward_m_s"),
            self.max_backward_m_s,
            0.0,
            2.0,
        )?;
        in_range(
            &format!("{w}.max_sideways_m_s"),
            self.max_sideways_m_s,
            0.0,
            1.0,
        )?;
        in_range(
            &format!("{w}.max_turn_deg_s"),
            self.max_turn_deg_s,
            0.0,
            360.0,
        )?;
        in_range(
            &format!("{w}.accel_forward_m_s2"),
            self.accel_forward_m_s2,
            0.01,
            10.0,
        )?;
        if let Some(decel) = self.decel_forward_m_s2 {
            in_range(&format!("{w}.decel_forward_m_s2"), decel, 0.01, 10.0)?;
        }
        if let Some(k) = &self.kick_step {
            k.validate()?;
        }
        in_range(
            &format!("{w}.accel_sideways_m_s2"),
            self.accel_sideways_m_s2,
            0.01,
            10.0,
        )?;
        in_range(
            &format!("{w}.accel_turn_deg_s2"),
            self.accel_turn_deg_s2,
            1.0,
            2000.0,
        )?;
        in_range(
            &format!("{w}.arm_swing_deg_per_m"),
            self.arm_swing_deg_per_m,
            -500.0,
            500.0,
        )?;
        // Joint names are checked against the robot model in `SkillParams::validate`.
        for (joint, g) in &self.leg_gains {
            in_range(&format!("{w}.leg_gains.{joint}.kp"), g.kp, 0.0, MAX_KP)?;
            in_range(&format!("{w}.leg_gains.{joint}.kd"), g.kd, 0.0, MAX_KD)?;
        }
        let b = &self.balance;
        let gain = |name: &str, v: f64| in_range(&format!("{w}.balance.{name}"), v, -5.0, 5.0);
        gain("ankle_pitch_per_gyro", b.ankle_pitch_per_gyro)?;
        gain("ankle_pitch_per_tilt", b.ankle_pitch_per_tilt)?;
        gain("hip_pitch_per_gyro", b.hip_pitch_per_gyro)?;
        gain("ankle_roll_per_gyro", b.ankle_roll_per_gyro)?;
        gain("hip_roll_per_gyro", b.hip_roll_per_gyro)?;
        in_range(
            &format!("{w}.balance.step_x_per_tilt_m"),
            b.step_x_per_tilt_m,
            -0.05,
            0.05,
        )?;
        in_range(
            &format!("{w}.balance.rest_correction_scale"),
            b.rest_correction_scale,
            0.0,
            2.0,
        )?;
        in_range(
            &format!("{w}.balance.stop_capture_min_deg"),
            b.stop_capture_min_deg,
            0.0,
            30.0,
        )?;
        in_range(
            &format!("{w}.balance.lean_per_accel_deg"),
            b.lean_per_accel_deg,
            0.0,
            20.0,
        )?;
        in_range(
            &format!("{w}.balance.max_correction_deg"),
            b.max_correction_deg,
            0.0,
            30.0,
        )?;
        let t = &self.walk_to;
        in_range(&format!("{w}.walk_to.gain_per_s"), t.gain_per_s, 0.01, 10.0)?;
        in_range(
            &format!("{w}.walk_to.turn_gain_per_s"),
            t.turn_gain_per_s,
            0.01,
            10.0,
        )?;
        in_range(
            &format!("{w}.walk_to.face_target_beyond_m"),
            t.face_target_beyond_m,
            0.0,
            100.0,
        )?;
        in_range(&format!("{w}.walk_to.arrive_m"), t.arrive_m, 0.001, 1.0)?;
        in_range(&format!("{w}.walk_to.arrive_deg"), t.arrive_deg, 0.1, 90.0)?;
        in_range(
            &format!("{w}.walk_to.restart_m"),
            t.restart_m,
            t.arrive_m,
            2.0,
        )?;
        in_range(
            &format!("{w}.walk_to.restart_deg"),
            t.restart_deg,
            t.arrive_deg,
            90.0,
        )?;
        Ok(())
    }
}
