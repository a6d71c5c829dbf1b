//! Roll and pitch: which way is "up" in the torso frame, from the gyro, the accelerometer and
//! the legs.

use super::{Localizer, ACCEL_SMOOTHING, STANDARD_GRAVITY};
use nalgebra::{Isometry3, UnitQuaternion, Vector3};

/// Both soles this level with each other [m] ...
const STANDING_HEIGHT_M: f64 = 0.01;
/// ... this parallel [deg] ...
const STANDING_SOLES_DEG: f64 = 2.0;
/// ... and this close along the torso's forward axis [m]: feet side by side, standing. A
/// walk's double support has them a step apart.
const STANDING_SPREAD_M: f64 = 0.03;

/// World "up" in the torso frame as the legs have it.
#[derive(Debug, Clone, Copy)]
pub(super) struct LegUp {
    /// Through the support leg (the lower foot), its sole taken flat on the ground.
    up: Vector3<f64>,
    /// Both feet stand flat side by side: the robot stands on them.
    standing: bool,
}

impl Localizer {
    /// A complementary filter: the gyro carries "up" from cycle to cycle, the accelerometer
    /// pulls it back slowly. The accelerometer alone is fooled while walking: the torso's sway
    /// and step accelerations tilt the measured specific force by up to ±20°, which throws every
    /// landmark and ball projected through the camera.
    ///
    /// Upright, the legs give "up" far better than the accelerometer (`leg_up`, see
    /// [`Localizer::leg_up`]): walking at 0.65 m/s its pitch is off the truth by 0.24°
    /// rms against the accelerometer-pulled filter's 2.2°, which also lagged a forward
    /// runaway by up to 15° (NOTES.md, session 35); the gyro alone drifts ~0.35°/s nose-up.
    /// Standing, the accelerometer read a robot taking the walk's posture (leaning 5°
    /// forward) as leaning 3° back (NOTES.md, session 36).
    pub(super) fn update_tilt(
        &mut self,
        gyro_deg: Option<[f64; 3]>,
        accel: Option<[f64; 3]>,
        dt: f64,
        leg_up: Option<LegUp>,
    ) {
        if let Some(w) = gyro_deg.map(Vector3::from) {
            let dt = if dt.is_finite() {
                dt.clamp(0.0, 0.2)
            } else {
                0.0
            };
            if w.iter().all(|c| c.is_finite()) {
                // A world-fixed vector seen from a frame turning at ω turns at −ω.
                let turn = w.map(f64::to_radians) * -dt;
                self.up = UnitQuaternion::from_scaled_axis(turn) * self.up;
            }
        }
        let p = &self.params;
        if let Some(a) = accel.map(Vector3::from) {
            let g = a.norm();
            // Free fall or a hard impact says nothing about "up".
            if a.iter().all(|c| c.is_finite()) && (3.0..=20.0).contains(&g) {
                // Standing still, the accelerometer is the truth and is trusted at once (a beam or
                // a monitor move turns the body without the gyro seeing it).
                // (The magnitude alone cannot tell: a sideways sway changes it only second-order.)
                let steady = (a - self.accel_smoothed).norm() < p.still_accel_tolerance
                    && (g - STANDARD_GRAVITY).abs() < p.still_accel_tolerance;
                let still = steady
                    && gyro_deg.is_some_and(|w| w.iter().all(|c| c.abs() < p.still_gyro_deg_s));
                let gate = p.tilt_leg_gate_deg.to_radians();
                let leg = leg_up
                    .filter(|leg| leg.up.angle(&self.up) <= gate)
                    .map(|leg| {
                        let gain = if leg.standing {
                            p.tilt_stand_correction
                        } else {
                            p.tilt_leg_correction
                        };
                        (leg.up, gain)
                    })
                    .filter(|(_, gain)| *gain > 0.0);
                // The legs when they agree with the gyro; else the accelerometer, at once when
                // still (a beam or a monitor move turns the body unseen by the gyro).
                let (towards, gain) = match (self.tilt_known, leg, still) {
                    (false, _, _) => (a / g, 1.0),
                    (true, Some(leg), _) => leg,
                    (true, None, true) => (a / g, p.tilt_accel_correction_still),
                    (true, None, false) => (a / g, p.tilt_accel_correction),
                };
                self.up = turned_towards(self.up, towards, gain);
                self.accel_smoothed = if self.tilt_known {
                    self.accel_smoothed + ACCEL_SMOOTHING * (a - self.accel_smoothed)
                } else {
                    a
                };
                self.tilt_known = true;
            }
        }
        match self.up.try_normalize(1e-9) {
            Some(up) => self.up = up,
            None => self.up = Vector3::z(),
        }
        if let Some(t) = UnitQuaternion::rotation_between(&self.up, &Vector3::z()) {
            self.tilt = t;
        } else if self.up.z < 0.0 {
            // Exactly upside down: any half turn about a horizontal axis levels it.
            self.tilt = UnitQuaternion::from_axis_angle(&Vector3::x_axis(), std::f64::consts::PI);
        }
    }

    /// World "up" in the torso frame as the legs have it: the support foot (the lower one as
    /// the current estimate levels them) taken flat on the ground; standing when both soles
    /// are level, parallel and side by side.
    pub(super) fn leg_up(&self) -> Option<LegUp> {
        let [l, r] = self.foot_frames?;
        let (left, right) = (self.poses.frame_in_torso(l)?, self.poses.frame_in_torso(r)?);
        let level = |foot: &Isometry3<f64>| self.tilt * foot.translation.vector;
        let (left_at, right_at) = (level(left), level(right));
        let support = if left_at.z <= right_at.z { left } else { right };
        let sole_up = |foot: &Isometry3<f64>| foot.rotation * Vector3::z();
        let standing = (left_at.z - right_at.z).abs() < STANDING_HEIGHT_M
            && sole_up(left).angle(&sole_up(right)) < STANDING_SOLES_DEG.to_radians()
            && (left.translation.x - right.translation.x).abs() < STANDING_SPREAD_M;
        Some(LegUp {
            up: sole_up(support),
            standing,
        })
    }
}

/// `from` turned towards `to` (both unit vectors) by `fraction` of the angle between them. A
/// linear blend `from + k·(to − from)` would do the same for small angles, but barely turns a
/// vector that points the other way: the estimate then stayed on the back for the whole of a
/// get-up from lying face down (a monitor placement had turned the body unseen by the gyro).
pub(super) fn turned_towards(from: Vector3<f64>, to: Vector3<f64>, fraction: f64) -> Vector3<f64> {
    let angle = from.angle(&to);
    if angle < 1e-12 {
        return to;
    }
    // Opposite vectors: any axis at right angles to `from` will do.
    let axis = from.cross(&to).try_normalize(1e-9).unwrap_or_else(|| {
        let other = if from.x.abs() < 0.9 {
            Vector3::x()
        } else {
            Vector3::y()
        };
        from.cross(&other).normalize()
    });
    UnitQuaternion::from_axis_angle(&nalgebra::Unit::new_unchecked(axis), fraction * angle) * from
}
