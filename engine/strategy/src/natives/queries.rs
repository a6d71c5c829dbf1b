//! World queries: where things are, in the team's own frame.

use super::host::{own, value};
use super::{AgentHost, Native, Ports};
use libero_behavior::{NodeSpec, ParamSpec, Value, ValueType, Vec2};
use libero_world::{Own, Relation};

pub(super) const NODES: &[Native] = &[
    Native::query(opponent_goal_ports, opponent_goal),
    Native::query(ball_position_ports, ball_position),
    Native::query(ball_distance_ports, ball_distance),
    Native::query(my_position_ports, my_position),
    Native::query(formation_position_ports, formation_position),
    Native::query(play_time_ports, play_time),
    Native::query(am_closest_to_ball_ports, am_closest_to_ball),
    Native::query(distance_ports, distance),
];

fn distance_ports() -> NodeSpec {
    NodeSpec::query(
        "distance",
        ValueType::Float,
        "Distance between two field points (m), e.g. from the ball to the opponent goal.",
    )
    .param(
        ParamSpec::new("from", ValueType::Vec2)
            .unit("m")
            .doc("a point, own frame"),
    )
    .param(
        ParamSpec::new("to", ValueType::Vec2)
            .unit("m")
            .doc("another point, own frame"),
    )
}

fn distance(_: &AgentHost, ports: &Ports) -> Value {
    Value::Float(own(ports.vec2("from")).distance(own(ports.vec2("to"))))
}

fn opponent_goal_ports() -> NodeSpec {
    NodeSpec::query(
        "opponent_goal",
        ValueType::Vec2,
        "Centre of the opponent's goal line (m, own frame), from the team file's field; with `in_front`, the point that far in front of it on the field's long axis (where a cross from the wing is aimed).",
    )
    .param(
        ParamSpec::new("in_front", ValueType::Float)
            .unit("m")
            .range(0.0, 30.0)
            .default(Value::Float(0.0))
            .doc("distance in front of the goal line"),
    )
}

fn opponent_goal(host: &AgentHost, ports: &Ports) -> Value {
    let goal = host.strategy.field().opponent_goal();
    Value::Vec2(Vec2::new(goal.x - ports.float("in_front"), goal.y))
}

fn ball_position_ports() -> NodeSpec {
    NodeSpec::query(
        "ball_position",
        ValueType::Vec2,
        "Estimated ball position (m, own frame).",
    )
}

fn ball_position(host: &AgentHost, _: &Ports) -> Value {
    Value::Vec2(value(host.ball()))
}

fn ball_distance_ports() -> NodeSpec {
    NodeSpec::query(
        "ball_distance",
        ValueType::Float,
        "Distance from the robot to the ball (m).",
    )
}

fn ball_distance(host: &AgentHost, _: &Ports) -> Value {
    Value::Float(host.ball().distance(host.me()))
}

fn my_position_ports() -> NodeSpec {
    NodeSpec::query(
        "my_position",
        ValueType::Vec2,
        "Estimated robot position (m, own frame).",
    )
}

fn my_position(host: &AgentHost, _: &Ports) -> Value {
    Value::Vec2(value(host.me()))
}

fn formation_position_ports() -> NodeSpec {
    NodeSpec::query(
        "formation_position",
        ValueType::Vec2,
        "This player's formation position for the situation and ball (m, own frame): in play, that of the slot the role assignment gives it; with `clear_of_ball`, a position inside that circle round the ball is moved out to its edge (the referee relocates defenders within the centre-circle radius of an opponent set play's ball).",
    )
    .param(
        ParamSpec::new("clear_of_ball", ValueType::Float)
            .unit("m")
            .range(0.0, 20.0)
            .default(Value::Float(0.0))
            .doc("keep at least this far from the ball; 0 = no limit"),
    )
}

fn formation_position(host: &AgentHost, ports: &Ports) -> Value {
    let position = host.held_slot().moved_to.unwrap_or_else(|| {
        own(host
            .strategy
            .position(host.situation(), host.slot(), value(host.ball_at_rest()))
            .unwrap_or_else(|| value(host.me())))
    });
    let clear = ports.float("clear_of_ball");
    Value::Vec2(value(clear_of(position, host.ball(), clear)))
}

/// `p` moved radially out of the circle of `radius` round `ball` (from the ball's side away
/// from `p`; straight back towards the own goal when `p` is the ball itself).
pub(crate) fn clear_of(p: Own, ball: Own, radius: f64) -> Own {
    let away = p - ball;
    if radius <= 0.0 || away.norm() >= radius {
        return p;
    }
    let direction = if away.norm() > 1e-6 {
        away.scaled(1.0 / away.norm())
    } else {
        Own::new(-1.0, 0.0)
    };
    ball + direction.scaled(radius)
}

fn play_time_ports() -> NodeSpec {
    NodeSpec::query(
        "play_time",
        ValueType::Float,
        "Seconds since kick-off of the half.",
    )
}

fn play_time(host: &AgentHost, _: &Ports) -> Value {
    Value::Float(host.world.game.play_time)
}

fn am_closest_to_ball_ports() -> NodeSpec {
    NodeSpec::query(
        "am_closest_to_ball",
        ValueType::Bool,
        "True when no upright teammate seen in the last 2 s is closer to the ball.",
    )
}

fn am_closest_to_ball(host: &AgentHost, _: &Ports) -> Value {
    let world = host.world;
    let ball = world.ball.position;
    let dist = |p: [f64; 2]| (p[0] - ball[0]).hypot(p[1] - ball[1]);
    let mine = dist(world.me.position);
    Value::Bool(
        world
            .players
            .of(Relation::Teammate)
            .filter(|p| !p.fallen && p.age(world.time) < 2.0)
            .all(|p| dist(p.position) >= mine),
    )
}
