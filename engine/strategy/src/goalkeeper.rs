//! The goalkeeper (thesis 6.2): where to stand to cover the goal (the defense point), when to
//! leave it to clear the ball, and how to meet a shot. Numbers in `formations/goalkeeper.ron`.
//! Everything here is in the team's own frame (own goal at −x).

use crate::files::Field;
use libero_world::Own;

/// The line the defense point lies on.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DefenseLine {
    /// From the goal centre towards the ball.
    BallLine,
    /// The bisector of the angle the two posts make at the ball.
    PostBisector,
}

/// `formations/goalkeeper.ron`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GoalkeeperParams {
    pub line: DefenseLine,
    /// Distance out along the line: `min_distance_m + distance_per_ball_m` × the ball's
    /// distance, at most `max_distance_m` [m] ...
    pub min_distance_m: f64,
    pub max_distance_m: f64,
    pub distance_per_ball_m: f64,
    /// ... never closer to the goal line than this [m] ...
    pub min_line_offset_m: f64,
    /// ... and this far inside the goal area at least [m].
    pub area_margin_m: f64,
    /// The keeper goes for the ball when it lies this close to the goal centre [m] ...
    pub clear_within_m: f64,
    /// ... and the keeper reaches it this much sooner than any opponent [s].
    pub clear_margin_s: f64,
    /// Walking speed assumed when estimating who reaches the ball first [m/s].
    pub walk_speed_m_s: f64,
    /// A ball slower than this is not a shot [m/s].
    pub shot_min_speed_m_s: f64,
    /// A ball crossing the goal line this far outside a post still counts as a shot [m].
    pub post_margin_m: f64,
    /// The save motion starts once the ball is this close in time to the keeper's line [s].
    pub save_within_s: f64,
    /// A ball passing within this of the keeper is met by a block [m] ...
    pub block_reach_m: f64,
    /// ... one within this by a dive to its side [m]; beyond, the keeper can only walk.
    pub dive_reach_m: f64,
    /// While defending, the head leaves the ball to scan for landmarks every this long [s] ...
    pub scan_every_s: f64,
    /// ... for this long [s].
    pub scan_s: f64,
}

impl Default for GoalkeeperParams {
    fn default() -> Self {
        Self {
            line: DefenseLine::BallLine,
            min_distance_m: 0.6,
            max_distance_m: 2.0,
            distance_per_ball_m: 0.08,
            min_line_offset_m: 0.3,
            area_margin_m: 0.3,
            clear_within_m: 5.0,
            clear_margin_s: 1.0,
            walk_speed_m_s: 0.4,
            shot_min_speed_m_s: 0.6,
            post_margin_m: 0.3,
            save_within_s: 1.2,
            block_reach_m: 0.35,
            dive_reach_m: 1.3,
            scan_every_s: 4.0,
            scan_s: 1.0,
        }
    }
}

/// A ball on its way into our goal, as the ball prediction sees it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Shot {
    /// Where its path passes closest to the keeper ...
    pub passes_at: Own,
    /// ... that far to the keeper's left (robot frame; negative: right) [m] ...
    pub offset_left_m: f64,
    /// ... in this many seconds.
    pub in_s: f64,
}

/// What the keeper does about a shot this cycle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Save {
    /// Walk to the crossing point: there is time.
    Walk(Own),
    /// The ball comes at the keeper: block.
    Block,
    /// Dive to the keeper's left or right.
    Dive { left: bool },
}

impl GoalkeeperParams {
    /// Where the keeper stands for a ball at `ball` (thesis 6.2): on the chosen line, farther
    /// out the farther the ball, inside the goal area.
    pub fn defense_point(&self, ball: Own, field: &Field) -> Own {
        let goal_x = -field.half_length();
        let half_goal = field.goal_half_width();
        let origin = match self.line {
            DefenseLine::BallLine => Own::new(goal_x, 0.0),
            DefenseLine::PostBisector => {
                // The bisector from the ball meets the goal line where it divides the mouth in
                // the ratio of the ball's distances to the posts (angle bisector theorem).
                let left = Own::new(goal_x, half_goal);
                let right = Own::new(goal_x, -half_goal);
                let (dl, dr) = (ball.distance(left), ball.distance(right));
                if dl + dr < 1e-9 {
                    Own::new(goal_x, 0.0)
                } else {
                    left.lerp(right, dl / (dl + dr))
                }
            }
        };
        let offset = ball - origin;
        let length = offset.norm();
        let direction = if length < 1e-9 {
            Own::new(1.0, 0.0)
        } else {
            offset.scaled(1.0 / length)
        };
        let out = (self.min_distance_m + self.distance_per_ball_m * length)
            .min(self.max_distance_m)
            .max(self.min_distance_m);
        let p = origin + direction.scaled(out);
        let (depth, half_width) = field.goal_area();
        let x_max = (goal_x + depth - self.area_margin_m).max(goal_x + self.min_line_offset_m);
        let y_max = (half_width - self.area_margin_m).max(0.0);
        Own::new(
            p.x.clamp(goal_x + self.min_line_offset_m, x_max),
            p.y.clamp(-y_max, y_max),
        )
    }

    /// Whether a ball that crosses the goal line at `y` (own frame) is on target, with the
    /// margin outside the posts.
    pub fn on_target(&self, y: f64, field: &Field) -> bool {
        y.abs() <= field.goal_half_width() + self.post_margin_m
    }

    /// How the keeper meets `shot`: it walks to where the ball passes while there is time
    /// (or the ball passes beyond any dive), blocks a ball coming at it, dives beside it.
    pub fn save(&self, shot: &Shot) -> Save {
        let offset = shot.offset_left_m;
        let walk_time = offset.abs() / self.walk_speed_m_s.max(1e-3);
        let soon = shot.in_s <= self.save_within_s;
        if offset.abs() <= self.block_reach_m {
            if soon {
                Save::Block
            } else {
                Save::Walk(shot.passes_at)
            }
        } else if walk_time <= shot.in_s || !soon || offset.abs() > self.dive_reach_m {
            Save::Walk(shot.passes_at)
        } else {
            Save::Dive { left: offset > 0.0 }
        }
    }

    /// Whether the keeper should leave its point to clear the ball: it lies within
    /// `clear_within_m` of our goal and we get there `clear_margin_s` before any opponent.
    pub fn should_clear(
        &self,
        ball: Own,
        field: &Field,
        our_time: Option<f64>,
        opponents_best: Option<f64>,
    ) -> bool {
        let goal = Own::new(-field.half_length(), 0.0);
        if ball.distance(goal) > self.clear_within_m {
            return false;
        }
        match (our_time, opponents_best) {
            (Some(ours), Some(theirs)) => ours + self.clear_margin_s <= theirs,
            (Some(_), None) => true,
            (None, _) => false,
        }
    }
}

#[cfg(test)]
mod tests;
