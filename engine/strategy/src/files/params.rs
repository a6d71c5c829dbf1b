//! Reading the tunable strategy files (goalkeeper, shot and pass utility, obstacle avoidance) and the team
//! file choosing formations per situation and trees per role. What the numbers do lives with
//! the code that uses them (`goalkeeper`, `shot`, `pass`, `avoidance`).

use super::field::Field;
pub use crate::avoidance::{AvoidanceParams, GridParams};
pub use crate::goalkeeper::{DefenseLine, GoalkeeperParams};
pub use crate::pass::PassParams;
pub use crate::shot::ShotParams;
use libero_behavior::decode::{Decoder, Fields};
use libero_behavior::syntax::{Node, Span};
use libero_behavior::Vec2;
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

pub fn parse_goalkeeper(decoder: &mut Decoder, node: &Node) -> Option<GoalkeeperParams> {
    let mut fields = decoder.fields(node, "Goalkeeper")?;
    let line = match fields.take("line") {
        Some(n) => decoder.string(n).and_then(|name| match name.as_str() {
            "ball_line" => Some(DefenseLine::BallLine),
            "post_bisector" => Some(DefenseLine::PostBisector),
            other => {
                decoder
                    .error(
                        "invalid-value",
                        n.span,
                        format!("unknown defense line `{other}`"),
                    )
                    .hint = Some("`ball_line` or `post_bisector`".into());
                None
            }
        }),
        None => Some(DefenseLine::BallLine),
    };
    let d = GoalkeeperParams::default();
    let max_span = fields.peek_span("max_distance_m");
    let mut num = |name: &str, min: f64, max: f64, default: f64| {
        number(decoder, &mut fields, name, min, max, default)
    };
    let min_distance_m = num("min_distance_m", 0.0, 10.0, d.min_distance_m);
    let max_distance_m = num("max_distance_m", 0.0, 10.0, d.max_distance_m);
    let distance_per_ball_m = num("distance_per_ball_m", 0.0, 1.0, d.distance_per_ball_m);
    let min_line_offset_m = num("min_line_offset_m", 0.0, 3.0, d.min_line_offset_m);
    let area_margin_m = num("area_margin_m", 0.0, 3.0, d.area_margin_m);
    let clear_within_m = num("clear_within_m", 0.0, 30.0, d.clear_within_m);
    let clear_margin_s = num("clear_margin_s", 0.0, 10.0, d.clear_margin_s);
    let walk_speed_m_s = num("walk_speed_m_s", 0.01, 2.0, d.walk_speed_m_s);
    let shot_min_speed_m_s = num("shot_min_speed_m_s", 0.0, 20.0, d.shot_min_speed_m_s);
    let post_margin_m = num("post_margin_m", 0.0, 3.0, d.post_margin_m);
    let save_within_s = num("save_within_s", 0.0, 10.0, d.save_within_s);
    let block_reach_m = num("block_reach_m", 0.0, 2.0, d.block_reach_m);
    let dive_reach_m = num("dive_reach_m", 0.0, 4.0, d.dive_reach_m);
    let scan_every_s = num("scan_every_s", 0.5, 60.0, d.scan_every_s);
    let scan_s = num("scan_s", 0.0, 10.0, d.scan_s);
    let span = max_span.unwrap_or(fields.span);
    fields.finish(
        decoder,
        &[
            "line",
            "min_distance_m",
            "max_distance_m",
            "distance_per_ball_m",
            "min_line_offset_m",
            "area_margin_m",
            "clear_within_m",
            "clear_margin_s",
            "walk_speed_m_s",
            "shot_min_speed_m_s",
            "post_margin_m",
            "save_within_s",
            "block_reach_m",
            "dive_reach_m",
            "scan_every_s",
            "scan_s",
        ],
    );
    let params = GoalkeeperParams {
        line: line?,
        min_distance_m: min_distance_m?,
        max_distance_m: max_distance_m?,
        distance_per_ball_m: distance_per_ball_m?,
        min_line_offset_m: min_line_offset_m?,
        area_margin_m: area_margin_m?,
        clear_within_m: clear_within_m?,
        clear_margin_s: clear_margin_s?,
        walk_speed_m_s: walk_speed_m_s?,
        shot_min_speed_m_s: shot_min_speed_m_s?,
        post_margin_m: post_margin_m?,
        save_within_s: save_within_s?,
        block_reach_m: block_reach_m?,
        dive_reach_m: dive_reach_m?,
        scan_every_s: scan_every_s?,
        scan_s: scan_s?,
    };
    if params.max_distance_m < params.min_distance_m {
        let message = format!(
            "`max_distance_m` ({} m) is below `min_distance_m` ({} m)",
            params.max_distance_m, params.min_distance_m
        );
        decoder.error("out-of-range", span, message);
        return None;
    }
    Some(params)
}

pub fn parse_shot(decoder: &mut Decoder, node: &Node) -> Option<ShotParams> {
    let mut fields = decoder.fields(node, "ShotUtility")?;
    let d = ShotParams::default();
    let targets = match fields.take("targets") {
        Some(n) => decoder.int_in(n, 1, 101).map(|t| t as usize),
        None => Some(d.targets),
    };
    let mut num = |name: &str, min: f64, max: f64, default: f64| {
        number(decoder, &mut fields, name, min, max, default)
    };
    let post_margin_m = num("post_margin_m", 0.0, 3.0, d.post_margin_m);
    let max_distance_m = num("max_distance_m", 1.0, 60.0, d.max_distance_m);
    let ball_speed_m_s = num("ball_speed_m_s", 0.5, 30.0, d.ball_speed_m_s);
    let keeper_reach_m = num("keeper_reach_m", 0.0, 5.0, d.keeper_reach_m);
    let keeper_speed_m_s = num("keeper_speed_m_s", 0.0, 5.0, d.keeper_speed_m_s);
    let keeper_reaction_s = num("keeper_reaction_s", 0.0, 5.0, d.keeper_reaction_s);
    let block_radius_m = num("block_radius_m", 0.0, 3.0, d.block_radius_m);
    let threshold = num("threshold", 0.0, 1.0, d.threshold);
    let hysteresis = num("hysteresis", 0.0, 1.0, d.hysteresis);
    fields.finish(
        decoder,
        &[
            "targets",
            "post_margin_m",
            "max_distance_m",
            "ball_speed_m_s",
            "keeper_reach_m",
            "keeper_speed_m_s",
            "keeper_reaction_s",
            "block_radius_m",
            "threshold",
            "hysteresis",
        ],
    );
    Some(ShotParams {
        targets: targets?,
        post_margin_m: post_margin_m?,
        max_distance_m: max_distance_m?,
        ball_speed_m_s: ball_speed_m_s?,
        keeper_reach_m: keeper_reach_m?,
        keeper_speed_m_s: keeper_speed_m_s?,
        keeper_reaction_s: keeper_reaction_s?,
        block_radius_m: block_radius_m?,
        threshold: threshold?,
        hysteresis: hysteresis?,
    })
}

pub fn parse_pass(decoder: &mut Decoder, node: &Node) -> Option<PassParams> {
    let mut fields = decoder.fields(node, "PassUtility")?;
    let d = PassParams::default();
    let directions = match fields.take("directions") {
        Some(n) => decoder.int_in(n, 1, 181).map(|t| t as usize),
        None => Some(d.directions),
    };
    let mut num = |name: &str, min: f64, max: f64, default: f64| {
        number(decoder, &mut fields, name, min, max, default)
    };
    let fan_deg = num("fan_deg", 0.0, 180.0, d.fan_deg);
    let field_margin_m = num("field_margin_m", 0.0, 10.0, d.field_margin_m);
    let block_radius_m = num("block_radius_m", 0.0, 3.0, d.block_radius_m);
    let walk_speed_m_s = num("walk_speed_m_s", 0.05, 5.0, d.walk_speed_m_s);
    let race_scale_s = num("race_scale_s", 0.1, 60.0, d.race_scale_s);
    let opponent_at_most_s = num("opponent_at_most_s", 0.0, 120.0, d.opponent_at_most_s);
    let progress_weight = num("progress_weight", 0.0, 10.0, d.progress_weight);
    let race_weight = num("race_weight", 0.0, 10.0, d.race_weight);
    let hysteresis = num("hysteresis", 0.0, 1.0, d.hysteresis);
    let anticipate_within_m = num("anticipate_within_m", 0.0, 20.0, d.anticipate_within_m);
    let commit_within_m = num("commit_within_m", 0.0, 5.0, d.commit_within_m);
    let receive_beside_m = num("receive_beside_m", 0.0, 5.0, d.receive_beside_m);
    fields.finish(
        decoder,
        &[
            "directions",
            "fan_deg",
            "field_margin_m",
            "block_radius_m",
            "walk_speed_m_s",
            "race_scale_s",
            "opponent_at_most_s",
            "progress_weight",
            "race_weight",
            "hysteresis",
            "anticipate_within_m",
            "commit_within_m",
            "receive_beside_m",
        ],
    );
    Some(PassParams {
        directions: directions?,
        fan_deg: fan_deg?,
        field_margin_m: field_margin_m?,
        block_radius_m: block_radius_m?,
        walk_speed_m_s: walk_speed_m_s?,
        race_scale_s: race_scale_s?,
        opponent_at_most_s: opponent_at_most_s?,
        progress_weight: progress_weight?,
        race_weight: race_weight?,
        hysteresis: hysteresis?,
        anticipate_within_m: anticipate_within_m?,
        commit_within_m: commit_within_m?,
        receive_beside_m: receive_beside_m?,
    })
}

pub fn parse_avoidance(decoder: &mut Decoder, node: &Node) -> Option<AvoidanceParams> {
    let mut fields = decoder.fields(node, "Avoidance")?;
    let d = AvoidanceParams::default();
    let grid_node = fields.take("grid");
    let behind_span = fields.peek_span("behind_ball_m");
    let clear_handover_span = fields.peek_span("clear_handover_m");
    let mut num = |name: &str, min: f64, max: f64, default: f64| {
        number(decoder, &mut fields, name, min, max, default)
    };
    let robot_clearance_m = num("robot_clearance_m", 0.1, 3.0, d.robot_clearance_m);
    let post_clearance_m = num("post_clearance_m", 0.0, 3.0, d.post_clearance_m);
    let ball_clearance_m = num("ball_clearance_m", 0.0, 2.0, d.ball_clearance_m);
    let lookahead_m = num("lookahead_m", 0.1, 20.0, d.lookahead_m);
    let detour_margin_m = num("detour_margin_m", 0.0, 2.0, d.detour_margin_m);
    let memory_s = num("memory_s", 0.0, 30.0, d.memory_s);
    let handover_m = num("handover_m", 0.3, 5.0, d.handover_m);
    // Absent: no earlier hand-over (the plain `handover_m`).
    let clear_handover_m = num("clear_handover_m", 0.3, 10.0, f64::NAN);
    let behind_ball_m = num("behind_ball_m", 0.2, 3.0, d.behind_ball_m);
    let meeting_speed_m_s = num("meeting_speed_m_s", 0.05, 3.0, d.meeting_speed_m_s);
    fields.finish(
        decoder,
        &[
            "robot_clearance_m",
            "post_clearance_m",
            "ball_clearance_m",
            "lookahead_m",
            "detour_margin_m",
            "memory_s",
            "handover_m",
            "clear_handover_m",
            "behind_ball_m",
            "meeting_speed_m_s",
            "grid",
        ],
    );
    let grid = match grid_node {
        Some(n) => parse_grid(decoder, n),
        None => Some(d.grid),
    };
    let params = AvoidanceParams {
        robot_clearance_m: robot_clearance_m?,
        post_clearance_m: post_clearance_m?,
        ball_clearance_m: ball_clearance_m?,
        lookahead_m: lookahead_m?,
        detour_margin_m: detour_margin_m?,
        memory_s: memory_s?,
        handover_m: handover_m?,
        clear_handover_m: clear_handover_m.map(|m| {
            if m.is_nan() {
                handover_m.unwrap_or(d.handover_m)
            } else {
                m
            }
        })?,
        behind_ball_m: behind_ball_m?,
        meeting_speed_m_s: meeting_speed_m_s?,
        grid: grid?,
    };
    if params.behind_ball_m >= params.handover_m {
        let span = behind_span.unwrap_or(node.span);
        let message = format!(
            "`behind_ball_m` ({} m) must be below `handover_m` ({} m): the point behind the ball must lie inside the kick skill's hand-over distance",
            params.behind_ball_m, params.handover_m
        );
        decoder.error("out-of-range", span, message);
        return None;
    }
    if params.clear_handover_m < params.handover_m {
        let span = clear_handover_span.unwrap_or(node.span);
        let message = format!(
            "`clear_handover_m` ({} m) must not be below `handover_m` ({} m): with the way clear the kick skill takes over at least as early",
            params.clear_handover_m, params.handover_m
        );
        decoder.error("out-of-range", span, message);
        return None;
    }
    Some(params)
}

fn parse_grid(decoder: &mut Decoder, node: &Node) -> Option<GridParams> {
    let mut fields = decoder.fields(node, "Grid")?;
    let d = AvoidanceParams::default().grid;
    let mut num = |name: &str, min: f64, max: f64, default: f64| {
        number(decoder, &mut fields, name, min, max, default)
    };
    let cell_m = num("cell_m", 0.05, 2.0, d.cell_m);
    let inflation_m = num("inflation_m", 0.0, 2.0, d.inflation_m);
    let replan_s = num("replan_s", 0.0, 10.0, d.replan_s);
    let margin_m = num("margin_m", 0.0, 20.0, d.margin_m);
    fields.finish(decoder, &["cell_m", "inflation_m", "replan_s", "margin_m"]);
    Some(GridParams {
        cell_m: cell_m?,
        inflation_m: inflation_m?,
        replan_s: replan_s?,
        margin_m: margin_m?,
    })
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
    /// Which side kicks off the first half (`true` = left), when the competition says so:
    /// before that kick-off the team then takes its own or its kick-off-theirs positions.
    /// Unknown: the positions that are legal either way.
    pub left_kicks_off_first: Option<bool>,
    /// SimSpark: the heterogeneous NAO type of each uniform number (1 first), checked
    /// against the server's rules for a team's mix; none: the default mix.
    pub robot_types: Option<Vec<u8>>,
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
                    .hint = Some(format!("fields are {}", Field::names().join(", ")));
            }
            field
        }),
        None => Some(Field::default()),
    };
    let goalkeeper_tree = named(decoder, &mut fields, "goalkeeper_tree");
    let field_player_tree = named(decoder, &mut fields, "field_player_tree");
    let formations_node = fields.require(decoder, "formations");
    let left_kicks_off_first =
        fields
            .take("first_kick_off")
            .and_then(|n| match decoder.string(n).as_deref() {
                Some("Left") => Some(true),
                Some("Right") => Some(false),
                Some(other) => {
                    decoder
                        .error(
                            "invalid-value",
                            n.span,
                            format!("unknown side `{other}` for `first_kick_off`"),
                        )
                        .hint = Some("`Left` or `Right`; leave it out when unknown".into());
                    None
                }
                None => None,
            });
    let robot_types = fields
        .take("robot_types")
        .and_then(|n| robot_types(decoder, n));
    fields.finish(
        decoder,
        &[
            "field",
            "goalkeeper_tree",
            "field_player_tree",
            "formations",
            "first_kick_off",
            "robot_types",
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
                    libero_behavior::did_you_mean(name, Situation::ALL.iter().map(|s| s.name()));
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
        left_kicks_off_first,
        formations,
        robot_types,
    })
}

fn named(decoder: &mut Decoder, fields: &mut Fields, key: &str) -> Option<(String, Span)> {
    fields
        .require(decoder, key)
        .and_then(|n| decoder.string(n).map(|s| (s, n.span)))
}

/// `robot_types: [0, 3, …]`: a NAO type (0–4) per uniform number, a mix the server admits.
fn robot_types(decoder: &mut Decoder, node: &Node) -> Option<Vec<u8>> {
    let items = decoder.list(node)?;
    let mut types = Vec::with_capacity(items.len());
    for item in items {
        types.push(decoder.int_in(item, 0, 4)? as u8);
    }
    if let Err(rule) = libero_model::team_types::check_simspark_types(&types) {
        decoder
            .error(
                "invalid-value",
                node.span,
                format!("SimSpark would refuse this team: {rule}"),
            )
            .hint = Some(
            "at most 7 robots of a type, any two types together at most 9, at most 11 players"
                .into(),
        );
        return None;
    }
    Some(types)
}
