//! `PassReceived`: did the receiver get the pass where the ball was going to stop? The ball's
//! ground truth goes through the world model's own ball tracker (the model the agents predict
//! with), whose rest point, read once the kick has rolled for a moment, is the predicted stop
//! point; the receiver's first touch (its torso within reach of the ball) must come within
//! the condition's distance of it.

use crate::judge::{Observation, Verdict};
use libero_world::params::BallParams;
use libero_world::BallEstimate;
use nalgebra::Vector3;

/// The ball has been kicked once it is this far from its spot [m].
const KICKED_BEYOND_M: f64 = 0.3;
/// The stop point is read this long after the kick [s]: the tracker has fitted the launch.
const PREDICT_AFTER_S: f64 = 0.5;
/// A torso this close to the ball centre is a touch [m] (foot ahead of the torso, ball radius).
const TOUCH_M: f64 = 0.4;

pub struct PassTrack {
    ball: BallEstimate,
    start: Option<[f64; 2]>,
    kicked_at: Option<f64>,
    /// The world model's rest point for the kicked ball.
    pub predicted_stop: Option<[f64; 2]>,
}

impl PassTrack {
    pub fn new(ball: &BallParams) -> Self {
        Self {
            ball: BallEstimate::new(ball),
            start: None,
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
        self.ball.update(o.t, Some(Vector3::new(b[0], b[1], b[2])));
        let start = *self.start.get_or_insert(at);
        let t = o.t;
        if self.kicked_at.is_none() && distance(at, start) > KICKED_BEYOND_M {
            self.kicked_at = Some(t);
        }
        let Some(kicked_at) = self.kicked_at else {
            return state.clone();
        };
        if self.predicted_stop.is_none() && t - kicked_at >= PREDICT_AFTER_S {
            self.predicted_stop = Some(self.ball.predicted_stop);
        }
        let touched = o
            .ours
            .iter()
            .find(|(u, _)| *u == receiver)
            .is_some_and(|(_, p)| distance(*p, at) <= TOUCH_M);
        if !touched {
            return state.clone();
        }
        let stop = *self.predicted_stop.get_or_insert(self.ball.predicted_stop);
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
    use crate::spec::Success;

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
        let mut judge = Judge::new(&pass(1.0), &ball);
        let v = roll(&mut judge, 4.0, 0.8, [10.2, 0.1]);
        assert!(matches!(v, Verdict::Succeeded { .. }), "{v:?}");
    }

    #[test]
    fn a_touch_far_short_of_the_stop_point_is_no_reception() {
        let ball = libero_world::WorldParams::builtin().ball;
        // The receiver stands 4 m short of where the ball would stop: the ball runs into it.
        let mut judge = Judge::new(&pass(1.0), &ball);
        let v = roll(&mut judge, 4.0, 0.8, [6.0, 0.0]);
        assert!(
            matches!(&v, Verdict::Failed { why, .. } if why.contains("predicted stop point")),
            "{v:?}"
        );
        // Nobody near the ball's path: never received.
        let mut judge = Judge::new(&pass(1.0), &ball);
        let v = roll(&mut judge, 4.0, 0.8, [5.0, 6.0]);
        assert!(
            matches!(&v, Verdict::Failed { why, .. } if why.contains("not met")),
            "{v:?}"
        );
    }
}
