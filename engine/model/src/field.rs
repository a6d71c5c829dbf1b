//! Field geometry as RON data: dimensions, and the true positions of every landmark a server reports.
//!
//! All coordinates are in the server's global frame: origin at the centre spot on the ground, +x
//! towards the right goal, +y left of +x, +z up, metres.

use crate::data::{self, DataFile};
use crate::location::{Located, SourceLocation};
use serde::{Deserialize, Serialize};
use std::collections::HashSet;
use std::path::Path;

/// One point landmark (flag, goal post top, line junction) as the server names it in vision.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Landmark {
    pub name: String,
    /// True position (x, y, z) [m]. Where the server places a marker somewhere else than the
    /// field drawing says, this is where the server puts it.
    pub position: [f64; 3],
}

/// A straight field line segment on the ground, from `begin` to `end` (x, y) [m].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FieldLine {
    pub begin: [f64; 2],
    pub end: [f64; 2],
}

/// A rectangular box in front of a goal, given as depth from the goal line × total width.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AreaSize {
    pub depth: f64,
    pub width: f64,
}

/// A complete field description.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FieldGeometry {
    pub name: String,
    /// Goal line to goal line (x extent) [m].
    pub length: f64,
    /// Touchline to touchline (y extent) [m].
    pub width: f64,
    /// Inner width of the goal mouth [m].
    pub goal_width: f64,
    pub goal_height: f64,
    pub goal_depth: f64,
    pub centre_circle_radius: f64,
    /// Distance of the penalty mark from the goal line, where there is one.
    #[serde(default)]
    pub penalty_mark_distance: Option<f64>,
    /// Goal area (goalie box), where the field has one.
    #[serde(default)]
    pub goal_area: Option<AreaSize>,
    pub penalty_area: AreaSize,
    /// Playable ground outside the lines [m].
    pub border: f64,
    pub ball_radius: f64,
    /// Players per team the server admits on this field.
    pub players_per_team: u8,
    pub landmarks: Vec<Landmark>,
    /// Line segments as the server reports them (SimSpark), empty where it does not.
    #[serde(default)]
    pub lines: Vec<FieldLine>,
}

/// Why a field could not be used.
pub type FieldError = crate::data::DataError;

const BUILTIN: &[(&str, &str)] = &[
    ("fifa7vs7", include_str!("../fields/fifa7vs7.ron")),
    ("fifa", include_str!("../fields/fifa.ron")),
    ("simspark", include_str!("../fields/simspark.ron")),
];

impl FieldGeometry {
    pub fn builtin_names() -> Vec<&'static str> {
        data::builtin_names::<Self>()
    }

    /// A shipped field by name (case-insensitive): `fifa7vs7`, `fifa`, `simspark`.
    pub fn builtin(name: &str) -> Result<Self, FieldError> {
        data::builtin(name)
    }

    pub fn load(path: &Path) -> Result<Self, FieldError> {
        data::load(path)
    }

    /// Parse and validate RON text; `file` names the source in error messages.
    pub fn from_ron(file: &str, text: &str) -> Result<Self, FieldError> {
        data::from_ron(file, text)
    }

    /// Where the landmark the server calls `name` sits in [`FieldGeometry::landmarks`].
    pub fn landmark_index(&self, name: &str) -> Option<usize> {
        self.landmarks.iter().position(|l| l.name == name)
    }

    /// True position of the landmark the server calls `name`.
    pub fn landmark(&self, name: &str) -> Option<[f64; 3]> {
        self.landmarks
            .iter()
            .find(|l| l.name == name)
            .map(|l| l.position)
    }

    /// Half length and half width: the goal lines are at x = ±half_length.
    pub fn half_extent(&self) -> (f64, f64) {
        (self.length / 2.0, self.width / 2.0)
    }

    /// Whether (x, y) lies on the field, lines included (the field is symmetric, so this holds
    /// in the global frame and in either team's own frame).
    pub fn contains(&self, [x, y]: [f64; 2]) -> bool {
        let (hx, hy) = self.half_extent();
        x.abs() <= hx + 1e-9 && y.abs() <= hy + 1e-9
    }

    /// The nearest point on the field.
    pub fn clamp(&self, [x, y]: [f64; 2]) -> [f64; 2] {
        let (hx, hy) = self.half_extent();
        [x.clamp(-hx, hx), y.clamp(-hy, hy)]
    }

    /// Half the goal area's width and its depth, where the field has one.
    pub fn goal_area_half(&self) -> Option<(f64, f64)> {
        self.goal_area.map(|a| (a.depth, a.width / 2.0))
    }

    fn problems(&self, file: &str, text: &str) -> Vec<Located> {
        let mut errors = Vec::new();
        let mut report = |needle: &str, message: String| {
            errors.push(Located {
                file: file.to_string(),
                at: SourceLocation::of_first(text, needle).unwrap_or_default(),
                message,
            })
        };
        let mut sizes = vec![
            ("length", self.length),
            ("width", self.width),
            ("goal_width", self.goal_width),
            ("goal_height", self.goal_height),
            ("goal_depth", self.goal_depth),
            ("centre_circle_radius", self.centre_circle_radius),
            ("ball_radius", self.ball_radius),
            ("penalty_area", self.penalty_area.depth),
            ("penalty_area", self.penalty_area.width),
        ];
        if let Some(area) = self.goal_area {
            sizes.extend([("goal_area", area.depth), ("goal_area", area.width)]);
        }
        if let Some(d) = self.penalty_mark_distance {
            sizes.push(("penalty_mark_distance", d));
        }
        for (key, value) in sizes {
            if !(value.is_finite() && value > 0.0) {
                report(
                    key,
                    format!("`{key}` must be positive and finite, got {value}"),
                );
            }
        }
        if !(1..=22).contains(&self.players_per_team) {
            report(
                "players_per_team",
                format!(
                    "`players_per_team` must be 1 to 22, got {}",
                    self.players_per_team
                ),
            );
        }
        if !(self.border.is_finite() && self.border >= 0.0) {
            report("border", "`border` must be finite and not negative".into());
        }
        if self.goal_width >= self.width || self.penalty_area.width > self.width {
            report(
                "goal_width",
                "goal and penalty area must be narrower than the field".into(),
            );
        }
        let (hx, hy) = self.half_extent();
        // Generous on purpose: the rcssservermj fifa field really has penalty-area markers at
        // |y| = 40.32, beyond its 34 m half width. This catches unit and sign slips, not oddities.
        let reach = (2.0 * hx, 2.0 * hy);
        let mut names = HashSet::new();
        for landmark in &self.landmarks {
            let here = format!("\"{}\"", landmark.name);
            if !names.insert(landmark.name.as_str()) {
                report(
                    &here,
                    format!("landmark `{}` is listed twice", landmark.name),
                );
            }
            let [x, y, z] = landmark.position;
            let finite = landmark.position.iter().all(|v| v.is_finite());
            if !finite || x.abs() > reach.0 || y.abs() > reach.1 || !(0.0..=10.0).contains(&z) {
                report(
                    &here,
                    format!(
                        "landmark `{}` at {:?} is not finite or lies far off the field",
                        landmark.name, landmark.position
                    ),
                );
            }
        }
        for (i, line) in self.lines.iter().enumerate() {
            let inside = line
                .begin
                .iter()
                .chain(&line.end)
                .zip([hx, hy, hx, hy])
                .all(|(v, half)| v.is_finite() && v.abs() <= half + 1e-9);
            if !inside {
                report(
                    "lines",
                    format!("line {} leaves the field: {line:?}", i + 1),
                );
            }
        }
        errors
    }
}

impl DataFile for FieldGeometry {
    const KIND: &'static str = "field";
    const BUILTIN: &'static [(&'static str, &'static str)] = BUILTIN;

    fn problems(&self, file: &str, text: &str) -> Vec<Located> {
        FieldGeometry::problems(self, file, text)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_builtin_field_loads() {
        for name in FieldGeometry::builtin_names() {
            FieldGeometry::builtin(name).unwrap_or_else(|e| panic!("{name}: {e}"));
        }
    }

    #[test]
    fn rcssservermj_fields_keep_the_servers_misplaced_area_markers() {
        let small = FieldGeometry::builtin("fifa7vs7").unwrap();
        // The server uses the full area width as half-width (rcssservermj.md §7).
        assert_eq!(small.landmark("l_luga"), Some([-23.5, 7.3, 0.0]));
        assert_eq!(small.landmark("t_rlpa"), Some([27.5, -16.5, 0.0]));
        assert_eq!(small.goal_area.unwrap().width, 7.3);
        let big = FieldGeometry::builtin("fifa").unwrap();
        assert_eq!(big.landmark("l_rupa"), Some([36.0, 40.32, 0.0]));
        assert_eq!(big.landmark("g_llp"), Some([-52.5, -3.66, 2.44]));
        assert_eq!(big.landmark("p_rpm"), Some([41.5, 0.0, 0.0]));
        for field in [&small, &big] {
            assert_eq!(field.landmarks.len(), 30, "{}", field.name);
        }
    }

    #[test]
    fn simspark_has_flags_posts_and_21_lines() {
        let field = FieldGeometry::builtin("simspark").unwrap();
        assert_eq!(field.landmark("F2R"), Some([15.0, -10.0, 0.0]));
        assert_eq!(field.landmark("G1L"), Some([-15.0, 1.05, 0.8]));
        assert_eq!(field.lines.len(), 21);
        assert_eq!(field.half_extent(), (15.0, 10.0));
        assert_eq!(field.ball_radius, 0.042);
    }

    #[test]
    fn invalid_fields_are_rejected_with_locations() {
        let text = include_str!("../fields/simspark.ron")
            .replacen("length: 30.0", "length: -30.0", 1)
            .replacen("\"F1R\"", "\"F1L\"", 1);
        let Err(FieldError::Invalid(errors)) = FieldGeometry::from_ron("simspark.ron", &text)
        else {
            panic!("accepted");
        };
        assert!(errors
            .iter()
            .any(|e| e.message.contains("`length` must be positive")));
        assert!(errors
            .iter()
            .any(|e| e.message.contains("`F1L` is listed twice")));
        assert!(errors.iter().all(|e| e.at.line > 1), "{errors:?}");
    }
}
