//! The camera's own offset, told from the robot's view of itself.
//!
//! SimSpark adds to every point its camera reports a calibration offset drawn once per robot
//! (up to 5 mm per axis, in the camera frame; simspark.md, vision). Far away it is lost in the
//! noise; at the ball before a kick it is the largest error left (the kick bench: the robot's
//! ball estimate off by 2.7 mm sd, constant through each look). The robot sees its own feet,
//! whose place in the camera frame it knows from its joint angles, so the offset is the mean of
//! what it sees minus what it knows; the points placed on the field through
//! `Localizer::camera_to_field` (the ball, other robots) are corrected by it. The landmarks are
//! not: metres away, 5 mm is lost in their noise.

use nalgebra::{Isometry3, Point3, Vector3};

/// Own-body sightings further from where the joints put them than this are not the offset
/// (a part mis-named, or seen mid-jolt) and are left out [m].
const MAX_RESIDUAL_M: f64 = 0.03;
/// Sightings before the mean is used: one is off by up to the 5 mm distance rounding.
const MIN_SIGHTINGS: u32 = 20;
/// Beyond this many sightings, a running mean over about this many (bounded memory, and a
/// robot that is somehow re-created moves on to its new offset).
const WINDOW: u32 = 1000;

/// The running estimate of the offset the camera adds.
#[derive(Debug, Clone, Default)]
pub struct CameraCalibration {
    offset: Vector3<f64>,
    sightings: u32,
}

impl CameraCalibration {
    /// One sighting of an own body part: `seen` is where the camera put it (camera frame),
    /// `part_in_torso` where the joints put it and `camera_in_torso` the camera's pose.
    pub fn observe(
        &mut self,
        camera_in_torso: &Isometry3<f64>,
        part_in_torso: &Point3<f64>,
        seen: &Point3<f64>,
    ) {
        let known = camera_in_torso.inverse_transform_point(part_in_torso);
        let residual = seen - known;
        if !residual.iter().all(|c| c.is_finite()) || residual.norm() > MAX_RESIDUAL_M {
            return;
        }
        self.sightings = (self.sightings + 1).min(WINDOW);
        self.offset += (residual - self.offset) / f64::from(self.sightings);
    }

    /// The offset, once enough sightings agree on it.
    pub fn offset(&self) -> Option<Vector3<f64>> {
        (self.sightings >= MIN_SIGHTINGS).then_some(self.offset)
    }

    /// A camera-frame point with the offset taken out (unchanged before it is known).
    pub fn corrected(&self, seen: &Point3<f64>) -> Point3<f64> {
        match self.offset() {
            Some(offset) => seen - offset,
            None => *seen,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{Translation3, UnitQuaternion};

    /// Sightings of two feet from a camera looking down, each with the fixed offset and the
    /// server's rounding of the distance to 1 cm, as the robot steps (the feet move).
    #[test]
    fn the_offset_is_found_from_the_feet_and_taken_out_of_a_ball() {
        let offset = Vector3::new(0.004, -0.003, 0.0045);
        let camera = Isometry3::from_parts(
            Translation3::new(0.01, 0.0, 0.15),
            UnitQuaternion::from_euler_angles(0.0, 40f64.to_radians(), 0.0),
        );
        // What the server reports: the true camera-frame point plus the offset, its distance
        // rounded to 0.01 m (the direction kept).
        let report = |in_torso: Point3<f64>| {
            let v = camera.inverse_transform_point(&in_torso).coords + offset;
            let d = v.norm();
            Point3::from(v * ((d * 100.0).round() / 100.0 / d))
        };
        let mut calibration = CameraCalibration::default();
        assert_eq!(calibration.offset(), None);
        for step in 0..200 {
            let swing = 0.04 * (f64::from(step) * 0.37).sin();
            for (y, x) in [(0.05, swing), (-0.05, -swing)] {
                let foot = Point3::new(0.03 + x, y, -0.32 + 0.01 * swing.abs());
                calibration.observe(&camera, &foot, &report(foot));
            }
        }
        let found = calibration.offset().expect("enough sightings");
        assert!((found - offset).norm() < 0.0015, "{found:?} vs {offset:?}");
        // A ball before the kick: corrected, it is nearer the truth than the raw report.
        let ball = Point3::new(0.163, 0.05, -0.29);
        let raw = report(ball);
        let truth = camera.inverse_transform_point(&ball);
        let fixed = calibration.corrected(&raw);
        assert!(
            (fixed - truth).norm() < (raw - truth).norm() - 0.002,
            "raw off by {:.4}, corrected by {:.4}",
            (raw - truth).norm(),
            (fixed - truth).norm()
        );
        // A sighting far from where the joints put the part is not taken.
        let foot = Point3::new(0.03, 0.05, -0.32);
        calibration.observe(&camera, &foot, &Point3::new(0.5, 0.5, 0.5));
        assert_eq!(calibration.offset(), Some(found));
    }
}
