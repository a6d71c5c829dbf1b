//! Reading a behavior file's syntax into the tree AST, reporting every shape error.

use super::ast::*;
use super::utility::choice;
use crate::decode::{Decoder, Fields};
use crate::diagnostics::did_you_mean;
use crate::syntax::{Body, Node, NodeKind};
use crate::value::{Value, ValueType};
use std::sync::Arc;

const NODE_KINDS: &[&str] = &[
    "Sequence",
    "Fallback",
    "ReactiveSequence",
    "ReactiveFallback",
    "Parallel",
    "Invert",
    "ForceSuccess",
    "ForceFailure",
    "Repeat",
    "RetryUntilSuccess",
    "Timeout",
    "Cooldown",
    "Utility",
    "Condition",
    "Action",
    "SubTree",
    "Compare",
    "Set",
    "Wait",
    "Succeed",
    "Fail",
];
/// Counts and durations are bounded so a typo cannot make a node loop or wait for hours.
const MAX_COUNT: i64 = 10_000;
const MAX_SECONDS: f64 = 3600.0;

/// Reads `Behaviors(blackboard: {..}, trees: {..})`; returns what could be read even with errors.
pub fn parse_behavior_file(decoder: &mut Decoder, node: &Node) -> BehaviorFile {
    let mut file = BehaviorFile::default();
    let Some(mut fields) = decoder.fields(node, "Behaviors") else {
        return file;
    };
    if let Some(entries) = fields.take("blackboard").and_then(|n| decoder.map(n)) {
        for (key, value) in entries {
            let Some(name) = decoder.string(key) else {
                continue;
            };
            if let Some((ty, initial)) = typed_constant(decoder, value) {
                file.blackboard.push(BlackboardDecl {
                    key: name,
                    key_span: key.span,
                    ty,
                    initial,
                });
            }
        }
    }
    if let Some(entries) = fields
        .require(decoder, "trees")
        .and_then(|n| decoder.map(n))
    {
        for (key, value) in entries {
            let Some(name) = decoder.string(key) else {
                continue;
            };
            if let Some(tree) = tree_def(decoder, name, key, value) {
                file.trees.push(tree);
            }
        }
    }
    fields.finish(decoder, &["blackboard", "trees"]);
    file
}

fn tree_def(decoder: &mut Decoder, name: String, key: &Node, value: &Node) -> Option<TreeDef> {
    let mut params = Vec::new();
    let root = if Decoder::head(value).is_some_and(|(head, _)| head == "Tree") {
        let mut fields = decoder.fields(value, "Tree")?;
        if let Some(entries) = fields.take("params").and_then(|n| decoder.map(n)) {
            for (param_key, param_value) in entries {
                let Some(param_name) = decoder.string(param_key) else {
                    continue;
                };
                let declared = match &param_value.kind {
                    NodeKind::Unit(id) => {
                        value_type(decoder, &id.name, param_value).map(|ty| (ty, None))
                    }
                    _ => typed_constant(decoder, param_value).map(|(ty, v)| (ty, Some(v))),
                };
                if let Some((ty, default)) = declared {
                    params.push(TreeParam {
                        name: param_name,
                        span: param_key.span,
                        ty,
                        default,
                    });
                }
            }
        }
        let root = fields
            .require(decoder, "root")
            .and_then(|n| node_def(decoder, n));
        fields.finish(decoder, &["params", "root"]);
        root?
    } else {
        node_def(decoder, value)?
    };
    Some(TreeDef {
        name,
        name_span: key.span,
        params,
        root,
    })
}

fn value_type(decoder: &mut Decoder, name: &str, node: &Node) -> Option<ValueType> {
    let ty = ValueType::from_name(name);
    if ty.is_none() {
        let hint = did_you_mean(name, ValueType::ALL.iter().map(|t| t.name()));
        decoder
            .error("unknown-type", node.span, format!("unknown type `{name}`"))
            .hint = hint.or_else(|| Some("types are Bool, Int, Float, Vec2 and String".into()));
    }
    ty
}

/// `Float(1.0)`, `Vec2((0.0, 1.0))`, ... : a constant with its declared type.
fn typed_constant(decoder: &mut Decoder, node: &Node) -> Option<(ValueType, Value)> {
    let NodeKind::Struct {
        name: Some(id),
        body: Body::Items(items),
    } = &node.kind
    else {
        let message = format!(
            "expected a typed value such as `Float(1.0)`, found {}",
            node.describe()
        );
        decoder.error("invalid-value", node.span, message);
        return None;
    };
    let ty = value_type(decoder, &id.name, node)?;
    let [inner] = items.as_slice() else {
        decoder.error(
            "invalid-value",
            node.span,
            format!("`{}(..)` takes exactly one value", id.name),
        );
        return None;
    };
    let value = constant(decoder, inner)?;
    if !value.value_type().fits(ty) {
        let message = format!("expected a {ty} value, found {}", value.value_type());
        decoder.error("type-mismatch", inner.span, message);
        return None;
    }
    Some((ty, value.coerce(ty)))
}

fn constant(decoder: &mut Decoder, node: &Node) -> Option<Value> {
    Some(match &node.kind {
        NodeKind::Bool(b) => Value::Bool(*b),
        NodeKind::Int(i) => Value::Int(*i),
        NodeKind::Float(_) => Value::Float(decoder.float(node)?),
        NodeKind::Str(s) => Value::String(Arc::from(s.as_str())),
        NodeKind::Struct { name: None, .. } => Value::Vec2(decoder.vec2(node)?),
        _ => {
            let message = format!("expected a constant, found {}", node.describe());
            decoder.error("invalid-value", node.span, message);
            return None;
        }
    })
}

pub(crate) fn expr(decoder: &mut Decoder, node: &Node) -> Option<Expr> {
    let kind = match &node.kind {
        NodeKind::Struct {
            name: Some(id),
            body,
        } => match id.name.as_str() {
            "Bb" | "Param" => {
                let name = single_string(decoder, node, body, &id.name)?;
                if id.name == "Bb" {
                    ExprKind::Blackboard(name)
                } else {
                    ExprKind::Param(name)
                }
            }
            "Query" => ExprKind::Query(call(decoder, node, "Query")?),
            other => {
                let hint = did_you_mean(other, ["Bb", "Param", "Query"]);
                decoder.error("invalid-value", id.span, format!("unknown value form `{other}(..)`")).hint =
                    hint.or_else(|| Some("values are constants, `Bb(\"key\")`, `Param(\"name\")` or `Query(\"name\")`".into()));
                return None;
            }
        },
        _ => ExprKind::Const(constant(decoder, node)?),
    };
    Some(Expr {
        kind,
        span: node.span,
    })
}

fn single_string(decoder: &mut Decoder, node: &Node, body: &Body, form: &str) -> Option<String> {
    match body {
        Body::Items(items) if items.len() == 1 => decoder.string(&items[0]),
        _ => {
            decoder.error(
                "invalid-value",
                node.span,
                format!("`{form}(..)` takes one string"),
            );
            None
        }
    }
}

/// `Name("x")` or `Name(name: "x", arg: value, ..)`.
fn call(decoder: &mut Decoder, node: &Node, form: &str) -> Option<Call> {
    let NodeKind::Struct { body, .. } = &node.kind else {
        return None;
    };
    if let Body::Items(items) = body {
        let name_node = match items.as_slice() {
            [only] => only,
            _ => {
                decoder.error(
                    "invalid-value",
                    node.span,
                    format!("`{form}(..)` needs a name: `{form}(\"Name\")`"),
                );
                return None;
            }
        };
        let name = decoder.string(name_node)?;
        return Some(Call {
            name,
            name_span: name_node.span,
            args: Vec::new(),
            invalid_args: Vec::new(),
        });
    }
    let mut fields = decoder.fields(node, form)?;
    let name_node = fields.require(decoder, "name")?;
    let name = decoder.string(name_node)?;
    let (mut args, mut invalid_args) = (Vec::new(), Vec::new());
    for field in fields.rest() {
        match expr(decoder, &field.value) {
            Some(value) => args.push(Arg {
                name: field.name.name.clone(),
                name_span: field.name.span,
                value,
            }),
            None => invalid_args.push(field.name.name.clone()),
        }
    }
    Some(Call {
        name,
        name_span: name_node.span,
        args,
        invalid_args,
    })
}

fn children(decoder: &mut Decoder, node: &Node) -> Option<Vec<NodeDef>> {
    let items = decoder.list(node)?;
    let children: Vec<NodeDef> = items
        .iter()
        .filter_map(|child| node_def(decoder, child))
        .collect();
    (children.len() == items.len()).then_some(children)
}

/// The single child of `Invert(child)`.
fn only_child(decoder: &mut Decoder, node: &Node, body: &Body, head: &str) -> Option<NodeDef> {
    match body {
        Body::Items(items) if items.len() == 1 => node_def(decoder, &items[0]),
        _ => {
            decoder.error(
                "invalid-value",
                node.span,
                format!("`{head}` takes exactly one child node"),
            );
            None
        }
    }
}

fn count(decoder: &mut Decoder, fields: &mut Fields, name: &str) -> Option<u32> {
    let node = fields.require(decoder, name)?;
    decoder.int_in(node, 1, MAX_COUNT).map(|n| n as u32)
}

fn seconds(decoder: &mut Decoder, fields: &mut Fields) -> Option<f64> {
    let node = fields.require(decoder, "seconds")?;
    decoder.float_in(node, 0.0, MAX_SECONDS)
}

pub(crate) fn node_def(decoder: &mut Decoder, node: &Node) -> Option<NodeDef> {
    let Some((head, head_span)) = Decoder::head(node) else {
        let message = format!(
            "expected a node such as `Sequence([..])`, found {}",
            node.describe()
        );
        decoder.error("invalid-value", node.span, message);
        return None;
    };
    let body = match &node.kind {
        NodeKind::Struct { body, .. } => Some(body),
        _ => None,
    };
    let kind = match (head, body) {
        ("Succeed", None) => NodeDefKind::Succeed,
        ("Fail", None) => NodeDefKind::Fail,
        (_, None) if NODE_KINDS.contains(&head) => {
            decoder.error(
                "invalid-value",
                node.span,
                format!("`{head}` needs arguments in parentheses"),
            );
            return None;
        }
        (_, Some(body)) => match head {
            "Sequence" | "Fallback" | "ReactiveSequence" | "ReactiveFallback" => {
                let kind = CompositeKind::ALL.into_iter().find(|k| k.name() == head)?;
                let list = match body {
                    Body::Items(items) if items.len() == 1 => &items[0],
                    _ => {
                        decoder.error(
                            "invalid-value",
                            node.span,
                            format!("`{head}` takes a list of children: `{head}([..])`"),
                        );
                        return None;
                    }
                };
                NodeDefKind::Composite(kind, children(decoder, list)?)
            }
            "Invert" | "ForceSuccess" | "ForceFailure" => {
                let kind = DecoratorKind::ALL.into_iter().find(|k| k.name() == head)?;
                NodeDefKind::Decorator(kind, Box::new(only_child(decoder, node, body, head)?))
            }
            "Condition" => NodeDefKind::Condition(call(decoder, node, head)?),
            "Action" => NodeDefKind::Action(call(decoder, node, head)?),
            "SubTree" => NodeDefKind::SubTree(call(decoder, node, head)?),
            "Wait" if matches!(body, Body::Items(items) if items.len() == 1) => {
                let Body::Items(items) = body else {
                    return None;
                };
                NodeDefKind::Wait(decoder.float_in(&items[0], 0.0, MAX_SECONDS)?)
            }
            _ => return structured(decoder, node, head, head_span),
        },
        (_, None) => return unknown_kind(decoder, head, head_span),
    };
    Some(NodeDef {
        kind,
        span: node.span,
        head_span,
    })
}

fn unknown_kind(
    decoder: &mut Decoder,
    head: &str,
    head_span: crate::syntax::Span,
) -> Option<NodeDef> {
    let hint = did_you_mean(head, NODE_KINDS.iter().copied()).or_else(|| {
        Some("native nodes are written `Action(name: \"..\")` or `Condition(name: \"..\")`".into())
    });
    decoder
        .error(
            "unknown-node-kind",
            head_span,
            format!("unknown node kind `{head}`"),
        )
        .hint = hint;
    None
}

/// Nodes written with named fields.
fn structured(
    decoder: &mut Decoder,
    node: &Node,
    head: &str,
    head_span: crate::syntax::Span,
) -> Option<NodeDef> {
    if !NODE_KINDS.contains(&head) {
        return unknown_kind(decoder, head, head_span);
    }
    let mut fields = decoder.fields(node, head)?;
    let (kind, known): (Option<NodeDefKind>, &[&str]) = match head {
        "Parallel" => {
            let success = count(decoder, &mut fields, "success");
            let failure = count(decoder, &mut fields, "failure");
            let list = fields.require(decoder, "children");
            let children = list.and_then(|l| children(decoder, l));
            let threshold_span = fields.span;
            let kind = match (success, failure, children) {
                (Some(success), Some(failure), Some(children)) => Some(NodeDefKind::Parallel {
                    success,
                    failure,
                    threshold_span,
                    children,
                }),
                _ => None,
            };
            (kind, &["success", "failure", "children"])
        }
        "Repeat" | "RetryUntilSuccess" => {
            let n = count(decoder, &mut fields, "n");
            let child = fields
                .require(decoder, "child")
                .and_then(|c| node_def(decoder, c));
            let kind = if head == "Repeat" {
                CountKind::Repeat
            } else {
                CountKind::RetryUntilSuccess
            };
            (
                n.zip(child)
                    .map(|(n, child)| NodeDefKind::Counted(kind, n, Box::new(child))),
                &["n", "child"],
            )
        }
        "Timeout" | "Cooldown" => {
            let s = seconds(decoder, &mut fields);
            let child = fields
                .require(decoder, "child")
                .and_then(|c| node_def(decoder, c));
            let kind = if head == "Timeout" {
                TimedKind::Timeout
            } else {
                TimedKind::Cooldown
            };
            (
                s.zip(child)
                    .map(|(s, child)| NodeDefKind::Timed(kind, s, Box::new(child))),
                &["seconds", "child"],
            )
        }
        "Wait" => (
            seconds(decoder, &mut fields).map(NodeDefKind::Wait),
            &["seconds"],
        ),
        "Compare" => {
            let left = fields
                .require(decoder, "left")
                .and_then(|n| expr(decoder, n));
            let op = fields
                .require(decoder, "op")
                .and_then(|n| compare_op(decoder, n));
            let right = fields
                .require(decoder, "right")
                .and_then(|n| expr(decoder, n));
            let kind = match (left, op, right) {
                (Some(left), Some(op), Some(right)) => {
                    Some(NodeDefKind::Compare { left, op, right })
                }
                _ => None,
            };
            (kind, &["left", "op", "right"])
        }
        "Set" => {
            let key_node = fields.require(decoder, "key");
            let key = key_node.and_then(|n| decoder.string(n));
            let value = fields
                .require(decoder, "value")
                .and_then(|n| expr(decoder, n));
            let kind = match (key, key_node, value) {
                (Some(key), Some(key_node), Some(value)) => Some(NodeDefKind::Set {
                    key,
                    key_span: key_node.span,
                    value,
                }),
                _ => None,
            };
            (kind, &["key", "value"])
        }
        "Utility" => {
            let hysteresis = match fields.take("hysteresis") {
                Some(n) => decoder.float_in(n, 0.0, 1.0),
                None => Some(0.0),
            };
            let choices = fields
                .require(decoder, "choices")
                .and_then(|n| decoder.list(n))
                .map(|items| {
                    let parsed: Vec<Choice> = items
                        .iter()
                        .filter_map(|item| choice(decoder, item))
                        .collect();
                    (parsed.len() == items.len()).then_some(parsed)
                });
            let kind = match (hysteresis, choices.flatten()) {
                (Some(hysteresis), Some(choices)) if !choices.is_empty() => {
                    Some(NodeDefKind::Utility {
                        hysteresis,
                        choices,
                    })
                }
                (_, Some(_)) => {
                    decoder.error(
                        "invalid-value",
                        node.span,
                        "`Utility` needs at least one choice",
                    );
                    None
                }
                _ => None,
            };
            (kind, &["hysteresis", "choices"])
        }
        _ => {
            decoder.error(
                "invalid-value",
                node.span,
                format!("`{head}` takes a list of children or a single child"),
            );
            (None, &[])
        }
    };
    fields.finish(decoder, known);
    Some(NodeDef {
        kind: kind?,
        span: node.span,
        head_span,
    })
}

fn compare_op(decoder: &mut Decoder, node: &Node) -> Option<CompareOp> {
    let symbol = decoder.string(node)?;
    let op = CompareOp::ALL.into_iter().find(|op| op.symbol() == symbol);
    if op.is_none() {
        decoder
            .error(
                "invalid-value",
                node.span,
                format!("unknown comparison `{symbol}`"),
            )
            .hint = Some("use one of <, <=, >, >=, ==, !=".into());
    }
    op
}
