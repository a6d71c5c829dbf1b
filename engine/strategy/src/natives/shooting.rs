//! Shooting: the best target across the goal mouth and its scoring chance
//! (`formations/shot.ron`, logic in `crate::shot`).

use super::host::value;
use super::{AgentHost, Native, Ports};
use crate::shot::{Defenders, ShotChoice};
use libero_behavior::{NodeSpec, Value, ValueType};
use libero_world::{Own, Relation};

pub(super) const NODES: &[Native] = &[
    Native::query(best_shot_ports, best_shot),
    Native::query(shot_utility_ports, shot_utility),
    Native::condition(shot_is_good_ports, shot_is_good),
];

fn best_shot_ports() -> NodeSpec {
    NodeSpec::query(
        "best_shot",
        ValueType::Vec2,
        "The target across the opponents' goal mouth with the best chance of scoring from the ball's position (m, own frame; formations/shot.ron).",
    )
}

fn best_shot(host: &AgentHost, _: &Ports) -> Value {
    Value::Vec2(value(host.best_shot().target))
}

fn shot_utility_ports() -> NodeSpec {
    NodeSpec::query(
        "shot_utility",
        ValueType::Float,
        "The probability that a long kick at `best_shot` scores: the kick's measured spread, the keeper's reach, opponents near the line.",
    )
}

fn shot_utility(host: &AgentHost, _: &Ports) -> Value {
    Value::Float(host.best_shot().probability)
}

fn shot_is_good_ports() -> NodeSpec {
    NodeSpec::condition(
        "ShotIsGood",
        "True when `shot_utility` reaches the threshold in formations/shot.ron; once true, it stays true until the utility falls `hysteresis` below the threshold, and while the kick it chose is under way.",
    )
}

/// A shot judged good this recently still counts as chosen (the tick before) [s].
const CHOSEN_WITHIN_S: f64 = 0.5;

fn shot_is_good(host: &AgentHost, _: &Ports) -> bool {
    let params = host.strategy.shot.unwrap_or_default();
    let now = host.world.time;
    let chosen = host
        .memory
        .shot_good_at
        .get()
        .is_some_and(|at| (0.0..=CHOSEN_WITHIN_S).contains(&(now - at)));
    // A kick under way for a chosen shot is seen through: the chance swings by more than the
    // band when the keeper drops out of (or comes back into) the player's memory, and each
    // switch back to dribbling threw the kick's approach away.
    let kicking = matches!(
        host.skills.kick,
        libero_skills::KickState::Approaching | libero_skills::KickState::Kicking
    );
    let bar = if chosen {
        params.threshold - params.hysteresis
    } else {
        params.threshold
    };
    let best = host.best_shot();
    let good = (chosen && kicking) || best.probability >= bar;
    if good != chosen {
        let ball = host.ball();
        log::debug!(
            "shot: t {now:.2} {} at ({:.2}, {:.2}) from ball ({:.2}, {:.2}): chance {:.2}",
            if good { "good" } else { "not good" },
            best.target.x,
            best.target.y,
            ball.x,
            ball.y,
            best.probability
        );
    }
    host.memory.shot_good_at.set(good.then_some(now));
    good
}

impl AgentHost<'_> {
    /// The opponents that stand in the way of a shot at their goal: the one nearest their goal
    /// inside its area counts as the keeper; unseen for 3 s, they are forgotten.
    fn defenders(&self) -> Defenders {
        let field = self.strategy.field();
        let goal = Own::new(field.half_length(), 0.0);
        let (depth, half_width) = field.goal_area();
        // One more than the defenders counted: the keeper is taken out of them.
        let mut opponents: arrayvec::ArrayVec<Own, { crate::shot::MAX_DEFENDERS + 1 }> = self
            .world
            .players
            .of(Relation::Opponent)
            .filter(|p| !p.fallen && p.age(self.world.time) < 3.0)
            .map(|p| self.own_of(p.position))
            .take(crate::shot::MAX_DEFENDERS + 1)
            .collect();
        let keeper = opponents
            .iter()
            .enumerate()
            .filter(|(_, p)| p.x >= goal.x - depth && p.y.abs() <= half_width)
            .min_by(|(_, a), (_, b)| a.distance(goal).total_cmp(&b.distance(goal)))
            .map(|(i, _)| i);
        let keeper = keeper.map(|i| opponents.swap_remove(i));
        Defenders {
            keeper,
            field_players: opponents
                .into_iter()
                .take(crate::shot::MAX_DEFENDERS)
                .collect(),
        }
    }

    pub(crate) fn best_shot(&self) -> ShotChoice {
        *self.tick.best_shot.get_or_init(|| {
            let params = self.strategy.shot.unwrap_or_default();
            params.best(
                self.ball(),
                &self.strategy.field(),
                &self.skills.kick_spread,
                &self.defenders(),
            )
        })
    }
}
