//! The decisions of a trial's player: place the robot with the monitor (on SimSpark, once
//! its init shows, confirmed from the ground truth; lying, by a fall motion of its own), let
//! it settle, then follow the episode's script and record every cycle.

use crate::episode::Sample;
use crate::Recording;
use libero_agent::Decider;
use libero_server::Monitor;
use libero_skills::{BodyIntent, Intent, MotionId, SkillStatus};
use libero_world::World;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};

/// A robot placed standing that must fall before its episode starts (SimSpark).
pub(crate) struct Fall {
    motion: MotionId,
    /// Since when the placed robot has stood still (before the fall motion starts).
    standing_since: Option<f64>,
    /// The fall motion has started.
    falling: bool,
    /// Since when the torso has lain low and still.
    lying_since: Option<f64>,
}

impl Fall {
    pub(crate) fn by(motion: MotionId) -> Self {
        Self {
            motion,
            standing_since: None,
            falling: false,
            lying_since: None,
        }
    }
}

/// Standing at least this long after the placement before the fall motion starts [s].
const FALL_AFTER_S: f64 = 0.5;
/// Still is a body rate below this [deg/s] held for this long [s], standing before the fall
/// and lying after it. The placement drops the robot from a centimetre up and the monitor
/// confirms it a variable number of cycles later: a fall started while the body still rocked
/// (or a get-up from a body still settling, at 20 deg/s before) began each run from another
/// state, so one placement stood in one run and not in the next. From rest the start no
/// longer depends on when the commands arrived.
const STILL_DEG_S: f64 = 2.0;
const STILL_FOR_S: f64 = 0.4;
/// A placed robot that has not come to rest by then falls anyway [s].
const STAND_STILL_WITHIN_S: f64 = 3.0;
/// A fall that has not laid the robot down by now has failed [s].
const FALL_TIMEOUT_S: f64 = 8.0;

/// Decisions from a script, with placement, settling and recording around it.
pub(crate) struct ScriptedDecider<S> {
    /// Torso heights below this are a fall [m].
    pub(crate) low_below_m: f64,
    /// ... and from this up the robot stands [m].
    pub(crate) tall_from_m: f64,
    pub(crate) script: S,
    pub(crate) settle_s: f64,
    pub(crate) recording: Arc<Mutex<Recording>>,
    pub(crate) shutdown: Arc<AtomicBool>,
    /// Server time at which the placement was sent (after a fall: at which it lay still).
    pub(crate) placed_at: Option<f64>,
    /// Still to fall before the episode starts.
    pub(crate) fall: Option<Fall>,
    pub(crate) place_command: String,
    /// Where the placement must show in the ground truth before the episode goes on.
    pub(crate) confirm: Option<Confirm>,
    pub(crate) monitor: Arc<Mutex<Monitor>>,
    pub(crate) status: Arc<Mutex<SkillStatus>>,
}

/// A placement still to be seen in the ground truth.
pub(crate) struct Confirm {
    at: [f64; 2],
    sends: u32,
}

impl Confirm {
    /// The first placement at `at` (world x, y) has been asked for.
    pub(crate) fn at(at: [f64; 2]) -> Self {
        Self { at, sends: 1 }
    }
}

/// The placed torso within this of its target counts as placed [m] (SimSpark's `move` is
/// exact; a robot that was not moved is metres away).
const PLACED_WITHIN_M: f64 = 0.1;
/// A placement not seen after this is sent again [s] (the monitor reads commands every 40 ms
/// and reports every 40 ms).
const PLACEMENT_SHOWS_WITHIN_S: f64 = 0.3;
const PLACEMENT_SENDS: u32 = 10;

impl<S> ScriptedDecider<S> {
    fn send_placement(&mut self) {
        let sent = match self.monitor.lock() {
            Ok(mut m) => m.send(&self.place_command),
            Err(_) => Err(std::io::Error::other("monitor lock poisoned")),
        };
        if let Err(e) = sent {
            log::error!("trial: cannot place the robot: {e}");
            self.shutdown.store(true, Ordering::Relaxed);
        }
    }
}

impl<S> Decider for ScriptedDecider<S>
where
    S: FnMut(&World, f64) -> Option<Intent> + Send,
{
    fn decide(&mut self, world: &World) -> Intent {
        let stand = Intent::default();
        if self.placed_at.is_none() {
            // The side known: the server has taken the init, so it knows whom to place.
            if self.confirm.is_some() && world.game.side.is_none() {
                return stand;
            }
            self.send_placement();
            self.placed_at = Some(world.time);
            return stand;
        }
        let Some(placed) = self.placed_at else {
            return stand;
        };
        if let Some(confirm) = self.confirm.as_mut() {
            let there = world.truth.torso_position.is_some_and(|p| {
                (p[0] - confirm.at[0]).hypot(p[1] - confirm.at[1]) < PLACED_WITHIN_M
            });
            if there {
                // Settling counts from here.
                self.confirm = None;
                self.placed_at = Some(world.time);
            } else if world.time - placed > PLACEMENT_SHOWS_WITHIN_S {
                if confirm.sends >= PLACEMENT_SENDS {
                    log::error!(
                        "trial: the robot was not placed at {:?} after {PLACEMENT_SENDS} tries",
                        confirm.at
                    );
                    self.shutdown.store(true, Ordering::Relaxed);
                } else {
                    confirm.sends += 1;
                    self.send_placement();
                    self.placed_at = Some(world.time);
                }
            }
            return stand;
        }
        if let Some(fall) = self.fall.as_mut() {
            let motion = fall.motion;
            let since = world.time - placed;
            let [gx, gy, gz] = world.body.gyro;
            let still = (gx * gx + gy * gy + gz * gz).sqrt() < STILL_DEG_S;
            if !fall.falling {
                fall.standing_since = still.then(|| fall.standing_since.unwrap_or(world.time));
                let rested = fall
                    .standing_since
                    .is_some_and(|t| world.time - t >= STILL_FOR_S);
                if since < FALL_AFTER_S || !(rested || since > STAND_STILL_WITHIN_S) {
                    return stand;
                }
                if !rested {
                    log::warn!("trial: the placed robot did not come to rest; it falls rocking");
                }
                fall.falling = true;
            }
            let low = world
                .truth
                .torso_position
                .is_some_and(|p| p[2] < self.low_below_m);
            fall.lying_since = (low && still).then(|| fall.lying_since.unwrap_or(world.time));
            if fall
                .lying_since
                .is_some_and(|t| world.time - t >= STILL_FOR_S)
            {
                // The episode starts now, from lying still.
                self.fall = None;
                self.placed_at = Some(world.time);
            } else if since > STAND_STILL_WITHIN_S + FALL_TIMEOUT_S {
                log::error!(
                    "trial: the fall motion did not lay the robot down in {FALL_TIMEOUT_S} s"
                );
                self.shutdown.store(true, Ordering::Relaxed);
                return stand;
            }
            return Intent {
                body: BodyIntent::Motion { id: motion },
                ..Intent::default()
            };
        }
        let t = world.time - placed - self.settle_s;
        if t < 0.0 {
            return stand;
        }
        let intent = match (self.script)(world, t) {
            Some(intent) => intent,
            None => {
                self.shutdown.store(true, Ordering::Relaxed);
                return stand;
            }
        };
        if let Ok(mut r) = self.recording.lock() {
            r.samples
                .push(sample(world, t, self.low_below_m, self.tall_from_m));
            r.intents.push(intent.clone());
        }
        intent
    }

    fn observe(&mut self, status: &SkillStatus) {
        if let Ok(mut s) = self.status.lock() {
            *s = *status;
        }
    }
}

fn sample(world: &World, t: f64, low_below_m: f64, tall_from_m: f64) -> Sample {
    let position = world.truth.torso_position.unwrap_or([f64::NAN; 3]);
    let [w, x, y, z] = world.truth.torso_orientation.unwrap_or([f64::NAN; 4]);
    let yaw_deg = (2.0 * (w * z + x * y))
        .atan2(1.0 - 2.0 * (y * y + z * z))
        .to_degrees();
    let pitch_deg = (2.0 * (w * y - z * x)).clamp(-1.0, 1.0).asin().to_degrees();
    let roll_deg = (2.0 * (w * x + y * z))
        .atan2(1.0 - 2.0 * (x * x + y * y))
        .to_degrees();
    let tilt_deg = (1.0 - 2.0 * (x * x + y * y))
        .clamp(-1.0, 1.0)
        .acos()
        .to_degrees();
    Sample {
        t,
        position,
        yaw_deg,
        pitch_deg,
        roll_deg: -roll_deg,
        tilt_deg,
        posture: world.body.posture,
        low: position[2] < low_below_m,
        tall: position[2] >= tall_from_m,
        estimate: world.me.localized.then_some(world.me.position),
    }
}
