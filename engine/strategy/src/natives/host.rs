//! One tick's view of the world for the native nodes, and the intent they fill in.

use super::Natives;
use crate::Strategy;
use libero_behavior::Vec2;
use libero_skills::{Intent, SkillStatus};
use libero_world::{Global, Own, World};

/// What a player's native nodes remember between cycles (a path being followed, a save in
/// progress). Owned by the player's decider, handed to each tick.
#[derive(Debug, Clone, Default)]
pub struct PlayerMemory {
    pub avoidance: crate::avoidance::Planner,
    /// When `ShotIsGood` last held (conditions only read the host: hence a cell).
    pub shot_good_at: std::cell::Cell<Option<f64>>,
    /// When this player last asked for a kick while taking an own set play: until another
    /// robot has been at the ball it may not touch it again (`MayPlayBall`).
    pub set_play_kick_at: std::cell::Cell<Option<f64>>,
    /// Who holds which formation slot (kept between cycles for the hysteresis).
    pub roles: std::cell::RefCell<crate::roles::RoleAssignment>,
    /// This player's predicted time to the ball, when a tree asked (`am_ball_winner`): what it
    /// tells its teammates.
    pub time_to_ball: std::cell::Cell<Option<f64>>,
    /// Whether it was the ball winner last time it asked.
    pub ball_winner: std::cell::Cell<bool>,
    /// The pass direction chosen last (`best_pass`), held against small gains.
    pub pass_kept: std::cell::Cell<Option<KeptPass>>,
    /// The teammate's pass this player last expected (`formations/pass.ron`
    /// `anticipate_within_m`), held against small gains like its own.
    pub pass_expected: std::cell::Cell<Option<KeptPass>>,
}

/// A pass direction held: its direction [rad, own frame], the ball's spot when it was first
/// chosen and when it was last asked for [s].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct KeptPass {
    pub direction: f64,
    pub ball: Own,
    pub at: f64,
}

/// One tick's view of the world, and the intent it fills in.
pub struct AgentHost<'a> {
    pub world: &'a World,
    pub strategy: &'a Strategy,
    pub natives: &'a Natives,
    /// The skills' state after the previous cycle.
    pub skills: &'a SkillStatus,
    pub memory: &'a mut PlayerMemory,
    pub intent: &'a mut Intent,
    /// Answers several nodes ask for in one tick (a condition, then the action it guards),
    /// computed once.
    pub(crate) tick: TickCache,
}

/// Per-tick answers shared between nodes.
#[derive(Debug, Default)]
pub(crate) struct TickCache {
    pub(crate) best_shot: std::cell::OnceCell<crate::shot::ShotChoice>,
    pub(crate) best_pass: std::cell::OnceCell<crate::pass::PassChoice>,
    pub(crate) shot_on_goal: std::cell::OnceCell<Option<crate::goalkeeper::Shot>>,
    /// The formation slot this player holds: one role assignment (and one hysteresis step)
    /// per tick, however many nodes ask.
    pub(crate) slot: std::cell::OnceCell<HeldSlot>,
}

/// The formation slot a player holds this tick, and where it is when the slot has moved off
/// the formation (to receive an expected pass).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct HeldSlot {
    pub unum: u8,
    pub moved_to: Option<Own>,
}

impl<'a> AgentHost<'a> {
    pub fn new(
        world: &'a World,
        strategy: &'a Strategy,
        natives: &'a Natives,
        skills: &'a SkillStatus,
        memory: &'a mut PlayerMemory,
        intent: &'a mut Intent,
    ) -> Self {
        Self {
            world,
            strategy,
            natives,
            skills,
            memory,
            intent,
            tick: TickCache::default(),
        }
    }
}

/// A player meets the ball once it is this close [m] (a step's reach).
const MEETING_REACH_M: f64 = 0.3;
/// Who kicked the ball is judged from players seen or heard of this recently [s].
const KICKER_NEWS_S: f64 = 3.0;
/// The kicker stood this close to where the ball left [m] (a T1 kicks from ~0.3 m).
const KICKER_WITHIN_M: f64 = 1.5;

/// A tree value (always own frame) as a typed own-frame point.
pub(crate) fn own(v: Vec2) -> Own {
    Own::new(v.x, v.y)
}

/// A typed own-frame point as a tree value.
pub(crate) fn value(p: Own) -> Vec2 {
    Vec2::new(p.x, p.y)
}

impl AgentHost<'_> {
    /// A global-frame estimate in the team's own frame.
    pub(crate) fn own_of(&self, p: [f64; 2]) -> Own {
        self.world.side().own(Global::from_array(p))
    }

    pub(crate) fn global_of(&self, p: Own) -> Global {
        self.world.side().global(p)
    }

    pub(crate) fn ball(&self) -> Own {
        self.own_of(self.world.ball.position)
    }

    /// Where the ball comes to rest (the world model's prediction; the ball itself when it
    /// lies still): what positions are taken for, so that a long kick's receivers move on
    /// while it rolls.
    pub(crate) fn ball_at_rest(&self) -> Own {
        if self.ball_rolls() {
            self.own_of(self.world.ball.predicted_stop)
        } else {
            self.ball()
        }
    }

    /// The world model has the ball moving (it publishes no speed for the jitter of a ball
    /// at rest).
    pub(crate) fn ball_rolls(&self) -> bool {
        let [vx, vy] = self.world.ball.velocity;
        vx.hypot(vy) > 0.0
    }

    /// The earliest time [s] and place a player at `from` walking at `speed` meets the ball
    /// (within `MEETING_REACH_M`), or walking to where it comes to rest when it cannot.
    ///
    /// A ball one of us kicked (a pass) is met where it stops: a rolling ball met on its way
    /// bounces off a walking robot, and the pass went where the kicker wanted it.
    pub(crate) fn meeting(&self, from: Own, speed: f64) -> (f64, Own) {
        if !self.ball_rolls() || self.our_kick() {
            let ball = self.ball_at_rest();
            return (from.distance(ball) / speed.max(1e-3), ball);
        }
        let ball = &self.world.ball;
        match ball.interception(self.global_of(from).to_array(), speed, MEETING_REACH_M) {
            Some((t, at)) => (t, self.own_of(at)),
            None => {
                let rest = self.ball_at_rest();
                (from.distance(rest) / speed.max(1e-3), rest)
            }
        }
    }

    /// The rolling ball left its spot next to one of us (this player or a teammate, by where
    /// everyone is believed to be now): our kick.
    pub(crate) fn our_kick(&self) -> bool {
        let Some(from) = self.world.ball.launched_from() else {
            return false;
        };
        let from = Global::from_array(from);
        let distance = |p: [f64; 2]| Global::from_array(p).distance(from);
        let now = self.world.time;
        let nearest_other = self
            .world
            .players
            .known
            .iter()
            .filter(|p| p.age(now) < KICKER_NEWS_S)
            .map(|p| (distance(p.position), p.relation))
            .min_by(|a, b| a.0.total_cmp(&b.0));
        let me = distance(self.world.me.position);
        let (kicker_distance, ours) = match nearest_other {
            Some((d, relation)) if d < me => (d, relation == libero_world::Relation::Teammate),
            _ => (me, true),
        };
        ours && kicker_distance <= KICKER_WITHIN_M
    }

    /// While the robot still walks (or kicks, dribbles), it is asked to stand: the server
    /// puts a beamed robot down on straightened legs, and one beamed mid-step fell (all six
    /// field players after a goal, NOTES.md session 15).
    pub(crate) fn still_moving_before_a_beam(&mut self) -> bool {
        use libero_skills::ActiveSkill;
        let moving = matches!(
            self.skills.active,
            ActiveSkill::Walk | ActiveSkill::Dribble | ActiveSkill::Kick
        );
        if moving {
            self.intent.body = libero_skills::BodyIntent::Stand;
        }
        moving
    }

    pub(crate) fn me(&self) -> Own {
        self.own_of(self.world.me.position)
    }

    pub(crate) fn unum(&self) -> u8 {
        u8::try_from(self.world.game.unum).unwrap_or(u8::MAX)
    }
}

impl AgentHost<'_> {
    /// What to walk round: robots seen lately, the goal posts, and the ball when given.
    pub(crate) fn obstacles(&self, ball: Option<Own>) -> crate::avoidance::Obstacles {
        use crate::avoidance::Obstacle;
        let avoidance = self.strategy.avoidance.unwrap_or_default();
        let field = self.strategy.field();
        let world = self.world;
        let mut out: crate::avoidance::Obstacles = world
            .players
            .known
            .iter()
            .filter(|p| p.age(world.time) <= avoidance.memory_s)
            .filter(|p| {
                !(p.relation == libero_world::Relation::Teammate && p.unum == world.game.unum)
            })
            .map(|p| Obstacle {
                at: self.own_of(p.position),
                radius: avoidance.robot_clearance_m,
            })
            // Room for the posts and the ball.
            .take(crate::avoidance::MAX_OBSTACLES - 5)
            .collect();
        let (x, y) = (field.half_length(), field.goal_half_width());
        for (px, py) in [(x, y), (x, -y), (-x, y), (-x, -y)] {
            out.push(Obstacle {
                at: Own::new(px, py),
                radius: avoidance.post_clearance_m,
            });
        }
        if let Some(ball) = ball {
            out.push(Obstacle {
                at: ball,
                radius: avoidance.ball_clearance_m,
            });
        }
        out
    }
}

/// What a tick decided with, in the global field frame, for a view of the running team (read
/// after the tick; computing it does not change the player's memory).
#[derive(Debug, Clone, Default)]
pub struct DecisionNotes {
    /// The formation slot held (by its default uniform number) and its role's name.
    pub slot: u8,
    pub role: arrayvec::ArrayString<32>,
    /// Where the formation puts this player now.
    pub formation_target: Option<Global>,
    /// The goalkeeper's defense point (keeper only).
    pub defense_point: Option<Global>,
    /// The shot target this tick chose, with its probability of scoring, when a node asked.
    pub shot: Option<(Global, f64)>,
}

impl AgentHost<'_> {
    /// The notes of this tick: the slot the tree used (its own number when no node asked: an
    /// assignment here would step the roles' hysteresis), the formation target, the keeper's
    /// defense point and the shot a node chose.
    pub fn notes(&self) -> DecisionNotes {
        let held = self.tick.slot.get().copied();
        let slot = held.map_or_else(|| self.unum(), |h| h.unum);
        let situation = self.situation();
        let mut role = arrayvec::ArrayString::new();
        if let Some(r) = self
            .strategy
            .formation_for(situation)
            .and_then(|f| f.roles.iter().find(|r| r.unum == slot))
        {
            let end = r.name.len().min(role.capacity());
            // A role name cut at a character boundary.
            let end = (0..=end)
                .rev()
                .find(|&i| r.name.is_char_boundary(i))
                .unwrap_or(0);
            role.push_str(&r.name[..end]);
        }
        let formation_target = held
            .and_then(|h| h.moved_to)
            .or_else(|| {
                self.strategy
                    .position(situation, slot, value(self.ball_at_rest()))
                    .map(own)
            })
            .map(|p| self.global_of(p));
        let defense_point = (self.unum() == 1).then(|| self.global_of(self.defense_point()));
        let shot = self
            .tick
            .best_shot
            .get()
            .map(|choice| (self.global_of(choice.target), choice.probability));
        DecisionNotes {
            slot,
            role,
            formation_target,
            defense_point,
            shot,
        }
    }
}
