//! `PassReceived`: did the receiver get the pass where the ball was going to stop? The ball's
//! ground truth goes through the world model's own ball tracker (the model the agents predict
//! with); the receiver's first touch (its torso within reach of the ball) must come within the
//! condition's distance of the stop point it predicted just before the touch. A ball at rest
//! is its own stop point; a ball met at speed short of where it was going fails. (A stop point
//! read early in the roll is off by up to 1.5 m: the tracker refines it as the ball slows.)

use crate::judge::{Observation, Verdict};
use libero_world::params::BallParams;
use libero_world::BallEstimate;
use nalgebra::Vector3;

/// A torso this close to the ball centre is a touch [m] (foot ahead of the torso, ball radius).
pub(crate) const TOUCH_M: f64 = 0.4;

pub struct PassTrack {
    ball: BallEstimate,
    /// The tracker had the ball moving at the last sample.
    moving: bool,
    last_sample: Option<[f64; 3]>,
    kicked_at: Option<f64>,
    /// The world model's rest point for the kicked ball, as of the sample before.
    pub predicted_stop: Option<[f64; 2]>,
}

impl PassTrack {
    pub fn new(ball: &BallParams) -> Self {
        Self {
            ball: BallEstimate::new(ball),
            moving: false,
            last_sample: None,
            kicked_at: None,
            predicted_stop: None,
        }
    }

    /// One ground-truth sample; the verdict for `receiver` getting it within `within_m`.
    pub fn observe(
        &mut self,
        o: &Observation,
        receiver: u32,
        within_m: f64,
        state: &Verdict,
    ) -> Verdict {
        let Some(b) = o.ball else {
            return state.clone();
        };
        let at = [b[0], b[1]];
        let before = self.ball.predicted_stop;
        // The monitor updates less often than it is read: a repeated sample is no new sight
        // (fed again at a later time, it would look like a ball stopping dead).
        if self.last_sample != Some(b) {
            self.ball.update(o.t, Some(Vector3::new(b[0], b[1], b[2])));
            self.last_sample = Some(b);
        }
        let t = o.t;
        // Every launch the tracker sees (the ball leaving rest) is a new kick: a bump on the
        // approach that nudges the ball and stops is not the pass whose stop point counts.
        let moving = self.ball.velocity != [0.0; 2];
        if moving && !self.moving {
            self.kicked_at = Some(t);
        }
        self.moving = moving;
        if self.kicked_at.is_none() {
            return state.clone();
        }
        // The prediction from the samples before this one: a touch shows in the ball's path
        // only afterwards.
        self.predicted_stop = Some(before);
        let touched = o
            .ours
            .iter()
            .find(|(u, _)| *u == receiver)
            .is_some_and(|(_, p)| distance(*p, at) <= TOUCH_M);
        if !touched {
            return state.clone();
        }
        let stop = before;
        let off = distance(at, stop);
        if off <= within_m {
            Verdict::Succeeded { t }
        } else {
            Verdict::Failed {
                t,
                why: format!(
                    "our {receiver} first touched the ball at ({:.2}, {:.2}), {off:.2} m from its predicted stop point ({:.2}, {:.2})",
                    at[0], at[1], stop[0], stop[1]
                ),
            }
        }
    }
}

fn distance(a: [f64; 2], b: [f64; 2]) -> f64 {
    (a[0] - b[0]).hypot(a[1] - b[1])
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::judge::Judge;
    use crate::shot_judge::GoalMouth;
    use crate::spec::Success;

    const GOAL: GoalMouth = GoalMouth {
        line_x: 27.5,
        half_width: 1.83,
    };

    /// A ball rolling along +x from the origin, slowing evenly at `decel` from `v0`, sampled
    /// every 20 ms like the monitor; the receiver waits at `receiver_x` on the line.
    fn roll(judge: &mut Judge, v0: f64, decel: f64, receiver: [f64; 2]) -> Verdict {
        let stop_t = v0 / decel;
        for i in 0..600 {
            let t = f64::from(i) * 0.02;
            let rolled = if t < 0.2 {
                0.0
            } else {
                let s = (t - 0.2).min(stop_t);
                v0 * s - 0.5 * decel * s * s
            };
            let o = Observation {
                t,
                ball: Some([rolled, 0.0, 0.11]),
                ours: vec![(7, [-0.3, 0.0]), (4, receiver)],
                ..Observation::default()
            };
            judge.observe(&o);
            if judge.verdict().decided() {
                break;
            }
        }
        judge.finish(12.0, "time ran out")
    }

    fn pass(within_m: f64) -> Success {
        Success::PassReceived {
            receiver: 4,
            within_m,
        }
    }

    #[test]
    fn a_receiver_waiting_at_the_stop_point_gets_the_pass() {
        let ball = libero_world::WorldParams::builtin().ball;
        // 4 m/s slowing at 0.8 m/s²: stops 10 m on, after 5 s. The world model's own ball
        // tracker predicts that rest point from the first half second of the roll.
        let mut judge = Judge::new(&pass(1.0), &ball, GOAL);
        let v = roll(&mut judge, 4.0, 0.8, [10.2, 0.1]);
        assert!(matches!(v, Verdict::Succeeded { .. }), "{v:?}");
    }

    #[test]
    fn a_touch_far_short_of_the_stop_point_is_no_reception() {
        let ball = libero_world::WorldParams::builtin().ball;
        // The receiver stands 4 m short of where the ball would stop: the ball runs into it.
        let mut judge = Judge::new(&pass(1.0), &ball, GOAL);
        let v = roll(&mut judge, 4.0, 0.8, [6.0, 0.0]);
        assert!(
            matches!(&v, Verdict::Failed { why, .. } if why.contains("predicted stop point")),
            "{v:?}"
        );
        // Nobody near the ball's path: never received.
        let mut judge = Judge::new(&pass(1.0), &ball, GOAL);
        let v = roll(&mut judge, 4.0, 0.8, [5.0, 6.0]);
        assert!(
            matches!(&v, Verdict::Failed { why, .. } if why.contains("not met")),
            "{v:?}"
        );
    }

    #[test]
    fn a_bump_before_the_pass_is_not_the_pass() {
        let ball = libero_world::WorldParams::builtin().ball;
        let mut judge = Judge::new(&pass(1.0), &ball, GOAL);
        // The passer nudges the ball 0.4 m on its approach (it stops again), then passes:
        // 4 m/s slowing at 0.8 m/s², stopping 10 m on at (10.4, 0), where player 4 waits.
        let at = |t: f64| -> f64 {
            if t < 1.0 {
                0.0
            } else if t < 1.4 {
                0.4 * (t - 1.0) / 0.4
            } else if t < 3.0 {
                0.4
            } else {
                let s = (t - 3.0).min(5.0);
                0.4 + 4.0 * s - 0.4 * s * s
            }
        };
        for i in 0..700 {
            let t = f64::from(i) * 0.02;
            judge.observe(&Observation {
                t,
                ball: Some([at(t), 0.0, 0.11]),
                ours: vec![(7, [-0.3, 0.0]), (4, [10.6, 0.3])],
                ..Observation::default()
            });
            if judge.verdict().decided() {
                break;
            }
        }
        let v = judge.finish(14.0, "time ran out");
        assert!(matches!(v, Verdict::Succeeded { .. }), "{v:?}");
    }
}
