//! Shot utility (thesis 6.3): for target points across the goal mouth, the probability that a
//! long kick aimed there scores, from the kick's measured spread (direction and distance, in the
//! skill parameters), the keeper's reach and the opponents near the line. Numbers in
//! `formations/shot.ron`. Own frame: the opponents' goal is at +x.

use crate::files::Field;
use libero_skills::kick::KickSpread;
use libero_world::Own;

/// `formations/shot.ron`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ShotParams {
    /// Target points sampled across the goal mouth.
    pub targets: usize,
    /// The outermost targets lie this far inside the posts [m].
    pub post_margin_m: f64,
    /// No shot from farther than this [m].
    pub max_distance_m: f64,
    /// Mean ball speed over a shot, for how long the keeper has to react [m/s].
    pub ball_speed_m_s: f64,
    /// The keeper covers this far either side of itself at once [m] ...
    pub keeper_reach_m: f64,
    /// ... and this much more per second of the ball's travel [m/s] ...
    pub keeper_speed_m_s: f64,
    /// ... once it has seen the kick and started moving, this long after it [s].
    pub keeper_reaction_s: f64,
    /// A field player blocks a ball passing within this of it [m].
    pub block_radius_m: f64,
    /// Shoot when the best target's scoring probability reaches this.
    pub threshold: f64,
    /// Once good, a shot stays good until its probability falls this far below the
    /// threshold (estimates jitter; without it the player swapped between shooting and
    /// dribbling every few cycles, restarting each skill).
    pub hysteresis: f64,
}

impl Default for ShotParams {
    fn default() -> Self {
        Self {
            targets: 9,
            post_margin_m: 0.3,
            max_distance_m: 14.0,
            ball_speed_m_s: 4.0,
            keeper_reach_m: 0.5,
            keeper_speed_m_s: 0.25,
            keeper_reaction_s: 0.5,
            block_radius_m: 0.35,
            threshold: 0.3,
            hysteresis: 0.1,
        }
    }
}

/// Who stands in the way of a shot.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Defenders {
    pub keeper: Option<Own>,
    pub field_players: arrayvec::ArrayVec<Own, MAX_DEFENDERS>,
}

/// The most opponents a shot's chance counts (11 a side).
pub const MAX_DEFENDERS: usize = 11;

/// A target and its scoring probability.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ShotChoice {
    pub target: Own,
    pub probability: f64,
}

/// Standard normal cumulative distribution.
fn phi(z: f64) -> f64 {
    0.5 * (1.0 + libm::erf(z / std::f64::consts::SQRT_2))
}

/// Probability that a normal error of spread `sd` around `mean` falls within [lo, hi].
pub(crate) fn within(mean: f64, sd: f64, lo: f64, hi: f64) -> f64 {
    if sd < 1e-9 {
        return if (lo..=hi).contains(&mean) { 1.0 } else { 0.0 };
    }
    (phi((hi - mean) / sd) - phi((lo - mean) / sd)).clamp(0.0, 1.0)
}

/// Where `p` lies from a ball kicked along the unit vector `along`: the distance along the
/// kick line and the offset across it (+ to the left).
fn along_and_across(ball: Own, along: Own, p: Own) -> (f64, f64) {
    let d = p - ball;
    (
        d.x * along.x + d.y * along.y,
        -d.x * along.y + d.y * along.x,
    )
}

/// The probability that a ball kicked from `ball` along the unit vector `along`, with a
/// direction error of spread `sigma` [rad], passes a player at `at` farther than `reach` from
/// it: the player stands beside the line within its `distance` (a little beyond, as the ball
/// rolls on), and the lateral spread grows with the distance along it.
pub(crate) fn passes_by(
    ball: Own,
    along: Own,
    distance: f64,
    sigma: f64,
    at: Own,
    reach: f64,
) -> f64 {
    let (s, off) = along_and_across(ball, along, at);
    if s <= 0.0 || s > distance + 0.5 {
        return 1.0;
    }
    1.0 - within(0.0, s * sigma.tan(), off - reach, off + reach)
}

impl ShotParams {
    /// The target points, from one post to the other (own frame, on the goal line).
    pub fn targets(&self, field: &Field) -> impl Iterator<Item = Own> {
        let x = field.half_length();
        let half = (field.goal_half_width() - self.post_margin_m).max(0.0);
        let n = self.targets.max(1);
        (0..n).map(move |i| {
            if n == 1 {
                Own::new(x, 0.0)
            } else {
                Own::new(x, -half + 2.0 * half * i as f64 / (n - 1) as f64)
            }
        })
    }

    /// The probability that a long kick from `ball` aimed at `target` scores.
    pub fn probability(
        &self,
        ball: Own,
        target: Own,
        field: &Field,
        kick: &KickSpread,
        defenders: &Defenders,
    ) -> f64 {
        let distance = ball.distance(target);
        if distance > self.max_distance_m || distance < 1e-6 || target.x <= ball.x {
            return 0.0;
        }
        let sigma = kick.direction_sd_deg.to_radians();
        let along = (target - ball).scaled(1.0 / distance);
        let rolls = kick.distance_along(along.x, along.y);
        let reaches = phi((rolls - distance) / kick.distance_sd_m.max(1e-3));
        let half_goal = field.goal_half_width();
        // Between the posts: the direction error moves the crossing along the goal line.
        let inside = within(
            target.y,
            distance * sigma.tan() / along.x.max(0.1),
            -half_goal,
            half_goal,
        );
        let keeper = defenders.keeper.map_or(1.0, |k| {
            let (s, _) = along_and_across(ball, along, k);
            let travel_s = s.max(0.0) / self.ball_speed_m_s;
            let moving_s = (travel_s - self.keeper_reaction_s).max(0.0);
            let reach = self.keeper_reach_m + self.keeper_speed_m_s * moving_s;
            passes_by(ball, along, distance, sigma, k, reach)
        });
        let blockers: f64 = defenders
            .field_players
            .iter()
            .map(|p| passes_by(ball, along, distance, sigma, *p, self.block_radius_m))
            .product();
        reaches * inside * keeper * blockers
    }

    /// The best target across the goal mouth.
    pub fn best(
        &self,
        ball: Own,
        field: &Field,
        kick: &KickSpread,
        defenders: &Defenders,
    ) -> ShotChoice {
        self.targets(field)
            .map(|target| ShotChoice {
                target,
                probability: self.probability(ball, target, field, kick, defenders),
            })
            .max_by(|a, b| {
                a.probability
                    .total_cmp(&b.probability)
                    // Equal chances: the target nearer the middle.
                    .then(b.target.y.abs().total_cmp(&a.target.y.abs()))
            })
            .unwrap_or(ShotChoice {
                target: Own::new(field.half_length(), 0.0),
                probability: 0.0,
            })
    }
}

#[cfg(test)]
mod tests;
