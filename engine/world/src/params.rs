//! Tunable constants of the world model, read from RON and validated on load
//! (`engine/world/params/world.ron` is the shipped default).

use crate::ball_launch::LaunchTable;
use serde::{Deserialize, Serialize};
use std::path::Path;

/// Self-localization filter settings (see `params/world.ron` for the meaning of each).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LocalizationParams {
    pub vision_sigma_floor: f64,
    pub vision_sigma_per_metre: f64,
    pub odometry_sigma_per_cycle: f64,
    pub odometry_sigma_per_metre: f64,
    pub yaw_sigma_per_cycle_deg: f64,
    pub outlier_gate: f64,
    pub relocalize_distance: f64,
    pub relocalize_yaw_deg: f64,
    pub relocalize_fit_rms: f64,
    /// A fit rougher than `relocalize_fit_rms` but within this [m] still relocalizes when the
    /// estimate lies more than `relocalize_far_ratio` times its rms away (a placement).
    pub relocalize_far_fit_rms: f64,
    pub relocalize_far_ratio: f64,
    /// Once localized, a fit of fewer landmarks relocalizes only when the previous vision
    /// frame's fit agrees with it.
    pub relocalize_min_landmarks: usize,
    pub lost_after_rejected_frames: u32,
    pub tilt_accel_correction: f64,
    /// Upright, the stance leg's kinematics give "up" too (the support sole flat on the
    /// ground): the pull towards it per cycle, used instead of the accelerometer's while
    /// moving (0: off; absent from a file: 0) ...
    #[serde(default)]
    pub tilt_leg_correction: f64,
    /// ... when it lies within this of the gyro-carried "up" [deg] (a sole rolling over its
    /// toe or heel is not flat).
    #[serde(default)]
    pub tilt_leg_gate_deg: f64,
    /// ... and the pull towards the legs' "up" while both feet stand flat side by side (0:
    /// off; absent from a file: 0).
    #[serde(default)]
    pub tilt_stand_correction: f64,
    pub tilt_accel_correction_still: f64,
    pub still_gyro_deg_s: f64,
    pub still_accel_tolerance: f64,
}

/// Ball tracking and motion-model settings.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BallParams {
    pub fit_window_s: f64,
    pub new_track_gate: f64,
    pub start_gate: f64,
    /// A jump that would need a faster launch than this [m/s] was a placement (the referee,
    /// a monitor), not a kick: the ball starts a new track at rest, with no launch.
    pub max_launch_speed_m_s: f64,
    /// A track moves only when its window's straight-line velocity exceeds this many standard
    /// errors of the points' scatter about the line ...
    pub motion_significance: f64,
    /// ... taken as at least this [m] (vision's rounding).
    pub scatter_floor_m: f64,
    pub launch_fit_s: f64,
    pub rest_speed: f64,
    pub rolling_speed_ratio: f64,
    /// Deceleration constants by direction of travel (folded into 0–45°), ascending angles.
    pub friction_by_direction: Vec<DirectionalFriction>,
    pub drag_learning_rate: f64,
    pub drag_factor_bounds: (f64, f64),
    /// Stop points and early chord directions of spin-free launches (server physics).
    pub launch_table: LaunchTable,
}

/// Deceleration = constant + quadratic_drag·v² for a ball travelling at `angle_deg` to a
/// field axis.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DirectionalFriction {
    pub angle_deg: f64,
    /// Constant part while sliding [m/s²].
    pub sliding: f64,
    /// Constant part while rolling [m/s²].
    pub rolling: f64,
    /// [1/m]
    pub quadratic_drag: f64,
}

/// Other players' settings.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PlayerParams {
    pub fallen_head_height: f64,
    pub forget_after_s: f64,
}

/// The robot's own body.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BodyParams {
    /// The accelerometer must say lying for this long [s] before the robot counts as fallen.
    pub lying_confirm_s: f64,
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WorldParams {
    pub body: BodyParams,
    pub localization: LocalizationParams,
    pub ball: BallParams,
    pub players: PlayerParams,
}

#[derive(Debug, thiserror::Error)]
pub enum ParamsError {
    #[error("cannot read {0}: {1}")]
    Io(String, std::io::Error),
    #[error("{0}")]
    Syntax(libero_model::Located),
    #[error("{file}: invalid world parameters:\n  {}", .problems.join("\n  "))]
    Invalid { file: String, problems: Vec<String> },
}

const BUILTIN: &str = include_str!("../params/world.ron");

impl WorldParams {
    /// The shipped defaults (validated by a unit test, so this cannot fail at run time).
    pub fn builtin() -> Self {
        Self::from_ron("<builtin>/world.ron", BUILTIN).expect("shipped world.ron is valid")
    }

    pub fn load(path: &Path) -> Result<Self, ParamsError> {
        let text = std::fs::read_to_string(path)
            .map_err(|e| ParamsError::Io(path.display().to_string(), e))?;
        Self::from_ron(&path.display().to_string(), &text)
    }

    pub fn from_ron(file: &str, text: &str) -> Result<Self, ParamsError> {
        let params: WorldParams =
            libero_model::location::parse_ron(file, text).map_err(ParamsError::Syntax)?;
        let problems = params.problems();
        if problems.is_empty() {
            Ok(params)
        } else {
            Err(ParamsError::Invalid {
                file: file.to_string(),
                problems,
            })
        }
    }

    /// Every value that would make a filter or the motion model misbehave.
    pub fn problems(&self) -> Vec<String> {
        let mut problems = Vec::new();
        let l = &self.localization;
        let b = &self.ball;
        let mut positive = |name: &str, v: f64| {
            if !(v.is_finite() && v > 0.0) {
                problems.push(format!("`{name}` must be a positive number, not {v}"));
            }
        };
        positive("vision_sigma_floor", l.vision_sigma_floor);
        positive("odometry_sigma_per_cycle", l.odometry_sigma_per_cycle);
        positive("yaw_sigma_per_cycle_deg", l.yaw_sigma_per_cycle_deg);
        positive("outlier_gate", l.outlier_gate);
        positive("relocalize_distance", l.relocalize_distance);
        positive("relocalize_yaw_deg", l.relocalize_yaw_deg);
        positive("relocalize_fit_rms", l.relocalize_fit_rms);
        positive("relocalize_far_fit_rms", l.relocalize_far_fit_rms);
        positive("relocalize_far_ratio", l.relocalize_far_ratio);
        positive("fit_window_s", b.fit_window_s);
        positive("new_track_gate", b.new_track_gate);
        positive("start_gate", b.start_gate);
        positive("max_launch_speed_m_s", b.max_launch_speed_m_s);
        positive("motion_significance", b.motion_significance);
        positive("scatter_floor_m", b.scatter_floor_m);
        positive("launch_fit_s", b.launch_fit_s);
        positive("rest_speed", b.rest_speed);
        for (i, f) in b.friction_by_direction.iter().enumerate() {
            positive(&format!("friction_by_direction[{i}].sliding"), f.sliding);
            positive(&format!("friction_by_direction[{i}].rolling"), f.rolling);
        }
        positive("fallen_head_height", self.players.fallen_head_height);
        positive("forget_after_s", self.players.forget_after_s);
        let mut non_negative = |name: &str, v: f64| {
            if !(v.is_finite() && v >= 0.0) {
                problems.push(format!("`{name}` must be zero or positive, not {v}"));
            }
        };
        non_negative("lying_confirm_s", self.body.lying_confirm_s);
        non_negative("vision_sigma_per_metre", l.vision_sigma_per_metre);
        non_negative("odometry_sigma_per_metre", l.odometry_sigma_per_metre);
        non_negative("still_gyro_deg_s", l.still_gyro_deg_s);
        non_negative("still_accel_tolerance", l.still_accel_tolerance);
        for (i, f) in b.friction_by_direction.iter().enumerate() {
            non_negative(
                &format!("friction_by_direction[{i}].quadratic_drag"),
                f.quadratic_drag,
            );
        }
        non_negative("drag_learning_rate", b.drag_learning_rate);
        let mut fraction = |name: &str, v: f64| {
            if !(v.is_finite() && v > 0.0 && v <= 1.0) {
                problems.push(format!("`{name}` must be in (0, 1], not {v}"));
            }
        };
        fraction("tilt_accel_correction", l.tilt_accel_correction);
        fraction("tilt_accel_correction_still", l.tilt_accel_correction_still);
        fraction("rolling_speed_ratio", b.rolling_speed_ratio);
        let mut within = |name: &str, v: f64, lo: f64, hi: f64| {
            if !(v.is_finite() && (lo..=hi).contains(&v)) {
                problems.push(format!("`{name}` must be in [{lo}, {hi}], not {v}"));
            }
        };
        within("tilt_leg_correction", l.tilt_leg_correction, 0.0, 1.0);
        within("tilt_leg_gate_deg", l.tilt_leg_gate_deg, 0.0, 90.0);
        within("tilt_stand_correction", l.tilt_stand_correction, 0.0, 1.0);
        if l.relocalize_min_landmarks < 2 {
            problems.push(format!(
                "`relocalize_min_landmarks` must be at least 2 (a fit needs two landmarks), not {}",
                l.relocalize_min_landmarks
            ));
        }
        if b.drag_learning_rate > 1.0 {
            problems.push(format!(
                "`drag_learning_rate` must be at most 1, not {}",
                b.drag_learning_rate
            ));
        }
        let (lo, hi) = b.drag_factor_bounds;
        if !(lo.is_finite() && hi.is_finite() && 0.0 < lo && lo <= 1.0 && 1.0 <= hi) {
            problems.push(format!(
                "`drag_factor_bounds` must satisfy 0 < low ≤ 1 ≤ high, not ({lo}, {hi})"
            ));
        }
        let angles: Vec<f64> = b
            .friction_by_direction
            .iter()
            .map(|f| f.angle_deg)
            .collect();
        let ascending = angles.windows(2).all(|w| w[0] < w[1]);
        let in_range = angles.iter().all(|a| (0.0..=45.0).contains(a));
        if angles.is_empty() || !ascending || !in_range {
            problems.push(format!(
                "`friction_by_direction` needs at least one entry with ascending angles in 0–45°, \
                 got {angles:?}"
            ));
        }
        problems.extend(b.launch_table.problems());
        if l.lost_after_rejected_frames == 0 {
            problems.push("`lost_after_rejected_frames` must be at least 1".into());
        }
        problems
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shipped_parameters_are_valid() {
        let p = WorldParams::builtin();
        assert!(p.problems().is_empty());
    }

    #[test]
    fn invalid_values_are_reported_by_name() {
        let text = BUILTIN
            .replace("rolling_speed_ratio: 0.7135", "rolling_speed_ratio: 1.5")
            .replace("outlier_gate: 16.0", "outlier_gate: -1.0")
            .replace("angle_deg: 45.0", "angle_deg: 5.0")
            .replace("chord_times: [0.1,", "chord_times: [0.7,");
        let err = WorldParams::from_ron("w.ron", &text)
            .unwrap_err()
            .to_string();
        assert!(err.contains("rolling_speed_ratio"), "{err}");
        assert!(err.contains("outlier_gate"), "{err}");
        assert!(err.contains("friction_by_direction"), "{err}");
        assert!(err.contains("launch_table.chord_times"), "{err}");
        let err = WorldParams::from_ron("w.ron", "WorldParams(").unwrap_err();
        assert!(matches!(err, ParamsError::Syntax(_)), "{err}");
    }
}
