//! Writing a behavior file back as canonical RON (used by tools and the round-trip property test).

use super::ast::*;
use crate::value::Value;
use std::fmt::Write as _;

pub fn print_behavior_file(file: &BehaviorFile) -> String {
    let mut out = String::from("Behaviors(\n");
    if !file.blackboard.is_empty() {
        out.push_str("    blackboard: {\n");
        for decl in &file.blackboard {
            let _ = writeln!(
                out,
                "        {:?}: {}({}),",
                decl.key,
                decl.ty,
                constant(&decl.initial)
            );
        }
        out.push_str("    },\n");
    }
    out.push_str("    trees: {\n");
    for tree in &file.trees {
        let _ = write!(out, "        {:?}: ", tree.name);
        if tree.params.is_empty() {
            node(&mut out, &tree.root, 2);
        } else {
            out.push_str("Tree(\n            params: {\n");
            for param in &tree.params {
                let declared = match &param.default {
                    Some(value) => format!("{}({})", param.ty, constant(value)),
                    None => param.ty.to_string(),
                };
                let _ = writeln!(out, "                {:?}: {declared},", param.name);
            }
            out.push_str("            },\n            root: ");
            node(&mut out, &tree.root, 3);
            out.push_str(",\n        )");
        }
        out.push_str(",\n");
    }
    out.push_str("    },\n)\n");
    out
}

fn indent(out: &mut String, level: usize) {
    out.push_str(&"    ".repeat(level));
}

fn constant(value: &Value) -> String {
    match value {
        // `{:?}` keeps a decimal point on floats so they read back as floats.
        Value::Float(x) => format!("{x:?}"),
        Value::Vec2(v) => format!("({:?}, {:?})", v.x, v.y),
        other => other.to_string(),
    }
}

fn expr(value: &Expr) -> String {
    match &value.kind {
        ExprKind::Const(c) => constant(c),
        ExprKind::Blackboard(key) => format!("Bb({key:?})"),
        ExprKind::Param(name) => format!("Param({name:?})"),
        ExprKind::Query(c) => call("Query", c),
    }
}

fn call(head: &str, c: &Call) -> String {
    if c.args.is_empty() {
        return format!("{head}({:?})", c.name);
    }
    let args: Vec<String> = c
        .args
        .iter()
        .map(|a| format!("{}: {}", a.name, expr(&a.value)))
        .collect();
    format!("{head}(name: {:?}, {})", c.name, args.join(", "))
}

fn curve(c: &Curve) -> String {
    match c {
        Curve::Identity => "Identity".into(),
        Curve::Linear { from, to } => format!("Linear(from: {from:?}, to: {to:?})"),
        Curve::Power { from, to, exponent } => {
            format!("Power(from: {from:?}, to: {to:?}, exponent: {exponent:?})")
        }
        Curve::Logistic { mid, steepness } => {
            format!("Logistic(mid: {mid:?}, steepness: {steepness:?})")
        }
        Curve::Step { threshold, above } => {
            format!("Step(threshold: {threshold:?}, above: {above})")
        }
    }
}

fn child_list(out: &mut String, children: &[NodeDef], level: usize) {
    out.push_str("[\n");
    for child in children {
        indent(out, level + 1);
        node(out, child, level + 1);
        out.push_str(",\n");
    }
    indent(out, level);
    out.push(']');
}

fn node(out: &mut String, def: &NodeDef, level: usize) {
    match &def.kind {
        NodeDefKind::Composite(kind, children) => {
            let _ = write!(out, "{}(", kind.name());
            child_list(out, children, level);
            out.push(')');
        }
        NodeDefKind::Parallel {
            success,
            failure,
            children,
            ..
        } => {
            let _ = write!(
                out,
                "Parallel(success: {success}, failure: {failure}, children: "
            );
            child_list(out, children, level);
            out.push(')');
        }
        NodeDefKind::Decorator(kind, child) => {
            let _ = write!(out, "{}(", kind.name());
            node(out, child, level);
            out.push(')');
        }
        NodeDefKind::Counted(kind, n, child) => {
            let head = match kind {
                CountKind::Repeat => "Repeat",
                CountKind::RetryUntilSuccess => "RetryUntilSuccess",
            };
            let _ = write!(out, "{head}(n: {n}, child: ");
            node(out, child, level);
            out.push(')');
        }
        NodeDefKind::Timed(kind, seconds, child) => {
            let head = match kind {
                TimedKind::Timeout => "Timeout",
                TimedKind::Cooldown => "Cooldown",
            };
            let _ = write!(out, "{head}(seconds: {seconds:?}, child: ");
            node(out, child, level);
            out.push(')');
        }
        NodeDefKind::Utility {
            hysteresis,
            choices,
        } => {
            let _ = writeln!(out, "Utility(hysteresis: {hysteresis:?}, choices: [");
            for choice in choices {
                indent(out, level + 1);
                let considerations: Vec<String> = choice
                    .considerations
                    .iter()
                    .map(|c| {
                        format!(
                            "Consider(input: {}, curve: {}, weight: {:?})",
                            expr(&c.input),
                            curve(&c.curve),
                            c.weight
                        )
                    })
                    .collect();
                let _ = write!(
                    out,
                    "Choice(weight: {:?}, considerations: [{}], child: ",
                    choice.weight,
                    considerations.join(", ")
                );
                node(out, &choice.child, level + 1);
                out.push_str("),\n");
            }
            indent(out, level);
            out.push_str("])");
        }
        NodeDefKind::Condition(c) => out.push_str(&call("Condition", c)),
        NodeDefKind::Action(c) => out.push_str(&call("Action", c)),
        NodeDefKind::SubTree(c) => out.push_str(&call("SubTree", c)),
        NodeDefKind::Compare { left, op, right } => {
            let _ = write!(
                out,
                "Compare(left: {}, op: {:?}, right: {})",
                expr(left),
                op.symbol(),
                expr(right)
            );
        }
        NodeDefKind::Set { key, value, .. } => {
            let _ = write!(out, "Set(key: {key:?}, value: {})", expr(value));
        }
        NodeDefKind::Wait(seconds) => {
            let _ = write!(out, "Wait(seconds: {seconds:?})");
        }
        NodeDefKind::Succeed => out.push_str("Succeed"),
        NodeDefKind::Fail => out.push_str("Fail"),
    }
}
