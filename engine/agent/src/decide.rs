//! The decision stage: from beliefs to this cycle's intent.

use libero_skills::{BodyIntent, HeadIntent, Intent};
use libero_world::World;

/// Chooses what the skills should do this cycle.
pub trait Decider: Send {
    fn decide(&mut self, world: &World) -> Intent;
}

/// Beam to a fixed own-frame pose when the play mode allows, then stand and look around.
/// Used when no behavior tree is loaded.
pub struct StandAndBeam {
    pub beam_pose: [f64; 3],
}

impl Decider for StandAndBeam {
    fn decide(&mut self, world: &World) -> Intent {
        Intent {
            body: BodyIntent::Stand,
            head: HeadIntent::LookAround {
                amplitude_deg: None,
                period_s: None,
            },
            beam: world.game.play_mode.allows_beam().then_some(self.beam_pose),
            say: None,
        }
    }
}
