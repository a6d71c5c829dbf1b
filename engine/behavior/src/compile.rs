//! Lowering checked trees into flat, preorder node arrays with resolved ids, inlined subtrees
//! and structural hashes (used to carry node state across a hot reload).

use crate::check::Definitions;
use crate::tree::*;
use crate::value::{Value, ValueType};
use crate::vocabulary::{NativeId, NativeKind, Vocabulary};
use std::collections::hash_map::DefaultHasher;
use std::collections::HashMap;
use std::hash::{Hash, Hasher};

/// A blackboard slot index. Its `Debug` output is blank on purpose: structural hashes are taken
/// from `Debug` and must depend on the entry's key, not on where other keys shifted it.
#[derive(Clone, Copy, PartialEq, Eq)]
pub struct Slot(pub u32);

impl std::fmt::Debug for Slot {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("slot")
    }
}

/// A value computed at tick time.
#[derive(Debug, Clone, PartialEq)]
pub enum CExpr {
    Const(Value),
    Blackboard(Slot, std::sync::Arc<str>),
    Query(NativeId, Box<[CExpr]>),
}

#[derive(Debug, Clone, PartialEq)]
pub struct CConsideration {
    pub input: CExpr,
    pub curve: Curve,
    pub weight: f64,
}

#[derive(Debug, Clone, PartialEq)]
pub struct CChoice {
    pub weight: f64,
    pub considerations: Vec<CConsideration>,
}

#[derive(Debug, Clone, PartialEq)]
pub enum Op {
    Composite(CompositeKind),
    Parallel {
        success: u32,
        failure: u32,
    },
    Decorator(DecoratorKind),
    Counted(CountKind, u32),
    Timed(TimedKind, f64),
    Utility {
        hysteresis: f64,
        choices: Vec<CChoice>,
    },
    Condition(NativeId, Box<[CExpr]>),
    Action(NativeId, Box<[CExpr]>),
    /// A transparent wrapper kept so traces show which subtree runs.
    SubTree(String),
    Compare {
        left: CExpr,
        op: CompareOp,
        right: CExpr,
    },
    Set {
        slot: Slot,
        key: std::sync::Arc<str>,
        value: CExpr,
    },
    Wait(f64),
    Succeed,
    Fail,
}

#[derive(Debug, Clone)]
pub struct CNode {
    pub op: Op,
    pub children: Box<[u32]>,
    pub parent: Option<u32>,
    /// One past the last node of this node's subtree (subtrees are contiguous in preorder).
    pub end: u32,
    pub depth: u16,
    /// Hash of the op and all descendants: equal hashes mean identical subtrees.
    pub hash: u64,
    pub label: String,
}

/// One root tree with every subtree inlined.
#[derive(Debug)]
pub struct CompiledTree {
    pub name: String,
    pub nodes: Vec<CNode>,
}

impl CompiledTree {
    pub fn label(&self, node: u32) -> &str {
        &self.nodes[node as usize].label
    }

    /// Each node's parent (preorder index; `None` for the root), for drawing the tree.
    pub fn parents(&self) -> impl Iterator<Item = Option<u32>> + '_ {
        self.nodes.iter().map(|n| n.parent)
    }
}

/// Typed blackboard entries shared by all trees of a library.
#[derive(Debug, Clone, Default)]
pub struct BlackboardLayout {
    pub entries: Vec<(String, ValueType, Value)>,
    pub slots: HashMap<String, u32>,
}

impl BlackboardLayout {
    pub fn from_definitions(defs: &Definitions) -> Self {
        let mut layout = Self::default();
        for (key, decl) in &defs.blackboard {
            layout
                .slots
                .insert(key.to_string(), layout.entries.len() as u32);
            layout
                .entries
                .push((key.to_string(), decl.ty, decl.initial.clone()));
        }
        layout
    }
}

/// Compiles a checked tree; `None` only if checking was skipped and something is unresolved.
pub fn compile_tree(
    name: &str,
    defs: &Definitions,
    layout: &BlackboardLayout,
    vocabulary: &Vocabulary,
) -> Option<CompiledTree> {
    let mut compiler = Compiler {
        defs,
        layout,
        vocabulary,
        nodes: Vec::new(),
        depth: 0,
    };
    let (_, tree) = defs.trees.get(name)?;
    if tree.params.iter().any(|p| p.default.is_none()) {
        return None;
    }
    let env: HashMap<String, CExpr> = tree
        .params
        .iter()
        .map(|p| {
            (
                p.name.clone(),
                CExpr::Const(p.default.clone().unwrap_or(Value::Bool(false))),
            )
        })
        .collect();
    compiler.node(&tree.root, &env, None)?;
    Some(CompiledTree {
        name: name.to_string(),
        nodes: compiler.nodes,
    })
}

struct Compiler<'a> {
    defs: &'a Definitions<'a>,
    layout: &'a BlackboardLayout,
    vocabulary: &'a Vocabulary,
    nodes: Vec<CNode>,
    depth: u16,
}

type Env = HashMap<String, CExpr>;

/// Subtrees nest at most this deep; cycles are rejected by the checker, this guards the rest.
const MAX_INLINE_DEPTH: u16 = 512;

impl Compiler<'_> {
    fn expr(&self, expr: &Expr, env: &Env, ty: Option<ValueType>) -> Option<CExpr> {
        Some(match &expr.kind {
            ExprKind::Const(value) => CExpr::Const(match ty {
                Some(ty) => value.clone().coerce(ty),
                None => value.clone(),
            }),
            ExprKind::Blackboard(key) => {
                CExpr::Blackboard(Slot(*self.layout.slots.get(key)?), key.as_str().into())
            }
            ExprKind::Param(name) => env.get(name)?.clone(),
            ExprKind::Query(call) => {
                let id = self.vocabulary.find(NativeKind::Query, &call.name)?;
                CExpr::Query(id, self.native_args(id, call, env)?)
            }
        })
    }

    /// Arguments in the order of the spec's parameters, defaults filled in.
    fn native_args(&self, id: NativeId, call: &Call, env: &Env) -> Option<Box<[CExpr]>> {
        let spec = self.vocabulary.spec(id);
        spec.params
            .iter()
            .map(
                |param| match call.args.iter().find(|a| a.name == param.name) {
                    Some(arg) => self.expr(&arg.value, env, Some(param.ty)),
                    None => param
                        .default
                        .clone()
                        .map(|v| CExpr::Const(v.coerce(param.ty))),
                },
            )
            .collect()
    }

    fn push(&mut self, op: Op, label: String, parent: Option<u32>) -> u32 {
        let index = self.nodes.len() as u32;
        self.nodes.push(CNode {
            op,
            children: Box::new([]),
            parent,
            end: index + 1,
            depth: self.depth,
            hash: 0,
            label,
        });
        index
    }

    fn node(&mut self, def: &NodeDef, env: &Env, parent: Option<u32>) -> Option<u32> {
        if self.depth > MAX_INLINE_DEPTH {
            return None;
        }
        let (op, label, children): (Op, String, Vec<(&NodeDef, Option<Env>)>) = match &def.kind {
            NodeDefKind::Composite(kind, children) => (
                Op::Composite(*kind),
                kind.name().to_string(),
                children.iter().map(|c| (c, None)).collect(),
            ),
            NodeDefKind::Parallel {
                success,
                failure,
                children,
                ..
            } => (
                Op::Parallel {
                    success: *success,
                    failure: *failure,
                },
                format!("Parallel({success}/{failure})"),
                children.iter().map(|c| (c, None)).collect(),
            ),
            NodeDefKind::Decorator(kind, child) => (
                Op::Decorator(*kind),
                kind.name().to_string(),
                vec![(&**child, None)],
            ),
            NodeDefKind::Counted(kind, n, child) => (
                Op::Counted(*kind, *n),
                format!("{kind:?}({n})"),
                vec![(&**child, None)],
            ),
            NodeDefKind::Timed(kind, s, child) => (
                Op::Timed(*kind, *s),
                format!("{kind:?}({s}s)"),
                vec![(&**child, None)],
            ),
            NodeDefKind::Utility {
                hysteresis,
                choices,
            } => {
                let compiled = choices
                    .iter()
                    .map(|choice| {
                        let considerations = choice
                            .considerations
                            .iter()
                            .map(|c| {
                                Some(CConsideration {
                                    input: self.expr(&c.input, env, None)?,
                                    curve: c.curve,
                                    weight: c.weight,
                                })
                            })
                            .collect::<Option<Vec<_>>>()?;
                        Some(CChoice {
                            weight: choice.weight,
                            considerations,
                        })
                    })
                    .collect::<Option<Vec<_>>>()?;
                let children = choices.iter().map(|c| (&c.child, None)).collect();
                (
                    Op::Utility {
                        hysteresis: *hysteresis,
                        choices: compiled,
                    },
                    "Utility".into(),
                    children,
                )
            }
            NodeDefKind::Condition(call) => {
                let id = self.vocabulary.find(NativeKind::Condition, &call.name)?;
                (
                    Op::Condition(id, self.native_args(id, call, env)?),
                    format!("Condition {}", call.name),
                    vec![],
                )
            }
            NodeDefKind::Action(call) => {
                let id = self.vocabulary.find(NativeKind::Action, &call.name)?;
                (
                    Op::Action(id, self.native_args(id, call, env)?),
                    format!("Action {}", call.name),
                    vec![],
                )
            }
            NodeDefKind::SubTree(call) => {
                let (_, tree) = self.defs.trees.get(call.name.as_str())?;
                let mut inner = Env::new();
                for param in &tree.params {
                    let bound = match call.args.iter().find(|a| a.name == param.name) {
                        Some(arg) => self.expr(&arg.value, env, Some(param.ty))?,
                        None => CExpr::Const(param.default.clone()?.coerce(param.ty)),
                    };
                    inner.insert(param.name.clone(), bound);
                }
                (
                    Op::SubTree(call.name.clone()),
                    format!("SubTree {}", call.name),
                    vec![(&tree.root, Some(inner))],
                )
            }
            NodeDefKind::Compare { left, op, right } => (
                Op::Compare {
                    left: self.expr(left, env, None)?,
                    op: *op,
                    right: self.expr(right, env, None)?,
                },
                format!("Compare({})", op.symbol()),
                vec![],
            ),
            NodeDefKind::Set { key, value, .. } => {
                let slot = *self.layout.slots.get(key)?;
                let ty = self.layout.entries[slot as usize].1;
                (
                    Op::Set {
                        slot: Slot(slot),
                        key: key.as_str().into(),
                        value: self.expr(value, env, Some(ty))?,
                    },
                    format!("Set {key}"),
                    vec![],
                )
            }
            NodeDefKind::Wait(s) => (Op::Wait(*s), format!("Wait({s}s)"), vec![]),
            NodeDefKind::Succeed => (Op::Succeed, "Succeed".into(), vec![]),
            NodeDefKind::Fail => (Op::Fail, "Fail".into(), vec![]),
        };
        let index = self.push(op, label, parent);
        self.depth += 1;
        let mut child_ids = Vec::with_capacity(children.len());
        for (child, inner_env) in children {
            child_ids.push(self.node(child, inner_env.as_ref().unwrap_or(env), Some(index))?);
        }
        self.depth -= 1;
        let mut hasher = DefaultHasher::new();
        format!("{:?}", self.nodes[index as usize].op).hash(&mut hasher);
        for &child in &child_ids {
            self.nodes[child as usize].hash.hash(&mut hasher);
        }
        let end = self.nodes.len() as u32;
        let node = &mut self.nodes[index as usize];
        node.hash = hasher.finish();
        node.children = child_ids.into_boxed_slice();
        node.end = end;
        Some(index)
    }
}
