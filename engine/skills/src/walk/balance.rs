//! What the IMU says about the torso, and the corrections the balance loop derives from it.

use super::params::BalanceParams;
use libero_world::BodyState;

/// Torso attitude from the low-passed accelerometer [deg]: pitch > 0 leans forward (nose
/// down), roll > 0 leans to the right (left side up).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Attitude {
    pub pitch_deg: f64,
    pub roll_deg: f64,
    /// Angular rates about the torso's x (roll) and y (pitch) axes [deg/s].
    pub roll_rate_deg_s: f64,
    pub pitch_rate_deg_s: f64,
}

impl Attitude {
    /// Roll and pitch from the world model's filtered estimate (gyro-carried, slowly corrected
    /// by the accelerometer, so steps' accelerations do not fool it), rates from the gyro.
    pub fn from_world(world: &libero_world::World) -> Self {
        Self {
            pitch_deg: world.me.pitch_deg,
            roll_deg: world.me.roll_deg,
            roll_rate_deg_s: world.body.gyro[0],
            pitch_rate_deg_s: world.body.gyro[1],
        }
    }

    pub fn from_body(body: &BodyState) -> Self {
        let [gx, gy, gz] = body.gravity;
        Self {
            // The specific force points up; tilting the nose down turns it towards −x.
            pitch_deg: (-gx).atan2(gz).to_degrees(),
            roll_deg: gy.atan2(gz).to_degrees(),
            roll_rate_deg_s: body.gyro[0],
            pitch_rate_deg_s: body.gyro[1],
        }
    }
}

/// Joint offsets [deg] added on top of the leg IK solution.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Corrections {
    pub ankle_pitch: f64,
    pub hip_pitch: f64,
    pub ankle_roll: f64,
    pub hip_roll: f64,
}

impl Corrections {
    /// Every offset times `k`.
    pub fn scaled(self, k: f64) -> Self {
        Self {
            ankle_pitch: self.ankle_pitch * k,
            hip_pitch: self.hip_pitch * k,
            ankle_roll: self.ankle_roll * k,
            hip_roll: self.hip_roll * k,
        }
    }
}

/// The ankle and hip strategies: push against the measured tilt and its rate.
pub fn corrections(p: &BalanceParams, attitude: &Attitude, lean_deg: f64) -> Corrections {
    let limit = |v: f64| v.clamp(-p.max_correction_deg, p.max_correction_deg);
    let pitch_error = attitude.pitch_deg - lean_deg;
    Corrections {
        ankle_pitch: limit(
            p.ankle_pitch_per_gyro * attitude.pitch_rate_deg_s
                + p.ankle_pitch_per_tilt * pitch_error,
        ),
        hip_pitch: limit(p.hip_pitch_per_gyro * attitude.pitch_rate_deg_s),
        ankle_roll: limit(p.ankle_roll_per_gyro * attitude.roll_rate_deg_s),
        hip_roll: limit(p.hip_roll_per_gyro * attitude.roll_rate_deg_s),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn attitude_signs_follow_the_documented_accelerometer() {
        let mut body = BodyState::new(&libero_model::RobotModel::builtin("T1").unwrap());
        // Face down: specific force (−9.8, 0, 0) = pitched forward by 90°.
        body.gravity = [-9.8, 0.0, 0.0];
        assert!((Attitude::from_body(&body).pitch_deg - 90.0).abs() < 1e-9);
        body.gravity = [0.0, 9.81 * 0.1f64.sin(), 9.81 * 0.1f64.cos()];
        assert!((Attitude::from_body(&body).roll_deg - 0.1f64.to_degrees()).abs() < 1e-9);
    }
}
