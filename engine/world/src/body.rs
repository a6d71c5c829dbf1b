//! The agent's own body: joint angles, inertial sensors and posture.

use crate::params::BodyParams;
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
    /// Lying only once `gravity` has said so for `BodyParams::lying_confirm_s`: a step's or a
    /// kick's jolt tips the low-passed reading past 45° for a cycle or two, and every such
    /// blip read as a fall interrupts what the robot was doing.
    pub posture: Posture,
    /// What `gravity` says this cycle, and since when it has said lying.
    pub posture_reading: Posture,
    lying_read_since: Option<f64>,
    /// Percepts that named a joint the model does not have (a wrong robot model, or a new
    /// server): counted so it shows in logs rather than silently ignored.
    pub unknown_joints: u64,
    last_time: Option<f64>,
    /// The joint the k-th reading named last cycle: a server lists its joints in the same
    /// order every cycle, so one name comparison finds each.
    joint_of_reading: [Option<usize>; libero_protocol::percept::MAX_JOINTS],
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
            posture_reading: Posture::Upright,
            lying_read_since: None,
            unknown_joints: 0,
            joint_of_reading: [None; libero_protocol::percept::MAX_JOINTS],
            last_time: None,
        }
    }

    pub fn update(&mut self, model: &RobotModel, percept: &Percept<'_>, params: &BodyParams) {
        let dt = match (percept.time, self.last_time) {
            (Some(now), Some(before)) if now > before => Some(now - before),
            _ => None,
        };
        self.last_time = percept.time.or(self.last_time);
        for (k, reading) in percept.joints.iter().enumerate() {
            let as_before = self.joint_of_reading[k]
                .filter(|&id| model.joints[id].perceptor == reading.perceptor);
            let found = as_before.or_else(|| model.joint_by_perceptor(reading.perceptor));
            self.joint_of_reading[k] = found;
            let Some(id) = found else {
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
        let reading = posture_from_gravity(self.gravity);
        if reading != self.posture_reading {
            log::debug!(
                "posture reading {:?} -> {:?}, gravity {:.2?}",
                self.posture_reading,
                reading,
                self.gravity
            );
        }
        self.posture_reading = reading;
        let now = self.last_time.unwrap_or(0.0);
        self.lying_read_since = match self.posture_reading {
            Posture::Upright => None,
            _ => self.lying_read_since.or(Some(now)),
        };
        self.posture = match self.lying_read_since {
            Some(since) if now - since >= params.lying_confirm_s => self.posture_reading,
            _ => Posture::Upright,
        };
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

#[cfg(test)]
mod lying_confirmation {
    use super::*;

    fn feed(body: &mut BodyState, model: &RobotModel, time: f64, accel: [f64; 3]) -> Posture {
        let percept = Percept {
            time: Some(time),
            accel: Some(accel),
            ..Percept::default()
        };
        body.update(
            model,
            &percept,
            &BodyParams {
                lying_confirm_s: 0.2,
            },
        );
        body.posture
    }

    #[test]
    fn a_jolt_of_a_few_cycles_is_not_a_fall_but_lying_on_is() {
        let model = RobotModel::builtin("T1").unwrap();
        let mut body = BodyState::new(&model);
        let mut t = 0.0;
        for _ in 0..50 {
            t += 0.02;
            assert_eq!(
                feed(&mut body, &model, t, [0.0, 0.0, 9.81]),
                Posture::Upright
            );
        }
        // A kick's jolt: the low-passed reading tips past 45° for about 0.1 s.
        for _ in 0..8 {
            t += 0.02;
            feed(&mut body, &model, t, [40.0, 0.0, -5.0]);
            assert_eq!(body.posture, Posture::Upright);
        }
        assert_eq!(body.posture_reading, Posture::FallenBack);
        for _ in 0..10 {
            t += 0.02;
            feed(&mut body, &model, t, [0.0, 0.0, 9.81]);
        }
        assert_eq!(body.posture_reading, Posture::Upright);
        // Lying on the back for good: confirmed 0.2 s after the reading first says so.
        let mut confirmed_after = None;
        let start = t;
        let mut read_from = None;
        for _ in 0..50 {
            t += 0.02;
            feed(&mut body, &model, t, [9.81, 0.0, 0.3]);
            if body.posture_reading != Posture::Upright {
                read_from.get_or_insert(t);
            }
            if body.posture == Posture::FallenBack && confirmed_after.is_none() {
                confirmed_after = Some(t - read_from.unwrap());
            }
        }
        let confirmed_after = confirmed_after.expect("lying on is a fall");
        assert!(
            (0.19..0.23).contains(&confirmed_after),
            "{confirmed_after} s after {start}"
        );
    }
}
