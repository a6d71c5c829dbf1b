//! When and where a player can meet the ball (the interception estimate both sides use).

use super::BallEstimate;
use nalgebra::Vector2;

impl BallEstimate {
    /// The earliest time (seconds from now) and place where a player at `from`, moving at
    /// `speed` [m/s] in a straight line, can be within `reach` [m] of the ball.
    pub fn interception(&self, from: [f64; 2], speed: f64, reach: f64) -> Option<(f64, [f64; 2])> {
        let (origin, heading, ball_speed, roll) = self.kinematic_state();
        let from = Vector2::from(from);
        let motion = &self.tracker.motion;
        let stop_time = motion.stop_time(ball_speed, roll);
        let ball_at = |t: f64| origin + heading * motion.advance(ball_speed, roll, t).distance;
        let can_reach = |t: f64| (ball_at(t) - from).norm() - reach <= speed.max(0.0) * t;
        // Coarse scan while the ball moves (the gap closes monotonically once the ball is
        // slower than the player), then bisection for the first reachable moment.
        const STEP: f64 = 0.05;
        if can_reach(0.0) {
            return Some((0.0, ball_at(0.0).into()));
        }
        let mut before = 0.0;
        let mut t = STEP;
        // A ball that would roll for over a minute is no ball this side can meet.
        let scan_end = stop_time.min(60.0);
        while t < scan_end + STEP {
            let t_checked = t.min(scan_end);
            if can_reach(t_checked) {
                let (mut lo, mut hi) = (before, t_checked);
                for _ in 0..30 {
                    let mid = 0.5 * (lo + hi);
                    if can_reach(mid) {
                        hi = mid;
                    } else {
                        lo = mid;
                    }
                }
                return Some((hi, ball_at(hi).into()));
            }
            before = t_checked;
            t += STEP;
        }
        // At rest from `stop_time` on: walking straight to where it lies (a ball lying still,
        // the commonest case, is answered here at once; the scan over a minute of a resting
        // ball was most of the keeper's decision time).
        if speed <= 0.0 || stop_time > scan_end {
            return None;
        }
        let rest = ball_at(stop_time);
        let arrival = (((rest - from).norm() - reach) / speed).max(stop_time);
        (arrival <= stop_time + 60.0).then_some((arrival, rest.into()))
    }
}
