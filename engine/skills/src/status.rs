//! What the skill layer reports to the decision layer each cycle.

use crate::{kick, DribbleState, KickState, SaveState};

/// Which skill produced the latest targets.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ActiveSkill {
    Stand,
    Walk,
    GetUp,
    Kick,
    /// Dribbling: walking the ball along.
    Dribble,
    /// A goalkeeper save (dive or block), or lying still after a dive until the get-up starts.
    Save,
    /// A named motion of the parameter file (`BodyIntent::Motion`).
    Motion,
}

/// What the skill layer is doing, for the decision layer.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SkillStatus {
    pub active: ActiveSkill,
    pub kick: KickState,
    pub dribble: DribbleState,
    /// The long kick's measured spread (from the parameter file).
    pub kick_spread: kick::KickSpread,
    /// Where the kick wants the ball and how its balls curve (from the parameter file): for a
    /// beam straight to the kicking place.
    pub kick_geometry: kick::KickGeometry,
    pub save: SaveState,
    /// Kick steps the walk has begun (a dribble's kicks; a change says one began).
    pub kick_steps: u32,
}

impl Default for SkillStatus {
    fn default() -> Self {
        Self {
            active: ActiveSkill::Stand,
            kick: KickState::Idle,
            dribble: DribbleState::Idle,
            kick_spread: kick::KickSpread::default(),
            kick_geometry: kick::KickGeometry::default(),
            save: SaveState::Idle,
            kick_steps: 0,
        }
    }
}
