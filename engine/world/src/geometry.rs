//! Small conversions shared by the estimators.

use libero_protocol::percept::Polar;
use nalgebra::{Point3, UnitQuaternion, Vector2, Vector3};

/// A polar observation as a point in the camera frame (x forward, y left, z up), or `None` if a
/// number is not finite.
pub fn polar_to_point(p: &Polar) -> Option<Point3<f64>> {
    let (az, el) = (p.azimuth_deg.to_radians(), p.elevation_deg.to_radians());
    let d = p.distance;
    let v = Point3::new(
        d * el.cos() * az.cos(),
        d * el.cos() * az.sin(),
        d * el.sin(),
    );
    (v.iter().all(|c| c.is_finite()) && d >= 0.0).then_some(v)
}

/// Wrap an angle to (−π, π].
pub fn wrap_rad(a: f64) -> f64 {
    let w = (a + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU) - std::f64::consts::PI;
    if w <= -std::f64::consts::PI {
        w + std::f64::consts::TAU
    } else {
        w
    }
}

/// Wrap an angle to (−180°, 180°].
pub fn wrap_deg(a: f64) -> f64 {
    wrap_rad(a.to_radians()).to_degrees()
}

/// Heading of the torso's x axis projected on the ground [rad], from a torso→world rotation.
pub fn heading_of(rotation: &UnitQuaternion<f64>) -> f64 {
    let x = rotation * Vector3::x();
    x.y.atan2(x.x)
}

/// Heading [deg] of a ground-truth quaternion (w, x, y, z).
pub fn heading_deg_of_quaternion(q: [f64; 4]) -> f64 {
    let r = UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(q[0], q[1], q[2], q[3]));
    heading_of(&r).to_degrees()
}

/// Roll and pitch [deg] of a torso whose orientation is `q` (w, x, y, z; torso to world), as
/// the estimate publishes them (`Localizer::publish`: the Euler roll and pitch, which do not
/// depend on the heading): pitch > 0 nose down, roll > 0 leaning right.
pub fn roll_pitch_deg_of_quaternion(q: [f64; 4]) -> (f64, f64) {
    let r = UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(q[0], q[1], q[2], q[3]));
    let (roll, pitch, _) = r.euler_angles();
    (roll.to_degrees(), pitch.to_degrees())
}

/// Rotate a ground vector by `angle` [rad].
pub fn rotate2(v: Vector2<f64>, angle: f64) -> Vector2<f64> {
    let (s, c) = angle.sin_cos();
    Vector2::new(c * v.x - s * v.y, s * v.x + c * v.y)
}

pub fn finite2(v: [f64; 2]) -> bool {
    v.iter().all(|c| c.is_finite())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn polar_matches_the_server_convention() {
        // atan2(y, x) azimuth (+ left), asin(z/d) elevation (+ up).
        let p = polar_to_point(&Polar {
            distance: 2.0,
            azimuth_deg: 90.0,
            elevation_deg: 0.0,
        })
        .unwrap();
        assert!((p - Point3::new(0.0, 2.0, 0.0)).norm() < 1e-12);
        let p = polar_to_point(&Polar {
            distance: 1.0,
            azimuth_deg: 0.0,
            elevation_deg: -30.0,
        })
        .unwrap();
        assert!((p.z + 0.5).abs() < 1e-12);
        assert!(polar_to_point(&Polar {
            distance: f64::NAN,
            azimuth_deg: 0.0,
            elevation_deg: 0.0
        })
        .is_none());
    }

    #[test]
    fn roll_and_pitch_of_a_torso_orientation_follow_the_estimates_convention() {
        let q = |axis: nalgebra::Unit<nalgebra::Vector3<f64>>, deg: f64| {
            let r = UnitQuaternion::from_axis_angle(&axis, deg.to_radians());
            [r.w, r.i, r.j, r.k]
        };
        // About the torso's y axis (left), +20 deg turns x (forward) down: nose down.
        let (roll, pitch) = roll_pitch_deg_of_quaternion(q(nalgebra::Vector3::y_axis(), 20.0));
        assert!(
            roll.abs() < 1e-9 && (pitch - 20.0).abs() < 1e-9,
            "{roll} {pitch}"
        );
        // About x (forward), +10 deg lifts the left side: leaning right.
        let (roll, pitch) = roll_pitch_deg_of_quaternion(q(nalgebra::Vector3::x_axis(), 10.0));
        assert!(
            (roll - 10.0).abs() < 1e-9 && pitch.abs() < 1e-9,
            "{roll} {pitch}"
        );
        // A heading changes neither.
        let (roll, pitch) = roll_pitch_deg_of_quaternion(q(nalgebra::Vector3::z_axis(), 70.0));
        assert!(roll.abs() < 1e-9 && pitch.abs() < 1e-9);
    }

    #[test]
    fn wrapping() {
        assert!((wrap_deg(190.0) + 170.0).abs() < 1e-9);
        assert!((wrap_deg(-180.0) - 180.0).abs() < 1e-9);
        assert!((wrap_deg(720.5) - 0.5).abs() < 1e-9);
        // Yaw −90° as in the spawn pose sample (0.707, 0, 0, −0.707).
        assert!((heading_deg_of_quaternion([0.707, 0.0, 0.0, -0.707]) + 90.0).abs() < 1e-6);
    }
}
