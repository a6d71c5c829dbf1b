//! The goalkeeper's nodes: the defense point, shots on goal and saves, clearing the ball
//! (`formations/goalkeeper.ron`, logic in `crate::goalkeeper`).

use super::host::value;
use super::{AgentHost, Native, Ports};
use crate::goalkeeper::{Save, Shot};
use libero_behavior::{NodeSpec, Status, Value, ValueType};
use libero_skills::save::{DiveSide, SaveState};
use libero_skills::BodyIntent;
use libero_world::{Global, Own, Relation};

pub(super) const NODES: &[Native] = &[
    Native::query(defense_point_ports, defense_point),
    Native::condition(shot_on_goal_ports, shot_on_goal),
    Native::action(defend_goal_ports, defend_goal),
    Native::action(save_shot_ports, save_shot),
    Native::condition(should_clear_ball_ports, should_clear_ball),
    Native::query(clear_target_ports, clear_target),
];

fn defense_point_ports() -> NodeSpec {
    NodeSpec::query(
        "defense_point",
        ValueType::Vec2,
        "Where the keeper stands to cover the goal for the ball's position (m, own frame; formations/goalkeeper.ron).",
    )
}

fn defense_point(host: &AgentHost, _: &Ports) -> Value {
    Value::Vec2(value(host.defense_point()))
}

fn shot_on_goal_ports() -> NodeSpec {
    NodeSpec::condition(
        "ShotOnGoal",
        "True when the ball prediction has the ball crossing our goal line between the posts (with the file's margin) at shot speed.",
    )
}

fn shot_on_goal(host: &AgentHost, _: &Ports) -> bool {
    host.shot_on_goal().is_some()
}

fn defend_goal_ports() -> NodeSpec {
    NodeSpec::action(
        "DefendGoal",
        "Walks to the defense point (the walk stops there by itself) facing the ball, the head on the ball while it is known; runs until halted.",
    )
}

fn defend_goal(host: &mut AgentHost, _: &Ports) -> Status {
    let point = host.defense_point();
    let ball = host.ball();
    host.walk_to(point, Some(ball), false, f64::INFINITY, 0.0);
    // The head stays on the ball, but a keeper that only watches the ball sees too few
    // landmarks and its self-estimate drifts (then every ball estimate is wrong): it scans
    // for `scan_s` every `scan_every_s`.
    let keeper = host.goalkeeper();
    let phase = host.world.time % keeper.scan_every_s.max(keeper.scan_s + 0.1);
    let ball_known = host.world.ball.age(host.world.time) < 3.0;
    if ball_known && phase >= keeper.scan_s {
        host.look_at_ball();
    } else {
        host.intent.head = libero_skills::HeadIntent::LookAround {
            amplitude_deg: None,
            period_s: Some(keeper.scan_s.max(0.5)),
        };
    }
    Status::Running
}

fn save_shot_ports() -> NodeSpec {
    NodeSpec::action(
        "SaveShot",
        "Meets a shot on goal: walks to where the ball's path passes closest to the keeper while there is time, stands square to a ball coming at it, dives to its side when walking is too slow (the save motions in the skill parameters). Succeeds once no shot is coming or the save motion has played out.",
    )
}

fn save_shot(host: &mut AgentHost, _: &Ports) -> Status {
    match host.skills.save {
        // The motion plays to its end whatever is asked; keep asking for it meanwhile.
        SaveState::Diving(side) => {
            host.intent.body = BodyIntent::Dive { side };
            return Status::Running;
        }
        // Played out: stop asking, so the get-up follows.
        SaveState::Done(_) => return Status::Success,
        SaveState::Idle => {}
    }
    let Some(shot) = host.shot_on_goal() else {
        return Status::Success;
    };
    let keeper = host.goalkeeper();
    let ball = host.ball();
    log::debug!(
        "t {:.2} keeper {:?} shot {:?} -> {:?}",
        host.world.time,
        host.me(),
        shot,
        keeper.save(&shot)
    );
    match keeper.save(&shot) {
        Save::Walk(point) => host.walk_towards(point, Some(ball), f64::INFINITY),
        // Square to the ball with the feet together: the block motion spreads the legs, and a
        // ground ball at the keeper's middle rolled through between them.
        Save::Block => host.intent.body = BodyIntent::Stand,
        Save::Dive { left } => {
            let side = if left {
                DiveSide::Left
            } else {
                DiveSide::Right
            };
            host.intent.body = BodyIntent::Dive { side };
        }
    }
    host.look_at_ball();
    Status::Running
}

fn should_clear_ball_ports() -> NodeSpec {
    NodeSpec::condition(
        "ShouldClearBall",
        "True when the ball lies within the file's distance of our goal and we reach it sooner than any opponent by the file's margin (the world model's interception estimates).",
    )
}

fn should_clear_ball(host: &AgentHost, _: &Ports) -> bool {
    let keeper = host.goalkeeper();
    let world = host.world;
    if world.ball.age(world.time) > 2.0 {
        return false;
    }
    let speed = keeper.walk_speed_m_s;
    let reach = 0.3;
    let ours = world
        .ball
        .interception(world.me.position, speed, reach)
        .map(|(t, _)| t);
    let theirs = world
        .players
        .of(Relation::Opponent)
        .filter(|p| !p.fallen && p.age(world.time) < 3.0)
        .filter_map(|p| {
            world
                .ball
                .interception(p.position, speed, reach)
                .map(|(t, _)| t)
        })
        .reduce(f64::min);
    keeper.should_clear(host.ball(), &host.strategy.field(), ours, theirs)
}

fn clear_target_ports() -> NodeSpec {
    NodeSpec::query(
        "clear_target",
        ValueType::Vec2,
        "Where the keeper clears the ball to: up the field, away from the middle (m, own frame).",
    )
}

fn clear_target(host: &AgentHost, _: &Ports) -> Value {
    let ball = host.ball();
    let field = host.strategy.field();
    let side = if ball.y >= 0.0 { 1.0 } else { -1.0 };
    let target = Own::new(ball.x + 12.0, side * field.half_width() * 0.6);
    Value::Vec2(value(target))
}

impl AgentHost<'_> {
    pub(crate) fn goalkeeper(&self) -> crate::GoalkeeperParams {
        self.strategy.goalkeeper.unwrap_or_default()
    }

    pub(crate) fn defense_point(&self) -> Own {
        self.goalkeeper()
            .defense_point(self.ball(), &self.strategy.field())
    }

    /// The shot coming at our goal, if any: where its path passes closest to the keeper, how
    /// far to the keeper's left (robot frame) and when. Measured relative to the keeper's own
    /// estimate, the closest approach does not move with a constant error of that estimate (a
    /// few degrees of yaw put the path's crossing of a field line a metre off at 8 m).
    pub(crate) fn shot_on_goal(&self) -> Option<Shot> {
        *self.tick.shot_on_goal.get_or_init(|| self.predict_shot())
    }

    fn predict_shot(&self) -> Option<Shot> {
        let world = self.world;
        let keeper = self.goalkeeper();
        let ball = &world.ball;
        let [vx, vy] = ball.velocity;
        let speed = vx.hypot(vy);
        if ball.age(world.time) > 0.5 || speed < keeper.shot_min_speed_m_s {
            return None;
        }
        let field = self.strategy.field();
        let side = world.side();
        // On target: the path crosses our goal line between the posts (with the margin).
        let along_line = side.global(Own::new(0.0, 1.0));
        let goal_point = side.global(Own::new(-field.half_length(), 0.0));
        let (_, at_goal) = ball.line_crossing(goal_point.to_array(), along_line.to_array())?;
        if !keeper.on_target(side.own(Global::from_array(at_goal)).y, &field) {
            return None;
        }
        // Closest approach to the keeper, reached before the ball stops.
        let pose = world.pose();
        let me = pose.position;
        let from = Global::from_array(ball.position);
        let u = Global::new(vx / speed, vy / speed);
        let s = (me.x - from.x) * u.x + (me.y - from.y) * u.y;
        if s <= 0.0 {
            return None;
        }
        let passes_at = from + u.scaled(s);
        let normal = Global::new(-u.y, u.x);
        let (in_s, _) = ball.line_crossing(passes_at.to_array(), normal.to_array())?;
        Some(Shot {
            passes_at: side.own(passes_at),
            offset_left_m: pose.robot(passes_at).y,
            in_s,
        })
    }
}
