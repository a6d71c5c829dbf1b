//! What teammates tell each other (thesis 6.4): the speaker's position and whether it is down,
//! where it saw the ball and how long ago, how soon it can reach the ball (its claim to be the
//! ball winner) and whether it is going for it. One format for both servers: 9 bytes, sent as they are on rcssservermj
//! (≤ 10 bytes, base64 on the wire) and as 12 base64 characters on SimSpark (≤ 20 characters
//! of its safe alphabet). A CRC-16 seeded with the team name rejects garbage and the other
//! team's messages; nothing heard is trusted without it.

use base64::Engine;
use libero_model::{FieldGeometry, ServerKind};

const PAYLOAD_BYTES: usize = 7;
const MESSAGE_BYTES: usize = PAYLOAD_BYTES + 2;
/// Base64 of a message (SimSpark's `say` takes text).
const TEXT_BYTES: usize = 4 * MESSAGE_BYTES.div_ceil(3);

/// The most bytes a player says in one cycle (what either server accepts fits).
pub const SAID_MAX: usize = 32;

/// What a player says, on the stack.
pub type Said = arrayvec::ArrayVec<u8, SAID_MAX>;
const POSITION_X_BITS: u32 = 10;
const POSITION_Y_BITS: u32 = 9;
/// How far beyond the lines positions are representable [m].
const MARGIN_M: f64 = 2.0;
const AGE_STEP_S: f64 = 0.1;
const AGE_BITS: u32 = 5;
/// Times to the ball are told in 0.2 s steps up to 8 s, where who is first is close and
/// matters, and in 0.5 s steps beyond: six bits, leaving one for `going_for_ball`.
const TIME_STEP_S: f64 = 0.2;
const FINE_TIME_S: f64 = 8.0;
const COARSE_TIME_STEP_S: f64 = 0.5;
const TIME_BITS: u32 = 6;
/// The code that says "not claiming".
const NO_TIME: u64 = (1 << TIME_BITS) - 1;
const FINE_CODES: u64 = 40;
/// The longest time-to-ball a message can tell [s]; a claim of this much means "this or more".
pub const TIME_TO_BALL_MAX_S: f64 =
    FINE_TIME_S + COARSE_TIME_STEP_S * (NO_TIME - 1 - FINE_CODES) as f64;
const CHECK: crc::Crc<u16> = crc::Crc::<u16>::new(&crc::CRC_16_IBM_3740);

/// Each slot of the turn-taking carries this many speakers on rcssservermj (a listener hears
/// every message when at most three are said in a cycle, counting the other team's) and one
/// speaker every second cycle on SimSpark (each listener accepts one teammate message per two
/// cycles).
const SLOTS: u64 = 11;

/// A player's message.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TeamMessage {
    pub unum: u8,
    /// The speaker's own position estimate (global frame) [m].
    pub position: [f64; 2],
    pub fallen: bool,
    /// Where the speaker last saw the ball (global frame) and how long before speaking [s].
    pub ball: Option<([f64; 2], f64)>,
    /// The speaker's estimate of its time to reach the ball [s] (`None`: not claiming).
    pub time_to_ball_s: Option<f64>,
    /// The speaker is going for the ball (it judged itself the ball winner): its teammates
    /// give it the same head start it gives itself, so two players that both went for the
    /// ball compare their bare times and one of them gives way.
    pub going_for_ball: bool,
}

/// A time to the ball in the steps a message carries it [s] (beyond its ceiling too): a player
/// compares its own time in the steps it hears its teammates' in, so two players close to
/// each other agree on who is first.
pub fn told_time_to_ball(time_s: f64) -> f64 {
    time_of_code(time_code(time_s))
}

/// The code of a time to the ball (beyond the message's ceiling too).
fn time_code(time_s: f64) -> u64 {
    if time_s <= FINE_TIME_S {
        (time_s / TIME_STEP_S).round().max(0.0) as u64
    } else {
        FINE_CODES + ((time_s - FINE_TIME_S) / COARSE_TIME_STEP_S).round() as u64
    }
}

fn time_of_code(code: u64) -> f64 {
    if code <= FINE_CODES {
        code as f64 * TIME_STEP_S
    } else {
        FINE_TIME_S + (code - FINE_CODES) as f64 * COARSE_TIME_STEP_S
    }
}

/// Why a heard message was not taken.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Rejected {
    /// Not base64, or not our length.
    Malformed,
    /// The check failed: noise, or the other team.
    Foreign,
}

/// Whether `unum` has the channel in the cycle at server `time` [s].
pub fn may_speak(server: ServerKind, time: f64, unum: u32) -> bool {
    let cycle = (time / 0.02).round().max(0.0) as u64;
    let unum = u64::from(unum.max(1) - 1) % SLOTS;
    match server {
        // Two speakers per cycle: slots (2c, 2c + 1) mod 11.
        ServerKind::RcssMj => (0..2).any(|k| (2 * cycle + k) % SLOTS == unum),
        // One speaker every second cycle.
        ServerKind::SimSpark => cycle.is_multiple_of(2) && (cycle / 2) % SLOTS == unum,
    }
}

struct Bits {
    bytes: [u8; PAYLOAD_BYTES],
    at: u32,
}

impl Bits {
    fn put(&mut self, value: u64, bits: u32) {
        for i in (0..bits).rev() {
            if value >> i & 1 == 1 {
                self.bytes[(self.at / 8) as usize] |= 0x80 >> (self.at % 8);
            }
            self.at += 1;
        }
    }

    fn take(&mut self, bits: u32) -> u64 {
        let mut value = 0;
        for _ in 0..bits {
            let bit = self.bytes[(self.at / 8) as usize] >> (7 - self.at % 8) & 1;
            value = value << 1 | u64::from(bit);
            self.at += 1;
        }
        value
    }
}

/// Field positions to fixed-point and back, over the field and a margin round it.
struct Grid {
    half: [f64; 2],
}

impl Grid {
    fn of(field: &FieldGeometry) -> Self {
        let (x, y) = field.half_extent();
        Self {
            half: [x + MARGIN_M, y + MARGIN_M],
        }
    }

    fn quantize(&self, v: f64, axis: usize, bits: u32) -> u64 {
        let top = ((1u64 << bits) - 1) as f64;
        let unit = ((v + self.half[axis]) / (2.0 * self.half[axis])).clamp(0.0, 1.0);
        (unit * top).round() as u64
    }

    fn value(&self, q: u64, axis: usize, bits: u32) -> f64 {
        let top = ((1u64 << bits) - 1) as f64;
        q as f64 / top * 2.0 * self.half[axis] - self.half[axis]
    }

    fn put(&self, bits: &mut Bits, p: [f64; 2]) {
        bits.put(self.quantize(p[0], 0, POSITION_X_BITS), POSITION_X_BITS);
        bits.put(self.quantize(p[1], 1, POSITION_Y_BITS), POSITION_Y_BITS);
    }

    fn take(&self, bits: &mut Bits) -> [f64; 2] {
        let x = bits.take(POSITION_X_BITS);
        let y = bits.take(POSITION_Y_BITS);
        [
            self.value(x, 0, POSITION_X_BITS),
            self.value(y, 1, POSITION_Y_BITS),
        ]
    }
}

fn steps(v: f64, step: f64, bits: u32) -> u64 {
    let top = (1u64 << bits) - 1;
    ((v / step).round().max(0.0) as u64).min(top)
}

fn check(team: &str, payload: &[u8]) -> u16 {
    let mut digest = CHECK.digest();
    digest.update(team.as_bytes());
    digest.update(payload);
    digest.finalize()
}

impl TeamMessage {
    /// The message as the server's `say` takes it: raw bytes on rcssservermj (the action
    /// writer sends them base64), base64 text on SimSpark.
    pub fn encode(&self, team: &str, field: &FieldGeometry, server: ServerKind) -> Said {
        let grid = Grid::of(field);
        let mut bits = Bits {
            bytes: [0; PAYLOAD_BYTES],
            at: 0,
        };
        bits.put(u64::from(self.unum.min(15)), 4);
        bits.put(u64::from(self.fallen), 1);
        grid.put(&mut bits, self.position);
        bits.put(u64::from(self.ball.is_some()), 1);
        let (ball, age) = self.ball.unwrap_or(([0.0; 2], 0.0));
        grid.put(&mut bits, ball);
        bits.put(steps(age, AGE_STEP_S, AGE_BITS), AGE_BITS);
        let time = self
            .time_to_ball_s
            .map_or(NO_TIME, |t| time_code(t).min(NO_TIME - 1));
        bits.put(time, TIME_BITS);
        bits.put(u64::from(self.going_for_ball), 1);
        let mut bytes = [0u8; MESSAGE_BYTES];
        bytes[..PAYLOAD_BYTES].copy_from_slice(&bits.bytes);
        bytes[PAYLOAD_BYTES..].copy_from_slice(&check(team, &bits.bytes).to_be_bytes());
        let mut said = Said::new();
        match server {
            ServerKind::RcssMj => said.extend(bytes),
            ServerKind::SimSpark => {
                let mut text = [0u8; TEXT_BYTES];
                let written = base64::engine::general_purpose::STANDARD
                    .encode_slice(bytes, &mut text)
                    .unwrap_or(0);
                said.extend(text[..written].iter().copied());
            }
        }
        said
    }

    /// A heard message's text (base64 on both servers) back to a message, when it is ours.
    pub fn decode(text: &str, team: &str, field: &FieldGeometry) -> Result<TeamMessage, Rejected> {
        if text.len() > TEXT_BYTES {
            return Err(Rejected::Malformed);
        }
        // Room for what any text of that length could decode to.
        let mut decoded = [0u8; TEXT_BYTES];
        let length = base64::engine::general_purpose::STANDARD
            .decode_slice(text, &mut decoded)
            .map_err(|_| Rejected::Malformed)?;
        if length != MESSAGE_BYTES {
            return Err(Rejected::Malformed);
        }
        let bytes = &decoded[..length];
        let (payload, sum) = bytes.split_at(PAYLOAD_BYTES);
        if check(team, payload).to_be_bytes() != sum {
            return Err(Rejected::Foreign);
        }
        let grid = Grid::of(field);
        let mut bits = Bits {
            bytes: payload.try_into().map_err(|_| Rejected::Malformed)?,
            at: 0,
        };
        let unum = bits.take(4) as u8;
        let fallen = bits.take(1) == 1;
        let position = grid.take(&mut bits);
        let has_ball = bits.take(1) == 1;
        let ball = grid.take(&mut bits);
        let age = bits.take(AGE_BITS) as f64 * AGE_STEP_S;
        let time = bits.take(TIME_BITS);
        let going_for_ball = bits.take(1) == 1;
        Ok(TeamMessage {
            unum,
            position,
            fallen,
            ball: has_ball.then_some((ball, age)),
            time_to_ball_s: (time != NO_TIME).then(|| time_of_code(time)),
            going_for_ball,
        })
    }
}

#[cfg(test)]
mod tests;
