//! The agent's beliefs about itself, the game and (later) the ball and other players.
//!
//! Updated once per cycle from a percept, read by decisions and skills. Server ground truth
//! (`pos`, `quat`) is kept apart in [`GroundTruth`] for logs and tests: nothing that decides
//! reads it.

pub mod body;
pub mod game;

pub use body::{BodyState, Posture};
pub use game::{GameState, PlayMode, Side};

use libero_model::RobotModel;
use libero_protocol::Percept;

/// What the server says is true, for evaluation only.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct GroundTruth {
    pub torso_position: Option<[f64; 3]>,
    /// w, x, y, z
    pub torso_orientation: Option<[f64; 4]>,
}

/// Everything the agent believes at the current cycle.
#[derive(Debug, Clone)]
pub struct World {
    /// Server simulation time [s].
    pub time: f64,
    /// Cycles seen since the agent connected.
    pub cycle: u64,
    pub game: GameState,
    pub body: BodyState,
    pub truth: GroundTruth,
}

impl World {
    pub fn new(model: &RobotModel, team: &str, unum: u32) -> Self {
        Self {
            time: 0.0,
            cycle: 0,
            game: GameState::new(team, unum),
            body: BodyState::new(model),
            truth: GroundTruth::default(),
        }
    }

    /// Fold one percept into the beliefs.
    pub fn update(&mut self, model: &RobotModel, percept: &Percept<'_>) {
        self.cycle += 1;
        if let Some(t) = percept.time {
            self.time = t;
        }
        self.game.update(&percept.game);
        self.body.update(model, percept);
        self.truth = GroundTruth {
            torso_position: percept.truth_position,
            torso_orientation: percept.truth_orientation,
        };
    }
}
