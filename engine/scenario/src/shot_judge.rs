//! `ShotOnTarget`: a kick that sends the ball at least some distance towards their goal
//! between the posts. Where the ground truth last had the ball at rest (slower than a kick's
//! ball ever is) is where the kick began; once the ball is `min_m` from there, the line from
//! that spot through the ball must cross their goal line between the posts. A dribble's
//! pushes, which come to rest within a metre or two, never add up to one.

use crate::judge::{Observation, Verdict};
use libero_model::FieldGeometry;

/// A ball slower than this is at rest for a shot [m/s]: dribble pushes die away below it, a
/// kick leaves the foot at 4-6 m/s.
const REST_SPEED_M_S: f64 = 0.25;

/// Their goal (the right one, +x) as a shot sees it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GoalMouth {
    /// x of their goal line [m].
    pub line_x: f64,
    /// Half the inner width of the mouth [m].
    pub half_width: f64,
}

impl GoalMouth {
    pub fn of(field: &FieldGeometry) -> Self {
        Self {
            line_x: field.length / 2.0,
            half_width: field.goal_width / 2.0,
        }
    }

    /// Where the line from `from` through `to` crosses the goal line (y), if it heads there.
    fn crossing_y(&self, from: [f64; 2], to: [f64; 2]) -> Option<f64> {
        let dx = to[0] - from[0];
        if dx <= 1e-9 {
            return None;
        }
        Some(from[1] + (to[1] - from[1]) * (self.line_x - from[0]) / dx)
    }
}

pub struct ShotTrack {
    goal: GoalMouth,
    /// The last distinct ground-truth sample (time, place).
    last_sample: Option<(f64, [f64; 2])>,
    /// Where the ball was last at rest.
    rest_spot: Option<[f64; 2]>,
}

impl ShotTrack {
    /// Shots at `goal`.
    pub fn new(goal: GoalMouth) -> Self {
        Self {
            goal,
            last_sample: None,
            rest_spot: None,
        }
    }

    /// One ground-truth sample; the verdict for a shot of at least `min_m` on target.
    pub fn observe(&mut self, o: &Observation, min_m: f64, state: &Verdict) -> Verdict {
        let Some(b) = o.ball else {
            return state.clone();
        };
        let at = [b[0], b[1]];
        // The monitor updates less often than it is read: a repeated sample is no new sight.
        let Some((t_before, before)) = self.last_sample.replace((o.t, at)) else {
            self.rest_spot = Some(at);
            return state.clone();
        };
        if before == at || o.t <= t_before {
            self.last_sample = Some((t_before, before));
            return state.clone();
        }
        let speed = (at[0] - before[0]).hypot(at[1] - before[1]) / (o.t - t_before);
        if speed < REST_SPEED_M_S {
            self.rest_spot = Some(at);
            return state.clone();
        }
        let Some(from) = self.rest_spot else {
            return state.clone();
        };
        if (at[0] - from[0]).hypot(at[1] - from[1]) < min_m {
            return state.clone();
        }
        match self.goal.crossing_y(from, at) {
            Some(y) if y.abs() < self.goal.half_width => Verdict::Succeeded { t: o.t },
            _ => state.clone(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::judge::Judge;
    use crate::spec::Success;

    const GOAL: GoalMouth = GoalMouth {
        line_x: 27.5,
        half_width: 1.83,
    };

    /// The ball at rest at `from` for 1 s, then rolling towards `towards` at 4 m/s slowing at
    /// 0.8 m/s² (10 m to rest), sampled every 20 ms.
    fn shot(from: [f64; 2], towards: [f64; 2], pushes_first: bool) -> Verdict {
        let ball = libero_world::WorldParams::builtin().ball;
        let mut judge = Judge::new(&Success::ShotOnTarget { min_m: 6.0 }, &ball, GOAL);
        let (dx, dy) = (towards[0] - from[0], towards[1] - from[1]);
        let n = dx.hypot(dy);
        let (start, mut t) = if pushes_first {
            pushes(&mut judge, from, 3)
        } else {
            (from, 0.0)
        };
        for i in 0..400 {
            let s = (f64::from(i) * 0.02 - 1.0).clamp(0.0, 5.0);
            let d = 4.0 * s - 0.4 * s * s;
            judge.observe(&observation(
                t,
                [start[0] + d * dx / n, start[1] + d * dy / n],
            ));
            if judge.verdict().decided() {
                break;
            }
            t += 0.02;
        }
        judge.finish(20.0, "time ran out")
    }

    /// `count` dribble pushes of 1.5 m along +x from `from`, each coming to rest within 1 s,
    /// sampled every 20 ms: where the ball ends and when.
    fn pushes(judge: &mut Judge, from: [f64; 2], count: usize) -> ([f64; 2], f64) {
        let (mut spot, mut t) = (from, 0.0);
        for _ in 0..count {
            let start = spot;
            for i in 0..100 {
                let s = (f64::from(i) * 0.02).min(1.0);
                spot = [start[0] + 1.5 * (2.0 * s - s * s), start[1]];
                judge.observe(&observation(t, spot));
                t += 0.02;
            }
        }
        (spot, t)
    }

    fn observation(t: f64, at: [f64; 2]) -> Observation {
        Observation {
            t,
            ball: Some([at[0], at[1], 0.11]),
            ..Observation::default()
        }
    }

    #[test]
    fn a_long_kick_between_the_posts_is_a_shot_on_target() {
        let v = shot([17.0, 3.0], [27.5, -1.0], false);
        assert!(matches!(v, Verdict::Succeeded { t } if t > 2.0), "{v:?}");
    }

    #[test]
    fn a_kick_wide_of_the_post_or_away_from_the_goal_is_not() {
        // Heading for y = 2.5 on the line: outside the 1.83 m post.
        let v = shot([17.0, 0.0], [27.5, 2.5], false);
        assert!(matches!(v, Verdict::Failed { .. }), "{v:?}");
        // A long pass back towards our half.
        let v = shot([17.0, 0.0], [5.0, 0.0], false);
        assert!(matches!(v, Verdict::Failed { .. }), "{v:?}");
    }

    #[test]
    fn dribble_pushes_adding_up_to_the_distance_are_no_shot_but_a_kick_after_them_is() {
        // 6 m of pushes towards the goal, each stopping: no shot of 6 m ...
        let ball = libero_world::WorldParams::builtin().ball;
        let mut judge = Judge::new(&Success::ShotOnTarget { min_m: 6.0 }, &ball, GOAL);
        pushes(&mut judge, [10.0, 0.0], 4);
        assert_eq!(judge.verdict(), Verdict::Pending);
        // ... and a long kick after them is one.
        let v = shot([10.0, 0.0], [27.5, 1.0], true);
        assert!(matches!(v, Verdict::Succeeded { .. }), "{v:?}");
    }
}
