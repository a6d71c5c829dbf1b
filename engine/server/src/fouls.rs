//! The fouls SimSpark's referee calls, as its monitor stream reports them: `(foul INDEX TYPE
//! TEAM UNUM)` among a frame's game-state items, each sent once (simspark.md §5.9). Kept
//! bounded whatever a match produces: counts by team, uniform number and kind, and the most
//! recent fouls with their play time.

use std::collections::VecDeque;

/// The kinds by their TYPE number (`soccerruleaspect.h`).
pub const FOUL_KINDS: [&str; 8] = [
    "crowding",
    "touching",
    "illegal defence",
    "illegal attack",
    "incapable",
    "kick-off",
    "charging",
    "self-collision",
];

/// Uniform numbers counted (SimSpark's teams have at most 11 players).
const UNUMS: usize = 12;
/// The most recent fouls kept with their times.
pub const RECENT_FOULS: usize = 256;
/// Calls of one kind on one player this close together [s] are one foul.
const SAME_FOUL_S: f64 = 1.0;

/// One foul the referee called.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Foul {
    /// Play time [s] of the frame that reported it.
    pub time: f64,
    pub left: bool,
    pub unum: u32,
    pub kind: &'static str,
    /// Play time [s] of the last call that belonged to this foul.
    last_call: f64,
}

/// Fouls so far: exact counts, and the last [`RECENT_FOULS`] with their times.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct FoulTally {
    counts: [[[u32; FOUL_KINDS.len()]; UNUMS]; 2],
    recent: VecDeque<Foul>,
    last_index: Option<i64>,
}

impl FoulTally {
    /// Record a `(foul INDEX TYPE TEAM UNUM)` item's numbers, reported at play time `time`.
    /// A repeated or older index, an unknown kind or team, or a uniform number out of range
    /// is ignored (and said so by the result).
    pub fn record(&mut self, time: f64, [index, kind, team, unum]: [f64; 4]) -> bool {
        let index = index as i64;
        let kind = kind as usize;
        let unum_slot = unum as usize;
        let left = match team as i64 {
            1 => true,
            2 => false,
            _ => return false,
        };
        if self.last_index.is_some_and(|last| index <= last)
            || kind >= FOUL_KINDS.len()
            || unum < 1.0
            || unum_slot >= UNUMS
        {
            return false;
        }
        self.last_index = Some(index);
        // The referee calls a foul again every cycle it goes on (an incapable robot held in
        // the air: ~25 calls in 0.5 s) and once per limb (a self-collision of an arm and a leg:
        // two): calls of one kind on one player within `SAME_FOUL_S` are one foul.
        let latest =
            self.recent.iter_mut().rev().find(|f| {
                f.left == left && f.unum == unum_slot as u32 && f.kind == FOUL_KINDS[kind]
            });
        if let Some(f) = latest.filter(|f| (time - f.last_call).abs() <= SAME_FOUL_S) {
            f.last_call = time;
            return true;
        }
        self.counts[usize::from(!left)][unum_slot][kind] += 1;
        if self.recent.len() == RECENT_FOULS {
            self.recent.pop_front();
        }
        self.recent.push_back(Foul {
            time,
            left,
            unum: unum_slot as u32,
            kind: FOUL_KINDS[kind],
            last_call: time,
        });
        true
    }

    /// One side's counts: (uniform number, kind, count), by number then kind, zeros left out.
    pub fn counts(&self, left: bool) -> Vec<(u32, &'static str, u32)> {
        let side = &self.counts[usize::from(!left)];
        let mut out = Vec::new();
        for (unum, kinds) in side.iter().enumerate() {
            for (kind, &count) in kinds.iter().enumerate() {
                if count > 0 {
                    out.push((unum as u32, FOUL_KINDS[kind], count));
                }
            }
        }
        out
    }

    /// One side's most recent fouls, oldest first.
    pub fn recent(&self, left: bool) -> impl Iterator<Item = &Foul> {
        self.recent.iter().filter(move |f| f.left == left)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fouls_are_counted_once_by_side_player_and_kind() {
        let mut tally = FoulTally::default();
        assert!(tally.record(10.0, [0.0, 4.0, 1.0, 6.0]));
        assert!(tally.record(12.5, [1.0, 6.0, 2.0, 3.0]));
        assert!(tally.record(20.0, [2.0, 4.0, 1.0, 6.0]));
        // Called again every cycle while it lasts: still one foul.
        assert!(tally.record(20.02, [3.0, 4.0, 1.0, 6.0]));
        assert!(tally.record(20.5, [4.0, 4.0, 1.0, 6.0]));
        // The same index again (a resent item) and nonsense are not counted.
        assert!(!tally.record(20.6, [4.0, 4.0, 1.0, 6.0]));
        assert!(!tally.record(21.0, [5.0, 9.0, 1.0, 6.0]));
        assert!(!tally.record(21.0, [6.0, 4.0, 3.0, 6.0]));
        assert!(!tally.record(21.0, [7.0, 4.0, 1.0, 40.0]));
        assert_eq!(tally.counts(true), vec![(6, "incapable", 2)]);
        assert_eq!(tally.counts(false), vec![(3, "charging", 1)]);
        let times: Vec<f64> = tally.recent(true).map(|f| f.time).collect();
        assert_eq!(times, vec![10.0, 20.0]);
    }

    #[test]
    fn the_recent_fouls_stay_bounded_and_the_counts_exact() {
        let mut tally = FoulTally::default();
        for i in 0..(RECENT_FOULS as i64 + 100) {
            tally.record(2.0 * i as f64, [i as f64, 7.0, 1.0, 2.0]);
        }
        assert_eq!(tally.recent(true).count(), RECENT_FOULS);
        assert_eq!(tally.recent(true).next().unwrap().time, 200.0);
        assert_eq!(
            tally.counts(true),
            vec![(2, "self-collision", RECENT_FOULS as u32 + 100)]
        );
    }
}
