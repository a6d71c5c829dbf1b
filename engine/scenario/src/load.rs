//! `Scenario(...)` files: decoding and validation with located diagnostics.

use crate::conditions::success;
use crate::decode::{head, items, Decoder};
use crate::spec::{shortfall, BallSpec, Launch, Num, Place, Play, Point, Rng, Robot, Scenario};
use libero_behavior::diagnostics::{did_you_mean, Diagnostic, Report, SourceFile};
use libero_behavior::files::{read_text, strip_bom};
use libero_behavior::syntax::{self, Node, NodeKind, Span};
use libero_model::FieldGeometry;
use libero_world::WorldParams;
use std::path::Path;
use std::sync::Arc;

const SCENARIO_FIELDS: &[&str] = &[
    "name",
    "field",
    "ours",
    "theirs",
    "ball",
    "settle_s",
    "play_mode",
    "time_limit_s",
    "success",
];
const ROBOT_FIELDS: &[&str] = &["unum", "at", "heading_deg", "play"];
/// Torsos placed closer than this are warned about (they would start in contact) [m].
const MIN_PLACEMENT_GAP_M: f64 = 0.5;
/// Draws checked for launches that stop short of their target.
const LAUNCH_CHECKS: usize = 256;

/// Whether `text` is a scenario file: its top value is `Scenario(...)` (looked at after
/// comments, so a scenario with a syntax error further down still counts).
pub fn is_scenario_text(text: &str) -> bool {
    let mut rest = strip_bom(text);
    loop {
        rest = rest.trim_start();
        if let Some(after) = rest.strip_prefix("//") {
            rest = after.split_once('\n').map_or("", |(_, r)| r);
        } else if let Some(after) = rest.strip_prefix("/*") {
            rest = after.split_once("*/").map_or("", |(_, r)| r);
        } else if rest.starts_with("#!") {
            rest = rest.split_once('\n').map_or("", |(_, r)| r);
        } else {
            break;
        }
    }
    rest.strip_prefix("Scenario")
        .is_some_and(|r| r.trim_start().starts_with('('))
}

/// Read and validate one scenario file. Errors (and warnings) go to the report; `None` when
/// there were errors.
pub fn load_file(path: &Path, report: &mut Report) -> Option<Scenario> {
    let text = match read_text(path) {
        Ok(text) => text,
        Err(e) => {
            report.push(Diagnostic::error("io", e.describe(path)));
            return None;
        }
    };
    load_text(path, text, report)
}

/// Validate a scenario from its text (`path` names it in diagnostics).
pub fn load_text(path: &Path, text: String, report: &mut Report) -> Option<Scenario> {
    let file = Arc::new(SourceFile::new(path.to_path_buf(), text));
    let errors_before = report.error_count();
    let node = match syntax::parse(&file.text) {
        Ok(node) => node,
        Err(e) => {
            let mut d = Diagnostic::error("syntax", e.message).at(&file, e.span);
            d.hint = e.hint;
            report.push(d);
            return None;
        }
    };
    let mut decoder = Decoder::new(Arc::clone(&file), report);
    let scenario = scenario(&mut decoder, &node);
    (report.error_count() == errors_before)
        .then_some(scenario)
        .flatten()
}

/// Validate every scenario file among `files`.
pub fn validate_files(files: &[std::path::PathBuf]) -> Report {
    let mut report = Report::default();
    for f in files {
        load_file(f, &mut report);
    }
    report
}

fn scenario(d: &mut Decoder, node: &Node) -> Option<Scenario> {
    let mut f = d.fields(node, "Scenario")?;
    let name = f.require(d, "name").and_then(|n| d.string(n));
    if let (Some(n), Some(node)) = (&name, f.take("name")) {
        if n.trim().is_empty() {
            d.error("invalid-value", node.span, "the name is empty");
        }
    }
    let field = match f.take("field") {
        None => FieldGeometry::builtin("fifa7vs7").ok(),
        Some(node) => d
            .string(node)
            .and_then(|n| match FieldGeometry::builtin(&n) {
                Ok(g) => Some(g),
                Err(_) => {
                    let known = FieldGeometry::builtin_names();
                    let hint = did_you_mean(&n, known.iter().copied())
                        .unwrap_or_else(|| format!("built-in fields: {}", known.join(", ")));
                    d.error_hint(
                        "unknown-field-geometry",
                        node.span,
                        format!("unknown field `{n}`"),
                        hint,
                    );
                    None
                }
            }),
    };
    // Without a known field nothing else can be checked against it; check the shapes anyway.
    let geometry = field
        .clone()
        .or_else(|| FieldGeometry::builtin("fifa7vs7").ok())?;
    let max_unum = if geometry.length > 80.0 { 11 } else { 7 };
    let ball_node = f.require(d, "ball");
    let ball = ball_node.and_then(|n| ball(d, n, &geometry));
    let ours = f
        .require(d, "ours")
        .and_then(|n| team(d, n, "ours", Play::Tree, &geometry, max_unum, ball.as_ref()));
    let theirs = match f.take("theirs") {
        None => Some(Vec::new()),
        Some(n) => team(
            d,
            n,
            "theirs",
            Play::Stand,
            &geometry,
            max_unum,
            ball.as_ref(),
        ),
    };
    if let (Some(o), Some(node)) = (&ours, f.take("ours")) {
        if o.is_empty() {
            d.error_hint(
                "empty-team",
                node.span,
                "`ours` has no robot",
                "our team connects first and plays from the left: give it at least one robot",
            );
        }
    }
    // The only play mode the monitor of rcsssmj 0.2.1 can set with the ball where the file puts
    // it: `(dropBall)` gives PlayOn; `(playMode …)` is parsed and ignored, `(kickOff …)` moves
    // the ball to the centre.
    let play_mode_ok = match f.take("play_mode") {
        None => true,
        Some(n) => match &n.kind {
            NodeKind::Unit(id) if id.name == "PlayOn" => true,
            _ => {
                d.error_hint(
                    "unsupported-play-mode",
                    n.span,
                    format!("play mode {} cannot be set", n.describe()),
                    "rcssservermj 0.2.1 ignores `(playMode ...)` from the monitor; scenarios run in `PlayOn` (set with `(dropBall)`)",
                );
                false
            }
        },
    };
    let settle_s = match f.take("settle_s") {
        None => Some(1.0),
        Some(n) => d.float_in_unit(n, 0.0, 10.0, "s"),
    };
    let time_limit_s = f
        .require(d, "time_limit_s")
        .and_then(|n| d.float_in_unit(n, 0.1, 300.0, "s"));
    let success = f
        .require(d, "success")
        .and_then(|n| success(d, n, ours.as_deref().unwrap_or(&[]), ours.is_some()));
    f.finish(d, SCENARIO_FIELDS);
    if let (Some(o), Some(t)) = (&ours, &theirs) {
        placement_gaps(d, node, o, t);
    }
    if !play_mode_ok {
        return None;
    }
    Some(Scenario {
        name: name?,
        field: field?,
        ours: ours?,
        theirs: theirs?,
        ball: ball?,
        settle_s: settle_s?,
        time_limit_s: time_limit_s?,
        success: success?,
    })
}

fn team(
    d: &mut Decoder,
    node: &Node,
    side: &str,
    default_play: Play,
    field: &FieldGeometry,
    max_unum: i64,
    ball: Option<&BallSpec>,
) -> Option<Vec<Robot>> {
    let list = d.list(node)?;
    let mut robots = Vec::new();
    let mut seen: Vec<(u32, Span)> = Vec::new();
    let mut ok = true;
    for item in list {
        match robot(d, item, default_play, field, max_unum, ball) {
            Some((robot, unum_span)) => {
                if seen.iter().any(|(u, _)| *u == robot.unum) {
                    d.error_hint(
                        "duplicate-unum",
                        unum_span,
                        format!("uniform number {} is given twice in `{side}`", robot.unum),
                        "each robot of a team needs its own number",
                    );
                    ok = false;
                }
                seen.push((robot.unum, unum_span));
                robots.push(robot);
            }
            None => ok = false,
        }
    }
    ok.then_some(robots)
}

fn robot(
    d: &mut Decoder,
    node: &Node,
    default_play: Play,
    field: &FieldGeometry,
    max_unum: i64,
    ball: Option<&BallSpec>,
) -> Option<(Robot, Span)> {
    let mut f = d.fields(node, "Robot")?;
    let unum_node = f.require(d, "unum");
    let unum = unum_node.and_then(|n| d.int_in(n, 1, max_unum));
    let at = f.require(d, "at").and_then(|n| place(d, n, field, ball));
    let heading = match f.take("heading_deg") {
        None => Some(Num::Fixed(0.0)),
        Some(n) => num(d, n, -360.0, 360.0, "deg"),
    };
    let play = match f.take("play") {
        None => Some(default_play),
        Some(n) => match head(n) {
            Some(("Tree", _)) if matches!(n.kind, NodeKind::Unit(_)) => Some(Play::Tree),
            Some(("Stand", _)) if matches!(n.kind, NodeKind::Unit(_)) => Some(Play::Stand),
            _ => {
                d.error_hint(
                    "invalid-choice",
                    n.span,
                    format!("expected `Tree` or `Stand`, found {}", n.describe()),
                    "`Tree`: a Libero agent running its behavior tree; `Stand`: stands and looks around",
                );
                None
            }
        },
    };
    f.finish(d, ROBOT_FIELDS);
    Some((
        Robot {
            unum: unum? as u32,
            at: at?,
            heading_deg: heading?,
            play: play?,
        },
        unum_node?.span,
    ))
}

/// A robot's place: a field point, `FromBall(dx: .., dy: ..)` (an offset from the ball's spot)
/// or `AroundBall(distance_m: .., bearing_deg: ..)`, whose every draw lands on the field.
fn place(
    d: &mut Decoder,
    node: &Node,
    field: &FieldGeometry,
    ball: Option<&BallSpec>,
) -> Option<Place> {
    let (place, (dx_lo, dx_hi), (dy_lo, dy_hi)) = match head(node).map(|(n, _)| n) {
        Some("FromBall") => {
            let mut f = d.fields(node, "FromBall")?;
            let dx = f.require(d, "dx").and_then(|n| num(d, n, -60.0, 60.0, "m"));
            let dy = f.require(d, "dy").and_then(|n| num(d, n, -60.0, 60.0, "m"));
            f.finish(d, &["dx", "dy"]);
            let (dx, dy) = (dx?, dy?);
            (
                Place::FromBall { dx, dy },
                (dx.lo(), dx.hi()),
                (dy.lo(), dy.hi()),
            )
        }
        Some("AroundBall") => {
            let mut f = d.fields(node, "AroundBall")?;
            let distance = f
                .require(d, "distance_m")
                .and_then(|n| num(d, n, 0.0, 60.0, "m"));
            let bearing = f
                .require(d, "bearing_deg")
                .and_then(|n| num(d, n, -360.0, 360.0, "deg"));
            f.finish(d, &["distance_m", "bearing_deg"]);
            let (distance_m, bearing_deg) = (distance?, bearing?);
            // Checked against the square round the farthest draw: a little stricter than the arc.
            let r = distance_m.hi();
            (
                Place::AroundBall {
                    distance_m,
                    bearing_deg,
                },
                (-r, r),
                (-r, r),
            )
        }
        _ => return on_field(d, node, field, 0.0).map(Place::At),
    };
    // Without a valid ball there is nothing to check the offset against (its error is reported).
    let ball = ball?;
    let (hx, hy) = field.half_extent();
    let (x_lo, x_hi) = (ball.at.x.lo() + dx_lo, ball.at.x.hi() + dx_hi);
    let (y_lo, y_hi) = (ball.at.y.lo() + dy_lo, ball.at.y.hi() + dy_hi);
    if x_lo < -hx || x_hi > hx || y_lo < -hy || y_hi > hy {
        d.error_hint(
            "off-field",
            node.span,
            format!(
                "placed from the ball this robot can land off the {} field (x {x_lo:.2}…{x_hi:.2}, y {y_lo:.2}…{y_hi:.2} m)",
                field.name
            ),
            format!("the field spans x within ±{hx}, y within ±{hy} m"),
        );
        return None;
    }
    Some(place)
}

/// A fixed number or `Range(lo, hi)` with both ends within [min, max].
fn num(d: &mut Decoder, node: &Node, min: f64, max: f64, unit: &str) -> Option<Num> {
    match head(node) {
        Some(("Range", _)) => {
            let Some([lo, hi]) = items(node).filter(|i| i.len() == 2).map(|i| [&i[0], &i[1]])
            else {
                d.expected(node, "`Range(lo, hi)` with two numbers");
                return None;
            };
            let (lo_v, hi_v) = (
                d.float_in_unit(lo, min, max, unit),
                d.float_in_unit(hi, min, max, unit),
            );
            let (lo_v, hi_v) = (lo_v?, hi_v?);
            if lo_v >= hi_v {
                d.error_hint(
                    "empty-range",
                    node.span,
                    format!(
                        "Range({lo_v}, {hi_v}) is empty: the low end must be below the high end"
                    ),
                    format!("for a fixed value write the number itself, e.g. `{lo_v}`"),
                );
                return None;
            }
            Some(Num::Range(lo_v, hi_v))
        }
        _ if matches!(node.kind, NodeKind::Float(_) | NodeKind::Int(_)) => {
            d.float_in_unit(node, min, max, unit).map(Num::Fixed)
        }
        _ => {
            d.expected(node, "a number or `Range(lo, hi)`");
            None
        }
    }
}

/// `(x: .., y: ..)` or `(x, y)`, unchecked against the field.
fn point(d: &mut Decoder, node: &Node, limit: f64) -> Option<Point> {
    if let Some(items) = items(node).filter(|_| head(node).is_none()) {
        if items.len() == 2 {
            let x = num(d, &items[0], -limit, limit, "m");
            let y = num(d, &items[1], -limit, limit, "m");
            return Some(Point { x: x?, y: y? });
        }
        d.expected(node, "a point `(x: .., y: ..)` or `(x, y)`");
        return None;
    }
    let mut f = d.fields(node, "")?;
    let x = f
        .require(d, "x")
        .and_then(|n| num(d, n, -limit, limit, "m"));
    let y = f
        .require(d, "y")
        .and_then(|n| num(d, n, -limit, limit, "m"));
    f.finish(d, &["x", "y"]);
    Some(Point { x: x?, y: y? })
}

/// A point whose whole range lies on the field, or within `beyond_goal_line` metres behind a
/// goal line.
fn on_field(
    d: &mut Decoder,
    node: &Node,
    field: &FieldGeometry,
    beyond_goal_line: f64,
) -> Option<Point> {
    let p = point(d, node, 1000.0)?;
    let (hx, hy) = field.half_extent();
    let hx = hx + beyond_goal_line;
    let inside = |n: Num, h: f64| n.lo() >= -h && n.hi() <= h;
    if !inside(p.x, hx) || !inside(p.y, hy) {
        d.error_hint(
            "off-field",
            node.span,
            format!(
                "this point is off the {} field (x within ±{hx}, y within ±{hy} m)",
                field.name
            ),
            "global frame: origin at the centre, +x towards the right (their) goal, +y to the left",
        );
        return None;
    }
    Some(p)
}

fn ball(d: &mut Decoder, node: &Node, field: &FieldGeometry) -> Option<BallSpec> {
    let mut f = d.fields(node, "Ball")?;
    let at = f.require(d, "at").and_then(|n| on_field(d, n, field, 0.0));
    let launch = match f.take("launch") {
        None => Some(None),
        Some(n) if matches!(&n.kind, NodeKind::Unit(id) if id.name == "None") => Some(None),
        Some(n) => {
            let inner = match (head(n), items(n)) {
                (Some(("Some", _)), Some([inner])) => inner,
                _ => n,
            };
            launch(d, inner, field).map(|l| Some((l, inner.span)))
        }
    };
    f.finish(d, &["at", "launch"]);
    let (at, launch) = (at?, launch?);
    if let Some((l @ Launch::Towards { .. }, span)) = launch {
        launch_reaches(d, span, field, at, l);
    }
    Some(BallSpec {
        at,
        launch: launch.map(|(l, _)| l),
    })
}

fn launch(d: &mut Decoder, node: &Node, field: &FieldGeometry) -> Option<Launch> {
    match head(node) {
        Some(("Velocity", _)) => {
            let mut f = d.fields(node, "Velocity")?;
            let speed = f
                .require(d, "speed_m_s")
                .and_then(|n| num(d, n, 0.1, 15.0, "m/s"));
            let dir = f
                .require(d, "direction_deg")
                .and_then(|n| num(d, n, -360.0, 360.0, "deg"));
            f.finish(d, &["speed_m_s", "direction_deg"]);
            Some(Launch::Velocity {
                speed_m_s: speed?,
                direction_deg: dir?,
            })
        }
        Some(("Towards", _)) => {
            let mut f = d.fields(node, "Towards")?;
            let target = f
                .require(d, "target")
                .and_then(|n| on_field(d, n, field, field.goal_depth));
            let speed = f
                .require(d, "speed_m_s")
                .and_then(|n| num(d, n, 0.1, 15.0, "m/s"));
            f.finish(d, &["target", "speed_m_s"]);
            Some(Launch::Towards {
                target: target?,
                speed_m_s: speed?,
            })
        }
        _ => {
            let found = head(node).map_or_else(|| node.describe(), |(n, _)| format!("`{n}`"));
            d.error_hint(
                "invalid-choice",
                node.span,
                format!("expected a launch, found {found}"),
                "`Velocity(speed_m_s: .., direction_deg: ..)`, `Towards(target: (x: .., y: ..), speed_m_s: ..)` or `None`",
            );
            None
        }
    }
}

/// A launch towards a target must get there: draws from the ranges whose roll stops short are
/// an error when the target is in a goal mouth (a shot that is not on target), a warning
/// otherwise (a pass that is a little short is still a situation).
fn launch_reaches(d: &mut Decoder, span: Span, field: &FieldGeometry, at: Point, launch: Launch) {
    let Launch::Towards { target, speed_m_s } = launch else {
        return;
    };
    let ball = WorldParams::builtin().ball;
    let mut rng = Rng::new(1);
    let mut worst: Option<([f64; 2], [f64; 2], f64, f64)> = None;
    let corners = [Num::lo, Num::hi];
    let mut draws: Vec<([f64; 2], [f64; 2], f64)> = Vec::new();
    // Every corner of the ranges, then random draws.
    for bx in corners {
        for by in corners {
            for tx in corners {
                for ty in corners {
                    for v in corners {
                        draws.push((
                            [bx(at.x), by(at.y)],
                            [tx(target.x), ty(target.y)],
                            v(speed_m_s),
                        ));
                    }
                }
            }
        }
    }
    for _ in 0..LAUNCH_CHECKS {
        draws.push((
            at.draw(&mut rng),
            target.draw(&mut rng),
            speed_m_s.draw(&mut rng),
        ));
    }
    for (from, to, v) in draws {
        let short = shortfall(&ball, from, to, v);
        if short > 0.0 && worst.is_none_or(|w| short > w.3) {
            worst = Some((from, to, v, short));
        }
    }
    let Some((from, to, v, short)) = worst else {
        return;
    };
    let (hx, _) = field.half_extent();
    let in_goal = target.x.lo().abs() >= hx - 1e-9 || target.x.hi().abs() >= hx - 1e-9;
    let message = format!(
        "a ball launched at {v:.2} m/s from ({:.2}, {:.2}) towards ({:.2}, {:.2}) stops {short:.2} m short of it",
        from[0], from[1], to[0], to[1]
    );
    let hint = "raise the speed or bring the ball closer (rest distances from the world model's launch table: about 11 m at 5.4 m/s along a field axis, farther towards a diagonal)";
    if in_goal {
        d.error_hint(
            "launch-short",
            span,
            format!("not on target: {message}"),
            hint,
        );
    } else {
        d.warning_hint("launch-short", span, message, hint);
    }
}

/// Robots whose placements are fixed and closer than `MIN_PLACEMENT_GAP_M`: a warning.
fn placement_gaps(d: &mut Decoder, node: &Node, ours: &[Robot], theirs: &[Robot]) {
    let fixed = |r: &Robot| match r.at {
        Place::At(Point {
            x: Num::Fixed(x),
            y: Num::Fixed(y),
        }) => Some([x, y]),
        _ => None,
    };
    let all: Vec<(String, [f64; 2])> = ours
        .iter()
        .filter_map(|r| fixed(r).map(|p| (format!("our {}", r.unum), p)))
        .chain(
            theirs
                .iter()
                .filter_map(|r| fixed(r).map(|p| (format!("their {}", r.unum), p))),
        )
        .collect();
    for (i, (a, pa)) in all.iter().enumerate() {
        for (b, pb) in &all[i + 1..] {
            let gap = (pa[0] - pb[0]).hypot(pa[1] - pb[1]);
            if gap < MIN_PLACEMENT_GAP_M {
                d.warning_hint(
                    "robots-too-close",
                    node.span,
                    format!("{a} and {b} are placed {gap:.2} m apart"),
                    format!("torsos closer than {MIN_PLACEMENT_GAP_M} m start in contact"),
                );
            }
        }
    }
}
