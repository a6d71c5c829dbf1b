//! Joint targets: what the skills hand to the actuation stage.

use libero_model::RobotModel;

/// One joint's motor target.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct JointTarget {
    /// [deg]
    pub q_deg: f64,
    /// [deg/s]
    pub dq_deg: f64,
    pub kp: f64,
    pub kd: f64,
    /// [N·m]
    pub tau: f64,
}

/// A target for every joint of the model, in model order.
#[derive(Debug, Clone, Default)]
pub struct JointTargets {
    pub joints: Vec<JointTarget>,
}

impl JointTargets {
    /// Hold `pose` [deg per joint] with each joint's default gains.
    pub fn hold_pose(&mut self, model: &RobotModel, pose: &[f64]) {
        self.joints.clear();
        self.joints
            .extend(model.joints.iter().zip(pose).map(|(j, &q)| JointTarget {
                q_deg: q,
                dq_deg: 0.0,
                kp: j.gains.kp,
                kd: j.gains.kd,
                tau: 0.0,
            }));
    }

    /// Set the gains of joints given by index (resolved from names when parameters load).
    pub fn set_gains_of(&mut self, gains: &[(usize, libero_model::Gains)]) {
        for &(id, g) in gains {
            if let Some(t) = self.joints.get_mut(id) {
                t.kp = g.kp;
                t.kd = g.kd;
            }
        }
    }

    /// Set one joint's target angle by name, clamped to its limits. Unknown names are ignored
    /// (skill parameter files are validated against the model when loaded).
    pub fn set_angle(&mut self, model: &RobotModel, joint: &str, q_deg: f64) {
        if let Some(id) = model.joint_id(joint) {
            if let Some(t) = self.joints.get_mut(id) {
                t.q_deg = model.clamp_deg(id, q_deg);
            }
        }
    }
}
