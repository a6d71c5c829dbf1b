//! The kick objective: each candidate kicks from a few seeded places around the kicking place
//! (within the approach's tolerances, either foot, any field direction: quick, no long walk);
//! its cost per kick is minus the distance (capped), plus the direction error and the offset
//! from the asked line where the ball passes the asked distance, plus heavy penalties for a
//! fall or a kick not made.

use super::{select_tunables, tunable, Objective, Tunable};
use crate::episode::{Trial, TrialError};
use crate::kick_bench::{kick_once, setups_at_place, KickDirections, KickOutcome, KickSetup};
use libero_skills::SkillParams;

/// The long-kick numbers searched by default: contact geometry and swing.
pub const DEFAULT_KICK_TUNABLES: [&str; 6] = [
    "long.strike_height_m",
    "long.contact_yaw_deg",
    "long.windup_back_m",
    "long.follow_through_m",
    "long.swing_s",
    "long.landing_tilt_gain",
];

/// Every kick number the optimiser can search.
pub fn kick_tunables() -> Vec<Tunable> {
    vec![
        tunable!("long.strike_height_m", 0.05, 0.2, kick.long.strike_height_m),
        tunable!(
            "long.contact_yaw_deg",
            -5.0,
            20.0,
            kick.long.contact_yaw_deg
        ),
        tunable!("long.windup_back_m", 0.05, 0.35, kick.long.windup_back_m),
        tunable!("long.windup_lift_m", 0.0, 0.15, kick.long.windup_lift_m),
        tunable!(
            "long.follow_through_m",
            0.0,
            0.3,
            kick.long.follow_through_m
        ),
        tunable!("long.swing_s", 0.06, 0.3, kick.long.swing_s),
        tunable!("long.support_sag_m", 0.0, 0.12, kick.long.support_sag_m),
        tunable!(
            "long.swing_outward_m",
            -0.05,
            0.05,
            kick.long.swing_outward_m
        ),
        tunable!("long.weight_shift_m", 0.0, 0.12, kick.long.weight_shift_m),
        tunable!("long.kick_lean_deg", -5.0, 15.0, kick.long.kick_lean_deg),
        tunable!(
            "long.landing_tilt_gain",
            0.0,
            1.0,
            kick.long.landing_tilt_gain
        ),
        tunable!(
            "short.strike_height_m",
            0.05,
            0.2,
            kick.short.strike_height_m
        ),
        tunable!(
            "short.contact_yaw_deg",
            -5.0,
            20.0,
            kick.short.contact_yaw_deg
        ),
        tunable!("short.swing_s", 0.06, 0.5, kick.short.swing_s),
    ]
}

/// The kick tunables with these names, in the order given.
pub fn select_kick_tunables(names: &[&str]) -> Result<Vec<Tunable>, String> {
    select_tunables(kick_tunables(), names, "kick")
}

/// Distances beyond this earn nothing more [m]: past it, direction matters more.
const DISTANCE_CAP_M: f64 = 15.0;
/// Cost per degree of direction error, in metres of distance.
const COST_PER_DEG: f64 = 0.5;
/// Cost per metre of offset from the asked line where the ball passes the asked distance, in
/// metres of distance. Session 39: a kick this search found without the term rolled 15.2 m
/// instead of 11.6 (`libero bench kick --seed 1`) and passed 10 m out 0.47 m off the line
/// instead of 0.28 (`AROUND=1 SEED=5 kick_probe 24 10`); striker_alone scored 17 of 40 with
/// it against 30 of 40, its shots wide of the posts. At 25, the 0.19 m outweighs the 3.6 m.
const COST_PER_M_OFF: f64 = 25.0;
/// Cost of a fall or of a kick not made (more than any kick earns).
const FAILURE_COST: f64 = 2.0 * DISTANCE_CAP_M;
/// Time allowed from the request to the kick motion, starting at the place [s].
const KICK_LIMIT_S: f64 = 20.0;

/// Every candidate makes all of these kicks; its cost is the mean.
pub struct KickObjective {
    pub setups: Vec<KickSetup>,
}

impl KickObjective {
    /// `count` seeded kicks asking for `distance_m` from around the kicking place of `params`,
    /// in `directions`.
    pub fn at_place(
        count: usize,
        seed: u64,
        distance_m: f64,
        params: &SkillParams,
        directions: KickDirections,
    ) -> Self {
        Self {
            setups: setups_at_place(count, seed, distance_m, &params.kick.approach, directions),
        }
    }
}

/// Cost of one kick.
pub fn kick_cost(o: &KickOutcome) -> f64 {
    if o.fell || !o.kicked {
        FAILURE_COST
    } else {
        -o.distance_m.min(DISTANCE_CAP_M)
            + COST_PER_DEG * o.direction_error_deg.abs()
            + COST_PER_M_OFF * o.miss_at_distance_m.map_or(0.0, f64::abs)
    }
}

impl Objective for KickObjective {
    fn cost(&self, trial: &mut Trial, params: &SkillParams) -> Result<f64, TrialError> {
        let mut total = 0.0;
        for &s in &self.setups {
            total += kick_cost(&kick_once(trial, params, s, KICK_LIMIT_S)?);
        }
        Ok(total / self.setups.len().max(1) as f64)
    }

    fn explain(&self) -> String {
        format!(
            "mean over {} kicks of minus the distance (at most {DISTANCE_CAP_M} m) plus \
             {COST_PER_DEG} per degree of direction error and {COST_PER_M_OFF} per metre off the \
             line where the ball passes the asked distance; a fall or no kick costs {FAILURE_COST}",
            self.setups.len()
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_long_straight_kick_costs_less_than_a_short_crooked_one_and_failures_most() {
        let good = KickOutcome {
            kicked: true,
            distance_m: 11.0,
            direction_error_deg: 1.0,
            ..Default::default()
        };
        let crooked = KickOutcome {
            direction_error_deg: 12.0,
            distance_m: 8.0,
            ..good
        };
        let fell = KickOutcome { fell: true, ..good };
        let missed = KickOutcome {
            kicked: false,
            ..Default::default()
        };
        assert!(kick_cost(&good) < kick_cost(&crooked));
        assert!(kick_cost(&crooked) < 0.0);
        assert!(kick_cost(&fell) > 0.0 && kick_cost(&missed) == kick_cost(&fell));
        // Beyond the cap only the direction counts.
        let far = KickOutcome {
            distance_m: 30.0,
            ..good
        };
        assert_eq!(kick_cost(&far), -DISTANCE_CAP_M + COST_PER_DEG);
        // Session 39's two kicks: the shorter, straighter one costs less.
        let straight = KickOutcome {
            distance_m: 11.6,
            direction_error_deg: 5.0,
            miss_at_distance_m: Some(-0.28),
            ..good
        };
        let long_and_wide = KickOutcome {
            distance_m: 15.2,
            direction_error_deg: 6.0,
            miss_at_distance_m: Some(0.47),
            ..good
        };
        assert!(kick_cost(&straight) < kick_cost(&long_and_wide));
    }

    #[test]
    fn kick_tunables_select_by_name() {
        let picked = select_kick_tunables(&DEFAULT_KICK_TUNABLES).unwrap();
        assert_eq!(picked.len(), DEFAULT_KICK_TUNABLES.len());
        let err = select_kick_tunables(&["strike_height_m"]).err().unwrap();
        assert!(err.contains("long.strike_height_m"), "{err}");
    }
}
