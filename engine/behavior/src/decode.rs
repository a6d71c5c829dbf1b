//! Turning span-carrying syntax into typed values, reporting every shape error with its location.

use crate::diagnostics::{did_you_mean, Diagnostic, Report, SourceFile};
use crate::syntax::{Body, Field, Node, NodeKind, Span};
use crate::value::Vec2;
use std::sync::Arc;

/// Decoding context for one file: where to report and what to point at.
pub struct Decoder<'r> {
    pub file: Arc<SourceFile>,
    pub report: &'r mut Report,
}

impl<'r> Decoder<'r> {
    pub fn new(file: Arc<SourceFile>, report: &'r mut Report) -> Self {
        Self { file, report }
    }

    pub fn error(
        &mut self,
        code: &'static str,
        span: Span,
        message: impl Into<String>,
    ) -> &mut Diagnostic {
        self.report
            .push(Diagnostic::error(code, message).at(&self.file, span));
        self.report.diagnostics.last_mut().expect("just pushed")
    }

    pub fn warning(&mut self, code: &'static str, span: Span, message: impl Into<String>) {
        self.report
            .push(Diagnostic::warning(code, message).at(&self.file, span));
    }

    /// An error with a hint.
    pub fn error_hint(
        &mut self,
        code: &'static str,
        span: Span,
        message: impl Into<String>,
        hint: impl Into<String>,
    ) {
        self.error(code, span, message).hint = Some(hint.into());
    }

    /// A warning with a hint.
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

    /// Opens `Name(field: ..)` (or an anonymous `(field: ..)` when `name` is empty).
    pub fn fields<'n>(&mut self, node: &'n Node, name: &str) -> Option<Fields<'n>> {
        match &node.kind {
            NodeKind::Struct {
                name: found,
                body: Body::Fields(fields),
            } if found
                .as_ref()
                .is_none_or(|f| f.name == name || name.is_empty()) =>
            {
                Some(Fields::new(node.span, fields))
            }
            NodeKind::Struct {
                name: found,
                body: Body::Items(items),
            } if items.is_empty() && found.as_ref().is_none_or(|f| f.name == name) => {
                Some(Fields::new(node.span, &[]))
            }
            _ => {
                let shown = if name.is_empty() {
                    "a struct with named fields".into()
                } else {
                    format!("`{name}(...)`")
                };
                self.expected(node, &shown);
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

    pub fn float_in(&mut self, node: &Node, min: f64, max: f64) -> Option<f64> {
        self.float_in_unit(node, min, max, "")
    }

    /// A number within [min, max]; the message names the value with its `unit`.
    pub fn float_in_unit(&mut self, node: &Node, min: f64, max: f64, unit: &str) -> Option<f64> {
        let value = self.float(node)?;
        if value < min || value > max {
            let shown = if unit.is_empty() {
                value.to_string()
            } else {
                format!("{value} {unit}")
            };
            let message = format!("{shown} is out of range [{min}, {max}]");
            self.error("out-of-range", node.span, message);
            return None;
        }
        Some(value)
    }

    pub fn int(&mut self, node: &Node) -> Option<i64> {
        match node.kind {
            NodeKind::Int(i) => Some(i),
            _ => {
                self.expected(node, "an integer");
                None
            }
        }
    }

    pub fn int_in(&mut self, node: &Node, min: i64, max: i64) -> Option<i64> {
        let value = self.int(node)?;
        if value < min || value > max {
            self.error(
                "out-of-range",
                node.span,
                format!("{value} is out of range [{min}, {max}]"),
            );
            return None;
        }
        Some(value)
    }

    pub fn bool(&mut self, node: &Node) -> Option<bool> {
        match node.kind {
            NodeKind::Bool(b) => Some(b),
            _ => {
                self.expected(node, "`true` or `false`");
                None
            }
        }
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

    pub fn vec2(&mut self, node: &Node) -> Option<Vec2> {
        match &node.kind {
            NodeKind::Struct {
                name: None,
                body: Body::Items(items),
            } if items.len() == 2 => {
                let x = self.float(&items[0]);
                let y = self.float(&items[1]);
                Some(Vec2::new(x?, y?))
            }
            _ => {
                self.expected(node, "a point `(x, y)`");
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

    pub fn map<'n>(&mut self, node: &'n Node) -> Option<&'n [(Node, Node)]> {
        match &node.kind {
            NodeKind::Map(entries) => Some(entries),
            _ => {
                self.expected(node, "a map `{...}`");
                None
            }
        }
    }

    /// The name of a `Name(...)` or bare `Name`, with its span.
    pub fn head(node: &Node) -> Option<(&str, Span)> {
        match &node.kind {
            NodeKind::Struct { name: Some(id), .. } | NodeKind::Unit(id) => {
                Some((&id.name, id.span))
            }
            _ => None,
        }
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

    /// Where field `name`'s value is, without taking it.
    pub fn peek_span(&self, name: &str) -> Option<Span> {
        self.fields
            .iter()
            .find(|f| f.name.name == name)
            .map(|f| f.value.span)
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

    /// Fields not read yet, in file order.
    pub fn rest(&mut self) -> Vec<&'n Field> {
        let rest = self
            .fields
            .iter()
            .zip(&self.used)
            .filter(|(_, used)| !**used)
            .map(|(f, _)| f)
            .collect();
        self.used.iter_mut().for_each(|u| *u = true);
        rest
    }

    /// Reports unread fields (with a suggestion among `known`) and duplicates.
    pub fn finish(mut self, decoder: &mut Decoder, known: &[&str]) {
        let mut seen: Vec<&str> = Vec::new();
        for field in self.fields {
            if seen.contains(&field.name.name.as_str()) {
                decoder.error(
                    "duplicate-field",
                    field.name.span,
                    format!("field `{}` given twice", field.name.name),
                );
            }
            seen.push(&field.name.name);
        }
        for field in self.rest() {
            let hint = did_you_mean(&field.name.name, known.iter().copied());
            let hint = hint.or_else(|| Some(format!("expected one of: {}", known.join(", "))));
            decoder
                .error(
                    "unknown-field",
                    field.name.span,
                    format!("unknown field `{}`", field.name.name),
                )
                .hint = hint;
        }
    }
}
