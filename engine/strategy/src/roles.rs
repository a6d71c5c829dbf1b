//! Roles by optimal assignment: each cycle the formation's field positions go to the field
//! players so that the sum of squared walking distances is least (the Hungarian method), with
//! hysteresis so that roles do not flicker; the goalkeeper keeps its role. Every player
//! computes the same assignment from the same inputs (its own position and its teammates', seen
//! or heard), so all agree without a leader.

use arrayvec::ArrayVec;
use libero_world::Own;

/// The most field players an assignment places (SimSpark's 11 a side).
pub const MAX_PLAYERS: usize = 11;

/// One slot index per candidate, in candidate order.
pub type Assignment = ArrayVec<usize, MAX_PLAYERS>;

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
/// must be as many (and at most [`MAX_PLAYERS`]); otherwise there is none.
///
/// The Hungarian method with potentials (O(n³), n ≤ 11), on the stack: it runs every cycle,
/// and the general-purpose solvers allocate their matrices.
pub fn assign(candidates: &[Candidate], slots: &[Slot]) -> Option<Assignment> {
    let n = candidates.len();
    if n == 0 || n != slots.len() || n > MAX_PLAYERS {
        return None;
    }
    const N: usize = MAX_PLAYERS + 1;
    let cost_of = |i: usize, j: usize| cost(candidates[i - 1].at, slots[j - 1].at);
    // Rows are candidates, columns slots, both from 1; column 0 is the virtual start.
    let (mut row_potential, mut col_potential) = ([0i64; N], [0i64; N]);
    // The row matched to each column (0: none), and the column each was reached from.
    let (mut matched_row, mut came_from) = ([0usize; N], [0usize; N]);
    for row in 1..=n {
        matched_row[0] = row;
        let mut col = 0;
        let mut least = [i64::MAX; N];
        let mut used = [false; N];
        loop {
            used[col] = true;
            let i = matched_row[col];
            let (mut delta, mut next) = (i64::MAX, 0);
            for j in 1..=n {
                if used[j] {
                    continue;
                }
                let reduced = cost_of(i, j) - row_potential[i] - col_potential[j];
                if reduced < least[j] {
                    least[j] = reduced;
                    came_from[j] = col;
                }
                if least[j] < delta {
                    delta = least[j];
                    next = j;
                }
            }
            for j in 0..=n {
                if used[j] {
                    row_potential[matched_row[j]] += delta;
                    col_potential[j] -= delta;
                } else {
                    least[j] -= delta;
                }
            }
            col = next;
            if matched_row[col] == 0 {
                break;
            }
        }
        // Flip the augmenting path back to the start.
        while col != 0 {
            let previous = came_from[col];
            matched_row[col] = matched_row[previous];
            col = previous;
        }
    }
    let mut slot_of = [0usize; N];
    for j in 1..=n {
        slot_of[matched_row[j]] = j - 1;
    }
    Some(slot_of[1..=n].iter().copied().collect())
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
    held: ArrayVec<(u8, u8), MAX_PLAYERS>,
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
            self.held = candidates
                .iter()
                .take(MAX_PLAYERS)
                .map(|c| (c.unum, c.unum))
                .collect();
            return &self.held;
        };
        let kept: Option<Assignment> = candidates
            .iter()
            .map(|c| {
                let (_, slot) = self.held.iter().find(|(u, _)| *u == c.unum)?;
                slots.iter().position(|s| s.default_unum == *slot)
            })
            .collect();
        let kept = kept.filter(|k| {
            let mut sorted = k.clone();
            sorted.sort_unstable();
            sorted.windows(2).all(|w| w[0] != w[1])
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
