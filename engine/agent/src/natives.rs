//! The native nodes behavior trees call: conditions, actions and world queries over this
//! agent's world state, writing into the cycle's intent.
//!
//! The node declarations (names, parameters, units, docs) are the behavior engine's
//! `Vocabulary::reference()`: one definition serves `libero validate`, `libero nodes` and this
//! agent. `every_declared_node_has_a_handler` keeps the two in step.

use libero_behavior::{
    Args, Host, NativeId, NativeKind, Situation, Status, Strategy, Value, Vec2, Vocabulary,
};
use libero_skills::{BodyIntent, HeadIntent, Intent};
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
    BallPosition,
    BallDistance,
    MyPosition,
    FormationPosition,
    PlayTime,
    AmClosestToBall,
}

const HANDLERS: [(NativeKind, &str, Native); 13] = [
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
}
