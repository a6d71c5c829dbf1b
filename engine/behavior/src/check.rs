//! Checking behavior files against the vocabulary and each other: names, parameters, types,
//! ranges, blackboard keys, subtree references and cycles. Collects every error, never stops early.

use crate::diagnostics::{did_you_mean, Diagnostic, Report, SourceFile};
use crate::syntax::Span;
use crate::tree::*;
use crate::value::{Value, ValueType};
use crate::vocabulary::{NativeKind, ParamSpec, Vocabulary};
use std::collections::{BTreeMap, HashMap, HashSet};
use std::sync::Arc;

/// A parsed behavior file with its source.
pub struct LoadedBehaviors {
    pub source: Arc<SourceFile>,
    pub file: BehaviorFile,
}

/// Where each tree and blackboard entry is defined, across all files.
pub struct Definitions<'a> {
    pub trees: BTreeMap<&'a str, (&'a Arc<SourceFile>, &'a TreeDef)>,
    pub blackboard: BTreeMap<&'a str, &'a BlackboardDecl>,
}

fn position(source: &SourceFile, span: Span) -> String {
    let (line, column) = source.line_col(span.start);
    format!("{}:{line}:{column}", source.path.display())
}

pub fn collect_definitions<'a>(
    files: &'a [LoadedBehaviors],
    report: &mut Report,
) -> Definitions<'a> {
    let mut trees: BTreeMap<&str, (&Arc<SourceFile>, &TreeDef)> = BTreeMap::new();
    let mut blackboard: BTreeMap<&str, (&Arc<SourceFile>, &BlackboardDecl)> = BTreeMap::new();
    for loaded in files {
        for tree in &loaded.file.trees {
            if let Some((first_file, first)) = trees.get(tree.name.as_str()) {
                let hint = format!("first defined at {}", position(first_file, first.name_span));
                report.push(
                    Diagnostic::error(
                        "duplicate-tree",
                        format!("tree `{}` is defined twice", tree.name),
                    )
                    .at(&loaded.source, tree.name_span)
                    .hint(hint),
                );
            } else {
                trees.insert(&tree.name, (&loaded.source, tree));
            }
        }
        for decl in &loaded.file.blackboard {
            match blackboard.get(decl.key.as_str()) {
                Some((first_file, first))
                    if first.ty != decl.ty || first.initial != decl.initial =>
                {
                    let hint = format!(
                        "first declared at {} as {}({})",
                        position(first_file, first.key_span),
                        first.ty,
                        first.initial
                    );
                    let message = format!(
                        "blackboard entry `{}` is declared twice, differently",
                        decl.key
                    );
                    report.push(
                        Diagnostic::error("conflicting-blackboard-entry", message)
                            .at(&loaded.source, decl.key_span)
                            .hint(hint),
                    );
                }
                Some(_) => {}
                None => {
                    blackboard.insert(&decl.key, (&loaded.source, decl));
                }
            }
        }
    }
    Definitions {
        trees,
        blackboard: blackboard.into_iter().map(|(k, (_, d))| (k, d)).collect(),
    }
}

/// Subtree calls per tree: (callee, call site, file), for cycle detection.
type CallGraph<'a> = BTreeMap<&'a str, Vec<(&'a str, Span, &'a Arc<SourceFile>)>>;

/// Checks every tree; returns, per tree, the subtrees it calls (for cycle detection).
pub fn check_trees(
    files: &[LoadedBehaviors],
    defs: &Definitions,
    vocabulary: &Vocabulary,
    report: &mut Report,
) {
    let mut calls: CallGraph = BTreeMap::new();
    for loaded in files {
        for tree in &loaded.file.trees {
            let mut checker = Checker {
                source: &loaded.source,
                tree,
                defs,
                vocabulary,
                report,
                calls: Vec::new(),
            };
            checker.params_defaults();
            checker.node(&tree.root);
            let found = std::mem::take(&mut checker.calls);
            calls
                .entry(&tree.name)
                .or_default()
                .extend(found.into_iter().map(|(n, s)| (n, s, &loaded.source)));
        }
    }
    report_cycles(&calls, report);
}

struct Checker<'a, 'r> {
    source: &'a Arc<SourceFile>,
    tree: &'a TreeDef,
    defs: &'a Definitions<'a>,
    vocabulary: &'a Vocabulary,
    report: &'r mut Report,
    calls: Vec<(&'a str, Span)>,
}

impl<'a> Checker<'a, '_> {
    fn error(&mut self, code: &'static str, span: Span, message: String, hint: Option<String>) {
        self.report.push(
            Diagnostic::error(code, message)
                .at(self.source, span)
                .maybe_hint(hint),
        );
    }

    fn params_defaults(&mut self) {
        let mut seen = HashSet::new();
        for param in &self.tree.params {
            if !seen.insert(param.name.as_str()) {
                self.error(
                    "duplicate-parameter",
                    param.span,
                    format!("parameter `{}` declared twice", param.name),
                    None,
                );
            }
        }
    }

    fn node(&mut self, node: &'a NodeDef) {
        match &node.kind {
            NodeDefKind::Composite(kind, children) => {
                if children.is_empty() {
                    self.error(
                        "empty-composite",
                        node.head_span,
                        format!("`{}` has no children", kind.name()),
                        None,
                    );
                }
                children.iter().for_each(|c| self.node(c));
            }
            NodeDefKind::Parallel {
                success,
                failure,
                threshold_span,
                children,
            } => {
                let n = children.len() as u32;
                if *success > n || *failure > n {
                    let message = format!("`Parallel` thresholds (success: {success}, failure: {failure}) exceed its {n} children");
                    self.error(
                        "bad-threshold",
                        *threshold_span,
                        message,
                        Some("each threshold must be between 1 and the number of children".into()),
                    );
                }
                children.iter().for_each(|c| self.node(c));
            }
            NodeDefKind::Decorator(_, child)
            | NodeDefKind::Counted(_, _, child)
            | NodeDefKind::Timed(_, _, child) => self.node(child),
            NodeDefKind::Utility { choices, .. } => {
                for choice in choices {
                    for consideration in &choice.considerations {
                        if let Some(ty) = self.expr(&consideration.input) {
                            if !ty.is_scalar() {
                                let message = format!(
                                    "a consideration's input must be numeric or Bool, found {ty}"
                                );
                                self.error(
                                    "type-mismatch",
                                    consideration.input.span,
                                    message,
                                    None,
                                );
                            }
                        }
                    }
                    self.node(&choice.child);
                }
            }
            NodeDefKind::Condition(call) => self.native(NativeKind::Condition, call),
            NodeDefKind::Action(call) => self.native(NativeKind::Action, call),
            NodeDefKind::SubTree(call) => self.subtree(call),
            NodeDefKind::Compare { left, op, right } => {
                let (l, r) = (self.expr(left), self.expr(right));
                if let (Some(l), Some(r)) = (l, r) {
                    let ordered = matches!(
                        op,
                        CompareOp::Lt | CompareOp::Le | CompareOp::Gt | CompareOp::Ge
                    );
                    let comparable = if ordered {
                        l.is_scalar() && r.is_scalar()
                    } else {
                        l.fits(r) || r.fits(l) || (l.is_scalar() && r.is_scalar())
                    };
                    if !comparable {
                        let message = format!("cannot compare {l} {} {r}", op.symbol());
                        self.error("type-mismatch", node.span, message, None);
                    }
                }
            }
            NodeDefKind::Set {
                key,
                key_span,
                value,
            } => {
                let declared = self.blackboard_type(key, *key_span);
                if let (Some(declared), Some(found)) = (declared, self.expr(value)) {
                    if !found.fits(declared) {
                        let message = format!(
                            "blackboard entry `{key}` is {declared}, but the value is {found}"
                        );
                        self.error("type-mismatch", value.span, message, None);
                    }
                }
            }
            NodeDefKind::Wait(_) | NodeDefKind::Succeed | NodeDefKind::Fail => {}
        }
    }

    fn blackboard_type(&mut self, key: &str, span: Span) -> Option<ValueType> {
        let declared = self.defs.blackboard.get(key).map(|d| d.ty);
        if declared.is_none() {
            let hint = did_you_mean(key, self.defs.blackboard.keys().copied())
                .or_else(|| Some("declare it in a file's `blackboard: { .. }`".into()));
            self.error(
                "unknown-blackboard-entry",
                span,
                format!("unknown blackboard entry `{key}`"),
                hint,
            );
        }
        declared
    }

    /// The type of an expression, or `None` after reporting why it has none.
    fn expr(&mut self, expr: &Expr) -> Option<ValueType> {
        match &expr.kind {
            ExprKind::Const(value) => Some(value.value_type()),
            ExprKind::Blackboard(key) => self.blackboard_type(key, expr.span),
            ExprKind::Param(name) => {
                let declared = self
                    .tree
                    .params
                    .iter()
                    .find(|p| &p.name == name)
                    .map(|p| p.ty);
                if declared.is_none() {
                    let hint = did_you_mean(name, self.tree.params.iter().map(|p| p.name.as_str())).or_else(|| {
                        Some(format!("declare it with `\"{}\": Tree(params: {{ \"{name}\": Float }}, root: ..)`", self.tree.name))
                    });
                    let message = format!("tree `{}` has no parameter `{name}`", self.tree.name);
                    self.error("unknown-tree-parameter", expr.span, message, hint);
                }
                declared
            }
            ExprKind::Query(call) => {
                let Some(id) = self.vocabulary.find(NativeKind::Query, &call.name) else {
                    let hint = did_you_mean(&call.name, self.vocabulary.names(NativeKind::Query));
                    self.error(
                        "unknown-query",
                        call.name_span,
                        format!("unknown query `{}`", call.name),
                        hint,
                    );
                    return None;
                };
                let spec = self.vocabulary.spec(id);
                self.args(&spec.params, call, &format!("query `{}`", call.name));
                spec.returns
            }
        }
    }

    fn native(&mut self, kind: NativeKind, call: &Call) {
        let Some(id) = self.vocabulary.find(kind, &call.name) else {
            let other = [NativeKind::Condition, NativeKind::Action, NativeKind::Query]
                .into_iter()
                .find(|k| *k != kind && self.vocabulary.find(*k, &call.name).is_some());
            let hint = match other {
                Some(other) => Some(format!(
                    "`{}` is a {}, not a {}",
                    call.name,
                    other.name(),
                    kind.name()
                )),
                None => did_you_mean(&call.name, self.vocabulary.names(kind)),
            };
            let message = format!("unknown {} `{}`", kind.name(), call.name);
            self.error("unknown-node", call.name_span, message, hint);
            return;
        };
        let spec = self.vocabulary.spec(id);
        self.args(
            &spec.params,
            call,
            &format!("{} `{}`", kind.name(), call.name),
        );
    }

    /// Checks a call's arguments against declared parameters: names, presence, types, ranges.
    fn args(&mut self, params: &[ParamSpec], call: &Call, what: &str) {
        let mut given = HashSet::new();
        for arg in &call.args {
            if !given.insert(arg.name.as_str()) {
                self.error(
                    "duplicate-parameter",
                    arg.name_span,
                    format!("parameter `{}` given twice", arg.name),
                    None,
                );
            }
            let Some(param) = params.iter().find(|p| p.name == arg.name) else {
                let hint =
                    did_you_mean(&arg.name, params.iter().map(|p| p.name.as_str())).or_else(|| {
                        let names: Vec<&str> = params.iter().map(|p| p.name.as_str()).collect();
                        Some(if names.is_empty() {
                            format!("{what} takes no parameters")
                        } else {
                            format!("parameters are: {}", names.join(", "))
                        })
                    });
                self.error(
                    "unknown-parameter",
                    arg.name_span,
                    format!("{what} has no parameter `{}`", arg.name),
                    hint,
                );
                continue;
            };
            self.arg_value(param, arg);
        }
        let reported =
            |name: &str| given.contains(name) || call.invalid_args.iter().any(|a| a == name);
        for param in params
            .iter()
            .filter(|p| p.default.is_none() && !reported(&p.name))
        {
            let hint = Some(format!("add `{}: <{}>`", param.name, param.ty));
            let message = format!("{what} needs parameter `{}` ({})", param.name, param.ty);
            self.error("missing-parameter", call.name_span, message, hint);
        }
    }

    fn arg_value(&mut self, param: &ParamSpec, arg: &Arg) {
        let Some(found) = self.expr(&arg.value) else {
            return;
        };
        if !found.fits(param.ty) {
            let message = format!(
                "parameter `{}` is {}, but the value is {found}",
                param.name, param.ty
            );
            self.error("type-mismatch", arg.value.span, message, None);
            return;
        }
        let ExprKind::Const(value) = &arg.value.kind else {
            return;
        };
        if let (Some((min, max)), true) = (param.range, found.is_scalar()) {
            let x = value.as_f64();
            if x < min || x > max {
                let unit = if param.unit.is_empty() {
                    String::new()
                } else {
                    format!(" {}", param.unit)
                };
                let message = format!(
                    "{x}{unit} is out of range [{min}, {max}] for `{}`",
                    param.name
                );
                self.error("out-of-range", arg.value.span, message, None);
            }
        }
        if let Value::String(s) = value {
            if !param.choices.is_empty() && !param.choices.iter().any(|c| c.as_str() == &**s) {
                let hint = did_you_mean(s, param.choices.iter().map(String::as_str))
                    .or_else(|| Some(format!("one of: {}", param.choices.join(", "))));
                let message = format!("`{s}` is not a valid `{}`", param.name);
                self.error("invalid-choice", arg.value.span, message, hint);
            }
        }
    }

    fn subtree(&mut self, call: &'a Call) {
        let Some((_, tree)) = self.defs.trees.get(call.name.as_str()) else {
            let hint = did_you_mean(&call.name, self.defs.trees.keys().copied());
            self.error(
                "missing-subtree",
                call.name_span,
                format!("no tree named `{}`", call.name),
                hint,
            );
            return;
        };
        self.calls.push((&call.name, call.name_span));
        let params: Vec<ParamSpec> = tree
            .params
            .iter()
            .map(|p| ParamSpec {
                default: p.default.clone(),
                ..ParamSpec::new(&p.name, p.ty)
            })
            .collect();
        self.args(&params, call, &format!("tree `{}`", call.name));
    }
}

fn report_cycles(calls: &CallGraph, report: &mut Report) {
    #[derive(Clone, Copy, PartialEq)]
    enum Mark {
        Active,
        Done,
    }
    fn visit<'a>(
        tree: &'a str,
        calls: &CallGraph<'a>,
        marks: &mut HashMap<&'a str, Mark>,
        path: &mut Vec<&'a str>,
        report: &mut Report,
    ) {
        marks.insert(tree, Mark::Active);
        path.push(tree);
        for (callee, span, source) in calls.get(tree).into_iter().flatten() {
            match marks.get(callee) {
                Some(Mark::Active) => {
                    let start = path.iter().position(|t| t == callee).unwrap_or(0);
                    let cycle: Vec<&str> = path[start..].iter().copied().chain([*callee]).collect();
                    let message = format!("subtree cycle: {}", cycle.join(" → "));
                    report.push(
                        Diagnostic::error("subtree-cycle", message)
                            .at(source, *span)
                            .hint("a tree cannot contain itself; break the cycle"),
                    );
                }
                Some(Mark::Done) => {}
                None => visit(callee, calls, marks, path, report),
            }
        }
        path.pop();
        marks.insert(tree, Mark::Done);
    }
    let mut marks = HashMap::new();
    for tree in calls.keys() {
        if !marks.contains_key(tree) {
            visit(tree, calls, &mut marks, &mut Vec::new(), report);
        }
    }
}
