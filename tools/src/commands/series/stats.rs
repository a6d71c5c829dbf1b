//! What a series of matches or runs says, and when it has said enough.
//!
//! The early stop is Wald's sequential probability ratio test on the sign of each match
//! (home win or loss; draws say nothing about which team is better), run both ways: "home wins
//! a decisive match with probability `effect`" and "away does", each against "either wins half
//! of them". It stops when one side's ratio passes its upper bound (significant at `alpha`,
//! split between the two sides), or when both pass their lower bounds (no difference as large
//! as `effect`, with power 1 − `beta`). The intervals are the usual fixed-sample ones.

use serde::Serialize;
use statrs::distribution::{Binomial, ContinuousCDF, DiscreteCDF, StudentsT};

/// The sequential test's settings.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct Sprt {
    /// Chance of calling a difference when there is none (both sides together).
    pub alpha: f64,
    /// Chance of missing a difference as large as `effect`.
    pub beta: f64,
    /// The better team's share of the decisive matches that counts as a difference.
    pub effect: f64,
}

/// Where the sequential test stands.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Verdict {
    HomeBetter,
    AwayBetter,
    /// Neither team is better by as much as `effect`.
    NoDifference,
    Undecided,
}

impl Verdict {
    pub fn decided(self) -> bool {
        self != Verdict::Undecided
    }

    pub fn describe(self, sprt: &Sprt) -> String {
        match self {
            Verdict::HomeBetter => format!("home is better (significant at {})", sprt.alpha),
            Verdict::AwayBetter => format!("away is better (significant at {})", sprt.alpha),
            Verdict::NoDifference => format!(
                "no difference as large as {:.0} % of decisive matches (power {})",
                sprt.effect * 100.0,
                1.0 - sprt.beta
            ),
            Verdict::Undecided => "undecided: more matches needed".into(),
        }
    }
}

impl Sprt {
    /// (upper, lower) bounds on each side's log likelihood ratio.
    fn bounds(&self) -> (f64, f64) {
        let side_alpha = self.alpha / 2.0;
        (
            ((1.0 - self.beta) / side_alpha).ln(),
            (self.beta / (1.0 - side_alpha)).ln(),
        )
    }

    /// The log likelihood ratios (home better, away better) after `wins` and `losses`.
    pub fn ratios(&self, wins: u32, losses: u32) -> (f64, f64) {
        let (w, l) = (f64::from(wins), f64::from(losses));
        let up = (2.0 * self.effect).ln();
        let down = (2.0 * (1.0 - self.effect)).ln();
        (w * up + l * down, l * up + w * down)
    }

    pub fn verdict(&self, wins: u32, losses: u32) -> Verdict {
        let (upper, lower) = self.bounds();
        let (home, away) = self.ratios(wins, losses);
        if home >= upper {
            Verdict::HomeBetter
        } else if away >= upper {
            Verdict::AwayBetter
        } else if home <= lower && away <= lower {
            Verdict::NoDifference
        } else {
            Verdict::Undecided
        }
    }

    pub fn validate(&self) -> Result<(), String> {
        if !(self.alpha > 0.0 && self.alpha < 0.5) {
            return Err("--alpha must be in (0, 0.5)".into());
        }
        if !(self.beta > 0.0 && self.beta < 0.5) {
            return Err("--beta must be in (0, 0.5)".into());
        }
        if !(self.effect > 0.5 && self.effect < 1.0) {
            return Err("--effect must be in (0.5, 1)".into());
        }
        Ok(())
    }
}

/// A mean with its 95 % confidence interval (Student's t; none from fewer than two values).
#[derive(Debug, Clone, Copy, Serialize)]
pub struct Estimate {
    pub mean: f64,
    pub low: Option<f64>,
    pub high: Option<f64>,
}

pub fn mean_with_interval(values: &[f64]) -> Estimate {
    let n = values.len();
    if n == 0 {
        return Estimate {
            mean: f64::NAN,
            low: None,
            high: None,
        };
    }
    let mean = values.iter().sum::<f64>() / n as f64;
    if n < 2 {
        return Estimate {
            mean,
            low: None,
            high: None,
        };
    }
    let var = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1) as f64;
    let t = StudentsT::new(0.0, 1.0, (n - 1) as f64)
        .map(|d| d.inverse_cdf(0.975))
        .unwrap_or(f64::NAN);
    let half = t * (var / n as f64).sqrt();
    Estimate {
        mean,
        low: Some(mean - half),
        high: Some(mean + half),
    }
}

/// A success rate with its 95 % Wilson score interval.
pub fn rate_with_interval(successes: u32, trials: u32) -> Estimate {
    if trials == 0 {
        return Estimate {
            mean: f64::NAN,
            low: None,
            high: None,
        };
    }
    let (k, n) = (f64::from(successes), f64::from(trials));
    let z: f64 = 1.959_963_984_540_054;
    let p = k / n;
    let centre = (p + z * z / (2.0 * n)) / (1.0 + z * z / n);
    let half = z / (1.0 + z * z / n) * (p * (1.0 - p) / n + z * z / (4.0 * n * n)).sqrt();
    Estimate {
        mean: p,
        low: Some((centre - half).max(0.0)),
        high: Some((centre + half).min(1.0)),
    }
}

/// Two-sided exact sign test: the chance of a split at least this uneven if both teams win
/// half of the decisive matches.
pub fn sign_test_p(wins: u32, losses: u32) -> f64 {
    let n = u64::from(wins + losses);
    if n == 0 {
        return 1.0;
    }
    let k = u64::from(wins.min(losses));
    let tail = Binomial::new(0.5, n).map(|b| b.cdf(k)).unwrap_or(1.0);
    (2.0 * tail).min(1.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    const SPRT: Sprt = Sprt {
        alpha: 0.05,
        beta: 0.1,
        effect: 0.75,
    };

    #[test]
    fn nine_straight_wins_decide_and_eight_do_not() {
        // Upper bound ln(0.9 / 0.025) = 3.58; a win adds ln 1.5 = 0.405.
        assert_eq!(SPRT.verdict(8, 0), Verdict::Undecided);
        assert_eq!(SPRT.verdict(9, 0), Verdict::HomeBetter);
        assert_eq!(SPRT.verdict(0, 9), Verdict::AwayBetter);
        // A loss takes a win and a half back: 12 wins, 2 losses is 4.86 - 1.39 = 3.48.
        assert_eq!(SPRT.verdict(12, 2), Verdict::Undecided);
        assert_eq!(SPRT.verdict(13, 2), Verdict::HomeBetter);
    }

    #[test]
    fn an_even_split_ends_in_no_difference() {
        // Each side: w·0.405 − l·0.693 ≤ ln(0.1 / 0.975) = −2.28 once both are low enough.
        assert_eq!(SPRT.verdict(3, 3), Verdict::Undecided);
        assert_eq!(SPRT.verdict(8, 8), Verdict::NoDifference);
    }

    #[test]
    fn intervals_match_hand_worked_values() {
        // Mean 2, sd 1 over 4 values: t(3, 0.975) = 3.182, half width 1.591.
        let e = mean_with_interval(&[1.0, 2.0, 3.0, 2.0]);
        assert!((e.mean - 2.0).abs() < 1e-12);
        assert!((e.high.unwrap() - 2.0 - 3.182 * (2.0f64 / 3.0).sqrt() / 2.0).abs() < 1e-3);
        // Wilson, 8 of 10: 0.490–0.943.
        let r = rate_with_interval(8, 10);
        assert!((r.low.unwrap() - 0.4902).abs() < 1e-3, "{r:?}");
        assert!((r.high.unwrap() - 0.9433).abs() < 1e-3, "{r:?}");
        // 9 of 9 one way: 2 · 0.5⁹ = 0.0039.
        assert!((sign_test_p(9, 0) - 0.003_906_25).abs() < 1e-9);
        assert!((sign_test_p(5, 5) - 1.0).abs() < 1e-9);
    }
}
