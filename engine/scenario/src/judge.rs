//! Deciding a run from the server's ground truth, cycle by cycle.
//!
//! Each leaf condition latches: a goal, a reached ball or a collision cannot be undone. Some
//! conditions are *invariants* (`BallKeptOut`, `NoCollision`): they hold until broken, so
//! they never end a run by themselves but count as met when it ends. `All` succeeds once every
//! part has succeeded or still holds (at least one having succeeded); `Any` once one part has.
//! At the time limit, or when play stops (a goal, the ball out of play), holding conditions
//! succeed and pending ones fail.

use crate::pass_judge::PassTrack;
use crate::shot_judge::{GoalMouth, ShotTrack};
use crate::spec::Success;
use libero_world::params::BallParams;

/// What the ground truth shows at one moment.
#[derive(Debug, Clone, Default)]
pub struct Observation {
    /// Seconds since the launch.
    pub t: f64,
    /// Ball centre [m], global frame.
    pub ball: Option<[f64; 3]>,
    /// Our robots' torso positions (x, y) [m] by uniform number.
    pub ours: Vec<(u32, [f64; 2])>,
    pub theirs: Vec<(u32, [f64; 2])>,
    /// Goals since the launch.
    pub goals_for: u32,
    pub goals_against: u32,
}

impl Observation {
    /// One of our torsos within reach of the ball (ground plane).
    pub fn ours_touch_ball(&self) -> bool {
        self.ball.is_some_and(|b| {
            self.ours
                .iter()
                .any(|(_, p)| (b[0] - p[0]).hypot(b[1] - p[1]) <= crate::pass_judge::TOUCH_M)
        })
    }
}

/// The state of a condition.
#[derive(Debug, Clone, PartialEq)]
pub enum Verdict {
    /// Not decided yet and not met if the run ended now.
    Pending,
    /// Not broken so far: met if the run ended now.
    Holding,
    Succeeded {
        t: f64,
    },
    Failed {
        t: f64,
        why: String,
    },
}

impl Verdict {
    pub fn decided(&self) -> bool {
        matches!(self, Verdict::Succeeded { .. } | Verdict::Failed { .. })
    }
}

enum Node {
    Leaf {
        condition: Success,
        state: Verdict,
        /// The ball model's view of a pass or a shot (`PassReceived`, `ShotOnTarget`).
        track: Option<Track>,
    },
    All(Vec<Node>),
    Any(Vec<Node>),
}

enum Track {
    Pass(Box<PassTrack>),
    Shot(Box<ShotTrack>),
}

/// A run's judge: feed it observations, read the verdict.
pub struct Judge {
    root: Node,
    /// Where the ball was at the launch.
    ball_start: Option<[f64; 2]>,
    /// Closest approach of two torsos so far [m], and who.
    pub closest: Option<(f64, String)>,
}

impl Judge {
    /// A judge of `success`; `ball` is the world model's ball (a pass's stop point is its
    /// prediction), `goal` the one our team attacks.
    pub fn new(success: &Success, ball: &BallParams, goal: GoalMouth) -> Self {
        Self {
            root: build(success, ball, goal),
            ball_start: None,
            closest: None,
        }
    }

    /// Take one observation into account.
    pub fn observe(&mut self, o: &Observation) {
        if self.ball_start.is_none() {
            self.ball_start = o.ball.map(|b| [b[0], b[1]]);
        }
        let pair = closest_pair(o);
        if let Some((gap, ref who)) = pair {
            if self.closest.as_ref().is_none_or(|(g, _)| gap < *g) {
                self.closest = Some((gap, who.clone()));
            }
        }
        let start = self.ball_start;
        visit(&mut self.root, &mut |condition, state, track| {
            if state.decided() {
                return;
            }
            *state = match (condition, track) {
                (Success::PassReceived { receiver, within_m }, Some(Track::Pass(track))) => {
                    track.observe(o, *receiver, *within_m, state)
                }
                (Success::ShotOnTarget { min_m }, Some(Track::Shot(track))) => {
                    track.observe(o, *min_m, state)
                }
                _ => leaf(condition, state, o, start, pair.as_ref()),
            };
        });
    }

    pub fn verdict(&self) -> Verdict {
        combine(&self.root)
    }

    /// The run ends at `t` (time limit, or play stopped): holding conditions are met, pending
    /// ones are not.
    pub fn finish(&mut self, t: f64, reason: &str) -> Verdict {
        visit(&mut self.root, &mut |condition, state, _| match state {
            Verdict::Holding => *state = Verdict::Succeeded { t },
            Verdict::Pending => {
                *state = Verdict::Failed {
                    t,
                    why: format!("{} not met when {reason}", condition.describe()),
                }
            }
            _ => {}
        });
        self.verdict()
    }
}

fn build(s: &Success, ball: &BallParams, goal: GoalMouth) -> Node {
    let parts = |parts: &[Success]| parts.iter().map(|p| build(p, ball, goal)).collect();
    match s {
        Success::All(p) => Node::All(parts(p)),
        Success::Any(p) => Node::Any(parts(p)),
        leaf => Node::Leaf {
            condition: leaf.clone(),
            state: match leaf {
                Success::BallKeptOut | Success::NoCollision { .. } => Verdict::Holding,
                _ => Verdict::Pending,
            },
            track: match leaf {
                Success::PassReceived { .. } => Some(Track::Pass(Box::new(PassTrack::new(ball)))),
                Success::ShotOnTarget { .. } => Some(Track::Shot(Box::new(ShotTrack::new(goal)))),
                _ => None,
            },
        },
    }
}

fn visit(node: &mut Node, f: &mut impl FnMut(&Success, &mut Verdict, Option<&mut Track>)) {
    match node {
        Node::Leaf {
            condition,
            state,
            track,
        } => f(condition, state, track.as_mut()),
        Node::All(parts) | Node::Any(parts) => parts.iter_mut().for_each(|p| visit(p, f)),
    }
}

fn leaf(
    condition: &Success,
    state: &Verdict,
    o: &Observation,
    ball_start: Option<[f64; 2]>,
    pair: Option<&(f64, String)>,
) -> Verdict {
    let t = o.t;
    match condition {
        Success::GoalScored if o.goals_for > 0 => Verdict::Succeeded { t },
        Success::BallKeptOut if o.goals_against > 0 => Verdict::Failed {
            t,
            why: format!("goal against at {t:.2} s"),
        },
        Success::BallReached { unum, within_m } => {
            let reached = o
                .ball
                .zip(o.ours.iter().find(|(u, _)| u == unum))
                .is_some_and(|(b, (_, p))| (b[0] - p[0]).hypot(b[1] - p[1]) <= *within_m);
            if reached {
                Verdict::Succeeded { t }
            } else {
                state.clone()
            }
        }
        Success::BallMoved { min_m } => {
            let moved = o
                .ball
                .zip(ball_start)
                .is_some_and(|(b, s)| (b[0] - s[0]).hypot(b[1] - s[1]) >= *min_m);
            if moved {
                Verdict::Succeeded { t }
            } else {
                state.clone()
            }
        }
        Success::NoCollision { min_distance_m } => match pair {
            Some((gap, who)) if gap < min_distance_m => Verdict::Failed {
                t,
                why: format!("{who} {gap:.2} m apart at {t:.2} s"),
            },
            _ => state.clone(),
        },
        _ => state.clone(),
    }
}

fn combine(node: &Node) -> Verdict {
    match node {
        Node::Leaf { state, .. } => state.clone(),
        Node::All(parts) => {
            let verdicts: Vec<Verdict> = parts.iter().map(combine).collect();
            if let Some(failed) = verdicts
                .iter()
                .filter(|v| matches!(v, Verdict::Failed { .. }))
                .min_by(|a, b| time(a).total_cmp(&time(b)))
            {
                return failed.clone();
            }
            if verdicts.contains(&Verdict::Pending) {
                return Verdict::Pending;
            }
            let succeeded: Vec<f64> = verdicts
                .iter()
                .filter(|v| matches!(v, Verdict::Succeeded { .. }))
                .map(time)
                .collect();
            match succeeded.iter().copied().reduce(f64::max) {
                Some(t) => Verdict::Succeeded { t },
                None => Verdict::Holding,
            }
        }
        Node::Any(parts) => {
            let verdicts: Vec<Verdict> = parts.iter().map(combine).collect();
            if let Some(t) = verdicts
                .iter()
                .filter(|v| matches!(v, Verdict::Succeeded { .. }))
                .map(time)
                .reduce(f64::min)
            {
                return Verdict::Succeeded { t };
            }
            if verdicts.contains(&Verdict::Holding) {
                return Verdict::Holding;
            }
            if verdicts.contains(&Verdict::Pending) {
                return Verdict::Pending;
            }
            // Every part failed: the last failure decides.
            verdicts
                .into_iter()
                .max_by(|a, b| time(a).total_cmp(&time(b)))
                .unwrap_or(Verdict::Pending)
        }
    }
}

fn time(v: &Verdict) -> f64 {
    match v {
        Verdict::Succeeded { t } | Verdict::Failed { t, .. } => *t,
        _ => f64::INFINITY,
    }
}

/// The two torsos closest to each other of the pairs with one of ours in them (how close
/// their robots stand to each other is not ours to judge), with names for messages.
fn closest_pair(o: &Observation) -> Option<(f64, String)> {
    let all: Vec<(String, [f64; 2])> = o
        .ours
        .iter()
        .map(|(u, p)| (format!("our {u}"), *p))
        .chain(o.theirs.iter().map(|(u, p)| (format!("their {u}"), *p)))
        .collect();
    let mut best: Option<(f64, String)> = None;
    for (i, (a, pa)) in all.iter().enumerate().take(o.ours.len()) {
        for (b, pb) in &all[i + 1..] {
            let gap = (pa[0] - pb[0]).hypot(pa[1] - pb[1]);
            if best.as_ref().is_none_or(|(g, _)| gap < *g) {
                best = Some((gap, format!("{a} and {b}")));
            }
        }
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;

    fn obs(t: f64) -> Observation {
        Observation {
            t,
            ball: Some([0.0, 0.0, 0.11]),
            ours: vec![(9, [3.0, 0.0])],
            theirs: vec![(1, [5.0, 0.0])],
            ..Observation::default()
        }
    }

    fn judge(s: &Success) -> Judge {
        Judge::new(
            s,
            &libero_world::WorldParams::builtin().ball,
            GoalMouth {
                line_x: 27.5,
                half_width: 1.83,
            },
        )
    }

    #[test]
    fn kept_out_holds_until_the_end_and_fails_on_a_goal() {
        let mut j = judge(&Success::BallKeptOut);
        j.observe(&obs(1.0));
        assert_eq!(j.verdict(), Verdict::Holding);
        assert_eq!(j.finish(8.0, "time ran out"), Verdict::Succeeded { t: 8.0 });
        let mut j = judge(&Success::BallKeptOut);
        let mut o = obs(2.5);
        o.goals_against = 1;
        j.observe(&o);
        assert!(matches!(j.verdict(), Verdict::Failed { t, .. } if t == 2.5));
    }

    #[test]
    fn all_ends_when_the_goal_parts_succeed_and_invariants_still_hold() {
        let s = Success::All(vec![
            Success::BallReached {
                unum: 9,
                within_m: 0.5,
            },
            Success::NoCollision {
                min_distance_m: 0.45,
            },
        ]);
        let mut j = judge(&s);
        j.observe(&obs(1.0));
        assert_eq!(j.verdict(), Verdict::Pending);
        let mut o = obs(2.0);
        o.ours = vec![(9, [0.3, 0.0])];
        j.observe(&o);
        assert_eq!(j.verdict(), Verdict::Succeeded { t: 2.0 });
        // A collision fails it.
        let mut j = judge(&s);
        let mut o = obs(1.5);
        o.ours = vec![(9, [4.7, 0.0])];
        j.observe(&o);
        assert!(matches!(j.verdict(), Verdict::Failed { ref why, .. } if why.contains("their 1")));
    }

    #[test]
    fn any_succeeds_at_the_first_part_and_pending_parts_fail_at_the_end() {
        let s = Success::Any(vec![Success::GoalScored, Success::BallMoved { min_m: 2.0 }]);
        let mut j = judge(&s);
        j.observe(&obs(0.0));
        let mut o = obs(3.0);
        o.ball = Some([2.5, 0.0, 0.11]);
        j.observe(&o);
        assert_eq!(j.verdict(), Verdict::Succeeded { t: 3.0 });
        let mut j = judge(&Success::GoalScored);
        j.observe(&obs(0.0));
        assert!(matches!(j.finish(20.0, "time ran out"), Verdict::Failed { t, .. } if t == 20.0));
    }
}
