//! A pose from landmarks alone: the closed-form least-squares fit that starts the localizer's
//! filter and restarts it when the robot was moved.

use super::LevelledLandmark;
use crate::geometry::rotate2;
use nalgebra::Vector2;

/// A pose from landmarks alone.
#[derive(Debug, Clone, Copy)]
pub(super) struct PoseFit {
    pub(super) position: Vector2<f64>,
    pub(super) yaw: f64,
    /// Weighted RMS distance between the landmarks and where the fit puts them [m].
    pub(super) rms: f64,
    /// RMS distance of the observed landmarks from their centroid [m]: how well yaw is fixed.
    pub(super) spread: f64,
}

/// Weighted least squares over all landmarks of `field ≈ p + R(yaw)·offset` (on the ground
/// plane): the closed-form 2-D Procrustes solution. Needs two landmarks that are apart.
pub(super) fn closed_form_fit(landmarks: &[LevelledLandmark]) -> Option<PoseFit> {
    if landmarks.len() < 2 {
        return None;
    }
    let weight = |l: &LevelledLandmark| 1.0 / (l.sigma * l.sigma);
    let total: f64 = landmarks.iter().map(weight).sum();
    let mean = |f: &dyn Fn(&LevelledLandmark) -> Vector2<f64>| {
        landmarks
            .iter()
            .fold(Vector2::zeros(), |acc, l| acc + f(l) * weight(l))
            / total
    };
    let field_mean = mean(&|l| l.field.xy());
    let seen_mean = mean(&|l| l.offset.xy());
    let (mut cos_sum, mut sin_sum, mut spread) = (0.0, 0.0, 0.0);
    for l in landmarks {
        let (q, h) = (l.field.xy() - field_mean, l.offset.xy() - seen_mean);
        let w = weight(l);
        cos_sum += w * (h.x * q.x + h.y * q.y);
        sin_sum += w * (h.x * q.y - h.y * q.x);
        spread += w * h.norm_squared();
    }
    let spread = (spread / total).sqrt();
    if spread < 0.5 {
        return None;
    }
    let yaw = sin_sum.atan2(cos_sum);
    let position = field_mean - rotate2(seen_mean, yaw);
    let rms = (landmarks
        .iter()
        .map(|l| weight(l) * (position + rotate2(l.offset.xy(), yaw) - l.field.xy()).norm_squared())
        .sum::<f64>()
        / total)
        .sqrt();
    let fit = PoseFit {
        position,
        yaw,
        rms,
        spread,
    };
    (position.iter().all(|c| c.is_finite()) && yaw.is_finite() && rms.is_finite()).then_some(fit)
}
