//! Dribbling: walking the ball to a field point (the skill in `libero_skills::dribble`).

use super::host::own;
use super::{AgentHost, Native, Ports};
use libero_behavior::{NodeSpec, ParamSpec, Status, Value, ValueType};
use libero_skills::BodyIntent;
use libero_world::Own;

pub(super) const NODES: &[Native] = &[Native::action(dribble_to_ports, dribble_to)];

fn dribble_to_ports() -> NodeSpec {
    NodeSpec::action(
        "DribbleTo",
        "Walks the ball to a field point: round obstacles (never through the ball) to behind the ball on the line to the target, then on through it without stopping, steering and turning with the ball. Succeeds once the ball is within `tolerance` of the target; fails when the ball has not been seen for `lost_after` seconds.",
    )
    .param(
        ParamSpec::new("target", ValueType::Vec2)
            .unit("m")
            .doc("where the ball should go, own frame"),
    )
    .param(
        ParamSpec::new("tolerance", ValueType::Float)
            .unit("m")
            .range(0.1, 10.0)
            .default(Value::Float(0.5))
            .doc("the ball this close to the target is there"),
    )
    .param(
        ParamSpec::new("kick_beyond", ValueType::Float)
            .unit("m")
            .range(0.0, 1000.0)
            .default(Value::Float(1000.0))
            .doc("while the ball is farther than this from the target, kick it on with kick steps of the walk (the skill's `walk.kick_step`) instead of walking it on; the default: never"),
    )
    .param(
        ParamSpec::new("lost_after", ValueType::Float)
            .unit("s")
            .range(0.5, 30.0)
            .default(Value::Float(4.0))
            .doc("give up when the ball is unseen this long"),
    )
}

fn dribble_to(host: &mut AgentHost, ports: &Ports) -> Status {
    host.dribble_to(
        own(ports.vec2("target")),
        ports.float("tolerance"),
        ports.float("kick_beyond"),
        ports.float("lost_after"),
    )
}

impl AgentHost<'_> {
    pub(crate) fn dribble_to(
        &mut self,
        target: Own,
        tolerance: f64,
        kick_beyond: f64,
        lost_after: f64,
    ) -> Status {
        let world = self.world;
        let ball_age = world.ball.age(world.time);
        if ball_age > lost_after {
            self.look_for_ball();
            return Status::Failure;
        }
        if !world.me.localized {
            self.look_for_ball();
            return Status::Running;
        }
        let ball = self.ball();
        if ball.distance(target) <= tolerance {
            return Status::Success;
        }
        let me = self.me();
        let avoidance = self.strategy.avoidance.unwrap_or_default();
        let dribbling = self.skills.dribble != libero_skills::DribbleState::Idle;
        // Far from the ball, walk round obstacles (the ball among them) to behind it on the
        // line; near it the skill lines up and pushes. Once dribbling, the skill keeps the ball
        // on its own estimate through short gaps (a ball at the feet is often out of view).
        if !dribbling && ball_age > 0.5 {
            self.look_for_ball();
            return Status::Running;
        }
        if !dribbling && me.distance(ball) > avoidance.handover_m {
            let (_, meet) = self.meeting(me, avoidance.meeting_speed_m_s);
            self.walk_behind_ball(meet, meet.bearing_to(target));
            return Status::Running;
        }
        let heading = world
            .pose()
            .relative_angle(self.global_of(ball).bearing_to(self.global_of(target)));
        log::trace!(
            "t {:.2} dribble: me {:?} ball {:?} skill {:?}",
            world.time,
            me,
            ball,
            self.skills.dribble
        );
        self.intent.body = BodyIntent::Dribble {
            ball: world.ball_relative(libero_world::FRESH_BALL_SIGHTING_S),
            direction_deg: heading.to_degrees(),
            kick_steps: ball.distance(target) > kick_beyond,
        };
        Status::Running
    }
}
