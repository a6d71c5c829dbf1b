//! Pass utility (thesis 6.3 and its future work, "pass"): where a long kick should send the ball
//! when no shot is good. Directions are sampled in a fan round the line to the opponents' goal;
//! the ball stops a measured long kick's distance along each (skill parameters, `measured`). A
//! direction is worth its progress towards their goal and the race for the stop point (our
//! nearest player against theirs), times the chance that the ball gets past the opponents near
//! its path (the kick's direction spread) and that it stops on the field (or in their goal).
//! Numbers in `formations/pass.ron`. Own frame: the opponents' goal is at +x.

use crate::files::Field;
use crate::shot::{passes_by, within, MAX_DEFENDERS};
use libero_skills::kick::KickSpread;
use libero_world::Own;

/// A teammate this close to the stop point along the path receives the ball there [m]; one
/// farther short of it is in the ball's way.
const TEAMMATE_RECEIVES_WITHIN_M: f64 = 1.5;

/// `formations/pass.ron`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PassParams {
    /// Directions sampled, evenly across the fan.
    pub directions: usize,
    /// The fan's half-width either side of the line to their goal [deg].
    pub fan_deg: f64,
    /// The ball must stop at least this far inside the touch and goal lines [m] (a ball into
    /// their goal mouth counts as on the field).
    pub field_margin_m: f64,
    /// An opponent blocks a ball passing within this of it [m].
    pub block_radius_m: f64,
    /// Walking speed of every player in the race for the stop point [m/s].
    pub walk_speed_m_s: f64,
    /// The race's scale: our player this many seconds first makes the race term ~0.73 [s].
    pub race_scale_s: f64,
    /// An opponent is taken to reach any point within this long, seen or not [s] (robots out
    /// of view; without it, on an empty field every direction's race was won alike and a
    /// free teammate counted for nothing).
    pub opponent_at_most_s: f64,
    /// Weight of the progress towards their goal ...
    pub progress_weight: f64,
    /// ... and of the race for the stop point.
    pub race_weight: f64,
    /// A new direction must be this much better than the one chosen before to replace it
    /// (estimates jitter; a target that swings makes the approach circle the ball).
    pub hysteresis: f64,
    /// While a teammate within this of the ball is about to play it [m], the formation slot
    /// nearest to where its pass would stop moves to the receiving spot beside that point (0:
    /// never; the receiver then walks there only once the ball rolls).
    pub anticipate_within_m: f64,
    /// Within this of the ball [m] on the kick's approach, the direction held is kept whatever
    /// another is worth, while it is worth anything: teammates walking across the paths made
    /// the choice step 10 deg at a time, and each step cost the robot at the ball another
    /// alignment (NOTES.md, session 22). 0: never.
    pub commit_within_m: f64,
    /// The receiving spot lies this far beside the pass's stop point, off its path [m].
    pub receive_beside_m: f64,
}

impl Default for PassParams {
    fn default() -> Self {
        Self {
            directions: 19,
            fan_deg: 90.0,
            field_margin_m: 1.0,
            block_radius_m: 0.5,
            walk_speed_m_s: 0.5,
            race_scale_s: 4.0,
            opponent_at_most_s: 10.0,
            progress_weight: 1.0,
            race_weight: 1.0,
            hysteresis: 0.1,
            anticipate_within_m: 0.0,
            commit_within_m: 0.0,
            receive_beside_m: 1.0,
        }
    }
}

/// The players in the race for a stop point (own frame; ours without the kicker).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct PassField {
    pub teammates: arrayvec::ArrayVec<Own, MAX_DEFENDERS>,
    pub opponents: arrayvec::ArrayVec<Own, MAX_DEFENDERS>,
}

/// How firmly the direction chosen before is held.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Commitment {
    /// Not kicking yet: against `hysteresis` only.
    Free,
    /// On the kick's approach: also while worth half the best.
    Approach,
    /// On the approach within `commit_within_m` of the ball: while worth anything.
    AtBall,
}

/// A pass: where the ball should stop, and what it is worth.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PassChoice {
    /// The stop point: the target a `KickTo` aims at.
    pub target: Own,
    /// Its direction from the ball [rad], own frame.
    pub direction: f64,
    pub utility: f64,
}

impl PassParams {
    /// The sampled directions [rad], own frame, from the right edge of the fan to the left.
    pub fn directions(&self, ball: Own, field: &Field) -> impl Iterator<Item = f64> {
        let towards_goal = ball.bearing_to(Own::new(field.half_length(), 0.0));
        let half = self.fan_deg.to_radians();
        let n = self.directions.max(1);
        (0..n).map(move |i| {
            if n == 1 {
                towards_goal
            } else {
                towards_goal - half + 2.0 * half * i as f64 / (n - 1) as f64
            }
        })
    }

    /// What a long kick from `ball` in `direction` is worth (0..1).
    pub fn utility(
        &self,
        ball: Own,
        direction: f64,
        field: &Field,
        kick: &KickSpread,
        players: &PassField,
    ) -> f64 {
        let along = Own::new(direction.cos(), direction.sin());
        let rolls = kick.distance_along(along.x, along.y);
        let Some((stop, travel)) = self.stop_point(ball, along, rolls, field) else {
            return 0.0;
        };
        if travel < 1e-6 {
            return 0.0;
        }
        let sigma = kick.direction_sd_deg.to_radians();
        // Into their goal: the direction error moves the crossing along the goal line, and
        // beside the posts it is a goal kick for them (from a sharp angle most kicks are).
        let goal_line = field.half_length();
        let on_target = if stop.x >= goal_line - 1e-9 {
            let half_goal = field.goal_half_width();
            let sd = travel * sigma.tan() / along.x.max(1e-3);
            within(stop.y, sd, -half_goal, half_goal)
        } else {
            1.0
        };
        let clear: f64 = players
            .opponents
            .iter()
            .map(|p| passes_by(ball, along, travel, sigma, *p, self.block_radius_m))
            .product();
        // A teammate in the path short of the stop point gets the ball at full speed against
        // its legs, and it bounces anywhere (scenarios/pass.ron, NOTES.md session 16); one
        // waiting at the stop point is the receiver.
        let short_of_stop = (travel - TEAMMATE_RECEIVES_WITHIN_M).max(0.0);
        let unhindered: f64 = players
            .teammates
            .iter()
            .map(|p| passes_by(ball, along, short_of_stop, sigma, *p, self.block_radius_m))
            .product();
        let clear = clear * unhindered;
        let goal = Own::new(field.half_length(), 0.0);
        // -1 (straight back) .. 1 (the kick's whole length towards their goal, or into it).
        let to_goal = ball.distance(goal);
        let progress = (to_goal - stop.distance(goal)) / rolls.min(to_goal).max(1.0);
        let speed = self.walk_speed_m_s.max(1e-3);
        let first = |of: &[Own]| {
            of.iter()
                .map(|p| p.distance(stop) / speed)
                .fold(f64::INFINITY, f64::min)
        };
        // The kicker itself follows the ball: it is in the race from the ball's spot.
        let ours = first(&players.teammates).min(travel / speed);
        let theirs = first(&players.opponents).min(self.opponent_at_most_s);
        let race = 1.0 / (1.0 + (-(theirs - ours) / self.race_scale_s.max(1e-3)).exp());
        let weights = (self.progress_weight + self.race_weight).max(1e-9);
        let worth =
            (self.progress_weight * 0.5 * (progress + 1.0) + self.race_weight * race) / weights;
        on_target * clear * worth
    }

    /// Where a ball kicked from `ball` along the unit vector `along` stops, and how far it
    /// travels: `distance` on, or where it crosses their goal line between the posts. None when
    /// it would stop off the field (within the margin) or leave it anywhere else.
    fn stop_point(
        &self,
        ball: Own,
        along: Own,
        distance: f64,
        field: &Field,
    ) -> Option<(Own, f64)> {
        let (hl, hw) = (field.half_length(), field.half_width());
        let stop = Own::new(ball.x + along.x * distance, ball.y + along.y * distance);
        if stop.x > hl && along.x > 1e-9 {
            let travel = (hl - ball.x) / along.x;
            let y = ball.y + along.y * travel;
            return (y.abs() < field.goal_half_width()).then_some((Own::new(hl, y), travel));
        }
        let margin = self.field_margin_m;
        let inside = stop.x.abs() <= hl - margin && stop.y.abs() <= hw - margin;
        inside.then_some((stop, distance))
    }

    /// The best direction; `kept` (the direction chosen before) stays unless another is
    /// `hysteresis` better, or, `commitment` `Approach` (the kick is under way), while it is
    /// worth at least half the best, or, `AtBall`, while it is worth anything.
    pub fn best(
        &self,
        ball: Own,
        field: &Field,
        kick: &KickSpread,
        players: &PassField,
        kept: Option<f64>,
        commitment: Commitment,
    ) -> PassChoice {
        let choice = |direction: f64| {
            let utility = self.utility(ball, direction, field, kick, players);
            let along = Own::new(direction.cos(), direction.sin());
            let target = self
                .stop_point(ball, along, kick.distance_along(along.x, along.y), field)
                .map_or(ball, |(stop, _)| stop);
            PassChoice {
                target,
                direction,
                utility,
            }
        };
        let best = self
            .directions(ball, field)
            .map(choice)
            .max_by(|a, b| a.utility.total_cmp(&b.utility))
            .unwrap_or_else(|| choice(0.0));
        match kept.map(choice) {
            Some(old)
                if old.utility > 0.0
                    && (old.utility + self.hysteresis >= best.utility
                        || match commitment {
                            Commitment::Free => false,
                            Commitment::Approach => 2.0 * old.utility >= best.utility,
                            Commitment::AtBall => true,
                        }) =>
            {
                old
            }
            _ => best,
        }
    }
}

impl PassChoice {
    /// Where a teammate waits for this pass: `beside` metres off its path at the stop point,
    /// on the side of `from`.
    pub fn receiving_spot(&self, beside: f64, from: Own) -> Own {
        let across = Own::new(-self.direction.sin(), self.direction.cos());
        let side = if (from - self.target).x * across.x + (from - self.target).y * across.y < 0.0 {
            -1.0
        } else {
            1.0
        };
        self.target + across.scaled(side * beside)
    }
}

#[cfg(test)]
mod tests;
