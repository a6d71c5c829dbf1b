//! The last stage: joint targets and intent → one outgoing message.

use libero_model::{RobotModel, ServerKind};
use libero_protocol::{ActionWriter, MotorCommand};
use libero_skills::{Intent, JointTargets};
use libero_world::{Side, World};

/// SimSpark joints are driven by velocity: v = gain · (target − angle) [1/s]. With a reply
/// acting two cycles later, 10/s closes a fifth of the error per 20 ms cycle without overshoot.
const SIMSPARK_POSITION_GAIN: f64 = 10.0;

/// Write every joint's command (the server wipes motor state whenever anyone joins or
/// leaves, so all joints go out every cycle), plus beam and say when asked.
pub fn write_actions(
    model: &RobotModel,
    world: &World,
    intent: &Intent,
    targets: &JointTargets,
    beam_now: bool,
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
            for ((joint, t), angle) in model
                .joints
                .iter()
                .zip(&targets.joints)
                .zip(&world.body.joint_angles)
            {
                let error_rad = (t.q_deg - angle).to_radians();
                writer.joint_velocity(joint, SIMSPARK_POSITION_GAIN * error_rad);
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
