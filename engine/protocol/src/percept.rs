//! Typed percepts: one server message turned into named, unit-documented fields.
//!
//! Both dialects land in the same [`Percept`]. Vectors from the body's sensors are given in one
//! robot frame for both servers: **x forward, y left, z up** (SimSpark's x-right/y-forward
//! readings are rotated here, once). Angles stay in degrees as on the wire.

use crate::sexp::{self, List, Sexp, SexpError};
use arrayvec::ArrayVec;
use libero_model::ServerKind;

// Capacities of a percept's lists: a percept lives on the stack, so reading one never touches
// the heap. Items beyond them are dropped and the block is named in `skipped`.
/// Joints (T1 23, NAO 22).
pub const MAX_JOINTS: usize = 32;
pub const MAX_FOOT_CONTACTS: usize = 4;
/// Landmarks in one vision frame (rcssservermj sees up to ~30 line ends, posts, spots).
pub const MAX_LANDMARKS: usize = 48;
/// Robots in one vision frame (11 a side).
pub const MAX_PLAYERS_SEEN: usize = 24;
/// Body parts of one seen robot (SimSpark 5, rcssservermj 3).
pub const MAX_PARTS: usize = 8;
/// Field lines in one vision frame (SimSpark).
pub const MAX_LINES: usize = 32;
pub const MAX_HEARD: usize = 16;
pub const MAX_SKIPPED: usize = 16;

/// A point seen by the camera, in the camera's polar coordinates.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Polar {
    /// Distance from the camera [m].
    pub distance: f64,
    /// Horizontal angle [deg], positive to the left.
    pub azimuth_deg: f64,
    /// Vertical angle [deg], positive up.
    pub elevation_deg: f64,
}

/// One joint reading.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct JointReading<'a> {
    /// The perceptor name, e.g. `q_llj1` or `llj1`.
    pub perceptor: &'a str,
    /// Angle [deg].
    pub angle_deg: f64,
    /// Angular velocity [deg/s]; rcssservermj only.
    pub velocity_deg: Option<f64>,
}

/// Contact force on a foot (SimSpark `FRP`), in the robot frame convention.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FootContact<'a> {
    pub name: &'a str,
    /// Centre of pressure in the foot frame [m].
    pub point: [f64; 3],
    /// Force on the foot [N].
    pub force: [f64; 3],
}

/// A named object seen in the camera (a landmark, or a body part of a player).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Seen<'a> {
    pub name: &'a str,
    pub at: Polar,
}

/// A robot seen in the camera.
#[derive(Debug, Clone, PartialEq)]
pub struct SeenPlayer<'a> {
    pub team: &'a str,
    pub unum: u32,
    /// Visible parts (`head`, `lfoot`, `rfoot`, `llowerarm`, ...).
    pub parts: ArrayVec<Seen<'a>, MAX_PARTS>,
}

/// A visible field line segment (SimSpark only).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SeenLine {
    pub from: Polar,
    pub to: Polar,
}

/// One vision frame.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Vision<'a> {
    /// Fixed landmarks by their server name (`l_luf`, `g_rup`, `F1L`, `G2R`, ...).
    pub landmarks: ArrayVec<Seen<'a>, MAX_LANDMARKS>,
    pub ball: Option<Polar>,
    pub players: ArrayVec<SeenPlayer<'a>, MAX_PLAYERS_SEEN>,
    pub lines: ArrayVec<SeenLine, MAX_LINES>,
    /// Some items did not fit the capacities above.
    pub overflowed: bool,
}

/// Which team a message came from, relative to the listener.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum HeardFrom<'a> {
    /// Our own message echoed back (SimSpark `self`).
    Myself,
    /// A direction [deg]: rcssservermj = azimuth in the head frame; SimSpark = bearing in the
    /// listener's team field frame.
    Direction(f64),
    /// Direction not given.
    Unknown(&'a str),
}

/// A message heard.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Heard<'a> {
    /// Speaker's team name (SimSpark only).
    pub team: Option<&'a str>,
    /// Game time of the message (SimSpark only).
    pub time: Option<f64>,
    pub from: HeardFrom<'a>,
    /// The message as sent: base64 text on rcssservermj, plain text on SimSpark.
    pub message: &'a str,
}

/// The `GS` game-state block.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct GameStatePercept<'a> {
    /// Play time [s].
    pub play_time: Option<f64>,
    /// Play-mode name as sent by the server.
    pub play_mode: Option<&'a str>,
    pub team_left: Option<&'a str>,
    pub team_right: Option<&'a str>,
    pub score_left: Option<u32>,
    pub score_right: Option<u32>,
    /// SimSpark: our uniform number, sent once after a successful init.
    pub unum: Option<u32>,
    /// SimSpark: `left` or `right`, sent once after a successful init.
    pub side: Option<&'a str>,
}

/// Everything one perception message says.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Percept<'a> {
    /// Server simulation time [s] (not play time).
    pub time: Option<f64>,
    pub game: GameStatePercept<'a>,
    /// Ground-truth torso orientation, quaternion w, x, y, z (rcssservermj; tests and evaluation only).
    pub truth_orientation: Option<[f64; 4]>,
    /// Ground-truth torso position [m] (rcssservermj; tests and evaluation only).
    pub truth_position: Option<[f64; 3]>,
    /// Torso angular velocity [deg/s], robot frame.
    pub gyro: Option<[f64; 3]>,
    /// Torso specific force [m/s²], robot frame (≈ +9.81 on z when upright).
    pub accel: Option<[f64; 3]>,
    pub joints: ArrayVec<JointReading<'a>, MAX_JOINTS>,
    pub foot_contacts: ArrayVec<FootContact<'a>, MAX_FOOT_CONTACTS>,
    pub vision: Option<Vision<'a>>,
    pub heard: ArrayVec<Heard<'a>, MAX_HEARD>,
    /// Top-level items we did not recognise, could not read or could not hold all of, by name
    /// (for diagnostics; the first [`MAX_SKIPPED`]).
    pub skipped: ArrayVec<&'a str, MAX_SKIPPED>,
}

/// Why a message could not be read at all.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PerceptError {
    #[error("the message is not UTF-8 text")]
    NotText,
    #[error("malformed message: {0}")]
    Syntax(#[from] SexpError),
}

/// Turn a raw payload into a percept. Items that are malformed are listed in `skipped`; only a
/// message that is not text or not balanced is an error.
pub fn parse_percept(payload: &[u8], server: ServerKind) -> Result<Percept<'_>, PerceptError> {
    let text = std::str::from_utf8(payload).map_err(|_| PerceptError::NotText)?;
    parse_percept_str(text, server)
}

/// As [`parse_percept`], from text.
pub fn parse_percept_str(text: &str, server: ServerKind) -> Result<Percept<'_>, PerceptError> {
    let mut p = Percept::default();
    for item in sexp::top_level(text) {
        let item = item?;
        let Some(list) = item.as_list() else {
            let _ = p.skipped.try_push(item.as_atom().unwrap_or(""));
            continue;
        };
        let name = list.head().unwrap_or("");
        let ok = match name {
            "time" => list
                .numbers::<1>("now")
                .map(|[t]| p.time = Some(t))
                .is_some(),
            "GS" => read_game_state(list, &mut p.game),
            "quat" => list
                .numbers::<4>("q")
                .map(|q| p.truth_orientation = Some(q))
                .is_some(),
            "pos" => list
                .numbers::<3>("p")
                .map(|v| p.truth_position = Some(v))
                .is_some(),
            "GYR" => list
                .numbers::<3>("rt")
                .map(|v| p.gyro = Some(to_robot_frame(v, server)))
                .is_some(),
            "ACC" => list
                .numbers::<3>("a")
                .map(|v| p.accel = Some(to_robot_frame(v, server)))
                .is_some(),
            "HJ" => read_joint(list).is_some_and(|j| p.joints.try_push(j).is_ok()),
            "FRP" => read_foot(list, server).is_some_and(|f| p.foot_contacts.try_push(f).is_ok()),
            "See" => {
                // Filled where it lies: a vision frame is kilobytes on the stack.
                let vision = p.vision.insert(Vision::default());
                read_vision(list, vision);
                !vision.overflowed
            }
            "MIC" => read_mic(list, &mut p.heard),
            "hear" => read_hear(list).is_some_and(|h| p.heard.try_push(h).is_ok()),
            _ => false,
        };
        if !ok {
            let _ = p.skipped.try_push(name);
        }
    }
    Ok(p)
}

/// SimSpark's body sensors use x right, y forward; ours are x forward, y left.
fn to_robot_frame(v: [f64; 3], server: ServerKind) -> [f64; 3] {
    match server {
        ServerKind::RcssMj => v,
        ServerKind::SimSpark => [v[1], -v[0], v[2]],
    }
}

fn read_game_state<'a>(list: List<'a>, gs: &mut GameStatePercept<'a>) -> bool {
    for child in list.tail().filter_map(|c| c.as_list()) {
        let value = child.tail().next().and_then(|v| v.as_atom());
        let Some(value) = value else { continue };
        match child.head() {
            Some("t") => gs.play_time = sexp::parse_finite(value),
            Some("pm") => gs.play_mode = Some(value),
            Some("tl") => gs.team_left = Some(value),
            Some("tr") => gs.team_right = Some(value),
            Some("sl") => gs.score_left = value.parse().ok(),
            Some("sr") => gs.score_right = value.parse().ok(),
            Some("unum") => gs.unum = value.parse().ok(),
            Some("team") => gs.side = Some(value),
            _ => {}
        }
    }
    true
}

/// One pass over the item's children: joints are most of every message.
fn read_joint(list: List<'_>) -> Option<JointReading<'_>> {
    let (mut perceptor, mut angle, mut velocity) = (None, None, None);
    for child in list.tail().filter_map(|c| c.as_list()) {
        match child.head() {
            Some("n") => perceptor = child.tail().next().and_then(|v| v.as_atom()),
            Some("ax") => angle = child.tail_numbers::<1>().map(|[v]| v),
            Some("vx") => velocity = child.tail_numbers::<1>().map(|[v]| v),
            _ => {}
        }
    }
    Some(JointReading {
        perceptor: perceptor?,
        angle_deg: angle?,
        velocity_deg: velocity,
    })
}

fn read_foot(list: List<'_>, server: ServerKind) -> Option<FootContact<'_>> {
    Some(FootContact {
        name: list.value("n")?,
        point: to_robot_frame(list.numbers::<3>("c")?, server),
        force: to_robot_frame(list.numbers::<3>("f")?, server),
    })
}

fn read_polar(list: List<'_>) -> Option<Polar> {
    let [distance, azimuth_deg, elevation_deg] = list.tail_numbers::<3>()?;
    Some(Polar {
        distance,
        azimuth_deg,
        elevation_deg,
    })
}

fn read_vision<'a>(list: List<'a>, vision: &mut Vision<'a>) {
    for item in list.tail().filter_map(|c| c.as_list()) {
        match item.head() {
            Some("P") => {
                if let Some(player) = read_player(item) {
                    vision.overflowed |= vision.players.try_push(player).is_err();
                }
            }
            Some("L") => {
                let mut ends = item
                    .tail()
                    .filter_map(|c| c.as_list())
                    .filter_map(read_polar);
                if let (Some(from), Some(to)) = (ends.next(), ends.next()) {
                    vision.overflowed |= vision.lines.try_push(SeenLine { from, to }).is_err();
                }
            }
            Some("B") => vision.ball = item.child("pol").and_then(read_polar),
            Some(name) => {
                if let Some(at) = item.child("pol").and_then(read_polar) {
                    vision.overflowed |= vision.landmarks.try_push(Seen { name, at }).is_err();
                }
            }
            None => {}
        }
    }
}

fn read_player(list: List<'_>) -> Option<SeenPlayer<'_>> {
    let mut player = SeenPlayer {
        team: list.value("team").unwrap_or(""),
        unum: list.value("id")?.parse().ok()?,
        parts: ArrayVec::new(),
    };
    for part in list.tail().filter_map(|c| c.as_list()) {
        if let (Some(name), Some(at)) = (part.head(), part.child("pol").and_then(read_polar)) {
            // A robot has no more parts than this; extra ones would be a server's invention.
            let _ = player.parts.try_push(Seen { name, at });
        }
    }
    Some(player)
}

/// rcssservermj: `(MIC hear (az b64) (az b64) …)`.
fn read_mic<'a>(list: List<'a>, heard: &mut ArrayVec<Heard<'a>, MAX_HEARD>) -> bool {
    for msg in list.tail().filter_map(|c| c.as_list()) {
        let mut parts = msg.iter();
        let (Some(az), Some(Sexp::Atom(text))) =
            (parts.next().and_then(|a| a.as_f64()), parts.next())
        else {
            continue;
        };
        if heard
            .try_push(Heard {
                team: None,
                time: None,
                from: HeardFrom::Direction(az),
                message: text,
            })
            .is_err()
        {
            return false;
        }
    }
    true
}

/// SimSpark: `(hear TEAM T self|DIR MSG)`, or the older `(hear T self|DIR MSG)`.
fn read_hear(list: List<'_>) -> Option<Heard<'_>> {
    let mut atoms = [""; 4];
    let mut count = 0;
    for atom in list.tail() {
        *atoms.get_mut(count)? = atom.as_atom()?;
        count += 1;
    }
    let (team, rest) = match count {
        4 => (Some(atoms[0]), &atoms[1..]),
        3 => (None, &atoms[..3]),
        _ => return None,
    };
    let from = match rest[1] {
        "self" => HeardFrom::Myself,
        dir => sexp::parse_finite(dir).map_or(HeardFrom::Unknown(dir), HeardFrom::Direction),
    };
    Some(Heard {
        team,
        time: sexp::parse_finite(rest[0]),
        from,
        message: rest[2],
    })
}
