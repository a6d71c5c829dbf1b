//! Aiming for the ball's curve: the kicking place and the roll-outs the decision layer needs,
//! and the launch direction that brings a curving ball to rest on the line asked for.

use super::KickParams;
use libero_world::World;

/// The kicking place and the curve of the kicks, as the decision layer needs them to beam a
/// set-play taker straight to its place.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct KickGeometry {
    /// At the kicking place the ball is this far ahead of the torso [m] ...
    pub ball_ahead_m: f64,
    /// ... and this far beside it, towards the kicking foot [m].
    pub ball_beside_m: f64,
    /// A beam to the kicking place lands this much nearer the ball (the stand pose's torso
    /// sits further forward than the walk posture's the kick starts from) [m].
    pub beam_nearer_m: f64,
    pub long_kick_from_m: f64,
    pub short_roll_out_m: f64,
    pub long_roll_out_m: f64,
    pub short_curve_share: f64,
    pub long_curve_share: f64,
}

impl Default for KickGeometry {
    /// Before the skill has reported: the shipped T1 place, kicks taken as straight.
    fn default() -> Self {
        Self {
            ball_ahead_m: 0.36,
            ball_beside_m: 0.1,
            beam_nearer_m: 0.0,
            long_kick_from_m: 3.0,
            short_roll_out_m: 0.0,
            long_roll_out_m: 0.0,
            short_curve_share: 1.0,
            long_curve_share: 1.0,
        }
    }
}

impl KickGeometry {
    pub fn of(k: &KickParams) -> Self {
        Self {
            ball_ahead_m: k.approach.ball_ahead_m,
            ball_beside_m: k.approach.ball_beside_m,
            beam_nearer_m: k.approach.beam_nearer_m,
            long_kick_from_m: k.long_kick_from_m,
            short_roll_out_m: k.short.roll_out_m,
            long_roll_out_m: k.long.roll_out_m,
            short_curve_share: k.short.curve_share,
            long_curve_share: k.long.curve_share,
        }
    }

    /// The field heading [deg] to launch a kick at so that its curving roll crosses the line
    /// `field_deg` `distance_m` away, or comes to rest on it when it rolls no farther (what
    /// [`aimed_for_curve`] asks of the skill).
    pub fn launch_heading_deg(&self, field_deg: f64, distance_m: f64, world: &World) -> f64 {
        let (roll_out, curve_share) = if distance_m >= self.long_kick_from_m {
            (self.long_roll_out_m, self.long_curve_share)
        } else {
            (self.short_roll_out_m, self.short_curve_share)
        };
        if roll_out <= 0.0 {
            return field_deg;
        }
        world
            .params
            .ball
            .launch_table
            .launch_heading_through(field_deg.to_radians(), roll_out, distance_m, curve_share)
            .to_degrees()
    }
}

/// The robot-frame direction to launch the ball in so that, curving as the server's ball does,
/// its roll crosses the line `direction_deg` (robot frame) asks for `distance_m` away (where a
/// shot crosses the goal line, where a pass meets its receiver), or comes to rest on it when it
/// rolls no farther. Uses the agent's own heading estimate: the curve depends on the direction
/// in the field.
pub fn aimed_for_curve(direction_deg: f64, distance_m: f64, world: &World, k: &KickParams) -> f64 {
    let field_deg = world.me.yaw_deg + direction_deg;
    let launch_deg = KickGeometry::of(k).launch_heading_deg(field_deg, distance_m, world);
    if launch_deg == field_deg {
        // No roll-out: the direction as asked, not a round trip through the field frame.
        return direction_deg;
    }
    libero_world::geometry::wrap_deg(direction_deg + launch_deg - field_deg)
}
