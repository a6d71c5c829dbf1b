//! Other robots: teammates and opponents from the body parts vision reports (`head`, `lfoot`,
//! `rfoot`, SimSpark also `llowerarm`/`rlowerarm`), remembered with their age when out of view,
//! and updatable from what teammates say.

use crate::params::PlayerParams;
use nalgebra::{Point3, Vector3};

/// Whose side a player is on, relative to us.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
pub enum Relation {
    Teammate,
    Opponent,
}

/// Where the latest information about a player came from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub enum Source {
    Vision,
    /// A message from a teammate.
    Heard,
}

/// One other robot (global field frame).
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct PlayerEstimate {
    pub relation: Relation,
    pub unum: u32,
    /// Ground position [m]: between the feet when both are seen, else below the head.
    pub position: [f64; 2],
    /// Facing direction [deg] from the feet (left foot is on its left), when both feet are seen.
    pub heading_deg: Option<f64>,
    /// Height of the head marker [m], when seen.
    pub head_height: Option<f64>,
    /// Lying on the ground (head marker low).
    pub fallen: bool,
    /// Simulation time of the latest information.
    pub last_update_time: f64,
    pub source: Source,
}

impl PlayerEstimate {
    /// Seconds since the latest information.
    pub fn age(&self, now: f64) -> f64 {
        now - self.last_update_time
    }
}

/// Everyone we have seen or heard of, except ourselves.
#[derive(Debug, Clone, Default)]
pub struct Players {
    pub known: Vec<PlayerEstimate>,
}

/// The seen parts of one robot, already in the field frame.
#[derive(Debug, Clone, Copy, Default)]
pub struct SeenParts {
    pub head: Option<Vector3<f64>>,
    pub left_foot: Option<Vector3<f64>>,
    pub right_foot: Option<Vector3<f64>>,
}

impl Players {
    pub fn get(&self, relation: Relation, unum: u32) -> Option<&PlayerEstimate> {
        self.known
            .iter()
            .find(|p| p.relation == relation && p.unum == unum)
    }

    /// Players of one side.
    pub fn of(&self, relation: Relation) -> impl Iterator<Item = &PlayerEstimate> {
        self.known.iter().filter(move |p| p.relation == relation)
    }

    /// Fold in one robot seen now.
    pub fn saw(
        &mut self,
        params: &PlayerParams,
        relation: Relation,
        unum: u32,
        parts: SeenParts,
        time: f64,
    ) {
        let feet = parts.left_foot.zip(parts.right_foot);
        let position = match (feet, parts.head, parts.left_foot.or(parts.right_foot)) {
            (Some((l, r)), _, _) => 0.5 * (l + r),
            (None, Some(head), _) => head,
            (None, None, Some(foot)) => foot,
            (None, None, None) => return,
        };
        // The left foot lies on the left of the facing direction: rotate right→left by −90°.
        let heading_deg = feet.and_then(|(l, r)| {
            let across = l.xy() - r.xy();
            (across.norm() > 0.05).then(|| across.y.atan2(across.x).to_degrees() - 90.0)
        });
        let head_height = parts.head.map(|h| h.z);
        let estimate = PlayerEstimate {
            relation,
            unum,
            position: [position.x, position.y],
            heading_deg: heading_deg.map(crate::geometry::wrap_deg),
            head_height,
            fallen: head_height.is_some_and(|h| h < params.fallen_head_height),
            last_update_time: time,
            source: Source::Vision,
        };
        if estimate.position.iter().all(|c| c.is_finite()) {
            self.upsert(estimate);
        }
    }

    /// A teammate's report (communication): only replaces older information.
    pub fn heard(
        &mut self,
        relation: Relation,
        unum: u32,
        position: [f64; 2],
        fallen: Option<bool>,
        time: f64,
    ) {
        if !position.iter().all(|c| c.is_finite()) {
            return;
        }
        let newer = self
            .get(relation, unum)
            .is_none_or(|p| p.last_update_time < time);
        if newer {
            let previous = self.get(relation, unum).cloned();
            self.upsert(PlayerEstimate {
                relation,
                unum,
                position,
                heading_deg: previous.as_ref().and_then(|p| p.heading_deg),
                head_height: None,
                fallen: fallen.unwrap_or_else(|| previous.is_some_and(|p| p.fallen)),
                last_update_time: time,
                source: Source::Heard,
            });
        }
    }

    /// Drop players we have had no news of for too long.
    pub fn forget_old(&mut self, params: &PlayerParams, now: f64) {
        self.known
            .retain(|p| now - p.last_update_time <= params.forget_after_s);
    }

    fn upsert(&mut self, estimate: PlayerEstimate) {
        match self
            .known
            .iter_mut()
            .find(|p| p.relation == estimate.relation && p.unum == estimate.unum)
        {
            Some(slot) => *slot = estimate,
            None => self.known.push(estimate),
        }
    }
}

/// Turn camera-frame parts into field-frame parts with `to_field`.
pub fn parts_in_field(
    parts: &[libero_protocol::percept::Seen<'_>],
    to_field: impl Fn(&Point3<f64>) -> Option<Vector3<f64>>,
) -> SeenParts {
    let mut out = SeenParts::default();
    for part in parts {
        let Some(p) = crate::geometry::polar_to_point(&part.at).and_then(|p| to_field(&p)) else {
            continue;
        };
        match part.name {
            "head" => out.head = Some(p),
            "lfoot" => out.left_foot = Some(p),
            "rfoot" => out.right_foot = Some(p),
            _ => {}
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::params::WorldParams;

    #[test]
    fn position_heading_and_posture_from_parts() {
        let params = WorldParams::builtin().players;
        let mut players = Players::default();
        // Facing +y: its left foot is at −x.
        let parts = SeenParts {
            head: Some(Vector3::new(2.0, 3.0, 1.2)),
            left_foot: Some(Vector3::new(1.9, 3.0, 0.04)),
            right_foot: Some(Vector3::new(2.1, 3.0, 0.04)),
        };
        players.saw(&params, Relation::Opponent, 4, parts, 10.0);
        let p = players.get(Relation::Opponent, 4).unwrap();
        assert!((p.position[0] - 2.0).abs() < 1e-9 && (p.position[1] - 3.0).abs() < 1e-9);
        assert!((p.heading_deg.unwrap() - 90.0).abs() < 1e-9);
        assert!(!p.fallen);
        let lying = SeenParts {
            head: Some(Vector3::new(2.0, 4.0, 0.15)),
            ..Default::default()
        };
        players.saw(&params, Relation::Opponent, 4, lying, 11.0);
        let p = players.get(Relation::Opponent, 4).unwrap();
        assert!(p.fallen && p.heading_deg.is_none());
        assert_eq!(players.known.len(), 1);
        // Older hearsay does not overwrite vision; newer does.
        players.heard(Relation::Opponent, 4, [0.0, 0.0], None, 10.5);
        assert_eq!(
            players.get(Relation::Opponent, 4).unwrap().source,
            Source::Vision
        );
        players.heard(Relation::Opponent, 4, [0.0, 0.0], None, 12.0);
        assert_eq!(
            players.get(Relation::Opponent, 4).unwrap().source,
            Source::Heard
        );
        players.forget_old(&params, 12.0 + params.forget_after_s + 1.0);
        assert!(players.known.is_empty());
    }
}
