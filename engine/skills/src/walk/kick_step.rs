//! The kick step: one step of the walk whose swing foot winds back and strikes forward through
//! the ball before it lands where the step would have put it.
//!
//! The kick motion (`crate::kick`) stops the walk, looks, shifts the weight and swings from a
//! still stance: strong, but seconds long. A kick step keeps walking: the swing foot of one
//! step lifts higher, pulls back, swings forward past its landing place at speed and comes
//! back to land, while the support foot and the torso's sway go on as in any step (B-Human's
//! and NUbots' in-walk kicks work the same way). It is weaker, and is what a dribble uses to
//! send the ball a few metres ahead instead of walking it there.

use super::params::Check;
use crate::walk::params::in_range;
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// The shape of a kick step (`walk.kick_step` in the skill parameter file).
#[derive(Debug, Clone, Copy, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct KickStepParams {
    /// Duration of the kick step [s] (a walking step lasts `step_period_s`).
    pub period_s: f64,
    /// How far behind its start the swing foot is pulled for the wind-up [m] ...
    pub windup_m: f64,
    /// ... and how far past its landing place the strike carries it [m].
    pub reach_m: f64,
    /// Height of the swing sole through the wind-up and the strike [m].
    pub lift_m: f64,
    /// The wind-up ends and the strike begins at this share of the step ...
    pub strike_from: f64,
    /// ... and the strike ends (the foot comes back to land) at this share.
    pub strike_to: f64,
}

impl KickStepParams {
    pub fn validate(&self) -> Check {
        let p = |name: &str| format!("walk.kick_step.{name}");
        in_range(&p("period_s"), self.period_s, 0.1, 2.0)?;
        in_range(&p("windup_m"), self.windup_m, 0.0, 0.3)?;
        in_range(&p("reach_m"), self.reach_m, 0.0, 0.4)?;
        in_range(&p("lift_m"), self.lift_m, 0.0, 0.2)?;
        in_range(&p("strike_from"), self.strike_from, 0.05, 0.9)?;
        in_range(
            &p("strike_to"),
            self.strike_to,
            self.strike_from + 0.05,
            0.95,
        )
    }

    /// The swing foot's forward offset at `phase` of the step, from `start` to `end` [m].
    pub fn swing_x(&self, start: f64, end: f64, phase: f64) -> f64 {
        let windup = start - self.windup_m;
        let reach = end + self.reach_m;
        let s = phase.clamp(0.0, 1.0);
        if s < self.strike_from {
            ease(start, windup, s / self.strike_from)
        } else if s < self.strike_to {
            ease(
                windup,
                reach,
                (s - self.strike_from) / (self.strike_to - self.strike_from),
            )
        } else {
            ease(reach, end, (s - self.strike_to) / (1.0 - self.strike_to))
        }
    }

    /// The swing sole's height above the ground at `phase` [m]: up during the wind-up, held
    /// through the strike, down while it comes back to land.
    pub fn swing_z(&self, phase: f64) -> f64 {
        self.lift_m * self.strike_share(phase)
    }

    /// How much of the strike's placement (its height, its shift across) the swing foot has
    /// at `phase`: rising 0 → 1 during the wind-up, 1 through the strike, back to 0 as the
    /// foot comes down.
    pub fn strike_share(&self, phase: f64) -> f64 {
        let s = phase.clamp(0.0, 1.0);
        if s < self.strike_from {
            ease(0.0, 1.0, s / self.strike_from)
        } else if s < self.strike_to {
            1.0
        } else {
            ease(1.0, 0.0, (s - self.strike_to) / (1.0 - self.strike_to))
        }
    }
}

/// A kick step for the walk's unit tests (the shape shipped for the T1).
#[cfg(test)]
pub(crate) fn example() -> KickStepParams {
    KickStepParams {
        period_s: 0.4,
        windup_m: 0.06,
        reach_m: 0.15,
        lift_m: 0.11,
        strike_from: 0.4,
        strike_to: 0.65,
    }
}

/// From `a` to `b` as `s` goes 0 → 1, starting and ending at rest.
fn ease(a: f64, b: f64, s: f64) -> f64 {
    a + (b - a) * (0.5 - 0.5 * (PI * s.clamp(0.0, 1.0)).cos())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn shape() -> KickStepParams {
        KickStepParams {
            period_s: 0.4,
            windup_m: 0.06,
            reach_m: 0.15,
            lift_m: 0.07,
            strike_from: 0.4,
            strike_to: 0.7,
        }
    }

    #[test]
    fn the_swing_winds_up_strikes_past_its_landing_place_and_lands_there() {
        let k = shape();
        let (start, end) = (-0.05, 0.05);
        assert!((k.swing_x(start, end, 0.0) - start).abs() < 1e-12);
        assert!((k.swing_x(start, end, k.strike_from) - (start - k.windup_m)).abs() < 1e-12);
        assert!((k.swing_x(start, end, k.strike_to) - (end + k.reach_m)).abs() < 1e-12);
        assert!((k.swing_x(start, end, 1.0) - end).abs() < 1e-12);
        // The strike is the fastest part: its mean speed beats the wind-up's and the return's.
        let strike = (end + k.reach_m - (start - k.windup_m)) / (k.strike_to - k.strike_from);
        let windup = k.windup_m / k.strike_from;
        let back = k.reach_m / (1.0 - k.strike_to);
        assert!(strike > 2.0 * windup.max(back), "{strike} {windup} {back}");
        validate_ok(&k);
    }

    #[test]
    fn the_sole_is_up_through_the_strike_and_on_the_ground_at_both_ends() {
        let k = shape();
        assert_eq!(k.swing_z(0.0), 0.0);
        assert!(k.swing_z(1.0).abs() < 1e-12);
        assert_eq!(k.swing_z(0.5 * (k.strike_from + k.strike_to)), k.lift_m);
    }

    #[test]
    fn a_strike_that_ends_before_it_starts_is_refused_by_name() {
        let k = KickStepParams {
            strike_to: 0.3,
            ..shape()
        };
        let err = k.validate().unwrap_err();
        assert!(err.contains("walk.kick_step.strike_to"), "{err}");
    }

    fn validate_ok(k: &KickStepParams) {
        k.validate().unwrap();
    }
}
