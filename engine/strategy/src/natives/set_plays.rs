//! Set plays: who takes them, where the others stand, and the double-touch rule (the player who
//! took a set play may not touch the ball again before another player has).

use super::host::{own, value};
use super::{AgentHost, Native, Ports};
use libero_behavior::{NodeSpec, ParamSpec, Status, Value, ValueType, Vec2};
use libero_skills::KickState;
use libero_world::Own;

pub(super) const NODES: &[Native] = &[
    Native::condition(has_role_ports, has_role),
    Native::query(role_position_ports, role_position),
    Native::action(beam_to_kick_place_ports, beam_to_kick_place),
    Native::condition(may_play_ball_ports, may_play_ball),
    Native::condition(taking_set_play_ports, taking_set_play),
];

/// Another robot this close to the ball [m] (torso to ball centre) has touched it, as far as
/// the taker can tell without being told.
const TOUCHED_WITHIN_M: f64 = 0.5;
/// A robot seen this recently counts for that [s].
const SEEN_WITHIN_S: f64 = 1.0;
/// After this long the taker plays the ball again whatever it saw [s].
const RELEASE_AFTER_S: f64 = 20.0;

fn has_role_ports() -> NodeSpec {
    NodeSpec::condition(
        "HasRole",
        "True when this player holds `role` in the formation of the current situation (the role names of formations/*.ron).",
    )
    .param(ParamSpec::new("role", ValueType::String).doc("a role name, e.g. `striker`"))
}

fn has_role(host: &AgentHost, ports: &Ports) -> bool {
    let unum = host.slot();
    host.strategy
        .formation_for(host.situation())
        .and_then(|f| f.roles.iter().find(|r| r.unum == unum))
        .is_some_and(|r| r.name == ports.str("role"))
}

fn role_position_ports() -> NodeSpec {
    NodeSpec::query(
        "role_position",
        ValueType::Vec2,
        "The formation position of the player holding `role` for the current situation and ball (m, own frame); this player's own position when no player holds it.",
    )
    .param(ParamSpec::new("role", ValueType::String).doc("a role name, e.g. `left_mid`"))
}

fn role_position(host: &AgentHost, ports: &Ports) -> Value {
    let role = ports.str("role");
    let position = host.strategy.formation_for(host.situation()).and_then(|f| {
        let unum = f.roles.iter().find(|r| r.name == role)?.unum;
        f.position(unum, value(host.ball()))
    });
    Value::Vec2(position.unwrap_or_else(|| value(host.me())))
}

fn beam_to_kick_place_ports() -> NodeSpec {
    NodeSpec::action(
        "BeamToKickPlace",
        "Beams to the kick skill's kicking place for a ball at `spot` kicked towards `target` (its place behind the ball from the skill parameters, facing along the kick): the set-play taker is ready to kick when play starts. Beams once the walk has come to a stop; succeeds when placed.",
    )
    .param(
        ParamSpec::new("target", ValueType::Vec2)
            .unit("m")
            .doc("where the kick goes, own frame"),
    )
    .param(
        ParamSpec::new("spot", ValueType::Vec2)
            .unit("m")
            .default(Value::Vec2(Vec2::new(0.0, 0.0)))
            .doc("where the ball will lie (the kick-off spot by default), own frame"),
    )
}

fn beam_to_kick_place(host: &mut AgentHost, ports: &Ports) -> Status {
    if host.still_moving_before_a_beam() {
        return Status::Running;
    }
    let spot = own(ports.vec2("spot"));
    let target = own(ports.vec2("target"));
    let geometry = host.skills.kick_geometry;
    // The server's balls curve: launch off the line so the ball comes to rest on it, as the
    // kick skill will aim (the curve is a matter of the global field direction).
    let (global_spot, global_target) = (host.global_of(spot), host.global_of(target));
    let field_deg = global_spot.bearing_to(global_target).to_degrees();
    let launch_deg = geometry.launch_heading_deg(field_deg, spot.distance(target), host.world);
    log::debug!(
        "beam to kick place: field {field_deg:.1}°, launch {launch_deg:.1}°, geometry {geometry:?}"
    );
    let turn = (launch_deg - field_deg).to_radians();
    let along = target - spot;
    let (s, c) = turn.sin_cos();
    let launched = spot + Own::new(c * along.x - s * along.y, s * along.x + c * along.y);
    host.intent.beam = Some(kicking_place(
        spot,
        launched,
        geometry.ball_ahead_m - geometry.beam_nearer_m,
        geometry.ball_beside_m,
    ));
    if host.world.game.side.is_some() {
        Status::Success
    } else {
        Status::Running
    }
}

/// The torso pose (x, y, yaw°) from which a foot kicks a ball at `spot` towards `target`: the
/// ball `ahead` in front of the torso and `beside` it towards the kicking foot's side (the kick
/// skill picks the foot on the ball's side of the robot). Of the two feet, the place further
/// back in the own half: a beam never places a robot in the opponent half (the server takes
/// x as −|x|), so a place beyond the half-way line would come out mirrored.
pub(crate) fn kicking_place(spot: Own, target: Own, ahead: f64, beside: f64) -> [f64; 3] {
    let towards = target - spot;
    let direction = if towards.norm() > 1e-6 {
        towards.scaled(1.0 / towards.norm())
    } else {
        Own::new(1.0, 0.0)
    };
    let left = Own::new(-direction.y, direction.x);
    let behind = spot - direction.scaled(ahead);
    // Left foot: the robot to the right of the kick line; right foot: to its left.
    let [left_foot, right_foot] = [behind - left.scaled(beside), behind + left.scaled(beside)];
    let at = if left_foot.x <= right_foot.x {
        left_foot
    } else {
        right_foot
    };
    [at.x, at.y, direction.y.atan2(direction.x).to_degrees()]
}

fn may_play_ball_ports() -> NodeSpec {
    NodeSpec::condition(
        "MayPlayBall",
        "False while this player took the last own set play and no other robot has been seen at the ball since (the double-touch rule); true otherwise.",
    )
}

fn may_play_ball(host: &AgentHost, _: &Ports) -> bool {
    let Some(kicked_at) = host.memory.set_play_kick_at.get() else {
        return true;
    };
    let mode = host.team_play_mode();
    if mode != "PlayOn" {
        // Still taking it, or a new situation: either way the rule is done with.
        if !host.taking_set_play() {
            host.memory.set_play_kick_at.set(None);
        }
        return true;
    }
    // A kick under way finishes (the rule allows touches within the first second).
    if matches!(host.skills.kick, KickState::Kicking) {
        return true;
    }
    let world = host.world;
    let ball = host.ball();
    let touched = world.players.known.iter().any(|p| {
        p.age(world.time) <= SEEN_WITHIN_S
            && p.unum != world.game.unum
            && host.own_of(p.position).distance(ball) <= TOUCHED_WITHIN_M
    }) || world.time - kicked_at > RELEASE_AFTER_S;
    if touched {
        host.memory.set_play_kick_at.set(None);
    }
    touched
}

fn taking_set_play_ports() -> NodeSpec {
    NodeSpec::condition(
        "TakingSetPlay",
        "True during a set play of ours: kick-off, throw-in, corner, goal kick or free kick.",
    )
}

fn taking_set_play(host: &AgentHost, _: &Ports) -> bool {
    host.taking_set_play()
}

impl AgentHost<'_> {
    /// An own set play (kick-off, throw-in, corner, goal kick, free kick) is being taken.
    pub(crate) fn taking_set_play(&self) -> bool {
        let mode = self.team_play_mode();
        mode.ends_with("Own") && mode != "GoalOwn"
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ball_in_robot_frame(place: [f64; 3], spot: Own) -> [f64; 2] {
        let (s, c) = place[2].to_radians().sin_cos();
        let (dx, dy) = (spot.x - place[0], spot.y - place[1]);
        [c * dx + s * dy, -s * dx + c * dy]
    }

    #[test]
    fn the_kicking_place_puts_the_ball_ahead_and_beside_a_foot_facing_the_target() {
        let spot = Own::new(0.0, 0.0);
        for target in [Own::new(0.0, 2.6), Own::new(-0.5, -2.5), Own::new(3.0, 0.5)] {
            let place = kicking_place(spot, target, 0.36, 0.1);
            let [ahead, beside] = ball_in_robot_frame(place, spot);
            assert!((ahead - 0.36).abs() < 1e-9, "{target:?}: {ahead}");
            assert!((beside.abs() - 0.1).abs() < 1e-9, "{target:?}: {beside}");
            let facing = place[2].to_radians();
            let bearing = target.y.atan2(target.x);
            assert!((facing - bearing).abs() < 1e-9);
            // Never beyond the half-way line, where a beam would mirror it.
            assert!(place[0] <= 0.0, "{target:?}: {place:?}");
        }
    }
}
