//! The `success:` condition of a scenario file.

use crate::decode::{head, items, Decoder};
use crate::spec::{Robot, Success};
use libero_behavior::diagnostics::did_you_mean;
use libero_behavior::syntax::{Node, NodeKind};

const SUCCESS_NAMES: &[&str] = &[
    "GoalScored",
    "BallKeptOut",
    "BallReached",
    "PassReceived",
    "BallMoved",
    "NoCollision",
    "ShotOnTarget",
    "All",
    "Any",
];

/// Decode a condition; `ours` (when `ours_known`) are the robots `BallReached` and
/// `PassReceived` may name.
pub(crate) fn success(
    d: &mut Decoder,
    node: &Node,
    ours: &[Robot],
    ours_known: bool,
) -> Option<Success> {
    let Some((name, name_span)) = head(node) else {
        d.expected(node, "a success condition such as `GoalScored`");
        return None;
    };
    let unit = matches!(node.kind, NodeKind::Unit(_));
    match name {
        "GoalScored" if unit => Some(Success::GoalScored),
        "BallKeptOut" if unit => Some(Success::BallKeptOut),
        "BallReached" | "PassReceived" => {
            let robot_field = if name == "BallReached" {
                "unum"
            } else {
                "receiver"
            };
            let mut f = d.fields(node, name)?;
            let unum_node = f.require(d, robot_field);
            let unum = unum_node.and_then(|n| d.int_in(n, 1, 11));
            let within = f
                .require(d, "within_m")
                .and_then(|n| d.float_in_unit(n, 0.05, 5.0, "m"));
            f.finish(d, &[robot_field, "within_m"]);
            if let (Some(u), Some(n)) = (unum, unum_node) {
                if ours_known && !ours.iter().any(|r| i64::from(r.unum) == u) {
                    let numbers: Vec<String> = ours.iter().map(|r| r.unum.to_string()).collect();
                    d.error_hint(
                        "unknown-robot",
                        n.span,
                        format!("our team has no robot number {u}"),
                        format!("`ours` has numbers: {}", numbers.join(", ")),
                    );
                    return None;
                }
            }
            let (unum, within_m) = (unum? as u32, within?);
            Some(if name == "BallReached" {
                Success::BallReached { unum, within_m }
            } else {
                Success::PassReceived {
                    receiver: unum,
                    within_m,
                }
            })
        }
        "BallMoved" | "ShotOnTarget" => {
            let mut f = d.fields(node, name)?;
            let min = f
                .require(d, "min_m")
                .and_then(|n| d.float_in_unit(n, 0.05, 60.0, "m"));
            f.finish(d, &["min_m"]);
            let min_m = min?;
            Some(if name == "BallMoved" {
                Success::BallMoved { min_m }
            } else {
                Success::ShotOnTarget { min_m }
            })
        }
        "NoCollision" => {
            let mut f = d.fields(node, "NoCollision")?;
            let min = f
                .require(d, "min_distance_m")
                .and_then(|n| d.float_in_unit(n, 0.05, 3.0, "m"));
            f.finish(d, &["min_distance_m"]);
            Some(Success::NoCollision {
                min_distance_m: min?,
            })
        }
        "All" | "Any" => {
            let Some([list]) = items(node) else {
                d.expected(node, &format!("`{name}([...])` with a list of conditions"));
                return None;
            };
            let parts = d.list(list)?;
            if parts.is_empty() {
                d.error(
                    "empty-composite",
                    node.span,
                    format!("`{name}` has no condition"),
                );
                return None;
            }
            let parts: Vec<Option<Success>> = parts
                .iter()
                .map(|p| success(d, p, ours, ours_known))
                .collect();
            let parts: Option<Vec<Success>> = parts.into_iter().collect();
            let parts = parts?;
            Some(if name == "All" {
                Success::All(parts)
            } else {
                Success::Any(parts)
            })
        }
        "GoalScored" | "BallKeptOut" => {
            d.expected(node, &format!("`{name}` without arguments"));
            None
        }
        _ => {
            let hint = did_you_mean(name, SUCCESS_NAMES.iter().copied())
                .unwrap_or_else(|| format!("expected one of: {}", SUCCESS_NAMES.join(", ")));
            d.error_hint(
                "unknown-condition",
                name_span,
                format!("unknown success condition `{name}`"),
                hint,
            );
            None
        }
    }
}
