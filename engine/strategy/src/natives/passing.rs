//! Passing: where a long kick sends the ball when no shot is good, and what that is worth
//! (`formations/pass.ron`, logic in `crate::pass`).

use super::host::value;
use super::{AgentHost, Native, Ports};
use crate::pass::{Commitment, PassChoice, PassField};
use crate::shot::MAX_DEFENDERS;
use libero_behavior::{NodeSpec, Value, ValueType};
use libero_world::Relation;

pub(super) const NODES: &[Native] = &[
    Native::query(best_pass_ports, best_pass),
    Native::query(pass_utility_ports, pass_utility),
];

fn best_pass_ports() -> NodeSpec {
    NodeSpec::query(
        "best_pass",
        ValueType::Vec2,
        "Where a long kick should send the ball (m, own frame; formations/pass.ron): the stop point, among directions fanned round the line to their goal, with the best progress and race for it (our nearest player against theirs), times the chance the ball gets past the opponents near its path and stays on the field. The direction chosen is kept until another is `hysteresis` better, and while the kick is under way as long as it is worth half the best.",
    )
}

fn best_pass(host: &AgentHost, _: &Ports) -> Value {
    Value::Vec2(value(host.best_pass().target))
}

fn pass_utility_ports() -> NodeSpec {
    NodeSpec::query(
        "pass_utility",
        ValueType::Float,
        "What the kick to `best_pass` is worth, 0..1: progress and the race for the stop point, times the chance it gets past the opponents and stays on the field.",
    )
}

fn pass_utility(host: &AgentHost, _: &Ports) -> Value {
    Value::Float(host.best_pass().utility)
}

/// A direction chosen this recently is still the one held [s] (a tick skipped, a branch
/// re-entered).
const KEPT_WITHIN_S: f64 = 1.0;
/// The direction held is dropped once the ball has moved this far from where it was chosen
/// [m]: another kick, a bump.
const KEPT_WHILE_BALL_WITHIN_M: f64 = 1.0;
/// Teammates and opponents with no news for this long are left out of the race [s].
const PLAYER_NEWS_S: f64 = 3.0;

impl AgentHost<'_> {
    pub(crate) fn pass_field(&self) -> PassField {
        let world = self.world;
        let upright = |relation| {
            world
                .players
                .of(relation)
                .filter(|p| !p.fallen && p.age(world.time) < PLAYER_NEWS_S)
                .map(|p| self.own_of(p.position))
                .take(MAX_DEFENDERS)
        };
        PassField {
            teammates: upright(Relation::Teammate).collect(),
            opponents: upright(Relation::Opponent).collect(),
        }
    }

    pub(crate) fn best_pass(&self) -> PassChoice {
        *self.tick.best_pass.get_or_init(|| {
            let params = self.strategy.pass.unwrap_or_default();
            let ball = self.ball();
            let now = self.world.time;
            let kicking = matches!(
                self.skills.kick,
                libero_skills::KickState::Approaching | libero_skills::KickState::Kicking
            );
            let kept = self.memory.pass_kept.get().filter(|k| {
                (kicking || (0.0..=KEPT_WITHIN_S).contains(&(now - k.at)))
                    && k.ball.distance(ball) <= KEPT_WHILE_BALL_WITHIN_M
            });
            let choice = params.best(
                ball,
                &self.strategy.field(),
                &self.skills.kick_spread,
                &self.pass_field(),
                kept.map(|k| k.direction),
                // Round the ball on the kick's approach a swinging target made the robot
                // circle it for 20 s (NOTES.md, session 16): the direction is held then, and
                // at the ball for good.
                if !kicking {
                    Commitment::Free
                } else if self.me().distance(ball) <= params.commit_within_m {
                    Commitment::AtBall
                } else {
                    Commitment::Approach
                },
            );
            self.memory.pass_kept.set(Some(super::host::KeptPass {
                direction: choice.direction,
                ball: kept.map_or(ball, |k| k.ball),
                at: now,
            }));
            choice
        })
    }
}
