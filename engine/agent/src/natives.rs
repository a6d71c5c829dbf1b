//! The native nodes behavior trees call: conditions, actions and world queries over this
//! agent's world state, writing into the cycle's intent.
//!
//! The node declarations (names, parameters, units, docs) are the behavior engine's
//! `Vocabulary::reference()`: one definition serves `libero validate`, `libero nodes` and this
//! agent. `every_declared_node_has_a_handler` keeps the two in step.

use libero_behavior::{
    Args, Host, NativeId, NativeKind, Situation, Status, Strategy, Value, Vec2, Vocabulary,
};
use libero_skills::kick::KickState;
use libero_skills::{BodyIntent, HeadIntent, Intent, SkillStatus};
use libero_world::{PlayMode, Posture, Relation, Side, World};

/// Every native node the agent implements.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Native {
    PlayModeIs,
    CanBeam,
    IsFallen,
    BeamToFormation,
    Stand,
    LookAround,
    WalkTo,
    KickTo,
    OpponentGoal,
    BallPosition,
    BallDistance,
    MyPosition,
    FormationPosition,
    PlayTime,
    AmClosestToBall,
}

const HANDLERS: [(NativeKind, &str, Native); 15] = [
    (NativeKind::Condition, "PlayModeIs", Native::PlayModeIs),
    (NativeKind::Condition, "CanBeam", Native::CanBeam),
    (NativeKind::Condition, "IsFallen", Native::IsFallen),
    (
        NativeKind::Action,
        "BeamToFormation",
        Native::BeamToFormation,
    ),
    (NativeKind::Action, "Stand", Native::Stand),
    (NativeKind::Action, "LookAround", Native::LookAround),
    (NativeKind::Action, "WalkTo", Native::WalkTo),
    (NativeKind::Action, "KickTo", Native::KickTo),
    (NativeKind::Query, "opponent_goal", Native::OpponentGoal),
    (NativeKind::Query, "ball_position", Native::BallPosition),
    (NativeKind::Query, "ball_distance", Native::BallDistance),
    (NativeKind::Query, "my_position", Native::MyPosition),
    (
        NativeKind::Query,
        "formation_position",
        Native::FormationPosition,
    ),
    (NativeKind::Query, "play_time", Native::PlayTime),
    (
        NativeKind::Query,
        "am_closest_to_ball",
        Native::AmClosestToBall,
    ),
];

/// The agent's vocabulary.
pub fn vocabulary() -> Vocabulary {
    Vocabulary::reference()
}

/// Native ids resolved to handlers once, so a tick dispatches by index.
#[derive(Debug, Clone)]
pub struct Natives {
    by_id: Vec<Option<Native>>,
}

impl Natives {
    pub fn new(vocabulary: &Vocabulary) -> Self {
        let mut by_id = vec![None; vocabulary.nodes().len()];
        for (kind, name, native) in HANDLERS {
            if let Some(id) = vocabulary.find(kind, name) {
                by_id[id.0 as usize] = Some(native);
            }
        }
        Self { by_id }
    }

    fn get(&self, id: NativeId) -> Option<Native> {
        self.by_id.get(id.0 as usize).copied().flatten()
    }
}

/// One tick's view of the world, and the intent it fills in.
pub struct AgentHost<'a> {
    pub world: &'a World,
    pub strategy: &'a Strategy,
    pub natives: &'a Natives,
    /// The skills' state after the previous cycle.
    pub skills: &'a SkillStatus,
    pub intent: &'a mut Intent,
}

impl AgentHost<'_> {
    fn own(&self, p: [f64; 2]) -> Vec2 {
        let [x, y] = self.world.to_own_frame(p);
        Vec2 { x, y }
    }

    fn ball(&self) -> Vec2 {
        self.own(self.world.ball.position)
    }

    fn me(&self) -> Vec2 {
        self.own(self.world.me.position)
    }

    fn ours(&self, side: Side) -> bool {
        self.world.game.side == Some(side)
    }

    /// The play mode as the team sees it (`PlayModeIs` choices).
    fn team_play_mode(&self) -> &'static str {
        let own =
            |s: Side, yes: &'static str, no: &'static str| if self.ours(s) { yes } else { no };
        match self.world.game.play_mode {
            PlayMode::BeforeKickOff => "BeforeKickOff",
            PlayMode::PlayOn => "PlayOn",
            PlayMode::GameOver => "GameOver",
            PlayMode::KickOff(s) => own(s, "KickOffOwn", "KickOffTheirs"),
            PlayMode::KickIn(s) => own(s, "ThrowInOwn", "ThrowInTheirs"),
            PlayMode::CornerKick(s) => own(s, "CornerKickOwn", "CornerKickTheirs"),
            PlayMode::GoalKick(s) => own(s, "GoalKickOwn", "GoalKickTheirs"),
            PlayMode::FreeKick(s)
            | PlayMode::DirectFreeKick(s)
            | PlayMode::PenaltyKick(s)
            | PlayMode::PenaltyShoot(s) => own(s, "FreeKickOwn", "FreeKickTheirs"),
            // `offside_left`: the left team was offside, so the right team takes the kick.
            PlayMode::Offside(s) => own(s, "FreeKickTheirs", "FreeKickOwn"),
            PlayMode::Goal(s) => own(s, "GoalOwn", "GoalTheirs"),
            PlayMode::Unknown => "",
        }
    }

    fn situation(&self) -> Situation {
        match self.team_play_mode() {
            // Before the first kick-off nobody knows who kicks off: take the positions that are
            // legal either way (the referee relocates defenders inside the centre circle).
            "KickOffTheirs" | "GoalOwn" | "BeforeKickOff" => Situation::KickOffTheirs,
            "KickOffOwn" | "GoalTheirs" => Situation::KickOffOwn,
            m if m.ends_with("Own") => Situation::SetPlayOwn,
            m if m.ends_with("Theirs") => Situation::SetPlayTheirs,
            _ => Situation::play_on(self.ball()),
        }
    }

    fn formation_position(&self) -> Vec2 {
        let unum = u8::try_from(self.world.game.unum).unwrap_or(u8::MAX);
        self.strategy
            .position(self.situation(), unum, self.ball())
            .unwrap_or_else(|| self.me())
    }

    fn am_closest_to_ball(&self) -> bool {
        let ball = self.world.ball.position;
        let dist = |p: [f64; 2]| (p[0] - ball[0]).hypot(p[1] - ball[1]);
        let mine = dist(self.world.me.position);
        self.world
            .players
            .of(Relation::Teammate)
            .filter(|p| !p.fallen && p.age(self.world.time) < 2.0)
            .all(|p| dist(p.position) >= mine)
    }

    fn walk_to(&mut self, target: Vec2, max_speed: f64, tolerance: f64) -> Status {
        if !self.world.me.localized {
            self.intent.head = HeadIntent::LookAround {
                amplitude_deg: None,
                period_s: None,
            };
            return Status::Running;
        }
        // Own frame → global frame is the same mirror as global → own.
        let [gx, gy] = self.world.to_own_frame([target.x, target.y]);
        let [mx, my] = self.world.me.position;
        let (dx, dy) = (gx - mx, gy - my);
        if dx.hypot(dy) <= tolerance {
            return Status::Success;
        }
        let yaw = self.world.me.yaw_deg.to_radians();
        let (s, c) = yaw.sin_cos();
        let relative = [c * dx + s * dy, -s * dx + c * dy];
        self.intent.body = BodyIntent::WalkTo {
            target: relative,
            heading_deg: relative[1].atan2(relative[0]).to_degrees(),
            max_speed_m_s: Some(max_speed),
        };
        Status::Running
    }
}

impl AgentHost<'_> {
    fn kick_to(&mut self, target: Vec2, distance: f64, lost_after: f64) -> Status {
        let world = self.world;
        let ball_age = world.ball.age(world.time);
        if !world.me.localized || ball_age > 0.5 {
            self.intent.head = HeadIntent::LookAround {
                amplitude_deg: None,
                period_s: None,
            };
            return if ball_age > lost_after {
                Status::Failure
            } else {
                Status::Running
            };
        }
        // The kick skill reports `Done` until it is asked for something else: succeed and
        // ask for nothing, so the next kick starts afresh.
        if self.skills.kick == KickState::Done {
            return Status::Success;
        }
        let ball = world.ball.position;
        let [tx, ty] = world.to_own_frame([target.x, target.y]);
        let direction = (ty - ball[1]).atan2(tx - ball[0]) - world.me.yaw_deg.to_radians();
        let to_target = (tx - ball[0]).hypot(ty - ball[1]);
        self.intent.body = BodyIntent::Kick {
            // Straight from the camera when fresh: the kick places the foot relative to the ball.
            ball: world.ball_relative(libero_world::FRESH_BALL_SIGHTING_S),
            direction_deg: direction.sin().atan2(direction.cos()).to_degrees(),
            distance_m: if distance > 0.0 { distance } else { to_target },
        };
        Status::Running
    }
}

impl Host for AgentHost<'_> {
    fn now(&self) -> f64 {
        self.world.time
    }

    fn query(&self, id: NativeId, _args: Args) -> Value {
        match self.natives.get(id) {
            Some(Native::BallPosition) => Value::Vec2(self.ball()),
            Some(Native::BallDistance) => Value::Float(self.ball().distance(self.me())),
            Some(Native::MyPosition) => Value::Vec2(self.me()),
            Some(Native::FormationPosition) => Value::Vec2(self.formation_position()),
            Some(Native::OpponentGoal) => Value::Vec2(Vec2 {
                x: self.world.field.half_extent().0,
                y: 0.0,
            }),
            Some(Native::PlayTime) => Value::Float(self.world.game.play_time),
            Some(Native::AmClosestToBall) => Value::Bool(self.am_closest_to_ball()),
            _ => Value::Bool(false),
        }
    }

    fn condition(&self, id: NativeId, args: Args) -> bool {
        match self.natives.get(id) {
            Some(Native::PlayModeIs) => self.team_play_mode() == args.str(0),
            Some(Native::CanBeam) => self.world.game.play_mode.allows_beam(),
            Some(Native::IsFallen) => self.world.body.posture != Posture::Upright,
            _ => false,
        }
    }

    fn action(&mut self, id: NativeId, args: Args) -> Status {
        match self.natives.get(id) {
            Some(Native::BeamToFormation) => {
                let unum = u8::try_from(self.world.game.unum).unwrap_or(u8::MAX);
                let p = self
                    .strategy
                    .position(self.situation(), unum, Vec2 { x: 0.0, y: 0.0 })
                    .unwrap_or_else(|| self.me());
                self.intent.beam = Some([p.x, p.y, 0.0]);
                // Until the server has told us our side (SimSpark: after `init` took effect) a
                // beam is not sent; keep asking.
                if self.world.game.side.is_some() {
                    Status::Success
                } else {
                    Status::Running
                }
            }
            Some(Native::Stand) => {
                self.intent.body = if self.world.body.posture == Posture::Upright {
                    BodyIntent::Stand
                } else {
                    BodyIntent::GetUp
                };
                Status::Running
            }
            Some(Native::LookAround) => {
                self.intent.head = HeadIntent::LookAround {
                    amplitude_deg: Some(args.float(0).to_degrees()),
                    period_s: Some(args.float(1)),
                };
                Status::Running
            }
            Some(Native::WalkTo) => self.walk_to(args.vec2(0), args.float(1), args.float(2)),
            Some(Native::KickTo) => self.kick_to(args.vec2(0), args.float(1), args.float(2)),
            _ => Status::Failure,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_declared_node_has_a_handler() {
        let vocabulary = vocabulary();
        let natives = Natives::new(&vocabulary);
        for (i, spec) in vocabulary.nodes().iter().enumerate() {
            assert!(
                natives.by_id[i].is_some(),
                "{} `{}` has no handler in the agent",
                spec.kind.name(),
                spec.name
            );
        }
        assert_eq!(
            vocabulary.nodes().len(),
            HANDLERS.len(),
            "a handler names a node the vocabulary lacks"
        );
    }

    fn kick_to_in(world: &World, target: Vec2, kick: KickState) -> (Status, Intent) {
        let vocabulary = vocabulary();
        let natives = Natives::new(&vocabulary);
        let library =
            libero_behavior::Library::load(&crate::build::default_data_dirs(), &vocabulary)
                .unwrap();
        let mut intent = Intent::default();
        let skills = SkillStatus {
            kick,
            ..SkillStatus::default()
        };
        let mut host = AgentHost {
            world,
            strategy: library.strategy(),
            natives: &natives,
            skills: &skills,
            intent: &mut intent,
        };
        let id = vocabulary.find(NativeKind::Action, "KickTo").unwrap();
        let args = [Value::Vec2(target), Value::Float(0.0), Value::Float(4.0)];
        let status = host.action(id, Args(&args));
        (status, intent)
    }

    #[test]
    fn kick_to_asks_for_a_kick_in_the_robot_frame_and_succeeds_once_the_kick_is_done() {
        let model = libero_model::RobotModel::builtin("T1").unwrap();
        let mut world = World::new(&model, "Libero", 2);
        // The right team: own frame = global frame turned by 180°.
        world.game.side = Some(Side::Right);
        world.time = 10.0;
        world.me.localized = true;
        world.me.position = [1.0, 1.0];
        world.me.yaw_deg = 180.0; // facing the opponent goal at global −x
        world.ball.position = [0.0, 2.0];
        world.ball.last_seen_time = Some(10.0);
        // Own frame: robot (−1, −1), ball (0, −2); target (4, −2) lies straight beyond the ball
        // along own +x, i.e. straight ahead of the robot.
        let (status, intent) = kick_to_in(&world, Vec2::new(4.0, -2.0), KickState::Idle);
        assert_eq!(status, Status::Running);
        let BodyIntent::Kick {
            ball,
            direction_deg,
            distance_m,
        } = intent.body
        else {
            panic!("no kick asked for: {:?}", intent.body)
        };
        // Ball 1 m ahead and 1 m to the right (robot frame: y left).
        assert!(
            (ball[0] - 1.0).abs() < 1e-9 && (ball[1] + 1.0).abs() < 1e-9,
            "{ball:?}"
        );
        assert!(direction_deg.abs() < 1e-9, "{direction_deg}");
        assert!((distance_m - 4.0).abs() < 1e-9, "{distance_m}");

        // While the skill approaches or kicks, the node runs on.
        for state in [KickState::Approaching, KickState::Kicking] {
            assert_eq!(
                kick_to_in(&world, Vec2::new(4.0, -2.0), state).0,
                Status::Running
            );
        }
        // Kicked: success, asking for no further kick (the skill resets for the next one).
        let (status, intent) = kick_to_in(&world, Vec2::new(4.0, -2.0), KickState::Done);
        assert_eq!(status, Status::Success);
        assert_eq!(intent.body, BodyIntent::Stand);
        // Unseen for longer than `lost_after`: give up, scanning for it.
        world.time = 15.0;
        let (status, intent) = kick_to_in(&world, Vec2::new(4.0, -2.0), KickState::Idle);
        assert_eq!(status, Status::Failure);
        assert!(matches!(intent.head, HeadIntent::LookAround { .. }));
    }
}
