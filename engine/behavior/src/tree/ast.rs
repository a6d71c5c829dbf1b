//! The syntax tree of a behavior file, with spans for located diagnostics.

use crate::syntax::Span;
use crate::value::{Value, ValueType};

#[derive(Debug, Clone, Default)]
pub struct BehaviorFile {
    pub blackboard: Vec<BlackboardDecl>,
    pub trees: Vec<TreeDef>,
}

/// A typed blackboard entry with its initial value.
#[derive(Debug, Clone)]
pub struct BlackboardDecl {
    pub key: String,
    pub key_span: Span,
    pub ty: ValueType,
    pub initial: Value,
}

#[derive(Debug, Clone)]
pub struct TreeDef {
    pub name: String,
    pub name_span: Span,
    pub params: Vec<TreeParam>,
    pub root: NodeDef,
}

/// A declared subtree parameter; without a default it must be bound by every caller.
#[derive(Debug, Clone)]
pub struct TreeParam {
    pub name: String,
    pub span: Span,
    pub ty: ValueType,
    pub default: Option<Value>,
}

#[derive(Debug, Clone)]
pub struct NodeDef {
    pub kind: NodeDefKind,
    /// The whole node.
    pub span: Span,
    /// The node's keyword, e.g. `Sequence`.
    pub head_span: Span,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum CompositeKind {
    Sequence,
    Fallback,
    ReactiveSequence,
    ReactiveFallback,
}

impl CompositeKind {
    pub const ALL: [CompositeKind; 4] = [
        CompositeKind::Sequence,
        CompositeKind::Fallback,
        CompositeKind::ReactiveSequence,
        CompositeKind::ReactiveFallback,
    ];
    pub fn name(self) -> &'static str {
        match self {
            CompositeKind::Sequence => "Sequence",
            CompositeKind::Fallback => "Fallback",
            CompositeKind::ReactiveSequence => "ReactiveSequence",
            CompositeKind::ReactiveFallback => "ReactiveFallback",
        }
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum DecoratorKind {
    Invert,
    ForceSuccess,
    ForceFailure,
}

impl DecoratorKind {
    pub const ALL: [DecoratorKind; 3] = [
        DecoratorKind::Invert,
        DecoratorKind::ForceSuccess,
        DecoratorKind::ForceFailure,
    ];
    pub fn name(self) -> &'static str {
        match self {
            DecoratorKind::Invert => "Invert",
            DecoratorKind::ForceSuccess => "ForceSuccess",
            DecoratorKind::ForceFailure => "ForceFailure",
        }
    }
}

/// Decorators with a count.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum CountKind {
    Repeat,
    RetryUntilSuccess,
}

/// Decorators with a duration.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum TimedKind {
    Timeout,
    Cooldown,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum CompareOp {
    Lt,
    Le,
    Gt,
    Ge,
    Eq,
    Ne,
}

impl CompareOp {
    pub const ALL: [CompareOp; 6] = [
        CompareOp::Lt,
        CompareOp::Le,
        CompareOp::Gt,
        CompareOp::Ge,
        CompareOp::Eq,
        CompareOp::Ne,
    ];
    pub fn symbol(self) -> &'static str {
        match self {
            CompareOp::Lt => "<",
            CompareOp::Le => "<=",
            CompareOp::Gt => ">",
            CompareOp::Ge => ">=",
            CompareOp::Eq => "==",
            CompareOp::Ne => "!=",
        }
    }
}

#[derive(Debug, Clone)]
pub enum NodeDefKind {
    Composite(CompositeKind, Vec<NodeDef>),
    Parallel {
        success: u32,
        failure: u32,
        threshold_span: Span,
        children: Vec<NodeDef>,
    },
    Decorator(DecoratorKind, Box<NodeDef>),
    Counted(CountKind, u32, Box<NodeDef>),
    Timed(TimedKind, f64, Box<NodeDef>),
    Utility {
        hysteresis: f64,
        choices: Vec<Choice>,
    },
    Condition(Call),
    Action(Call),
    SubTree(Call),
    Compare {
        left: Expr,
        op: CompareOp,
        right: Expr,
    },
    Set {
        key: String,
        key_span: Span,
        value: Expr,
    },
    Wait(f64),
    Succeed,
    Fail,
}

/// A named native node, query or subtree with its arguments.
#[derive(Debug, Clone)]
pub struct Call {
    pub name: String,
    pub name_span: Span,
    pub args: Vec<Arg>,
    /// Names of arguments whose values had errors (already reported), so they do not also
    /// count as missing.
    pub invalid_args: Vec<String>,
}

#[derive(Debug, Clone)]
pub struct Arg {
    pub name: String,
    pub name_span: Span,
    pub value: Expr,
}

#[derive(Debug, Clone)]
pub struct Expr {
    pub kind: ExprKind,
    pub span: Span,
}

#[derive(Debug, Clone)]
pub enum ExprKind {
    Const(Value),
    Blackboard(String),
    Param(String),
    Query(Call),
}

#[derive(Debug, Clone)]
pub struct Choice {
    pub weight: f64,
    pub considerations: Vec<Consideration>,
    pub child: NodeDef,
    pub span: Span,
}

#[derive(Debug, Clone)]
pub struct Consideration {
    pub input: Expr,
    pub curve: Curve,
    pub weight: f64,
}

/// Maps a raw input onto a score in [0, 1].
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Curve {
    Identity,
    /// `from` maps to 0 and `to` to 1, linearly, clamped; `from > to` makes it decreasing.
    Linear {
        from: f64,
        to: f64,
    },
    /// Linear's normalised input raised to `exponent`.
    Power {
        from: f64,
        to: f64,
        exponent: f64,
    },
    Logistic {
        mid: f64,
        steepness: f64,
    },
    Step {
        threshold: f64,
        above: bool,
    },
}

impl Curve {
    pub fn score(self, x: f64) -> f64 {
        let normalised = |from: f64, to: f64| {
            if from == to {
                f64::from(u8::from(x >= to))
            } else {
                ((x - from) / (to - from)).clamp(0.0, 1.0)
            }
        };
        let score = match self {
            Curve::Identity => x,
            Curve::Linear { from, to } => normalised(from, to),
            Curve::Power { from, to, exponent } => normalised(from, to).powf(exponent),
            Curve::Logistic { mid, steepness } => 1.0 / (1.0 + (-steepness * (x - mid)).exp()),
            Curve::Step { threshold, above } => f64::from(u8::from((x >= threshold) == above)),
        };
        if score.is_nan() {
            0.0
        } else {
            score.clamp(0.0, 1.0)
        }
    }
}
