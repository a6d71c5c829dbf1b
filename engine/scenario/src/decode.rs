//! Reading span-carrying RON into typed values, reporting every shape error at its place.
//!
//! The same reader (`libero_behavior::syntax`) and diagnostics as the tree and strategy files,
//! with a small decoder of its own so the behavior crate stays untouched.

use libero_behavior::diagnostics::{did_you_mean, Diagnostic, Report, SourceFile};
use libero_behavior::syntax::{Body, Field, Node, NodeKind, Span};
use std::sync::Arc;

/// Decoding context for one file.
pub struct Decoder<'r> {
    pub file: Arc<SourceFile>,
    pub report: &'r mut Report,
}

impl<'r> Decoder<'r> {
    pub fn new(file: Arc<SourceFile>, report: &'r mut Report) -> Self {
        Self { file, report }
    }

    pub fn error(&mut self, code: &'static str, span: Span, message: impl Into<String>) {
        self.report
            .push(Diagnostic::error(code, message).at(&self.file, span));
    }

    pub fn error_hint(
        &mut self,
        code: &'static str,
        span: Span,
        message: impl Into<String>,
        hint: impl Into<String>,
    ) {
        self.report.push(
            Diagnostic::error(code, message)
                .at(&self.file, span)
                .hint(hint),
        );
    }

    pub fn warning_hint(
        &mut self,
        code: &'static str,
        span: Span,
        message: impl Into<String>,
        hint: impl Into<String>,
    ) {
        self.report.push(
            Diagnostic::warning(code, message)
                .at(&self.file, span)
                .hint(hint),
        );
    }

    pub fn expected(&mut self, node: &Node, what: &str) {
        let message = format!("expected {what}, found {}", node.describe());
        self.error("invalid-value", node.span, message);
    }

    /// Opens `Name(field: ..)`, or an anonymous `(field: ..)`.
    pub fn fields<'n>(&mut self, node: &'n Node, name: &str) -> Option<Fields<'n>> {
        match &node.kind {
            NodeKind::Struct {
                name: found,
                body: Body::Fields(fields),
            } if found.as_ref().is_none_or(|f| f.name == name) => {
                Some(Fields::new(node.span, fields))
            }
            NodeKind::Struct {
                name: found,
                body: Body::Items(items),
            } if items.is_empty() && found.as_ref().is_none_or(|f| f.name == name) => {
                Some(Fields::new(node.span, &[]))
            }
            _ => {
                self.expected(node, &format!("`{name}(...)`"));
                None
            }
        }
    }

    pub fn float(&mut self, node: &Node) -> Option<f64> {
        match node.kind {
            NodeKind::Float(x) if x.is_finite() => Some(x),
            NodeKind::Int(i) => Some(i as f64),
            _ => {
                self.expected(node, "a finite number");
                None
            }
        }
    }

    pub fn float_in(&mut self, node: &Node, min: f64, max: f64, unit: &str) -> Option<f64> {
        let value = self.float(node)?;
        if value < min || value > max {
            let message = format!("{value} {unit} is out of range [{min}, {max}]");
            self.error("out-of-range", node.span, message);
            return None;
        }
        Some(value)
    }

    pub fn int_in(&mut self, node: &Node, min: i64, max: i64) -> Option<i64> {
        let value = match node.kind {
            NodeKind::Int(i) => i,
            _ => {
                self.expected(node, "an integer");
                return None;
            }
        };
        if value < min || value > max {
            let message = format!("{value} is out of range [{min}, {max}]");
            self.error("out-of-range", node.span, message);
            return None;
        }
        Some(value)
    }

    pub fn string(&mut self, node: &Node) -> Option<String> {
        match &node.kind {
            NodeKind::Str(s) => Some(s.clone()),
            _ => {
                self.expected(node, "a string");
                None
            }
        }
    }

    pub fn list<'n>(&mut self, node: &'n Node) -> Option<&'n [Node]> {
        match &node.kind {
            NodeKind::List(items) => Some(items),
            _ => {
                self.expected(node, "a list `[...]`");
                None
            }
        }
    }
}

/// The name of a `Name(...)` or bare `Name`, with its span.
pub fn head(node: &Node) -> Option<(&str, Span)> {
    match &node.kind {
        NodeKind::Struct { name: Some(id), .. } | NodeKind::Unit(id) => Some((&id.name, id.span)),
        _ => None,
    }
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

/// The named fields of one struct; tracks which were read so leftovers can be reported.
pub struct Fields<'n> {
    pub span: Span,
    fields: &'n [Field],
    used: Vec<bool>,
}

impl<'n> Fields<'n> {
    fn new(span: Span, fields: &'n [Field]) -> Self {
        Self {
            span,
            fields,
            used: vec![false; fields.len()],
        }
    }

    pub fn take(&mut self, name: &str) -> Option<&'n Node> {
        let index = self.fields.iter().position(|f| f.name.name == name)?;
        self.used[index] = true;
        Some(&self.fields[index].value)
    }

    pub fn require(&mut self, decoder: &mut Decoder, name: &str) -> Option<&'n Node> {
        let found = self.take(name);
        if found.is_none() {
            decoder.error(
                "missing-field",
                self.span,
                format!("missing field `{name}`"),
            );
        }
        found
    }

    /// Reports unread fields (with a suggestion among `known`) and duplicates.
    pub fn finish(self, decoder: &mut Decoder, known: &[&str]) {
        let mut seen: Vec<&str> = Vec::new();
        for (field, used) in self.fields.iter().zip(&self.used) {
            if seen.contains(&field.name.name.as_str()) {
                decoder.error(
                    "duplicate-field",
                    field.name.span,
                    format!("field `{}` given twice", field.name.name),
                );
                continue;
            }
            seen.push(&field.name.name);
            if !used {
                let hint = did_you_mean(&field.name.name, known.iter().copied())
                    .unwrap_or_else(|| format!("expected one of: {}", known.join(", ")));
                decoder.error_hint(
                    "unknown-field",
                    field.name.span,
                    format!("unknown field `{}`", field.name.name),
                    hint,
                );
            }
        }
    }
}
