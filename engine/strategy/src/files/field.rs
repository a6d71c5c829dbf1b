//! The field the team plays on, as strategy code sees it: the one field model
//! (`engine/model/fields/*.ron`) with the few helpers positions need, in the team's own frame.

use libero_behavior::Vec2;
use libero_model::FieldGeometry;
use std::sync::Arc;

/// A shipped field (`FieldGeometry::builtin`). The field is symmetric, so its geometry reads the
/// same in the global frame and in either team's own frame (own goal at −x).
#[derive(Debug, Clone, PartialEq)]
pub struct Field(Arc<FieldGeometry>);

impl Field {
    /// The shipped field of that name (`fifa7vs7`, `fifa`, `simspark`).
    pub fn by_name(name: &str) -> Option<Field> {
        FieldGeometry::builtin(name)
            .ok()
            .map(|g| Field(Arc::new(g)))
    }

    /// The names of the shipped fields.
    pub fn names() -> Vec<&'static str> {
        FieldGeometry::builtin_names()
    }

    pub fn geometry(&self) -> &FieldGeometry {
        &self.0
    }

    pub fn name(&self) -> &str {
        &self.0.name
    }

    pub fn players(&self) -> u8 {
        self.0.players_per_team
    }

    pub fn half_length(&self) -> f64 {
        self.0.length / 2.0
    }

    pub fn half_width(&self) -> f64 {
        self.0.width / 2.0
    }

    pub fn goal_half_width(&self) -> f64 {
        self.0.goal_width / 2.0
    }

    pub fn contains(&self, p: Vec2) -> bool {
        self.0.contains([p.x, p.y])
    }

    pub fn clamp(&self, p: Vec2) -> Vec2 {
        let [x, y] = self.0.clamp([p.x, p.y]);
        Vec2::new(x, y)
    }

    pub fn corners(&self) -> [Vec2; 4] {
        let (x, y) = (self.half_length(), self.half_width());
        [
            Vec2::new(-x, -y),
            Vec2::new(x, -y),
            Vec2::new(x, y),
            Vec2::new(-x, y),
        ]
    }

    /// The centre of our goal line (own frame).
    pub fn own_goal(&self) -> Vec2 {
        Vec2::new(-self.half_length(), 0.0)
    }

    /// The centre of the opponents' goal line (own frame).
    pub fn opponent_goal(&self) -> Vec2 {
        Vec2::new(self.half_length(), 0.0)
    }

    /// Our goal area as (depth from the goal line, half width), where the field has one; else
    /// the penalty area.
    pub fn goal_area(&self) -> (f64, f64) {
        self.0
            .goal_area_half()
            .unwrap_or((self.0.penalty_area.depth, self.0.penalty_area.width / 2.0))
    }
}

impl Default for Field {
    fn default() -> Self {
        Field::by_name("fifa7vs7").expect("the fifa7vs7 field is shipped")
    }
}
