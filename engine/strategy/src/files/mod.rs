//! Strategy files in `formations/`: formations, the team file and tuning parameters.

mod field;
mod formation;
mod params;
mod reader;

pub use field::Field;
pub use formation::{parse_formation, Formation, Role, Sample};
pub use params::*;
pub use reader::StrategyFiles;

use libero_behavior::Vec2;
use std::collections::BTreeMap;

/// Every strategy file of a library, validated.
#[derive(Debug, Clone, Default)]
pub struct Strategy {
    pub team: Option<TeamParams>,
    pub formations: BTreeMap<String, Formation>,
    pub goalkeeper: Option<GoalkeeperParams>,
    pub shot: Option<ShotParams>,
    pub pass: Option<PassParams>,
    pub avoidance: Option<AvoidanceParams>,
}

impl Strategy {
    pub fn field(&self) -> Field {
        self.team
            .as_ref()
            .map_or_else(Field::default, |t| t.field.clone())
    }

    pub fn formation(&self, name: &str) -> Option<&Formation> {
        self.formations.get(name)
    }

    /// The formation the team file assigns to a situation.
    pub fn formation_for(&self, situation: Situation) -> Option<&Formation> {
        let (name, _) = self.team.as_ref()?.formations.get(&situation)?;
        self.formations.get(name)
    }

    /// Player `unum`'s formation position for a situation and ball position (own frame).
    pub fn position(&self, situation: Situation, unum: u8, ball: Vec2) -> Option<Vec2> {
        self.formation_for(situation)?.position(unum, ball)
    }

    /// The root tree player `unum` runs (unum 1 is the goalkeeper).
    pub fn tree_for(&self, unum: u8) -> Option<&str> {
        let team = self.team.as_ref()?;
        Some(if unum == 1 {
            &team.goalkeeper_tree.0
        } else {
            &team.field_player_tree.0
        })
    }
}
