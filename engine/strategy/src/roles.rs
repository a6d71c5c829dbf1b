//! Roles by optimal assignment: each cycle the formation's field positions go to the field
//! players so that the sum of squared walking distances is least (the Hungarian method), with
//! hysteresis so that roles do not flicker; the goalkeeper keeps its role. Every player
//! computes the same assignment from the same inputs (its own position and its teammates', seen
//! or heard), so all agree without a leader.

use libero_world::Own;
use pathfinding::prelude::{kuhn_munkres_min, Matrix};

/// A field player the assignment places: its number and where it is.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Candidate {
    pub unum: u8,
    pub at: Own,
}

/// A formation role to fill: the number that holds it by default and its position.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Slot {
    pub default_unum: u8,
    pub at: Own,
}

/// Costs are squared distances in cm² (the method needs integers).
fn cost(from: Own, to: Own) -> i64 {
    let d = from.distance(to) * 100.0;
    (d * d).round() as i64
}

/// The assignment: for each candidate (in order), the index of its slot. Candidates and slots
/// must be as many; otherwise every candidate keeps its default slot where it has one.
pub fn assign(candidates: &[Candidate], slots: &[Slot]) -> Option<Vec<usize>> {
    if candidates.is_empty() || candidates.len() != slots.len() {
        return None;
    }
    let weights = Matrix::from_fn(candidates.len(), slots.len(), |(i, j)| {
        cost(candidates[i].at, slots[j].at)
    });
    Some(kuhn_munkres_min(&weights).1)
}

/// The total cost of an assignment.
pub fn total_cost(candidates: &[Candidate], slots: &[Slot], assignment: &[usize]) -> i64 {
    candidates
        .iter()
        .zip(assignment)
        .map(|(c, &j)| slots.get(j).map_or(i64::MAX / 64, |s| cost(c.at, s.at)))
        .sum()
}

/// The assignment kept from one cycle to the next: a new optimum replaces it only when it
/// saves more than `hysteresis_m2` of summed squared distance (a robot wobbling between two
/// equally good swaps does not swap every cycle).
#[derive(Debug, Clone, Default)]
pub struct RoleAssignment {
    /// (unum, slot's default unum) of the last assignment.
    held: Vec<(u8, u8)>,
}

impl RoleAssignment {
    /// This cycle's assignment as (player unum → default unum of its slot).
    pub fn update(
        &mut self,
        candidates: &[Candidate],
        slots: &[Slot],
        hysteresis_m2: f64,
    ) -> &[(u8, u8)] {
        let Some(best) = assign(candidates, slots) else {
            self.held = candidates.iter().map(|c| (c.unum, c.unum)).collect();
            return &self.held;
        };
        let kept: Option<Vec<usize>> = candidates
            .iter()
            .map(|c| {
                let (_, slot) = self.held.iter().find(|(u, _)| *u == c.unum)?;
                slots.iter().position(|s| s.default_unum == *slot)
            })
            .collect();
        let kept = kept.filter(|k| {
            let mut sorted = k.clone();
            sorted.sort_unstable();
            sorted.dedup();
            sorted.len() == k.len()
        });
        let margin = (hysteresis_m2 * 1e4).round() as i64;
        let chosen = match kept {
            Some(k)
                if total_cost(candidates, slots, &k)
                    <= total_cost(candidates, slots, &best) + margin =>
            {
                k
            }
            _ => best,
        };
        self.held = candidates
            .iter()
            .zip(&chosen)
            .map(|(c, &j)| (c.unum, slots[j].default_unum))
            .collect();
        &self.held
    }

    /// The default unum of the slot `unum` holds.
    pub fn slot_of(&self, unum: u8) -> Option<u8> {
        self.held.iter().find(|(u, _)| *u == unum).map(|(_, s)| *s)
    }
}

#[cfg(test)]
mod tests;
