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
        }
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
