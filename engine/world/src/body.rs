//! The agent's own body: joint angles, inertial sensors and posture.

use libero_model::RobotModel;
use libero_protocol::Percept;

/// Upright or lying, from the direction of gravity in the torso frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub enum Posture {
    Upright,
    /// Lying face down.
    FallenFront,
    /// Lying on the back.
    FallenBack,
    FallenSide,
}

/// Joint and inertial state, indexed like the robot model's joints.
#[derive(Debug, Clone)]
pub struct BodyState {
    /// [deg]
    pub joint_angles: Vec<f64>,
    /// [deg/s]; estimated from successive angles where the server does not send it.
    pub joint_velocities: Vec<f64>,
    /// [deg/s], robot frame
    pub gyro: [f64; 3],
    /// [m/s²], robot frame
    pub accel: [f64; 3],
    /// Low-passed accelerometer: the direction of gravity without step impacts.
    pub gravity: [f64; 3],
    pub posture: Posture,
    /// Percepts that named a joint the model does not have (a wrong robot model, or a new
    /// server): counted so it shows in logs rather than silently ignored.
    pub unknown_joints: u64,
    last_time: Option<f64>,
}

impl BodyState {
    pub fn new(model: &RobotModel) -> Self {
        let n = model.joints.len();
        Self {
            joint_angles: vec![0.0; n],
            joint_velocities: vec![0.0; n],
            gyro: [0.0; 3],
            accel: [0.0, 0.0, 9.81],
            gravity: [0.0, 0.0, 9.81],
            posture: Posture::Upright,
            unknown_joints: 0,
            last_time: None,
        }
    }

    pub fn update(&mut self, model: &RobotModel, percept: &Percept<'_>) {
        let dt = match (percept.time, self.last_time) {
            (Some(now), Some(before)) if now > before => Some(now - before),
            _ => None,
        };
        self.last_time = percept.time.or(self.last_time);
        for reading in &percept.joints {
            let Some(id) = model.joint_by_perceptor(reading.perceptor) else {
                self.unknown_joints += 1;
                continue;
            };
            let velocity = reading
                .velocity_deg
                .or_else(|| dt.map(|dt| (reading.angle_deg - self.joint_angles[id]) / dt));
            self.joint_angles[id] = reading.angle_deg;
            if let Some(v) = velocity {
                self.joint_velocities[id] = v;
            }
        }
        if let Some(g) = percept.gyro {
            self.gyro = g;
        }
        if let Some(a) = percept.accel {
            self.accel = a;
            const SMOOTHING: f64 = 0.2;
            for (g, a) in self.gravity.iter_mut().zip(a) {
                *g += SMOOTHING * (a - *g);
            }
        }
        self.posture = posture_from_gravity(self.gravity);
    }
}

/// Lying when gravity is closer to the torso's horizontal plane than to its z axis.
pub fn posture_from_gravity(g: [f64; 3]) -> Posture {
    let [x, y, z] = g;
    let horizontal = (x * x + y * y).sqrt();
    if z > horizontal {
        Posture::Upright
    } else if x.abs() >= y.abs() {
        // Face down, the specific force points backwards along the torso (−x).
        if x < 0.0 {
            Posture::FallenFront
        } else {
            Posture::FallenBack
        }
    } else {
        Posture::FallenSide
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn posture_from_documented_accelerometer_readings() {
        assert_eq!(posture_from_gravity([0.0, 0.0, 9.81]), Posture::Upright);
        assert_eq!(posture_from_gravity([-9.8, 0.0, 0.0]), Posture::FallenFront);
        assert_eq!(posture_from_gravity([9.8, 0.3, 0.5]), Posture::FallenBack);
        assert_eq!(posture_from_gravity([0.5, 9.7, 1.0]), Posture::FallenSide);
    }
}
