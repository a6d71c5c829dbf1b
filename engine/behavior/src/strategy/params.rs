//! Tunable strategy parameters: goalkeeper defense point, shot utility, obstacle avoidance,
//! and the team file choosing formations per situation and trees per role.

use super::field::Field;
use crate::decode::{Decoder, Fields};
use crate::syntax::{Node, Span};
use crate::value::Vec2;
use std::collections::BTreeMap;

fn number(
    decoder: &mut Decoder,
    fields: &mut Fields,
    name: &str,
    min: f64,
    max: f64,
    default: f64,
) -> Option<f64> {
    match fields.take(name) {
        Some(node) => decoder.float_in(node, min, max),
        None => Some(default),
    }
}

/// Where the goalkeeper stands: on the line from the goal centre to the ball, `radius` metres
/// out, at least `min_line_offset` in front of the goal line, and within `max_abs_y` sideways.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GoalkeeperParams {
    pub radius: f64,
    pub min_line_offset: f64,
    pub max_abs_y: f64,
}

impl GoalkeeperParams {
    pub fn defense_point(&self, ball: Vec2, field: &Field) -> Vec2 {
        let goal = field.own_goal();
        let (dx, dy) = (ball.x - goal.x, ball.y - goal.y);
        let length = (dx * dx + dy * dy).sqrt();
        let (ux, uy) = if length < 1e-9 {
            (1.0, 0.0)
        } else {
            (dx / length, dy / length)
        };
        let x = (goal.x + ux * self.radius).max(goal.x + self.min_line_offset);
        let y = (goal.y + uy * self.radius).clamp(-self.max_abs_y, self.max_abs_y);
        Vec2::new(x, y)
    }
}

pub fn parse_goalkeeper(decoder: &mut Decoder, node: &Node) -> Option<GoalkeeperParams> {
    let mut fields = decoder.fields(node, "Goalkeeper")?;
    let radius = number(decoder, &mut fields, "radius", 0.1, 10.0, 1.5);
    let min_line_offset = number(decoder, &mut fields, "min_line_offset", 0.0, 5.0, 0.3);
    let max_abs_y = number(decoder, &mut fields, "max_abs_y", 0.0, 10.0, 2.0);
    fields.finish(decoder, &["radius", "min_line_offset", "max_abs_y"]);
    Some(GoalkeeperParams {
        radius: radius?,
        min_line_offset: min_line_offset?,
        max_abs_y: max_abs_y?,
    })
}

/// Scores a shot from distance to goal and the angular opening between defenders.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ShotParams {
    pub max_distance: f64,
    pub min_opening: f64,
    pub distance_weight: f64,
    pub opening_weight: f64,
    pub threshold: f64,
}

impl ShotParams {
    /// Utility in [0, 1]; 0 when out of range or the opening is too narrow.
    pub fn utility(&self, distance: f64, opening: f64) -> f64 {
        if distance > self.max_distance || opening < self.min_opening {
            return 0.0;
        }
        let closeness = 1.0 - distance / self.max_distance;
        let width = (opening / std::f64::consts::FRAC_PI_2).min(1.0);
        let total = self.distance_weight + self.opening_weight;
        if total <= 0.0 {
            return 0.0;
        }
        (self.distance_weight * closeness + self.opening_weight * width) / total
    }

    pub fn should_shoot(&self, distance: f64, opening: f64) -> bool {
        self.utility(distance, opening) >= self.threshold
    }
}

pub fn parse_shot(decoder: &mut Decoder, node: &Node) -> Option<ShotParams> {
    let mut fields = decoder.fields(node, "ShotUtility")?;
    let max_distance = number(decoder, &mut fields, "max_distance", 1.0, 60.0, 12.0);
    let min_opening = number(decoder, &mut fields, "min_opening", 0.0, 1.5, 0.1);
    let distance_weight = number(decoder, &mut fields, "distance_weight", 0.0, 1.0, 0.5);
    let opening_weight = number(decoder, &mut fields, "opening_weight", 0.0, 1.0, 0.5);
    let threshold = number(decoder, &mut fields, "threshold", 0.0, 1.0, 0.4);
    let span = fields.span;
    fields.finish(
        decoder,
        &[
            "max_distance",
            "min_opening",
            "distance_weight",
            "opening_weight",
            "threshold",
        ],
    );
    let params = ShotParams {
        max_distance: max_distance?,
        min_opening: min_opening?,
        distance_weight: distance_weight?,
        opening_weight: opening_weight?,
        threshold: threshold?,
    };
    if params.distance_weight + params.opening_weight <= 0.0 {
        decoder
            .error("out-of-range", span, "shot weights are both zero")
            .hint = Some("give at least one weight a positive value".into());
        return None;
    }
    Some(params)
}

/// Potential-field obstacle avoidance: obstacles closer than `influence` push with `gain`;
/// closer than `radius` is a collision.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AvoidanceParams {
    pub radius: f64,
    pub influence: f64,
    pub gain: f64,
    pub ball_clearance: f64,
}

impl AvoidanceParams {
    /// Repulsion from one obstacle at `offset` from the robot (robot minus obstacle).
    pub fn repulsion(&self, offset: Vec2) -> Vec2 {
        let distance = (offset.x * offset.x + offset.y * offset.y).sqrt();
        if distance >= self.influence || distance < 1e-9 {
            return Vec2::default();
        }
        let strength = self.gain * (self.influence - distance.max(self.radius))
            / (self.influence - self.radius);
        Vec2::new(
            offset.x / distance * strength,
            offset.y / distance * strength,
        )
    }
}

pub fn parse_avoidance(decoder: &mut Decoder, node: &Node) -> Option<AvoidanceParams> {
    let mut fields = decoder.fields(node, "Avoidance")?;
    let radius = number(decoder, &mut fields, "radius", 0.05, 3.0, 0.5);
    let influence_node = fields.take("influence");
    let influence = match influence_node {
        Some(n) => decoder.float_in(n, 0.1, 10.0),
        None => Some(1.5),
    };
    let gain = number(decoder, &mut fields, "gain", 0.0, 10.0, 1.0);
    let ball_clearance = number(decoder, &mut fields, "ball_clearance", 0.0, 2.0, 0.3);
    let span = influence_node.map_or(fields.span, |n| n.span);
    fields.finish(decoder, &["radius", "influence", "gain", "ball_clearance"]);
    let params = AvoidanceParams {
        radius: radius?,
        influence: influence?,
        gain: gain?,
        ball_clearance: ball_clearance?,
    };
    if params.influence <= params.radius {
        let message = format!(
            "`influence` ({} m) must exceed `radius` ({} m)",
            params.influence, params.radius
        );
        decoder.error("out-of-range", span, message);
        return None;
    }
    Some(params)
}

/// The game situations that choose a formation. The agent classifies play modes into these.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Situation {
    KickOffOwn,
    KickOffTheirs,
    PlayOnAttack,
    PlayOnDefence,
    SetPlayOwn,
    SetPlayTheirs,
}

impl Situation {
    pub const ALL: [Situation; 6] = [
        Situation::KickOffOwn,
        Situation::KickOffTheirs,
        Situation::PlayOnAttack,
        Situation::PlayOnDefence,
        Situation::SetPlayOwn,
        Situation::SetPlayTheirs,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Situation::KickOffOwn => "KickOffOwn",
            Situation::KickOffTheirs => "KickOffTheirs",
            Situation::PlayOnAttack => "PlayOnAttack",
            Situation::PlayOnDefence => "PlayOnDefence",
            Situation::SetPlayOwn => "SetPlayOwn",
            Situation::SetPlayTheirs => "SetPlayTheirs",
        }
    }

    /// Play on splits into attack and defence by which half the ball is in (own frame).
    pub fn play_on(ball: Vec2) -> Situation {
        if ball.x >= 0.0 {
            Situation::PlayOnAttack
        } else {
            Situation::PlayOnDefence
        }
    }
}

/// The team file: which field, which tree each player runs, which formation each situation uses.
#[derive(Debug, Clone, PartialEq)]
pub struct TeamParams {
    pub field: Field,
    pub goalkeeper_tree: (String, Span),
    pub field_player_tree: (String, Span),
    pub formations: BTreeMap<Situation, (String, Span)>,
}

pub fn parse_team(decoder: &mut Decoder, node: &Node) -> Option<TeamParams> {
    let mut fields = decoder.fields(node, "Team")?;
    let field = match fields.take("field") {
        Some(n) => decoder.string(n).and_then(|name| {
            let field = Field::by_name(&name);
            if field.is_none() {
                decoder
                    .error(
                        "unknown-field-kind",
                        n.span,
                        format!("unknown field `{name}`"),
                    )
                    .hint = Some("fields are fifa7vs7 and fifa".into());
            }
            field
        }),
        None => Some(Field::default()),
    };
    let goalkeeper_tree = named(decoder, &mut fields, "goalkeeper_tree");
    let field_player_tree = named(decoder, &mut fields, "field_player_tree");
    let formations_node = fields.require(decoder, "formations");
    fields.finish(
        decoder,
        &[
            "field",
            "goalkeeper_tree",
            "field_player_tree",
            "formations",
        ],
    );
    let mut formations = BTreeMap::new();
    if let Some(node) = formations_node {
        for (key, value) in decoder.map(node).unwrap_or_default() {
            let Some((name, span)) = Decoder::head(key) else {
                decoder.error(
                    "invalid-value",
                    key.span,
                    "expected a situation such as `PlayOnAttack`",
                );
                continue;
            };
            let Some(situation) = Situation::ALL.into_iter().find(|s| s.name() == name) else {
                let hint =
                    crate::diagnostics::did_you_mean(name, Situation::ALL.iter().map(|s| s.name()));
                decoder
                    .error(
                        "unknown-situation",
                        span,
                        format!("unknown situation `{name}`"),
                    )
                    .hint = hint;
                continue;
            };
            if let Some(formation) = decoder.string(value) {
                formations.insert(situation, (formation, value.span));
            }
        }
        for situation in Situation::ALL {
            if !formations.contains_key(&situation) {
                decoder.error(
                    "missing-situation",
                    node.span,
                    format!("no formation for situation `{}`", situation.name()),
                );
            }
        }
    }
    Some(TeamParams {
        field: field?,
        goalkeeper_tree: goalkeeper_tree?,
        field_player_tree: field_player_tree?,
        formations,
    })
}

fn named(decoder: &mut Decoder, fields: &mut Fields, key: &str) -> Option<(String, Span)> {
    fields
        .require(decoder, key)
        .and_then(|n| decoder.string(n).map(|s| (s, n.span)))
}
