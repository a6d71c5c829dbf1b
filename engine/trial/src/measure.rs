//! Locomotion figures from a ground-truth recording.

use crate::episode::{Recording, Sample};

/// Mean velocity over the samples with `t` in `[from_s, to_s]`, in the robot's starting frame:
/// (forward m/s, left m/s, turn deg/s). `None` with fewer than two samples in the window.
pub fn mean_velocity(rec: &Recording, from_s: f64, to_s: f64) -> Option<[f64; 3]> {
    let window: Vec<&Sample> = rec
        .samples
        .iter()
        .filter(|s| s.t >= from_s && s.t <= to_s)
        .collect();
    let (first, last) = (window.first()?, window.last()?);
    let dt = last.t - first.t;
    if dt <= 0.0 {
        return None;
    }
    let heading = rec.samples.first()?.yaw_deg.to_radians();
    let dx = last.position[0] - first.position[0];
    let dy = last.position[1] - first.position[1];
    let forward = dx * heading.cos() + dy * heading.sin();
    let left = -dx * heading.sin() + dy * heading.cos();
    let turned = unwrapped_yaw_change(&window);
    Some([forward / dt, left / dt, turned / dt])
}

/// Total heading change along the samples [deg], counting whole turns.
pub fn unwrapped_yaw_change(samples: &[&Sample]) -> f64 {
    samples
        .windows(2)
        .map(|w| {
            let mut d = w[1].yaw_deg - w[0].yaw_deg;
            while d > 180.0 {
                d -= 360.0;
            }
            while d < -180.0 {
                d += 360.0;
            }
            d
        })
        .sum()
}

/// Distance along the starting heading covered by the whole recording [m].
pub fn forward_distance(rec: &Recording) -> f64 {
    let (Some(first), Some(last)) = (rec.samples.first(), rec.samples.last()) else {
        return 0.0;
    };
    let h = first.yaw_deg.to_radians();
    (last.position[0] - first.position[0]) * h.cos()
        + (last.position[1] - first.position[1]) * h.sin()
}

/// The agent's self-localization against the ground truth over a recording: the distance on
/// the ground between its estimate and its torso in every sample where it had one.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LocalizationError {
    pub median_m: f64,
    pub p90_m: f64,
    pub max_m: f64,
    /// Samples compared (those with an estimate and a true position).
    pub samples: usize,
    /// Share of the samples with no estimate (not yet localized, or lost).
    pub unlocalized_share: f64,
}

/// `None` when no sample has both an estimate and a true position.
pub fn localization_error(rec: &Recording) -> Option<LocalizationError> {
    let mut errors: Vec<f64> = rec
        .samples
        .iter()
        .filter_map(|s| {
            let e = s.estimate?;
            let d = (e[0] - s.position[0]).hypot(e[1] - s.position[1]);
            d.is_finite().then_some(d)
        })
        .collect();
    if errors.is_empty() {
        return None;
    }
    errors.sort_by(f64::total_cmp);
    let at = |q: f64| errors[((errors.len() - 1) as f64 * q).round() as usize];
    Some(LocalizationError {
        median_m: at(0.5),
        p90_m: at(0.9),
        max_m: at(1.0),
        samples: errors.len(),
        unlocalized_share: rec.samples.iter().filter(|s| s.estimate.is_none()).count() as f64
            / rec.samples.len() as f64,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use libero_world::Posture;

    fn s(t: f64, x: f64, y: f64, yaw: f64) -> Sample {
        Sample {
            t,
            position: [x, y, 0.6],
            yaw_deg: yaw,
            pitch_deg: 0.0,
            roll_deg: 0.0,
            tilt_deg: 0.0,
            posture: Posture::Upright,
            low: false,
            tall: true,
            estimate: None,
        }
    }

    #[test]
    fn localization_error_is_the_ground_distance_to_the_estimate() {
        let mut samples: Vec<Sample> = (0..5).map(|i| s(f64::from(i), 1.0, 2.0, 0.0)).collect();
        for (i, sample) in samples.iter_mut().enumerate().skip(1) {
            // Errors 0.1, 0.2, 0.3, 0.4 m (3-4-5 triangles), the first sample unlocalized.
            let d = 0.1 * i as f64;
            sample.estimate = Some([1.0 + 0.6 * d, 2.0 - 0.8 * d]);
        }
        let e = localization_error(&Recording {
            samples,
            intents: Vec::new(),
        })
        .unwrap();
        assert_eq!(e.samples, 4);
        assert!((e.median_m - 0.3).abs() < 1e-9, "{e:?}");
        assert!((e.max_m - 0.4).abs() < 1e-9, "{e:?}");
        assert!((e.unlocalized_share - 0.2).abs() < 1e-9, "{e:?}");
    }

    #[test]
    fn velocities_are_taken_in_the_starting_frame_and_turns_unwrap() {
        let rec = Recording {
            samples: vec![
                s(0.0, 0.0, 0.0, 90.0),
                s(1.0, 0.0, 0.5, 170.0),
                s(2.0, -0.2, 1.0, -110.0),
            ],
            intents: vec![],
        };
        let [f, l, w] = mean_velocity(&rec, 0.0, 2.0).unwrap();
        assert!((f - 0.5).abs() < 1e-9 && (l - 0.1).abs() < 1e-9, "{f} {l}");
        assert!((w - 80.0).abs() < 1e-9, "{w}");
    }
}
