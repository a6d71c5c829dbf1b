//! Writing actions. Joint names come only from a [`RobotModel`]'s joints and every number is
//! checked to be finite, so nothing written here can crash a server (rcssservermj dies on an
//! unknown 6-element actuator command; NaN zeroes all its motors).

use base64::Engine as _;
use libero_model::{Joint, RobotModel, ServerKind};
use std::fmt::Write as _;

/// A motor target for rcssservermj: `torque = kp·(q − q_meas) + kd·(dq − dq_meas) + tau`.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct MotorCommand {
    /// Target angle [deg].
    pub q_deg: f64,
    /// Target velocity [deg/s].
    pub dq_deg: f64,
    /// N·m/rad
    pub kp: f64,
    /// N·m·s/rad
    pub kd: f64,
    /// Feed-forward torque [N·m].
    pub tau: f64,
}

/// Something the caller asked for that cannot be put on the wire.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ActionError {
    #[error("`{0}` cannot be sent as a name: use 1–32 letters, digits, `_` or `-`")]
    BadName(String),
    #[error("message of {0} bytes is too long: {1} at most on this server")]
    MessageTooLong(usize, usize),
    #[error("message contains a character this server does not carry (printable ASCII except space and parentheses)")]
    MessageCharacter,
    #[error("{0} is for the other server")]
    WrongServer(&'static str),
    #[error("non-finite number in `{0}`: not sent")]
    NotFinite(&'static str),
}

/// Builds one outgoing message. Reuse it between cycles: clearing keeps its buffer.
#[derive(Debug, Clone)]
pub struct ActionWriter {
    server: ServerKind,
    text: String,
    /// Joint commands dropped because a number was not finite (counted, never sent).
    dropped: usize,
}

impl ActionWriter {
    pub fn new(server: ServerKind) -> Self {
        Self {
            server,
            text: String::with_capacity(2048),
            dropped: 0,
        }
    }

    pub fn server(&self) -> ServerKind {
        self.server
    }

    pub fn clear(&mut self) {
        self.text.clear();
        self.dropped = 0;
    }

    /// Commands dropped since the last clear because a number was not finite.
    pub fn dropped(&self) -> usize {
        self.dropped
    }

    /// rcssservermj: `(init <model> <team> <unum>)`; SimSpark: `(init (unum N)(teamname T))`.
    pub fn init(&mut self, model: &RobotModel, team: &str, unum: u32) -> Result<(), ActionError> {
        check_name(team)?;
        match self.server {
            ServerKind::RcssMj => {
                check_name(&model.name)?;
                write!(self.text, "(init {} {team} {unum})", model.name).ok();
            }
            ServerKind::SimSpark => {
                write!(self.text, "(init (unum {unum})(teamname {team}))").ok();
            }
        }
        Ok(())
    }

    /// SimSpark: `(scene <path> [type])`, the first message of a connection.
    pub fn scene(&mut self, model: &RobotModel) -> Result<(), ActionError> {
        let scene = model
            .scene
            .as_deref()
            .ok_or(ActionError::WrongServer("scene"))?;
        if !scene
            .bytes()
            .all(|b| b.is_ascii_graphic() && b != b'(' && b != b')')
        {
            return Err(ActionError::BadName(scene.to_string()));
        }
        self.text.push_str("(scene ");
        self.text.push_str(scene);
        if let Some(t) = model.hetero_type {
            write!(self.text, " {t}").ok();
        }
        self.text.push(')');
        Ok(())
    }

    /// rcssservermj motor command for `joint` (angles in degrees, as the server expects).
    pub fn motor(&mut self, joint: &Joint, cmd: MotorCommand) {
        let values = [cmd.q_deg, cmd.dq_deg, cmd.kp, cmd.kd, cmd.tau];
        if self.server != ServerKind::RcssMj || values.iter().any(|v| !v.is_finite()) {
            self.dropped += 1;
            return;
        }
        self.text.push('(');
        self.text.push_str(&joint.effector);
        for (v, decimals) in values.into_iter().zip([3, 3, 2, 3, 3]) {
            self.text.push(' ');
            write_fixed(&mut self.text, v, decimals);
        }
        self.text.push(')');
    }

    /// SimSpark joint velocity [rad/s], clamped to the joint's speed limit.
    pub fn joint_velocity(&mut self, joint: &Joint, rad_per_s: f64) {
        if self.server != ServerKind::SimSpark || !rad_per_s.is_finite() {
            self.dropped += 1;
            return;
        }
        let limit = joint.max_speed_deg.map_or(f64::INFINITY, f64::to_radians);
        self.text.push('(');
        self.text.push_str(&joint.effector);
        self.text.push(' ');
        write_fixed(&mut self.text, rad_per_s.clamp(-limit, limit), 4);
        self.text.push(')');
    }

    /// `(beam x y θ)` in the server's own convention (rcssservermj: global x sign forced per
    /// side, y global; SimSpark: own team frame).
    pub fn beam(&mut self, x: f64, y: f64, theta_deg: f64) -> Result<(), ActionError> {
        if ![x, y, theta_deg].iter().all(|v| v.is_finite()) {
            return Err(ActionError::NotFinite("beam"));
        }
        self.text.push_str("(beam ");
        write_fixed(&mut self.text, x, 3);
        self.text.push(' ');
        write_fixed(&mut self.text, y, 3);
        self.text.push(' ');
        write_fixed(&mut self.text, theta_deg, 2);
        self.text.push(')');
        Ok(())
    }

    /// Broadcast a message: rcssservermj ≤ 10 bytes (sent base64), SimSpark ≤ 20 characters of
    /// printable ASCII without space or parentheses.
    pub fn say(&mut self, message: &[u8]) -> Result<(), ActionError> {
        match self.server {
            ServerKind::RcssMj => {
                if message.is_empty() || message.len() > 10 {
                    return Err(ActionError::MessageTooLong(message.len(), 10));
                }
                self.text.push_str("(SPK say 100 ");
                base64::engine::general_purpose::STANDARD.encode_string(message, &mut self.text);
                self.text.push(')');
            }
            ServerKind::SimSpark => {
                if message.is_empty() || message.len() > 20 {
                    return Err(ActionError::MessageTooLong(message.len(), 20));
                }
                if !message
                    .iter()
                    .all(|&b| b.is_ascii_graphic() && b != b'(' && b != b')')
                {
                    return Err(ActionError::MessageCharacter);
                }
                self.text.push_str("(say ");
                // Checked above to be ASCII.
                self.text
                    .push_str(std::str::from_utf8(message).unwrap_or_default());
                self.text.push(')');
            }
        }
        Ok(())
    }

    /// `(syn)`: answers a cycle in sync mode.
    pub fn syn(&mut self) {
        self.text.push_str("(syn)");
    }

    /// The message so far.
    pub fn as_str(&self) -> &str {
        &self.text
    }

    /// Append the message as a frame to `out`. An empty message becomes `(syn)`, because an
    /// empty frame makes rcssservermj drop the agent.
    pub fn frame_into(&mut self, out: &mut Vec<u8>) {
        if self.text.is_empty() {
            self.syn();
        }
        crate::frame::encode_frame(self.text.as_bytes(), out);
    }
}

fn check_name(name: &str) -> Result<(), ActionError> {
    let ok = (1..=32).contains(&name.len())
        && name
            .bytes()
            .all(|b| b.is_ascii_alphanumeric() || b == b'_' || b == b'-');
    if ok {
        Ok(())
    } else {
        Err(ActionError::BadName(name.to_string()))
    }
}

/// Write a finite `v` with a fixed number of decimals, without going through `fmt` floats
/// (they dominate the encode cost otherwise). Values beyond ±1e9 are clamped: no joint,
/// gain or coordinate is that large, and this keeps the integer arithmetic exact.
fn write_fixed(out: &mut String, v: f64, decimals: u32) {
    let scale = 10u64.pow(decimals);
    let v = v.clamp(-1e9, 1e9);
    let scaled = (v.abs() * scale as f64).round() as u64;
    if v < 0.0 && scaled != 0 {
        out.push('-');
    }
    let mut ints = itoa::Buffer::new();
    out.push_str(ints.format(scaled / scale));
    let frac = scaled % scale;
    if frac != 0 {
        out.push('.');
        let digits = ints.format(frac);
        for _ in digits.len()..decimals as usize {
            out.push('0');
        }
        out.push_str(digits.trim_end_matches('0'));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn fixed(v: f64, d: u32) -> String {
        let mut s = String::new();
        write_fixed(&mut s, v, d);
        s
    }

    #[test]
    fn fixed_point_numbers() {
        assert_eq!(fixed(0.0, 3), "0");
        assert_eq!(fixed(-0.0001, 3), "0");
        assert_eq!(fixed(12.5, 3), "12.5");
        assert_eq!(fixed(-3.0405, 3), "-3.041");
        assert_eq!(fixed(0.05, 3), "0.05");
        assert_eq!(fixed(1e300, 2), "1000000000");
        for v in [-123.456, 0.001, 7.0, -0.5] {
            assert!((fixed(v, 3).parse::<f64>().unwrap() - v).abs() < 1e-9);
        }
    }

    #[test]
    fn motor_commands_use_model_names_and_drop_non_finite_values() {
        let t1 = RobotModel::builtin("T1").unwrap();
        let mut w = ActionWriter::new(ServerKind::RcssMj);
        let cmd = MotorCommand {
            q_deg: -12.0,
            dq_deg: 0.0,
            kp: 200.0,
            kd: 5.0,
            tau: 0.0,
        };
        w.motor(&t1.joints[11], cmd);
        w.motor(
            &t1.joints[12],
            MotorCommand {
                q_deg: f64::NAN,
                ..cmd
            },
        );
        assert_eq!(w.as_str(), "(lle1 -12 0 200 5 0)");
        assert_eq!(w.dropped(), 1);
    }

    #[test]
    fn init_beam_say_and_empty_messages() {
        let t1 = RobotModel::builtin("T1").unwrap();
        let mut w = ActionWriter::new(ServerKind::RcssMj);
        w.init(&t1, "Libero", 3).unwrap();
        assert_eq!(w.as_str(), "(init T1 Libero 3)");
        assert!(w.init(&t1, "bad name", 3).is_err());
        assert!(w.init(&t1, "x)(foo 0 0 1 1 0", 3).is_err());
        w.clear();
        assert!(w.beam(f64::INFINITY, 0.0, 0.0).is_err());
        w.say(b"hello10").unwrap();
        assert_eq!(w.as_str(), "(SPK say 100 aGVsbG8xMA==)");
        assert!(w.say(b"12345678901").is_err());
        w.clear();
        let mut out = Vec::new();
        w.frame_into(&mut out);
        assert_eq!(&out[4..], b"(syn)");
        assert_eq!(&out[..4], &[0, 0, 0, 5]);
    }

    #[test]
    fn simspark_say_rules() {
        let mut w = ActionWriter::new(ServerKind::SimSpark);
        assert!(w.say(b"has space").is_err());
        assert!(w.say(b"(x)").is_err());
        assert!(w.say(b"abcdefghijklmnopqrstu").is_err());
        w.say(b"ball:1.2,3").unwrap();
        assert_eq!(w.as_str(), "(say ball:1.2,3)");
    }
}
