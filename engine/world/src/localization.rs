//! Self-localization: where the torso is on the field and which way it faces.
//!
//! Every cycle: roll and pitch come from the accelerometer (gravity direction), yaw is carried
//! forward by the gyro and position by leg odometry (the support foot stays put). On vision
//! frames each known landmark's polar observation is taken to the torso frame through the
//! camera pose (forward kinematics of the head joints), levelled with roll/pitch, and fused in an
//! extended Kalman filter over (x, y, yaw). With two or more landmarks a closed-form least-squares
//! fit (2-D Procrustes) initialises the filter and re-initialises it when the robot was moved.
//!
//! Everything is in the server's global field frame (+x towards the right goal), for both
//! teams; see [`crate::World::to_own_frame`] for the team's own frame.

use crate::camera_calibration::CameraCalibration;
use crate::geometry::{heading_of, polar_to_point, rotate2, wrap_rad};
use crate::params::LocalizationParams;
use libero_model::kinematics::{BodyPoses, Kinematics};
use libero_model::FieldGeometry;
use libero_protocol::percept::{Seen, Vision, MAX_LANDMARKS};
use nalgebra::{Matrix2, Matrix2x3, Matrix3, Point3, UnitQuaternion, Vector2, Vector3};
use pose_fit::{closed_form_fit, PoseFit};

#[path = "localization_pose_fit.rs"]
mod pose_fit;
#[path = "localization_tilt.rs"]
mod tilt;

/// The agent's belief about its own torso pose.
/// Magnitude of gravity [m/s²] (MuJoCo and SimSpark both use it).
const STANDARD_GRAVITY: f64 = 9.81;
/// Low-pass factor per cycle of the accelerometer copy used to detect a still body.
const ACCEL_SMOOTHING: f64 = 0.3;

#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct SelfEstimate {
    /// Torso position on the ground, global field frame [m].
    pub position: [f64; 2],
    /// Heading of the torso's x axis in the global field frame [deg], 0 = facing +x, + = left.
    pub yaw_deg: f64,
    /// Torso height above the ground from landmark elevations [m] (`None` before any vision).
    pub height: Option<f64>,
    /// Torso roll and pitch from the accelerometer [deg].
    pub roll_deg: f64,
    pub pitch_deg: f64,
    /// 1-σ position uncertainty [m] (largest axis) and heading uncertainty [deg].
    pub position_sigma: f64,
    pub yaw_sigma_deg: f64,
    /// True once vision has fixed the pose at least once.
    pub localized: bool,
    /// Simulation time of the last vision frame that contributed a landmark.
    pub last_fix_time: Option<f64>,
    /// Landmarks used in the latest vision frame.
    pub landmarks_used: usize,
    /// Closed-form re-initialisations so far (robot moved by the referee, a beam, a monitor).
    pub relocalizations: u32,
}

impl Default for SelfEstimate {
    fn default() -> Self {
        Self {
            position: [0.0; 2],
            yaw_deg: 0.0,
            height: None,
            roll_deg: 0.0,
            pitch_deg: 0.0,
            position_sigma: f64::INFINITY,
            yaw_sigma_deg: 180.0,
            localized: false,
            last_fix_time: None,
            landmarks_used: 0,
            relocalizations: 0,
        }
    }
}

/// One landmark observation levelled to the yaw-only frame.
#[derive(Debug, Clone, Copy)]
struct LevelledLandmark {
    /// True position on the field.
    field: Vector3<f64>,
    /// Offset from the torso, rotated by roll/pitch but not yaw.
    offset: Vector3<f64>,
    sigma: f64,
}

/// The localization filter and the kinematic buffers it reuses every cycle.
#[derive(Debug, Clone)]
pub struct Localizer {
    params: LocalizationParams,
    kinematics: Kinematics,
    poses: BodyPoses,
    camera_frame: Option<usize>,
    foot_frames: Option<[usize; 2]>,
    default_height: f64,
    /// (x, y, yaw [rad]) and its covariance.
    state: Vector3<f64>,
    covariance: Matrix3<f64>,
    initialized: bool,
    /// World "up" seen from the torso (unit), carried by the gyro and pulled towards the
    /// accelerometer.
    up: Vector3<f64>,
    /// The accelerometer low-passed over a few cycles, to tell a still body from a swaying one.
    accel_smoothed: Vector3<f64>,
    /// False until the first usable accelerometer reading, which sets "up" outright.
    tilt_known: bool,
    /// Torso → levelled frame (roll and pitch only).
    tilt: UnitQuaternion<f64>,
    previous_feet: Option<[Vector3<f64>; 2]>,
    /// Frames the camera reports when the robot sees itself, by the part name it uses.
    seen_parts: Vec<(String, usize)>,
    calibration: CameraCalibration,
    rejected_frames: u32,
    /// The previous vision frame's fit from landmarks alone (a fit of few landmarks must agree
    /// with it before it relocalizes).
    previous_fit: Option<PoseFit>,
    height: Option<f64>,
    scratch: Vec<LevelledLandmark>,
    estimate: SelfEstimate,
}

impl Localizer {
    pub fn new(
        model: &libero_model::RobotModel,
        kinematics: Kinematics,
        params: LocalizationParams,
    ) -> Self {
        let camera_frame = kinematics.frame_id("camera");
        let foot_frames = kinematics
            .frame_id("left_foot")
            .zip(kinematics.frame_id("right_foot"))
            .map(|(l, r)| [l, r]);
        let seen_parts = model
            .frames
            .iter()
            .filter_map(|f| Some((f.seen_as.clone()?, kinematics.frame_id(&f.name)?)))
            .collect();
        Self {
            params,
            poses: kinematics.new_poses(),
            kinematics,
            camera_frame,
            foot_frames,
            default_height: model.standing_torso_height,
            state: Vector3::zeros(),
            covariance: Matrix3::from_diagonal(&Vector3::new(1e4, 1e4, 10.0)),
            initialized: false,
            up: Vector3::z(),
            tilt_known: false,
            accel_smoothed: Vector3::z() * STANDARD_GRAVITY,
            tilt: UnitQuaternion::identity(),
            previous_feet: None,
            seen_parts,
            calibration: CameraCalibration::default(),
            rejected_frames: 0,
            previous_fit: None,
            height: None,
            scratch: Vec::with_capacity(32),
            estimate: SelfEstimate::default(),
        }
    }

    pub fn estimate(&self) -> &SelfEstimate {
        &self.estimate
    }

    /// Torso → global-field rotation (estimated roll, pitch and yaw).
    pub fn orientation(&self) -> UnitQuaternion<f64> {
        UnitQuaternion::from_axis_angle(&Vector3::z_axis(), self.state.z) * self.tilt
    }

    /// Torso origin in the global field frame (height from vision, else the model's standing height).
    pub fn torso_position(&self) -> Vector3<f64> {
        Vector3::new(
            self.state.x,
            self.state.y,
            self.height.unwrap_or(self.default_height),
        )
    }

    /// The camera-frame point `p` in the global field frame, using the current pose estimate.
    pub fn camera_to_field(&self, p: &Point3<f64>) -> Option<Vector3<f64>> {
        let camera = self.poses.frame_in_torso(self.camera_frame?)?;
        let p = self.calibration.corrected(p);
        let v = self.orientation() * (camera * p).coords + self.torso_position();
        v.iter().all(|c| c.is_finite()).then_some(v)
    }

    /// The robot's own parts in this cycle's vision (SimSpark reports the feet when they are
    /// in view): each tells the camera's offset (`CameraCalibration`). After [`Self::update`].
    pub fn observe_own_parts(&mut self, parts: &[Seen<'_>]) {
        if self.seen_parts.is_empty() {
            return;
        }
        let Some(camera) = self
            .camera_frame
            .and_then(|c| self.poses.frame_in_torso(c))
            .copied()
        else {
            return;
        };
        for seen in parts {
            let Some(&(_, frame)) = self.seen_parts.iter().find(|(n, _)| n == seen.name) else {
                continue;
            };
            let (Some(part), Some(at)) =
                (self.poses.frame_in_torso(frame), polar_to_point(&seen.at))
            else {
                continue;
            };
            let part = Point3::from(part.translation.vector);
            self.calibration.observe(&camera, &part, &at);
        }
    }

    /// One cycle. `joint_angles` are the body's current angles (model order), `dt` the time since
    /// the previous percept (0 if unknown), `upright` whether leg odometry applies.
    #[allow(clippy::too_many_arguments)]
    pub fn update(
        &mut self,
        field: &FieldGeometry,
        joint_angles: &[f64],
        gyro_deg: Option<[f64; 3]>,
        accel: Option<[f64; 3]>,
        vision: Option<&Vision<'_>>,
        time: f64,
        dt: f64,
        upright: bool,
    ) {
        let kinematics_ok = self
            .kinematics
            .forward(joint_angles, &mut self.poses)
            .is_ok();
        // Both leg gains off, nothing of the legs is worked out per cycle.
        let legs_used =
            self.params.tilt_leg_correction > 0.0 || self.params.tilt_stand_correction > 0.0;
        let leg_up = (kinematics_ok && upright && legs_used)
            .then(|| self.leg_up())
            .flatten();
        self.update_tilt(gyro_deg, accel, dt, leg_up);
        if self.initialized {
            self.predict(gyro_deg, dt, kinematics_ok && upright);
        }
        if let (Some(vision), true) = (vision, kinematics_ok) {
            self.correct(field, vision, time);
        }
        self.publish();
    }

    fn predict(&mut self, gyro_deg: Option<[f64; 3]>, dt: f64, odometry: bool) {
        let dt = if dt.is_finite() {
            dt.clamp(0.0, 0.2)
        } else {
            0.0
        };
        if let Some(g) = gyro_deg.map(Vector3::from) {
            if g.iter().all(|c| c.is_finite()) {
                let world_rate = (self.tilt * g.map(f64::to_radians)).z;
                self.state.z = wrap_rad(self.state.z + world_rate * dt);
            }
        }
        let mut moved = 0.0;
        let feet = self.feet_in_yaw_frame();
        if let (Some(now), Some(before), true) = (feet, self.previous_feet, odometry) {
            // The lower foot carries the weight and stays where it is on the ground.
            let support = if now[0].z <= now[1].z { 0 } else { 1 };
            let delta = -(now[support] - before[support]).xy();
            // A beam or a referee relocation resets the joints: not a step.
            if delta.norm() < 0.1 {
                self.state.x += delta.x;
                self.state.y += delta.y;
                moved = delta.norm();
            }
        }
        self.previous_feet = feet;
        let p = &self.params;
        let sigma_xy = p.odometry_sigma_per_cycle + p.odometry_sigma_per_metre * moved;
        let sigma_yaw = p.yaw_sigma_per_cycle_deg.to_radians();
        self.covariance += Matrix3::from_diagonal(&Vector3::new(
            sigma_xy * sigma_xy,
            sigma_xy * sigma_xy,
            sigma_yaw * sigma_yaw,
        ));
    }

    /// Both feet relative to the torso, rotated into the field's axes (yaw included).
    fn feet_in_yaw_frame(&self) -> Option<[Vector3<f64>; 2]> {
        let [l, r] = self.foot_frames?;
        let rotation = self.orientation();
        let left = rotation * self.poses.frame_in_torso(l)?.translation.vector;
        let right = rotation * self.poses.frame_in_torso(r)?.translation.vector;
        Some([left, right])
    }

    fn correct(&mut self, field: &FieldGeometry, vision: &Vision<'_>, time: f64) {
        let Some(camera) = self.camera_frame.and_then(|c| self.poses.frame_in_torso(c)) else {
            return;
        };
        let camera = *camera;
        self.scratch.clear();
        // Each name looked up once; a name listed twice is ambiguous: use neither copy.
        let known: arrayvec::ArrayVec<Option<usize>, MAX_LANDMARKS> = vision
            .landmarks
            .iter()
            .map(|seen| field.landmark_index(seen.name))
            .collect();
        for (i, seen) in vision.landmarks.iter().enumerate() {
            let Some(index) = known[i] else {
                continue;
            };
            let duplicate = known
                .iter()
                .enumerate()
                .any(|(j, other)| j != i && *other == Some(index));
            let (Some(p), false) = (polar_to_point(&seen.at), duplicate) else {
                continue;
            };
            let true_pos = field.landmarks[index].position;
            let offset = self.tilt * (camera * p).coords;
            let sigma = self.params.vision_sigma_floor
                + self.params.vision_sigma_per_metre * seen.at.distance;
            self.scratch.push(LevelledLandmark {
                field: Vector3::from(true_pos),
                offset,
                sigma,
            });
        }
        if self.scratch.is_empty() {
            return;
        }
        self.update_height();
        let fit = closed_form_fit(&self.scratch);
        let previous_fit = std::mem::replace(&mut self.previous_fit, fit);
        if let Some(fit) = fit {
            if self.should_relocalize(&fit, self.scratch.len(), previous_fit.as_ref()) {
                self.reset_to(&fit);
                self.estimate.last_fix_time = Some(time);
                self.estimate.landmarks_used = self.scratch.len();
                return;
            }
        }
        if !self.initialized {
            return;
        }
        let mut used = 0;
        for k in 0..self.scratch.len() {
            let landmark = self.scratch[k];
            if self.fuse_landmark(&landmark) {
                used += 1;
            }
        }
        self.estimate.landmarks_used = used;
        if used > 0 {
            self.rejected_frames = 0;
            self.estimate.last_fix_time = Some(time);
        } else {
            self.rejected_frames += 1;
            if self.rejected_frames >= self.params.lost_after_rejected_frames {
                // Vision keeps disagreeing: the position is what is most likely wrong (the
                // gyro keeps the yaw); widen it so the next landmarks pull it back.
                self.covariance[(0, 0)] += 4.0;
                self.covariance[(1, 1)] += 4.0;
                self.rejected_frames = 0;
            }
        }
    }

    fn update_height(&mut self) {
        let n = self.scratch.len() as f64;
        let mean = self
            .scratch
            .iter()
            .map(|l| l.field.z - l.offset.z)
            .sum::<f64>()
            / n;
        if mean.is_finite() {
            self.height = Some(mean);
        }
    }

    fn should_relocalize(
        &self,
        fit: &PoseFit,
        landmarks: usize,
        previous: Option<&PoseFit>,
    ) -> bool {
        // Two landmarks fix a pose whatever their offsets say, and a camera tilted by a fast
        // turn says them wrong: such a fit once moved a robot 0.86 m for one frame, its ball
        // with it, and a shot was chosen from 11 m (striker_alone, NOTES.md session 30). Once
        // localized, a fit of fewer than `relocalize_min_landmarks` relocalizes only when the
        // previous vision frame's fit agrees with it (a robot really moved stays moved).
        if self.initialized && landmarks < self.params.relocalize_min_landmarks {
            let agrees = previous.is_some_and(|p| {
                (p.position - fit.position).norm() <= 0.5 * self.params.relocalize_distance
                    && wrap_rad(p.yaw - fit.yaw).abs().to_degrees()
                        <= 0.5 * self.params.relocalize_yaw_deg
            });
            if !agrees {
                return false;
            }
        }
        let distance = (fit.position - self.state.xy()).norm();
        // A rougher fit still wins when the estimate is far further off than the fit could
        // be: the robot was placed elsewhere (a beam, the referee, a monitor), which neither
        // odometry nor the gyro saw. Measured: fits of 0.1-0.7 m rms right after a placement
        // while the estimate was 30 m and 90 degrees away.
        if fit.rms > self.params.relocalize_fit_rms {
            return self.initialized
                && fit.rms <= self.params.relocalize_far_fit_rms
                && distance > self.params.relocalize_far_ratio * fit.rms;
        }
        if !self.initialized {
            return true;
        }
        let yaw = wrap_rad(fit.yaw - self.state.z).abs().to_degrees();
        distance > self.params.relocalize_distance || yaw > self.params.relocalize_yaw_deg
    }

    fn reset_to(&mut self, fit: &PoseFit) {
        self.state = Vector3::new(fit.position.x, fit.position.y, fit.yaw);
        let s = self.params.vision_sigma_floor.max(fit.rms);
        let yaw_sigma = (s / fit.spread.max(0.1)).min(1.0);
        self.covariance =
            Matrix3::from_diagonal(&Vector3::new(s * s, s * s, yaw_sigma * yaw_sigma));
        self.initialized = true;
        self.rejected_frames = 0;
        self.previous_feet = None;
        self.estimate.relocalizations += 1;
    }

    /// One EKF update with one landmark; false if it was rejected as an outlier.
    fn fuse_landmark(&mut self, l: &LevelledLandmark) -> bool {
        let yaw = self.state.z;
        let from_torso = l.field.xy() - self.state.xy();
        let predicted = rotate2(from_torso, -yaw);
        let residual = l.offset.xy() - predicted;
        let (s, c) = yaw.sin_cos();
        // d/dp of R(−yaw)(q − p) is −R(−yaw); d/dyaw is R'(−yaw)(q − p).
        let d_yaw = Vector2::new(
            -s * from_torso.x + c * from_torso.y,
            -c * from_torso.x - s * from_torso.y,
        );
        let h = Matrix2x3::new(-c, -s, d_yaw.x, s, -c, d_yaw.y);
        let innovation_cov =
            h * self.covariance * h.transpose() + Matrix2::identity() * (l.sigma * l.sigma);
        let Some(inverse) = innovation_cov.try_inverse() else {
            return false;
        };
        let mahalanobis = (residual.transpose() * inverse * residual)[(0, 0)];
        // NaN fails this test too.
        if mahalanobis.is_nan() || mahalanobis > self.params.outlier_gate {
            return false;
        }
        let gain = self.covariance * h.transpose() * inverse;
        let correction = gain * residual;
        if !correction.iter().all(|c| c.is_finite()) {
            return false;
        }
        self.state += correction;
        self.state.z = wrap_rad(self.state.z);
        let i_kh = Matrix3::identity() - gain * h;
        // Joseph form: stays symmetric positive definite through thousands of updates.
        self.covariance = i_kh * self.covariance * i_kh.transpose()
            + gain * (l.sigma * l.sigma) * gain.transpose();
        true
    }

    fn publish(&mut self) {
        let rotation = self.orientation();
        let e = &mut self.estimate;
        e.localized = self.initialized;
        if !self.initialized {
            return;
        }
        e.position = [self.state.x, self.state.y];
        e.yaw_deg = heading_of(&rotation).to_degrees();
        e.height = self.height;
        let (roll, pitch, _) = self.tilt.euler_angles();
        e.roll_deg = roll.to_degrees();
        e.pitch_deg = pitch.to_degrees();
        let position_var = self
            .covariance
            .fixed_view::<2, 2>(0, 0)
            .symmetric_eigenvalues()
            .max();
        e.position_sigma = position_var.max(0.0).sqrt();
        e.yaw_sigma_deg = self.covariance[(2, 2)].max(0.0).sqrt().to_degrees();
    }
}

#[cfg(test)]
#[path = "localization_tests.rs"]
mod tests;
