//! Field geometry for position checks.

use crate::value::Vec2;
use serde::Serialize;

/// A pitch as rcssservermj defines it, in the team's own frame (own goal at −x).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Field {
    pub name: &'static str,
    pub length: f64,
    pub width: f64,
    pub goal_width: f64,
    pub players: u8,
}

impl Field {
    pub const FIFA_7VS7: Field = Field {
        name: "fifa7vs7",
        length: 55.0,
        width: 36.0,
        goal_width: 5.0,
        players: 7,
    };
    pub const FIFA: Field = Field {
        name: "fifa",
        length: 105.0,
        width: 68.0,
        goal_width: 7.32,
        players: 11,
    };
    pub const ALL: [Field; 2] = [Field::FIFA_7VS7, Field::FIFA];

    pub fn by_name(name: &str) -> Option<Field> {
        Self::ALL.into_iter().find(|f| f.name == name)
    }

    pub fn half_length(&self) -> f64 {
        self.length / 2.0
    }

    pub fn half_width(&self) -> f64 {
        self.width / 2.0
    }

    pub fn contains(&self, p: Vec2) -> bool {
        p.x.abs() <= self.half_length() + 1e-9 && p.y.abs() <= self.half_width() + 1e-9
    }

    pub fn clamp(&self, p: Vec2) -> Vec2 {
        Vec2::new(
            p.x.clamp(-self.half_length(), self.half_length()),
            p.y.clamp(-self.half_width(), self.half_width()),
        )
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

    pub fn own_goal(&self) -> Vec2 {
        Vec2::new(-self.half_length(), 0.0)
    }
}

impl Default for Field {
    fn default() -> Self {
        Field::FIFA_7VS7
    }
}
