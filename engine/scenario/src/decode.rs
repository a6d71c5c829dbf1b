//! Reading span-carrying RON into typed values, reporting every shape error at its place: the
//! tree engine's reader (`libero_behavior::syntax`) and decoder, plus positional items.

pub use libero_behavior::decode::{Decoder, Fields};
use libero_behavior::syntax::{Body, Node, NodeKind, Span};

/// The name of a `Name(...)` or bare `Name`, with its span.
pub fn head(node: &Node) -> Option<(&str, Span)> {
    Decoder::head(node)
}

/// The positional items of `Name(a, b)` or `(a, b)`.
pub fn items(node: &Node) -> Option<&[Node]> {
    match &node.kind {
        NodeKind::Struct {
            body: Body::Items(items),
            ..
        } => Some(items),
        _ => None,
    }
}
