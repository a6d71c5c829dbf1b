//! Team play: who holds which formation role (the optimal assignment of `roles`) and who goes
//! for the ball (the predicted time to reach it, this player's against its teammates' claims).

use super::host::HeldSlot;
use super::{AgentHost, Native, Ports};
use crate::roles::{Candidate, Slot, MAX_PLAYERS};
use crate::Situation;
use arrayvec::ArrayVec;
use libero_behavior::{NodeSpec, ParamSpec, Value, ValueType};
use libero_world::team_message::TIME_TO_BALL_MAX_S;
use libero_world::{BallClaim, Own, Relation};

pub(super) const NODES: &[Native] = &[Native::query(am_ball_winner_ports, am_ball_winner)];

/// Teammates with no news for longer than this are taken to be at their own slot [s].
const TEAMMATE_NEWS_S: f64 = 4.0;
/// Saved summed squared distance [m²] an assignment must offer to replace the one held.
const ROLE_HYSTERESIS_M2: f64 = 4.0;
/// A ball that will come to rest this close to where it is counts as lying still [m].
const STILL_WITHIN_M: f64 = 1.0;
/// A teammate's claim (or sighting) counts this long [s].
const CLAIM_FRESH_S: f64 = 1.0;

fn am_ball_winner_ports() -> NodeSpec {
    NodeSpec::query(
        "am_ball_winner",
        ValueType::Bool,
        "True when this player reaches the ball first of the field players: its predicted time (to meet the ball walking at `walk_speed`: a rolling ball where its path is reached first, else where it comes to rest; the turn to face that point at `turn_rate`; `get_up` when lying) against each teammate's claim heard in the last second, or the same prediction from where it was seen. Once winner, a teammate must be `hysteresis` faster to take over. Whoever goes for the ball (this player, or a teammate that says so) starts `hysteresis` ahead; two that both go compare bare times. This player's time, and whether it goes, is what it tells its teammates.",
    )
    .param(
        ParamSpec::new("walk_speed", ValueType::Float)
            .unit("m/s")
            .range(0.05, 3.0)
            .default(Value::Float(0.5))
            .doc("walking speed of the prediction"),
    )
    .param(
        ParamSpec::new("turn_rate", ValueType::Float)
            .unit("deg/s")
            .range(1.0, 720.0)
            .default(Value::Float(60.0))
            .doc("turning speed of the prediction"),
    )
    .param(
        ParamSpec::new("get_up", ValueType::Float)
            .unit("s")
            .range(0.0, 30.0)
            .default(Value::Float(5.0))
            .doc("added for a robot lying down"),
    )
    .param(
        ParamSpec::new("hysteresis", ValueType::Float)
            .unit("s")
            .range(0.0, 10.0)
            .default(Value::Float(0.5))
            .doc("the head start of whoever goes for the ball: how much faster another must be to take it over"),
    )
}

/// The prediction's numbers.
struct Pace {
    walk_speed: f64,
    turn_rate: f64,
    get_up: f64,
}

impl Pace {
    /// The time to meet the ball (a rolling one where its path can be reached first) from
    /// `from`, turning there from `heading_deg`.
    fn time(&self, host: &AgentHost, from: Own, heading_deg: Option<f64>, fallen: bool) -> f64 {
        let (walk, at) = host.meeting(from, self.walk_speed);
        let turn = heading_deg.map_or(0.0, |h| {
            let to_ball = from.bearing_to(at).to_degrees();
            libero_world::geometry::wrap_deg(to_ball - h).abs() / self.turn_rate
        });
        walk + turn + if fallen { self.get_up } else { 0.0 }
    }
}

fn am_ball_winner(host: &AgentHost, ports: &Ports) -> Value {
    let pace = Pace {
        walk_speed: ports.float("walk_speed"),
        turn_rate: ports.float("turn_rate"),
        get_up: ports.float("get_up"),
    };
    let world = host.world;
    let fallen = world.body.posture != libero_world::Posture::Upright;
    let mine = pace.time(
        host,
        host.me(),
        Some(world.yaw_to_own_frame(world.me.yaw_deg)),
        fallen,
    );
    host.memory.time_to_ball.set(Some(mine));
    let now = world.time;
    let head_start = ports.float("hysteresis");
    // Whoever goes for the ball (this player by its memory, a teammate by its word) starts
    // `hysteresis` ahead: a teammate must be that much quicker to take the ball over. Two
    // that both went for it compare their bare times and the slower gives way; when each
    // gave itself the head start alone, both kept going and ran into each other (matches,
    // NOTES.md session 30). Times are compared as messages tell them, ties by uniform number.
    let told = libero_world::team_message::told_time_to_ball;
    let me = (
        told(mine)
            - if host.memory.ball_winner.get() {
                head_start
            } else {
                0.0
            },
        world.game.unum,
    );
    let claims: ArrayVec<&BallClaim, MAX_PLAYERS> =
        world.heard.recent_claims(now).take(MAX_PLAYERS).collect();
    let quickest_other = world
        .players
        .of(Relation::Teammate)
        .filter(|p| p.unum != 1 && p.unum != world.game.unum && p.age(now) <= CLAIM_FRESH_S)
        .map(|p| {
            let claim = claims.iter().find(|c| c.unum == p.unum);
            // A claim at the message's ceiling says only "this or more": then the prediction
            // from where the teammate is (otherwise every player far away waits for another).
            let heard = claim
                .and_then(|c| c.time_to_ball_s)
                .filter(|t| *t < TIME_TO_BALL_MAX_S - 1e-6);
            // Lying or not by its own word when heard: seen from 6 m, a standing T1's head was
            // judged 0.42 m high (fallen), and two players went for the ball it was at.
            let fallen = claim.map_or(p.fallen, |c| c.fallen);
            let time = heard.unwrap_or_else(|| {
                told(pace.time(
                    host,
                    host.own_of(p.position),
                    p.heading_deg.map(|h| world.yaw_to_own_frame(h)),
                    fallen,
                ))
            });
            let going = claim.is_some_and(|c| c.going_for_ball);
            (time - if going { head_start } else { 0.0 }, p.unum)
        })
        .min_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
    let winner = quickest_other.is_none_or(|other| {
        me.0 < other.0 - 1e-9 || ((me.0 - other.0).abs() <= 1e-9 && me.1 < other.1)
    });
    host.memory.ball_winner.set(winner);
    Value::Bool(winner)
}

impl AgentHost<'_> {
    /// Who goes for the ball, as this player sees it: itself when its last `am_ball_winner`
    /// said so, else the teammate with the quickest claim heard lately.
    fn ball_winner_unum(&self) -> Option<u8> {
        if self.memory.ball_winner.get() {
            return Some(self.unum());
        }
        let now = self.world.time;
        // The teammate that says it goes for the ball; else the quickest claim.
        self.world
            .heard
            .recent_claims(now)
            .filter(|c| c.unum != 1)
            .filter_map(|c| Some((!c.going_for_ball, c.time_to_ball_s?, c.unum)))
            .min_by(|a, b| a.0.cmp(&b.0).then(a.1.total_cmp(&b.1)).then(a.2.cmp(&b.2)))
            .and_then(|(_, _, u)| u8::try_from(u).ok())
    }

    /// While teammate `winner` is at the ball (at rest) about to play it, the slot nearest
    /// to where its pass would stop moves to the receiving spot beside that point: the
    /// receiver is there when the ball comes, not 8-12 m away (`formations/pass.ron`
    /// `anticipate_within_m`; the pass as this player works it out, with itself in the race).
    /// The slot moved (its default uniform number) and where to.
    fn anticipate_pass(&self, winner: u8, slots: &mut [Slot]) -> Option<(u8, Own)> {
        let params = self.strategy.pass.unwrap_or_default();
        let world = self.world;
        let ball = self.ball();
        // Still, or nudged: the tracker fits slow rolls to a ball at the kicker's feet.
        let at_rest = self.ball_at_rest().distance(ball) <= STILL_WITHIN_M;
        if params.anticipate_within_m <= 0.0 || !at_rest {
            return None;
        }
        let near_ball = world
            .players
            .get(Relation::Teammate, u32::from(winner))
            .filter(|p| p.age(world.time) <= TEAMMATE_NEWS_S)
            .is_some_and(|p| self.own_of(p.position).distance(ball) <= params.anticipate_within_m);
        if !near_ball {
            return None;
        }
        let mut players = self.pass_field();
        let _ = players.teammates.try_push(self.me());
        let kept = self
            .memory
            .pass_expected
            .get()
            .filter(|k| k.ball.distance(ball) <= 1.0);
        let pass = params.best(
            ball,
            &self.strategy.field(),
            &self.skills.kick_spread,
            &players,
            kept.map(|k| k.direction),
            crate::pass::Commitment::Free,
        );
        self.memory.pass_expected.set(Some(super::host::KeptPass {
            direction: pass.direction,
            ball: kept.map_or(ball, |k| k.ball),
            at: world.time,
        }));
        if pass.utility <= 0.0 {
            return None;
        }
        let slot = slots.iter_mut().min_by(|a, b| {
            a.at.distance(pass.target)
                .total_cmp(&b.at.distance(pass.target))
        })?;
        slot.at = pass.receiving_spot(params.receive_beside_m, slot.at);
        Some((slot.default_unum, slot.at))
    }

    /// The formation slot (by its default uniform number) this player holds: in play, the
    /// ball winner the slot nearest the ball and the others the optimal assignment of the rest;
    /// in kick-offs and set plays, and for the goalkeeper, its own.
    pub(crate) fn slot(&self) -> u8 {
        self.held_slot().unum
    }

    /// The slot held, with where it has moved to when it waits for an expected pass.
    pub(crate) fn held_slot(&self) -> HeldSlot {
        *self.tick.slot.get_or_init(|| {
            let mut moved_to = None;
            let unum = self.assigned_slot(&mut moved_to);
            HeldSlot { unum, moved_to }
        })
    }

    /// The slot this player holds; `moved_to` gets where it lies when it has moved off the
    /// formation.
    fn assigned_slot(&self, moved_to: &mut Option<Own>) -> u8 {
        let unum = self.unum();
        let situation = self.situation();
        let in_play = matches!(
            situation,
            Situation::PlayOnAttack | Situation::PlayOnDefence
        );
        if unum == 1 || !in_play {
            return unum;
        }
        let Some(formation) = self.strategy.formation_for(situation) else {
            return unum;
        };
        // Slots for where the ball will lie: a long kick's receivers move on while it rolls.
        let ball_at = self.ball_at_rest();
        let ball = super::host::value(ball_at);
        let mut slots: ArrayVec<Slot, MAX_PLAYERS> = formation
            .roles
            .iter()
            .filter(|r| r.unum != 1)
            .filter_map(|r| {
                Some(Slot {
                    default_unum: r.unum,
                    at: super::host::own(formation.position(r.unum, ball)?),
                })
            })
            .take(MAX_PLAYERS)
            .collect();
        // The ball winner goes for the ball: it takes the slot nearest the ball, and the others
        // share the rest, so the slots ahead of the ball stay held when it kicks long.
        let winner = self.ball_winner_unum();
        let winner_slot = winner.and_then(|_| {
            let nearest = slots
                .iter()
                .enumerate()
                .min_by(|a, b| {
                    a.1.at
                        .distance(ball_at)
                        .total_cmp(&b.1.at.distance(ball_at))
                })?
                .0;
            Some(slots.remove(nearest).default_unum)
        });
        if winner == Some(unum) {
            return winner_slot.unwrap_or(unum);
        }
        let moved = winner.and_then(|w| self.anticipate_pass(w, &mut slots));
        let world = self.world;
        let candidates: ArrayVec<Candidate, MAX_PLAYERS> = formation
            .roles
            .iter()
            .map(|r| r.unum)
            .filter(|u| *u != 1 && Some(*u) != winner)
            .map(|player| {
                let own_slot = || {
                    formation
                        .position(player, ball)
                        .map_or(ball_at, super::host::own)
                };
                let at = if player == unum {
                    self.me()
                } else {
                    world
                        .players
                        .get(Relation::Teammate, u32::from(player))
                        .filter(|p| p.age(world.time) <= TEAMMATE_NEWS_S)
                        .map_or_else(own_slot, |p| self.own_of(p.position))
                };
                Candidate { unum: player, at }
            })
            .take(MAX_PLAYERS)
            .collect();
        let mut roles = self.memory.roles.borrow_mut();
        roles.update(&candidates, &slots, ROLE_HYSTERESIS_M2);
        let held = roles.slot_of(unum).unwrap_or(unum);
        *moved_to = moved.filter(|(slot, _)| *slot == held).map(|(_, at)| at);
        held
    }
}
