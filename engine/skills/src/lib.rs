//! Low-level skills. Each turns an [`Intent`] and the world state into joint targets for the
//! next cycle; none of them decides *what* to do (that is the behavior tree's job).

pub mod intent;
pub mod params;
pub mod pose;

pub use intent::{BodyIntent, HeadIntent, Intent};
pub use params::{ParamsError, SkillParams};
pub use pose::{JointTarget, JointTargets};

use libero_model::RobotModel;
use libero_world::World;

/// The skill layer of one agent.
pub struct Skills {
    params: SkillParams,
    stand: Vec<f64>,
}

impl Skills {
    pub fn new(model: &RobotModel, params: SkillParams) -> Result<Self, ParamsError> {
        let stand = params.stand_pose(model)?;
        Ok(Self { params, stand })
    }

    pub fn params(&self) -> &SkillParams {
        &self.params
    }

    /// The stand posture [deg per joint].
    pub fn stand_pose(&self) -> &[f64] {
        &self.stand
    }

    /// Joint targets realising `intent` this cycle.
    pub fn act(
        &mut self,
        model: &RobotModel,
        world: &World,
        intent: &Intent,
        out: &mut JointTargets,
    ) {
        out.hold_pose(model, &self.stand);
        match intent.body {
            BodyIntent::Stand => {}
        }
        match intent.head {
            HeadIntent::Hold => {}
            HeadIntent::LookAround => {
                let la = &self.params.look_around;
                let phase = world.time * std::f64::consts::TAU / la.period_s.max(0.1);
                out.set_angle(model, "head_yaw", la.yaw_amplitude_deg * phase.sin());
                out.set_angle(model, "head_pitch", la.pitch_deg);
            }
        }
    }
}
