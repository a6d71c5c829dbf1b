//! Moving the robot: beaming, standing, looking, walking to a point round obstacles, kicking.

use super::host::own;
use super::{AgentHost, Native, Ports};
use libero_behavior::{NodeSpec, ParamSpec, Status, Value, ValueType};
use libero_skills::kick::KickState;
use libero_skills::{BodyIntent, HeadIntent};
use libero_world::Own;

pub(super) const NODES: &[Native] = &[
    Native::action(beam_to_formation_ports, beam_to_formation),
    Native::action(stand_ports, stand),
    Native::action(look_around_ports, look_around),
    Native::action(walk_to_ports, walk_to),
    Native::action(kick_to_ports, kick_to),
    Native::action(search_ball_ports, search_ball),
];

/// An approach under way is given up for the walk behind the ball once the ball is this many
/// hand-over distances away (the hand-over itself wobbles with the estimates).
const REAPPROACH_BEYOND_HANDOVER: f64 = 2.0;
/// A pass of ours is waited for beside its stop point while it has this far still to roll [m].
const WAIT_FOR_PASS_BEYOND_M: f64 = 1.5;
/// The receiver of a pass waits this far beside the ball's path at its stop point [m]: out of
/// the path (the ball's lateral spread at 11 m is ~0.5 m), a step from the ball.
const WAIT_BESIDE_PASS_M: f64 = 1.0;
/// ... within this of the waiting point [m].
const WAIT_TOLERANCE_M: f64 = 0.3;
/// The ball's way to the stop point is walked round as obstacles this far apart [m] ...
const PASS_PATH_STEP_M: f64 = 0.8;
/// ... keeping this far from each [m] (half the step and a stride's sway).
const PASS_PATH_CLEARANCE_M: f64 = 0.5;

fn beam_to_formation_ports() -> NodeSpec {
    NodeSpec::action(
        "BeamToFormation",
        "Beams to this player's kick-off formation position, once the walk has come to a stop (a robot beamed mid-step falls); succeeds when placed.",
    )
}

fn beam_to_formation(host: &mut AgentHost, _: &Ports) -> Status {
    if host.still_moving_before_a_beam() {
        return Status::Running;
    }
    let p = host
        .strategy
        .position(
            host.situation(),
            host.unum(),
            libero_behavior::Vec2::new(0.0, 0.0),
        )
        .map(own)
        .unwrap_or_else(|| host.me());
    // Facing the kick-off spot: the ball in view from the first look.
    let yaw = if p.norm() > 0.5 {
        (-p.y).atan2(-p.x).to_degrees()
    } else {
        0.0
    };
    host.intent.beam = Some([p.x, p.y, yaw]);
    // Until the server has told us our side (SimSpark: after `init` took effect) a beam is not
    // sent; keep asking.
    if host.world.game.side.is_some() {
        Status::Success
    } else {
        Status::Running
    }
}

fn stand_ports() -> NodeSpec {
    NodeSpec::action(
        "Stand",
        "Holds the standing pose; a robot lying for the get-up's rest time gets up first (the skill's fall detector). Runs until halted.",
    )
}

fn stand(host: &mut AgentHost, _: &Ports) -> Status {
    // Not `GetUp`: that starts at once, and a jolt (a placement, a bump) that fakes a fall for
    // a moment then throws a standing robot down. The skill gets up by itself once the fall
    // detector has reported lying for its rest time.
    host.intent.body = BodyIntent::Stand;
    Status::Running
}

fn look_around_ports() -> NodeSpec {
    NodeSpec::action(
        "LookAround",
        "Pans the head to scan the field; runs until halted.",
    )
    .param(
        ParamSpec::new("amplitude", ValueType::Float)
            .unit("rad")
            .range(0.0, 2.0)
            .default(Value::Float(1.2))
            .doc("pan half-range"),
    )
    .param(
        ParamSpec::new("period", ValueType::Float)
            .unit("s")
            .range(0.2, 20.0)
            .default(Value::Float(4.0))
            .doc("time for a full sweep"),
    )
}

fn look_around(host: &mut AgentHost, ports: &Ports) -> Status {
    host.intent.head = HeadIntent::LookAround {
        amplitude_deg: Some(ports.float("amplitude").to_degrees()),
        period_s: Some(ports.float("period")),
    };
    Status::Running
}

fn walk_to_ports() -> NodeSpec {
    NodeSpec::action(
        "WalkTo",
        "Walks to a field point round the robots and goal posts in the way (a detour beside the first one, a grid path when the detour is blocked: formations/avoidance.ron); succeeds within `tolerance`.",
    )
    .param(
        ParamSpec::new("target", ValueType::Vec2)
            .unit("m")
            .doc("destination, own frame"),
    )
    .param(
        ParamSpec::new("speed", ValueType::Float)
            .unit("m/s")
            .range(0.0, 2.0)
            .default(Value::Float(0.6))
            .doc("walking speed"),
    )
    .param(
        ParamSpec::new("tolerance", ValueType::Float)
            .unit("m")
            .range(0.05, 5.0)
            .default(Value::Float(0.3))
            .doc("arrival radius"),
    )
    .param(
        ParamSpec::new("avoid_ball", ValueType::Bool)
            .default(Value::Bool(false))
            .doc("walk round the ball too (a set play's taker, who may not touch it again)"),
    )
}

fn walk_to(host: &mut AgentHost, ports: &Ports) -> Status {
    let target = own(ports.vec2("target"));
    let avoid_ball = ports.bool("avoid_ball");
    host.walk_to(
        target,
        None,
        avoid_ball,
        ports.float("speed"),
        ports.float("tolerance"),
    )
}

fn kick_to_ports() -> NodeSpec {
    NodeSpec::action(
        "KickTo",
        "Kicks the ball towards a field point: walks round obstacles (never through the ball) to a point behind the ball on the kick line, then the kick skill takes its kicking place and kicks (short or long by distance). Succeeds once the kick skill reports the kick done; fails when the ball has not been seen for `lost_after` seconds.",
    )
    .param(
        ParamSpec::new("target", ValueType::Vec2)
            .unit("m")
            .doc("where the ball should go, own frame"),
    )
    .param(
        ParamSpec::new("distance", ValueType::Float)
            .unit("m")
            .range(0.0, 40.0)
            .default(Value::Float(0.0))
            .doc("how far to kick; 0 = as far as the target"),
    )
    .param(
        ParamSpec::new("lost_after", ValueType::Float)
            .unit("s")
            .range(0.5, 30.0)
            .default(Value::Float(4.0))
            .doc("give up when the ball is unseen this long"),
    )
}

fn kick_to(host: &mut AgentHost, ports: &Ports) -> Status {
    if host.taking_set_play() {
        host.memory.set_play_kick_at.set(Some(host.world.time));
    }
    host.kick_to(
        own(ports.vec2("target")),
        ports.float("distance"),
        ports.float("lost_after"),
    )
}

fn search_ball_ports() -> NodeSpec {
    NodeSpec::action(
        "SearchBall",
        "Turns on the spot, towards where the ball was last believed to be, with the head scanning, until the ball has been seen within `seen_within` seconds (then succeeds). For a ball lost out of the head's reach: behind the robot, after a fall.",
    )
    .param(
        ParamSpec::new("turn", ValueType::Float)
            .unit("deg/s")
            .range(5.0, 90.0)
            .default(Value::Float(40.0))
            .doc("turning speed"),
    )
    .param(
        ParamSpec::new("seen_within", ValueType::Float)
            .unit("s")
            .range(0.05, 10.0)
            .default(Value::Float(0.5))
            .doc("a ball seen this recently is found"),
    )
}

fn search_ball(host: &mut AgentHost, ports: &Ports) -> Status {
    let world = host.world;
    if world.ball.age(world.time) <= ports.float("seen_within") {
        return Status::Success;
    }
    // The shorter way round to where the ball was last believed to be.
    let bearing = world.ball_relative(libero_world::FRESH_BALL_SIGHTING_S);
    let sign = if bearing[1] < 0.0 { -1.0 } else { 1.0 };
    host.intent.body = BodyIntent::Walk {
        forward_m_s: 0.0,
        sideways_m_s: 0.0,
        turn_deg_s: sign * ports.float("turn"),
    };
    host.look_for_ball();
    Status::Running
}

impl AgentHost<'_> {
    pub(crate) fn look_for_ball(&mut self) {
        self.intent.head = HeadIntent::LookAround {
            amplitude_deg: None,
            period_s: None,
        };
    }

    /// Walks towards `target` (own frame) round obstacles; `face` is the point to face on
    /// arrival (else the walking direction). Succeeds within `tolerance`.
    pub(crate) fn walk_to(
        &mut self,
        target: Own,
        face: Option<Own>,
        avoid_ball: bool,
        max_speed: f64,
        tolerance: f64,
    ) -> Status {
        if !self.world.me.localized {
            self.look_for_ball();
            return Status::Running;
        }
        let obstacles = self.obstacles(avoid_ball.then(|| self.ball()));
        self.walk_round(target, face, &obstacles, max_speed, tolerance)
    }

    /// `walk_to` round the given obstacles.
    pub(crate) fn walk_round(
        &mut self,
        target: Own,
        face: Option<Own>,
        obstacles: &crate::avoidance::Obstacles,
        max_speed: f64,
        tolerance: f64,
    ) -> Status {
        let me = self.me();
        if me.distance(target) <= tolerance {
            return Status::Success;
        }
        let avoidance = self.strategy.avoidance.unwrap_or_default();
        let field = self.strategy.field();
        let waypoint = self.memory.avoidance.next_waypoint(
            &avoidance,
            &field,
            me,
            target,
            obstacles,
            self.world.time,
        );
        self.walk_towards(
            waypoint,
            if waypoint == target { face } else { None },
            max_speed,
        );
        Status::Running
    }

    /// One cycle's walk intent towards an own-frame point, facing `face` (or the point itself).
    pub(crate) fn walk_towards(&mut self, point: Own, face: Option<Own>, max_speed: f64) {
        let pose = self.world.pose();
        let relative = pose.robot(self.global_of(point));
        let heading_deg = match face {
            Some(f) => {
                let f = pose.robot(self.global_of(f));
                f.y.atan2(f.x).to_degrees()
            }
            None => relative.y.atan2(relative.x).to_degrees(),
        };
        self.intent.body = BodyIntent::WalkTo {
            target: relative.to_array(),
            heading_deg,
            max_speed_m_s: Some(max_speed),
        };
    }

    pub(crate) fn kick_to(&mut self, target: Own, distance: f64, lost_after: f64) -> Status {
        let world = self.world;
        let ball_age = world.ball.age(world.time);
        if ball_age > lost_after {
            self.look_for_ball();
            return Status::Failure;
        }
        // Once the kick skill has the ball, it keeps it on its own estimate through short gaps
        // (a ball behind the robot at the hand-over cannot be looked at): dropping the request
        // for a search restarted the skill every cycle.
        let kicking = matches!(
            self.skills.kick,
            KickState::Approaching | KickState::Kicking
        );
        if !world.me.localized || (ball_age > 0.5 && !kicking) {
            self.look_for_ball();
            return Status::Running;
        }
        // The kick skill reports `Done` until it is asked for something else: succeed and ask
        // for nothing, so the next kick starts afresh.
        if self.skills.kick == KickState::Done {
            return Status::Success;
        }
        let ball = self.ball();
        let me = self.me();
        let avoidance = self.strategy.avoidance.unwrap_or_default();
        // Far from the ball (and not yet kicking), walk round obstacles, the ball among them, to
        // a point behind it on the kick line; there the kick skill's own approach takes over.
        // A ball that rolled away from an approach under way (kicked on by another robot) is
        // walked after again: the approach walks at its own slow speed and round nothing.
        // A pass of ours still rolling: wait beside the point where it stops (facing it), out
        // of its path; standing on the path short of it, the receiver had the ball bounce off
        // its legs (scenarios/pass.ron, NOTES.md session 16).
        let rest = self.ball_at_rest();
        let path = rest - ball;
        let length = path.norm().max(1e-6);
        // Only a pass still on its way: a ball nudged at the robot's feet (the tracker fits a
        // short roll from the touch) is kicked as it lies; waiting beside it, the robot
        // stood at the ball for 2 minutes (NOTES.md, session 16).
        let pass_on_its_way =
            length > WAIT_FOR_PASS_BEYOND_M && me.distance(ball) > avoidance.handover_m;
        if pass_on_its_way
            && self.ball_rolls()
            && self.our_kick()
            && self.skills.kick != KickState::Kicking
        {
            let across = Own::new(-path.y / length, path.x / length);
            let my_side = (me - rest).x * across.x + (me - rest).y * across.y;
            let side = if my_side < 0.0 { -1.0 } else { 1.0 };
            let wait = rest + across.scaled(side * WAIT_BESIDE_PASS_M);
            // Round the ball's way to its stop point, not across it.
            let mut obstacles = self.obstacles(Some(ball));
            let along = Own::new(path.x / length, path.y / length);
            let mut s = PASS_PATH_STEP_M;
            while s < length {
                let at = ball + along.scaled(s);
                let radius = PASS_PATH_CLEARANCE_M;
                if obstacles
                    .try_push(crate::avoidance::Obstacle { at, radius })
                    .is_err()
                {
                    break;
                }
                s += PASS_PATH_STEP_M;
            }
            let arrived = self.walk_round(
                wait,
                Some(rest),
                &obstacles,
                f64::INFINITY,
                WAIT_TOLERANCE_M,
            );
            if arrived == Status::Success {
                self.intent.body = BodyIntent::Stand;
            }
            self.look_at_ball();
            return Status::Running;
        }
        // With nothing but the ball in the way (and the ball at rest), the kick skill's own
        // approach takes over early: it walks round the ball at full pace, while the walk to a
        // point behind the ball slowed down there and handed over at a standstill.
        let way_clear = crate::avoidance::way_clear(me, ball, &self.obstacles(None));
        let hand_over_m = if !self.ball_rolls() && way_clear {
            avoidance.clear_handover_m
        } else {
            avoidance.handover_m
        };
        // An approach under way is judged by the way alone, not by whether the ball rolls: a
        // ball at rest seen rolling now and then (the tracker's fit right after a placement)
        // swapped the approach and the walk behind the ball every few cycles for 2.5 s, each
        // swap turning the robot 10-15 deg (striker_alone, NOTES.md session 30).
        let reapproach_m = if way_clear {
            avoidance.clear_handover_m
        } else {
            avoidance.handover_m
        } * REAPPROACH_BEYOND_HANDOVER;
        let far = me.distance(ball) > reapproach_m;
        let approaching = match self.skills.kick {
            KickState::Idle => false,
            KickState::Approaching => !far,
            _ => true,
        };
        if !approaching && me.distance(ball) > hand_over_m {
            // A rolling ball: to where it is met, kicked on from there towards the target.
            let (_, meet) = self.meeting(me, avoidance.meeting_speed_m_s);
            self.walk_behind_ball(meet, meet.bearing_to(target));
            return Status::Running;
        }
        let heading = self
            .world
            .pose()
            .relative_angle(self.global_of(ball).bearing_to(self.global_of(target)));
        let to_target = ball.distance(target);
        log::trace!(
            "kick to {target:?}: ball {ball:?}, heading {:.1}°",
            heading.to_degrees()
        );
        self.intent.body = BodyIntent::Kick {
            // Straight from the camera when fresh: the kick places the foot relative to the ball.
            ball: world.ball_relative(libero_world::FRESH_BALL_SIGHTING_S),
            direction_deg: heading.to_degrees(),
            distance_m: if distance > 0.0 { distance } else { to_target },
        };
        Status::Running
    }

    /// One cycle's walk round obstacles, the ball among them, to `avoidance.behind_ball_m`
    /// behind the ball on the line leaving it at `direction` [rad, own frame], facing and
    /// watching the ball (the far part of `KickTo` and `DribbleTo`).
    pub(crate) fn walk_behind_ball(&mut self, ball: Own, direction: f64) {
        let world = self.world;
        let me = self.me();
        let avoidance = self.strategy.avoidance.unwrap_or_default();
        let behind =
            ball - Own::new(direction.cos(), direction.sin()).scaled(avoidance.behind_ball_m);
        let obstacles = self.obstacles(Some(ball));
        let field = self.strategy.field();
        let waypoint = self
            .memory
            .avoidance
            .next_waypoint(&avoidance, &field, me, behind, &obstacles, world.time);
        log::trace!(
            "t {:.2} me {:?} to {:?} via {:?} obstacles {:?}",
            world.time,
            me,
            behind,
            waypoint,
            obstacles
                .iter()
                .map(|o| (o.at.x, o.at.y))
                .collect::<Vec<_>>()
        );
        self.walk_towards(waypoint, Some(ball), f64::INFINITY);
        self.look_at_ball();
    }

    /// Points the head at the ball's estimate.
    pub(crate) fn look_at_ball(&mut self) {
        self.intent.head = HeadIntent::LookAt {
            target: self
                .world
                .ball_relative(libero_world::FRESH_BALL_SIGHTING_S),
        };
    }
}
