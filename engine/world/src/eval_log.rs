//! The evaluation log: one JSON object per cycle with the agent's estimates and, when the server
//! sends it, the ground truth, so anyone can measure accuracy offline. The truth is only
//! written here, never read back into an estimate.
//!
//! Line format (fields absent when unknown):
//! `{"time":…, "cycle":…, "team":…, "unum":…, "side":"Left", "play_mode":…,
//!   "me":{"position":[x,y], "yaw_deg":…, "height":…, "position_sigma":…, "localized":…, …},
//!   "ball":{"position":[x,y], "velocity":[vx,vy], "predicted_stop":[x,y], "last_seen_time":…, …},
//!   "players":[{"relation":"Opponent","unum":3,"position":[x,y],…}],
//!   "truth":{"position":[x,y,z], "yaw_deg":…, "roll_deg":…, "pitch_deg":…}}` (truth roll and
//!   pitch in the estimate's convention, to check the tilt filter against)

use crate::{BallEstimate, PlayerEstimate, SelfEstimate, Side, World};
use serde::Serialize;
use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

#[derive(Serialize)]
struct Truth {
    position: [f64; 3],
    yaw_deg: f64,
    #[serde(skip_serializing_if = "Option::is_none")]
    roll_deg: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pitch_deg: Option<f64>,
}

#[derive(Serialize)]
struct Record<'a, X: Serialize> {
    time: f64,
    cycle: u64,
    team: &'a str,
    unum: u32,
    side: Option<Side>,
    play_mode: &'a str,
    me: &'a SelfEstimate,
    ball: Option<&'a BallEstimate>,
    players: &'a [PlayerEstimate],
    heard: &'a crate::HeardNews,
    truth: Option<Truth>,
    /// The decision trace of the cycle (active leaves and their statuses), when requested.
    #[serde(skip_serializing_if = "Option::is_none")]
    trace: Option<&'a str>,
    /// Whatever else the caller logs (the decision a field view replays), flattened in.
    #[serde(flatten, skip_serializing_if = "Option::is_none")]
    extra: Option<&'a X>,
}

/// Writes one line per [`EvalLogger::write`] call; flushes on drop.
pub struct EvalLogger<W: Write = BufWriter<File>> {
    out: W,
    buffer: Vec<u8>,
}

/// One robot's log under a team's or a series' `prefix`: `PREFIX.TEAM.UNUM` (what
/// `tools/eval_match.py` reads).
pub fn robot_log_path(prefix: &Path, team: &str, unum: u32) -> PathBuf {
    let mut name = prefix.as_os_str().to_owned();
    name.push(format!(".{team}.{unum}"));
    PathBuf::from(name)
}

impl EvalLogger<BufWriter<File>> {
    /// Create (truncate) the log file.
    pub fn create(path: &Path) -> std::io::Result<Self> {
        Ok(Self::new(BufWriter::new(File::create(path)?)))
    }

    /// Open the log file to write on at its end (created if missing): a second connection
    /// of the same robot in one run (a scenario's server restarted) adds to its log.
    pub fn append(path: &Path) -> std::io::Result<Self> {
        let file = std::fs::OpenOptions::new()
            .create(true)
            .append(true)
            .open(path)?;
        Ok(Self::new(BufWriter::new(file)))
    }
}

impl<W: Write> EvalLogger<W> {
    pub fn new(out: W) -> Self {
        Self {
            out,
            buffer: Vec::with_capacity(2048),
        }
    }

    /// Append the current cycle.
    pub fn write(&mut self, world: &World) -> std::io::Result<()> {
        self.write_with_trace(world, None)
    }

    /// Append the current cycle with the decision trace that produced its intent.
    pub fn write_with_trace(&mut self, world: &World, trace: Option<&str>) -> std::io::Result<()> {
        self.write_record::<()>(world, trace, None)
    }

    /// Append the current cycle with the trace and `extra`'s fields (an object) merged in.
    pub fn write_record<X: Serialize>(
        &mut self,
        world: &World,
        trace: Option<&str>,
        extra: Option<&X>,
    ) -> std::io::Result<()> {
        let record = Record {
            time: world.time,
            cycle: world.cycle,
            team: &world.game.team,
            unum: world.game.unum,
            side: world.game.side,
            play_mode: &world.game.play_mode_name,
            me: &world.me,
            ball: (world.ball.last_seen_time.is_some() || world.ball.heard_time.is_some())
                .then_some(&world.ball),
            heard: &world.heard,
            players: &world.players.known,
            truth: world.truth_pose().map(|(position, yaw_deg)| {
                let tilt = world
                    .truth
                    .torso_orientation
                    .map(crate::geometry::roll_pitch_deg_of_quaternion);
                Truth {
                    position,
                    yaw_deg,
                    roll_deg: tilt.map(|t| t.0),
                    pitch_deg: tilt.map(|t| t.1),
                }
            }),
            trace,
            extra,
        };
        self.buffer.clear();
        // Non-finite numbers (an unknown σ) become `null`, keeping every line valid JSON.
        serde_json::to_writer(&mut self.buffer, &record).map_err(std::io::Error::other)?;
        self.buffer.push(b'\n');
        self.out.write_all(&self.buffer)
    }

    pub fn flush(&mut self) -> std::io::Result<()> {
        self.out.flush()
    }

    pub fn into_inner(self) -> W {
        self.out
    }
}
