//! Formations: player positions as a function of the ball position, from samples interpolated
//! over their Delaunay triangulation (as in HELIOS formations), then pulled toward the ball and
//! clamped to a region per role (as in SBSP).

use super::field::Field;
use libero_behavior::decode::Decoder;
use libero_behavior::did_you_mean;
use libero_behavior::syntax::{Node, Span};
use libero_behavior::Vec2;

#[derive(Debug, Clone, PartialEq)]
pub struct Role {
    pub unum: u8,
    pub name: String,
    /// Fraction of the way toward the ball, per axis, added after interpolation.
    pub attraction: Vec2,
    /// Where this role may stand: (min corner, max corner).
    pub region: Option<(Vec2, Vec2)>,
}

#[derive(Debug, Clone, PartialEq)]
pub struct Sample {
    pub ball: Vec2,
    /// Index `unum - 1`.
    pub positions: Vec<Vec2>,
}

#[derive(Debug, Clone, PartialEq)]
pub struct Formation {
    pub name: String,
    pub field: Field,
    pub roles: Vec<Role>,
    pub samples: Vec<Sample>,
    triangles: Vec<[usize; 3]>,
}

/// Triangles thinner than this (m²) make the interpolation numerically meaningless.
const MIN_TRIANGLE_AREA: f64 = 0.05;

fn area(a: Vec2, b: Vec2, c: Vec2) -> f64 {
    ((b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y)) / 2.0
}

/// Barycentric weights of `p` in triangle abc, if it is inside (with a small tolerance).
fn barycentric(p: Vec2, a: Vec2, b: Vec2, c: Vec2) -> Option<[f64; 3]> {
    let total = area(a, b, c);
    if total.abs() < 1e-12 {
        return None;
    }
    let weights = [
        area(p, b, c) / total,
        area(a, p, c) / total,
        area(a, b, p) / total,
    ];
    weights.iter().all(|w| *w >= -1e-9).then_some(weights)
}

impl Formation {
    /// Where player `unum` stands for a ball at `ball`. Balls outside the field are clamped
    /// onto it first, so every ball position has an answer.
    pub fn position(&self, unum: u8, ball: Vec2) -> Option<Vec2> {
        let index = (unum as usize).checked_sub(1)?;
        let role = self.roles.iter().find(|r| r.unum == unum)?;
        let ball = self.field.clamp(ball);
        let interpolated = self.interpolate(index, ball)?;
        let mut position = Vec2::new(
            interpolated.x + role.attraction.x * (ball.x - interpolated.x),
            interpolated.y + role.attraction.y * (ball.y - interpolated.y),
        );
        if let Some((min, max)) = role.region {
            position = Vec2::new(
                position.x.clamp(min.x, max.x),
                position.y.clamp(min.y, max.y),
            );
        }
        Some(self.field.clamp(position))
    }

    fn interpolate(&self, index: usize, ball: Vec2) -> Option<Vec2> {
        let point = |sample: usize| self.samples[sample].ball;
        let located = self
            .triangles
            .iter()
            .find_map(|t| barycentric(ball, point(t[0]), point(t[1]), point(t[2])).map(|w| (t, w)))
            .or_else(|| {
                // Validation guarantees the hull covers the field; rounding at its edge may
                // still miss, so fall back to the triangle with the nearest vertex.
                let nearest = self.triangles.iter().min_by(|a, b| {
                    let d = |t: &&[usize; 3]| {
                        t.iter()
                            .map(|&s| point(s).distance(ball))
                            .fold(f64::INFINITY, f64::min)
                    };
                    d(a).total_cmp(&d(b))
                })?;
                let weights = [1.0 / 3.0; 3];
                Some((nearest, weights))
            })?;
        let (triangle, weights) = located;
        let mut out = Vec2::default();
        for (corner, weight) in triangle.iter().zip(weights) {
            let p = self.samples[*corner].positions.get(index)?;
            out.x += weight * p.x;
            out.y += weight * p.y;
        }
        Some(out)
    }

    pub fn triangles(&self) -> &[[usize; 3]] {
        &self.triangles
    }
}

/// Reads and validates `Formation(name, field, roles, samples)`.
pub fn parse_formation(decoder: &mut Decoder, node: &Node) -> Option<Formation> {
    let errors_before = decoder.report.error_count();
    let mut fields = decoder.fields(node, "Formation")?;
    let name = fields
        .require(decoder, "name")
        .and_then(|n| decoder.string(n));
    let field = match fields.take("field") {
        Some(n) => decoder.string(n).and_then(|name| {
            let field = Field::by_name(&name);
            if field.is_none() {
                let hint = did_you_mean(&name, Field::names());
                decoder
                    .error(
                        "unknown-field-kind",
                        n.span,
                        format!("unknown field `{name}`"),
                    )
                    .hint =
                    hint.or_else(|| Some(format!("fields are {}", Field::names().join(", "))));
            }
            field
        }),
        None => Some(Field::default()),
    };
    let roles_node = fields.require(decoder, "roles");
    let samples_node = fields.require(decoder, "samples");
    fields.finish(decoder, &["name", "field", "roles", "samples"]);
    let field = field?;
    let roles = roles_node
        .map(|n| roles(decoder, n, &field))
        .unwrap_or_default();
    let (samples, spans) = samples_node
        .map(|n| samples(decoder, n, &field))
        .unwrap_or_default();
    let triangles = samples_node
        .map(|n| triangulate(decoder, n.span, &samples, &spans, &field))
        .unwrap_or_default();
    if decoder.report.error_count() > errors_before {
        return None;
    }
    Some(Formation {
        name: name?,
        field,
        roles,
        samples,
        triangles,
    })
}

fn unum(decoder: &mut Decoder, node: &Node, field: &Field) -> Option<u8> {
    decoder
        .int_in(node, 1, i64::from(field.players()))
        .map(|u| u as u8)
}

fn point_on_field(decoder: &mut Decoder, node: &Node, field: &Field) -> Option<Vec2> {
    let p = decoder.vec2(node)?;
    if !field.contains(p) {
        let message = format!("({}, {}) is off the {} field", p.x, p.y, field.name());
        decoder.error("off-field", node.span, message).hint = Some(format!(
            "x must be within ±{}, y within ±{}",
            field.half_length(),
            field.half_width()
        ));
        return None;
    }
    Some(p)
}

fn roles(decoder: &mut Decoder, node: &Node, field: &Field) -> Vec<Role> {
    let mut roles: Vec<Role> = Vec::new();
    // Players whose role had other errors still count as present, to avoid a second error.
    let mut present: Vec<u8> = Vec::new();
    for item in decoder.list(node).unwrap_or_default() {
        let Some(mut fields) = decoder.fields(item, "Role") else {
            continue;
        };
        let unum_node = fields.require(decoder, "unum");
        let unum = unum_node.and_then(|n| unum(decoder, n, field));
        let name = fields
            .require(decoder, "name")
            .and_then(|n| decoder.string(n));
        let attraction = match fields.take("attraction") {
            Some(n) => decoder.vec2(n).and_then(|a| {
                let ok = (0.0..=1.0).contains(&a.x) && (0.0..=1.0).contains(&a.y);
                if !ok {
                    decoder.error(
                        "out-of-range",
                        n.span,
                        "attraction components must be in [0, 1]",
                    );
                }
                ok.then_some(a)
            }),
            None => Some(Vec2::default()),
        };
        let region = match fields.take("region") {
            Some(n) => region(decoder, n, field).map(Some),
            None => Some(None),
        };
        fields.finish(decoder, &["unum", "name", "attraction", "region"]);
        if let (Some(unum), Some(unum_node)) = (unum, unum_node) {
            if present.contains(&unum) {
                decoder.error(
                    "duplicate-player",
                    unum_node.span,
                    format!("player {unum} has two roles"),
                );
            }
            present.push(unum);
            if let (Some(name), Some(attraction), Some(region)) = (name, attraction, region) {
                roles.push(Role {
                    unum,
                    name,
                    attraction,
                    region,
                });
            }
        }
    }
    for unum in 1..=field.players() {
        if !present.contains(&unum) {
            decoder
                .error(
                    "missing-player",
                    node.span,
                    format!("no role for player {unum}"),
                )
                .hint = Some(format!(
                "a {} formation needs roles for players 1 to {}",
                field.name(),
                field.players()
            ));
        }
    }
    roles
}

fn region(decoder: &mut Decoder, node: &Node, field: &Field) -> Option<(Vec2, Vec2)> {
    let mut fields = decoder.fields(node, "Region")?;
    let min = fields
        .require(decoder, "min")
        .and_then(|n| point_on_field(decoder, n, field));
    let max = fields
        .require(decoder, "max")
        .and_then(|n| point_on_field(decoder, n, field));
    fields.finish(decoder, &["min", "max"]);
    let (min, max) = (min?, max?);
    if min.x > max.x || min.y > max.y {
        decoder.error(
            "invalid-value",
            node.span,
            "a region's `min` must be below and left of its `max`",
        );
        return None;
    }
    Some((min, max))
}

fn samples(decoder: &mut Decoder, node: &Node, field: &Field) -> (Vec<Sample>, Vec<Span>) {
    let (mut samples, mut spans): (Vec<Sample>, Vec<Span>) = (Vec::new(), Vec::new());
    for item in decoder.list(node).unwrap_or_default() {
        let Some(mut fields) = decoder.fields(item, "Sample") else {
            continue;
        };
        let ball_node = fields.require(decoder, "ball");
        let ball = ball_node.and_then(|n| point_on_field(decoder, n, field));
        let positions = fields
            .require(decoder, "positions")
            .and_then(|n| positions(decoder, n, field));
        fields.finish(decoder, &["ball", "positions"]);
        let (Some(ball), Some(ball_node), Some(positions)) = (ball, ball_node, positions) else {
            continue;
        };
        if let Some(first) = samples
            .iter()
            .position(|s: &Sample| s.ball.distance(ball) < 1e-6)
        {
            let (line, _) = decoder.file.line_col(spans[first].start);
            decoder
                .error(
                    "duplicate-sample",
                    ball_node.span,
                    format!("two samples for ball ({}, {})", ball.x, ball.y),
                )
                .hint = Some(format!("the other one is on line {line}"));
            continue;
        }
        samples.push(Sample { ball, positions });
        spans.push(ball_node.span);
    }
    (samples, spans)
}

fn positions(decoder: &mut Decoder, node: &Node, field: &Field) -> Option<Vec<Vec2>> {
    let entries = decoder.map(node)?;
    let mut positions: Vec<Option<Vec2>> = vec![None; field.players() as usize];
    let mut complete = true;
    for (key, value) in entries {
        let unum = unum(decoder, key, field);
        let position = point_on_field(decoder, value, field);
        match (unum, position) {
            (Some(u), Some(p)) if positions[u as usize - 1].is_none() => {
                positions[u as usize - 1] = Some(p)
            }
            (Some(u), Some(_)) => {
                decoder.error(
                    "duplicate-player",
                    key.span,
                    format!("player {u} is placed twice"),
                );
                complete = false;
            }
            _ => complete = false,
        }
    }
    let missing: Vec<String> = (1..=field.players())
        .filter(|u| positions[*u as usize - 1].is_none())
        .map(|u| u.to_string())
        .collect();
    if complete && !missing.is_empty() {
        decoder
            .error(
                "missing-player",
                node.span,
                format!("no position for player(s) {}", missing.join(", ")),
            )
            .hint = Some(format!(
            "every sample places players 1 to {}",
            field.players()
        ));
    }
    positions.into_iter().collect()
}

fn triangulate(
    decoder: &mut Decoder,
    span: Span,
    samples: &[Sample],
    spans: &[Span],
    field: &Field,
) -> Vec<[usize; 3]> {
    if samples.len() < 3 {
        decoder
            .error(
                "field-not-covered",
                span,
                "a formation needs at least 3 samples",
            )
            .hint = Some("add samples at the field corners and centre".into());
        return Vec::new();
    }
    let points: Vec<delaunator::Point> = samples
        .iter()
        .map(|s| delaunator::Point {
            x: s.ball.x,
            y: s.ball.y,
        })
        .collect();
    let triangulation = delaunator::triangulate(&points);
    let triangles: Vec<[usize; 3]> = triangulation
        .triangles
        .chunks_exact(3)
        .map(|t| [t[0], t[1], t[2]])
        .collect();
    let ball = |i: usize| samples[i].ball;
    for triangle in &triangles {
        let a = area(ball(triangle[0]), ball(triangle[1]), ball(triangle[2])).abs();
        if a < MIN_TRIANGLE_AREA {
            let corners: Vec<String> = triangle
                .iter()
                .map(|&i| format!("({}, {})", ball(i).x, ball(i).y))
                .collect();
            let message = format!("degenerate triangle {} (area {a:.4} m²)", corners.join(" "));
            decoder
                .error("degenerate-triangle", spans[triangle[0]], message)
                .hint = Some(
                "move or remove one of these samples: nearly collinear samples cannot interpolate"
                    .into(),
            );
        }
    }
    let covered = |p: Vec2| {
        triangles
            .iter()
            .any(|t| barycentric(p, ball(t[0]), ball(t[1]), ball(t[2])).is_some())
    };
    let uncovered: Vec<String> = field
        .corners()
        .into_iter()
        .filter(|c| !covered(*c))
        .map(|c| format!("({}, {})", c.x, c.y))
        .collect();
    if !uncovered.is_empty() {
        let message = format!(
            "the samples' triangulation does not cover the field: corner(s) {} outside",
            uncovered.join(", ")
        );
        decoder.error("field-not-covered", span, message).hint =
            Some("add samples whose ball positions are the field's corners".into());
    }
    triangles
}
