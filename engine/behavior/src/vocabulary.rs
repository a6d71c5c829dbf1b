//! The native nodes the agent provides: conditions, actions and world queries, each declared
//! with typed parameters and a one-line doc, so validation and `libero nodes` come from code.

use crate::value::{Value, ValueType};
use serde::Serialize;
use std::collections::HashMap;
use std::fmt::Write as _;

/// Index of a native node in its [`Vocabulary`]; names are resolved to ids at load time so a
/// tick never looks up strings.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize)]
pub struct NativeId(pub u32);

#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
pub enum NativeKind {
    Condition,
    Action,
    Query,
}

impl NativeKind {
    pub fn name(self) -> &'static str {
        match self {
            NativeKind::Condition => "condition",
            NativeKind::Action => "action",
            NativeKind::Query => "query",
        }
    }
}

#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ParamSpec {
    pub name: String,
    pub ty: ValueType,
    /// SI unit of the value (`m`, `s`, `rad`, `m/s`), empty when dimensionless.
    pub unit: String,
    /// Inclusive bounds checked on constants at load time.
    pub range: Option<(f64, f64)>,
    /// Used when the parameter is omitted; a parameter without default is required.
    pub default: Option<Value>,
    /// For enum-like strings: the accepted values (empty means any string).
    pub choices: Vec<String>,
    pub doc: String,
}

impl ParamSpec {
    pub fn new(name: &str, ty: ValueType) -> Self {
        Self {
            name: name.into(),
            ty,
            unit: String::new(),
            range: None,
            default: None,
            choices: Vec::new(),
            doc: String::new(),
        }
    }
    pub fn unit(mut self, unit: &str) -> Self {
        self.unit = unit.into();
        self
    }
    pub fn range(mut self, min: f64, max: f64) -> Self {
        self.range = Some((min, max));
        self
    }
    pub fn default(mut self, value: Value) -> Self {
        self.default = Some(value);
        self
    }
    pub fn choices(mut self, choices: &[&str]) -> Self {
        self.choices = choices.iter().map(|c| c.to_string()).collect();
        self
    }
    pub fn doc(mut self, doc: &str) -> Self {
        self.doc = doc.into();
        self
    }
}

#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct NodeSpec {
    pub name: String,
    pub kind: NativeKind,
    pub params: Vec<ParamSpec>,
    /// The result type of a query; `None` for conditions and actions.
    pub returns: Option<ValueType>,
    pub doc: String,
}

impl NodeSpec {
    pub fn condition(name: &str, doc: &str) -> Self {
        Self {
            name: name.into(),
            kind: NativeKind::Condition,
            params: Vec::new(),
            returns: None,
            doc: doc.into(),
        }
    }
    pub fn action(name: &str, doc: &str) -> Self {
        Self {
            kind: NativeKind::Action,
            ..Self::condition(name, doc)
        }
    }
    pub fn query(name: &str, returns: ValueType, doc: &str) -> Self {
        Self {
            kind: NativeKind::Query,
            returns: Some(returns),
            ..Self::condition(name, doc)
        }
    }
    pub fn param(mut self, param: ParamSpec) -> Self {
        self.params.push(param);
        self
    }
    pub fn param_index(&self, name: &str) -> Option<usize> {
        self.params.iter().position(|p| p.name == name)
    }
}

/// Every native node of one agent build.
#[derive(Debug, Clone, Default, Serialize)]
pub struct Vocabulary {
    nodes: Vec<NodeSpec>,
    #[serde(skip)]
    by_name: HashMap<(NativeKind, String), NativeId>,
}

impl Vocabulary {
    pub fn new() -> Self {
        Self::default()
    }

    /// Registers a node and returns its id.
    ///
    /// # Panics
    /// When a node of the same kind and name is already registered: that is a bug in the
    /// agent's code, not in a data file.
    pub fn add(&mut self, spec: NodeSpec) -> NativeId {
        let id = NativeId(self.nodes.len() as u32);
        let key = (spec.kind, spec.name.clone());
        assert!(
            !self.by_name.contains_key(&key),
            "native {} `{}` registered twice",
            spec.kind.name(),
            spec.name
        );
        self.by_name.insert(key, id);
        self.nodes.push(spec);
        id
    }

    pub fn with(mut self, spec: NodeSpec) -> Self {
        self.add(spec);
        self
    }

    pub fn find(&self, kind: NativeKind, name: &str) -> Option<NativeId> {
        self.by_name.get(&(kind, name.to_string())).copied()
    }

    pub fn spec(&self, id: NativeId) -> &NodeSpec {
        &self.nodes[id.0 as usize]
    }

    pub fn nodes(&self) -> &[NodeSpec] {
        &self.nodes
    }

    pub fn names(&self, kind: NativeKind) -> impl Iterator<Item = &str> {
        self.nodes
            .iter()
            .filter(move |n| n.kind == kind)
            .map(|n| n.name.as_str())
    }

    /// The node reference as Markdown: the tree language, then every native node.
    pub fn to_markdown(&self) -> String {
        let mut out = String::from(
            "# Behavior vocabulary\n\n## Tree language\n\n| node | doc |\n| --- | --- |\n",
        );
        for (syntax, doc) in crate::tree::LANGUAGE {
            let _ = writeln!(out, "| `{syntax}` | {doc} |");
        }
        for (kind, title) in [
            (NativeKind::Condition, "Conditions"),
            (NativeKind::Action, "Actions"),
            (NativeKind::Query, "Queries"),
        ] {
            let _ = write!(out, "\n## {title}\n");
            for node in self.nodes.iter().filter(|n| n.kind == kind) {
                let returns = node
                    .returns
                    .map(|ty| format!(" → `{ty}`"))
                    .unwrap_or_default();
                let _ = write!(out, "\n### `{}`{returns}\n\n{}\n", node.name, node.doc);
                if node.params.is_empty() {
                    continue;
                }
                out.push_str("\n| parameter | type | unit | range | default | doc |\n| --- | --- | --- | --- | --- | --- |\n");
                for p in &node.params {
                    let range = match (&p.range, p.choices.is_empty()) {
                        (Some((lo, hi)), _) => format!("[{lo}, {hi}]"),
                        (None, false) => p.choices.join(", "),
                        (None, true) => String::new(),
                    };
                    let default = p
                        .default
                        .as_ref()
                        .map(|v| format!("`{v}`"))
                        .unwrap_or_else(|| "required".into());
                    let _ = writeln!(
                        out,
                        "| `{}` | {} | {} | {range} | {default} | {} |",
                        p.name, p.ty, p.unit, p.doc
                    );
                }
            }
        }
        out
    }

    pub fn to_json(&self) -> String {
        let language: Vec<_> = crate::tree::LANGUAGE
            .iter()
            .map(|(syntax, doc)| serde_json::json!({ "syntax": syntax, "doc": doc }))
            .collect();
        serde_json::json!({ "language": language, "nodes": self.nodes }).to_string()
    }
}
