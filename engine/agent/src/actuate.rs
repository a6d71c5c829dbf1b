//! The last stage: joint targets and intent → one outgoing message.

use libero_model::{RobotModel, ServerKind};
use libero_protocol::{ActionWriter, MotorCommand};
use libero_skills::{Intent, JointTarget, JointTargets};
use libero_world::{Side, World};

/// Server cycle length [s]: SimSpark integrates a joint velocity over one such step.
const SIMSPARK_STEP_S: f64 = 0.02;

/// Targets stay this far inside a joint's range: commanding into a limit asks for a velocity
/// the server's limit check ignores (simspark.md §2.2).
const SIMSPARK_LIMIT_MARGIN_DEG: f64 = 0.5;

/// Position control on SimSpark's velocity motors (simspark.md §8.2): the reply to percept k
/// acts during the step after the one the previous reply still drives, so the angle it starts
/// from is predicted, θ̂ = θ_k + v_prev·h, and v = g·(θ* − θ̂)/h with g the joint's `kp`
/// (1: the error gone in one step; stable for 0 < g < 2). A plain v = g'·(θ* − θ_k) must keep
/// g'·h below 0.25 to avoid overshoot: a 100 ms lag that a 0.3 s step cannot walk on.
#[derive(Debug)]
pub struct VelocityServo {
    /// The velocity each joint was last sent [rad/s], one per model joint.
    sent_rad_s: Vec<f64>,
}

impl VelocityServo {
    /// For a robot of `joints` joints, nothing sent yet (sized once: the cycle allocates
    /// nothing).
    pub fn new(joints: usize) -> Self {
        Self {
            sent_rad_s: vec![0.0; joints],
        }
    }

    /// Forget what was sent: the server wipes motor state when anyone joins or leaves.
    pub fn reset(&mut self) {
        self.sent_rad_s.iter_mut().for_each(|v| *v = 0.0);
    }

    fn command(
        &mut self,
        index: usize,
        joint: &libero_model::Joint,
        target: &JointTarget,
        angle_deg: f64,
    ) -> f64 {
        let (lo, hi) = joint.limits_deg;
        let margin = SIMSPARK_LIMIT_MARGIN_DEG.min((hi - lo) / 4.0);
        let target_deg = target.q_deg.clamp(lo + margin, hi - margin);
        let predicted_rad = angle_deg.to_radians() + self.sent_rad_s[index] * SIMSPARK_STEP_S;
        let limit = joint.max_speed_deg.map_or(f64::INFINITY, f64::to_radians);
        let v = target.kp * (target_deg.to_radians() - predicted_rad) / SIMSPARK_STEP_S;
        let v = if v.is_finite() {
            v.clamp(-limit, limit)
        } else {
            0.0
        };
        self.sent_rad_s[index] = v;
        v
    }
}

/// Write every joint's command (the server wipes motor state whenever anyone joins or
/// leaves, so all joints go out every cycle), plus beam and say when asked.
pub fn write_actions(
    model: &RobotModel,
    world: &World,
    intent: &Intent,
    targets: &JointTargets,
    beam_now: bool,
    servo: &mut VelocityServo,
    writer: &mut ActionWriter,
) {
    match model.server {
        ServerKind::RcssMj => {
            for (joint, t) in model.joints.iter().zip(&targets.joints) {
                let cmd = MotorCommand {
                    q_deg: t.q_deg,
                    dq_deg: t.dq_deg,
                    kp: t.kp,
                    kd: t.kd,
                    tau: t.tau.clamp(-joint.max_torque, joint.max_torque),
                };
                writer.motor(joint, cmd);
            }
        }
        ServerKind::SimSpark => {
            for (index, ((joint, t), &angle)) in model
                .joints
                .iter()
                .zip(&targets.joints)
                .zip(&world.body.joint_angles)
                .enumerate()
            {
                writer.joint_velocity(joint, servo.command(index, joint, t, angle));
            }
        }
    }
    if let (true, Some(pose)) = (beam_now, intent.beam) {
        let [x, y, theta] = beam_on_wire(model.server, world.game.side, pose);
        if let Err(e) = writer.beam(x, y, theta) {
            log::warn!("beam not sent: {e}");
        }
    }
    if let Some(message) = &intent.say {
        if let Err(e) = writer.say(message) {
            log::warn!("say not sent: {e}");
        }
    }
    if model.server == ServerKind::SimSpark {
        writer.syn();
    }
}

/// Own-frame pose (own goal at −x) → what the server's `beam` expects.
///
/// rcssservermj takes global coordinates, forces the x sign by side and adds 180° for the right
/// team without mirroring y; SimSpark takes the team's own frame as it is.
pub fn beam_on_wire(server: ServerKind, side: Option<Side>, [x, y, theta]: [f64; 3]) -> [f64; 3] {
    match (server, side) {
        (ServerKind::RcssMj, Some(Side::Right)) => [x, -y, theta],
        _ => [x, y, theta],
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn nao_joint(name: &str) -> libero_model::Joint {
        let model = RobotModel::builtin("nao_type0").unwrap();
        model.joints[model.joint_id(name).unwrap()].clone()
    }

    fn target(q_deg: f64, kp: f64) -> JointTarget {
        JointTarget {
            q_deg,
            dq_deg: 0.0,
            kp,
            kd: 0.0,
            tau: 0.0,
        }
    }

    #[test]
    fn the_servo_closes_the_predicted_error_in_one_step_at_gain_one() {
        let knee = nao_joint("left_knee");
        let mut servo = VelocityServo::new(1);
        // 2° to go from rest: 2° in one 20 ms step.
        let v = servo.command(0, &knee, &target(-22.0, 1.0), -20.0);
        assert!((v - (-2f64).to_radians() / 0.02).abs() < 1e-9, "{v}");
        // The next percept still shows the old angle (the command acts a step later): the
        // predicted angle is already the target, so nothing more is asked.
        let v = servo.command(0, &knee, &target(-22.0, 1.0), -20.0);
        assert!(v.abs() < 1e-9, "{v}");
        // Half the gain, half the correction.
        servo.reset();
        let v = servo.command(0, &knee, &target(-22.0, 0.5), -20.0);
        assert!((v - (-1f64).to_radians() / 0.02).abs() < 1e-9, "{v}");
    }

    #[test]
    fn the_servo_stays_inside_the_range_and_the_speed_limit() {
        let knee = nao_joint("left_knee");
        let (lo, _) = knee.limits_deg;
        let mut servo = VelocityServo::new(1);
        // A target beyond the limit is held half a degree inside it.
        let v = servo.command(0, &knee, &target(lo - 20.0, 1.0), lo + 0.2);
        assert!(v > 0.0, "pushed into the limit: {v}");
        // A far target asks for no more than the joint's top speed.
        servo.reset();
        let v = servo.command(0, &knee, &target(-120.0, 1.0), 0.0);
        let top = knee.max_speed_deg.unwrap().to_radians();
        assert!((v + top).abs() < 1e-9, "{v} vs {top}");
        // A bad angle asks for nothing rather than sending a non-number.
        assert_eq!(servo.command(0, &knee, &target(-30.0, 1.0), f64::NAN), 0.0);
    }

    #[test]
    fn right_team_beam_mirrors_y_only_on_rcssservermj() {
        assert_eq!(
            beam_on_wire(ServerKind::RcssMj, Some(Side::Right), [-3.0, 2.0, 10.0]),
            [-3.0, -2.0, 10.0]
        );
        assert_eq!(
            beam_on_wire(ServerKind::RcssMj, Some(Side::Left), [-3.0, 2.0, 10.0]),
            [-3.0, 2.0, 10.0]
        );
        assert_eq!(
            beam_on_wire(ServerKind::SimSpark, Some(Side::Right), [-3.0, 2.0, 10.0]),
            [-3.0, 2.0, 10.0]
        );
    }
}
