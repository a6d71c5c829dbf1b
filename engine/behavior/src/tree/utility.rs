//! Reading the Utility selector's choices, considerations and response curves.

use super::ast::*;
use super::parse::expr;
use crate::decode::{Decoder, Fields};
use crate::diagnostics::did_you_mean;
use crate::syntax::Node;

const CURVES: &[&str] = &["Identity", "Linear", "Power", "Logistic", "Step"];

pub(super) fn choice(decoder: &mut Decoder, node: &Node) -> Option<Choice> {
    let mut fields = decoder.fields(node, "Choice")?;
    let weight = match fields.take("weight") {
        Some(n) => decoder.float_in(n, 0.0, 100.0),
        None => Some(1.0),
    };
    let considerations = match fields.take("considerations") {
        Some(n) => decoder.list(n).map(|items| {
            let parsed: Vec<Consideration> = items
                .iter()
                .filter_map(|i| consideration(decoder, i))
                .collect();
            (parsed.len() == items.len()).then_some(parsed)
        }),
        None => Some(Some(Vec::new())),
    };
    let child = fields
        .require(decoder, "child")
        .and_then(|n| super::parse::node_def(decoder, n));
    fields.finish(decoder, &["weight", "considerations", "child"]);
    Some(Choice {
        weight: weight?,
        considerations: considerations.flatten()?,
        child: child?,
        span: node.span,
    })
}

fn consideration(decoder: &mut Decoder, node: &Node) -> Option<Consideration> {
    let mut fields = decoder.fields(node, "Consider")?;
    let input = fields
        .require(decoder, "input")
        .and_then(|n| expr(decoder, n));
    let curve = match fields.take("curve") {
        Some(n) => curve(decoder, n),
        None => Some(Curve::Identity),
    };
    let weight = match fields.take("weight") {
        Some(n) => decoder.float_in(n, 0.0, 100.0),
        None => Some(1.0),
    };
    fields.finish(decoder, &["input", "curve", "weight"]);
    Some(Consideration {
        input: input?,
        curve: curve?,
        weight: weight?,
    })
}

fn curve(decoder: &mut Decoder, node: &Node) -> Option<Curve> {
    let Some((head, head_span)) = Decoder::head(node) else {
        decoder.error(
            "invalid-value",
            node.span,
            format!("expected a curve, found {}", node.describe()),
        );
        return None;
    };
    if head == "Identity" {
        return Some(Curve::Identity);
    }
    if !CURVES.contains(&head) {
        let hint = did_you_mean(head, CURVES.iter().copied());
        decoder
            .error(
                "unknown-curve",
                head_span,
                format!("unknown response curve `{head}`"),
            )
            .hint = hint.or_else(|| Some(format!("curves are {}", CURVES.join(", "))));
        return None;
    }
    let mut fields = decoder.fields(node, head)?;
    let curve = match head {
        "Linear" => {
            let (from, to) = (
                number(decoder, &mut fields, "from"),
                number(decoder, &mut fields, "to"),
            );
            Some(Curve::Linear {
                from: from?,
                to: to?,
            })
        }
        "Power" => {
            let from = number(decoder, &mut fields, "from");
            let to = number(decoder, &mut fields, "to");
            let exponent = number(decoder, &mut fields, "exponent");
            Some(Curve::Power {
                from: from?,
                to: to?,
                exponent: exponent?,
            })
        }
        "Logistic" => {
            let mid = number(decoder, &mut fields, "mid");
            let steepness = number(decoder, &mut fields, "steepness");
            Some(Curve::Logistic {
                mid: mid?,
                steepness: steepness?,
            })
        }
        _ => {
            let threshold = number(decoder, &mut fields, "threshold");
            let above = match fields.take("above") {
                Some(n) => decoder.bool(n),
                None => Some(true),
            };
            Some(Curve::Step {
                threshold: threshold?,
                above: above?,
            })
        }
    };
    fields.finish(
        decoder,
        &[
            "from",
            "to",
            "exponent",
            "mid",
            "steepness",
            "threshold",
            "above",
        ],
    );
    curve
}

fn number(decoder: &mut Decoder, fields: &mut Fields, name: &str) -> Option<f64> {
    fields.require(decoder, name).and_then(|n| decoder.float(n))
}
