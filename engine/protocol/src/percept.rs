//! Typed percepts: one server message turned into named, unit-documented fields.
//!
//! Both dialects land in the same [`Percept`]. Vectors from the body's sensors are given in one
//! robot frame for both servers: **x forward, y left, z up** (SimSpark's x-right/y-forward
//! readings are rotated here, once). Angles stay in degrees as on the wire.

use crate::sexp::SexpError;
use arrayvec::ArrayVec;
use libero_model::ServerKind;

mod reader;

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
    reader::read_items(text, server, &mut p)?;
    Ok(p)
}
