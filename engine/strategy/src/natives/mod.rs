//! The native nodes behavior trees call: conditions, actions and world queries over one
//! agent's world state, writing the cycle's intent.
//!
//! Each node declares itself next to its handler (BehaviorTree.CPP's `providedPorts()` beside
//! `tick()`): a [`Native`] pairs the function that returns its [`NodeSpec`] (name, typed ports
//! with units, ranges and docs) with the function that runs it, and the handler reads its
//! arguments by port name through [`Ports`]. The groups below list their nodes; the
//! [`catalogue`] is the single source of `libero validate`, `libero nodes` and dispatch, so a
//! new node is one declaration, one handler and one entry in its group's list.

mod dribbling;
mod game;
mod host;
mod keeper;
mod motion;
mod passing;
mod queries;
mod set_plays;
mod shooting;
mod team_play;

pub use host::{AgentHost, DecisionNotes, PlayerMemory};

use libero_behavior::{
    Args, Host, NativeId, NativeKind, NodeSpec, Status, Value, Vec2, Vocabulary,
};

/// A node's handler, by kind.
#[derive(Clone, Copy)]
pub enum Handler {
    Condition(fn(&AgentHost, &Ports) -> bool),
    Action(fn(&mut AgentHost, &Ports) -> Status),
    Query(fn(&AgentHost, &Ports) -> Value),
}

impl Handler {
    fn kind(self) -> NativeKind {
        match self {
            Handler::Condition(_) => NativeKind::Condition,
            Handler::Action(_) => NativeKind::Action,
            Handler::Query(_) => NativeKind::Query,
        }
    }
}

/// One native node: its declaration and its handler.
#[derive(Clone, Copy)]
pub struct Native {
    pub declare: fn() -> NodeSpec,
    pub run: Handler,
}

impl Native {
    pub const fn condition(declare: fn() -> NodeSpec, run: fn(&AgentHost, &Ports) -> bool) -> Self {
        Self {
            declare,
            run: Handler::Condition(run),
        }
    }
    pub const fn action(
        declare: fn() -> NodeSpec,
        run: fn(&mut AgentHost, &Ports) -> Status,
    ) -> Self {
        Self {
            declare,
            run: Handler::Action(run),
        }
    }
    pub const fn query(declare: fn() -> NodeSpec, run: fn(&AgentHost, &Ports) -> Value) -> Self {
        Self {
            declare,
            run: Handler::Query(run),
        }
    }
}

/// Every native node the strategy layer provides, group by group.
pub fn catalogue() -> impl Iterator<Item = &'static Native> {
    [
        game::NODES,
        motion::NODES,
        dribbling::NODES,
        queries::NODES,
        keeper::NODES,
        shooting::NODES,
        passing::NODES,
        set_plays::NODES,
        team_play::NODES,
    ]
    .into_iter()
    .flatten()
}

/// The vocabulary trees are checked against: the catalogue's declarations.
pub fn vocabulary() -> Vocabulary {
    let mut vocabulary = Vocabulary::new();
    for native in catalogue() {
        let spec = (native.declare)();
        debug_assert_eq!(
            spec.kind,
            native.run.kind(),
            "node `{}` declared as another kind",
            spec.name
        );
        vocabulary.add(spec);
    }
    vocabulary
}

/// A call's arguments read by port name (values in declaration order, defaults filled in).
pub struct Ports<'a> {
    args: Args<'a>,
    spec: &'a NodeSpec,
}

impl<'a> Ports<'a> {
    pub fn new(args: Args<'a>, spec: &'a NodeSpec) -> Self {
        Self { args, spec }
    }

    fn value(&self, name: &str) -> Option<&'a Value> {
        let index = self.spec.param_index(name);
        debug_assert!(
            index.is_some(),
            "node `{}` has no port `{name}`",
            self.spec.name
        );
        self.args.get(index?)
    }

    pub fn float(&self, name: &str) -> f64 {
        self.value(name).map_or(0.0, Value::as_f64)
    }

    pub fn vec2(&self, name: &str) -> Vec2 {
        self.value(name).map_or_else(Vec2::default, Value::as_vec2)
    }

    pub fn str(&self, name: &str) -> &'a str {
        self.value(name).map_or("", Value::as_str)
    }

    pub fn bool(&self, name: &str) -> bool {
        self.value(name).is_some_and(Value::as_bool)
    }
}

/// Native ids resolved to handlers once, so a tick dispatches by index.
#[derive(Clone)]
pub struct Natives {
    by_id: Vec<(Handler, NodeSpec)>,
}

impl Natives {
    /// The dispatch table for a vocabulary built by [`vocabulary`] (same order).
    pub fn new() -> Self {
        Self {
            by_id: catalogue().map(|n| (n.run, (n.declare)())).collect(),
        }
    }

    fn get(&self, id: NativeId) -> Option<&(Handler, NodeSpec)> {
        self.by_id.get(id.0 as usize)
    }
}

impl Default for Natives {
    fn default() -> Self {
        Self::new()
    }
}

impl std::fmt::Debug for Natives {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Natives")
            .field("nodes", &self.by_id.len())
            .finish()
    }
}

impl Host for AgentHost<'_> {
    fn now(&self) -> f64 {
        self.world.time
    }

    fn query(&self, id: NativeId, args: Args) -> Value {
        match self.natives.get(id) {
            Some((Handler::Query(run), spec)) => run(self, &Ports::new(args, spec)),
            _ => Value::Bool(false),
        }
    }

    fn condition(&self, id: NativeId, args: Args) -> bool {
        match self.natives.get(id) {
            Some((Handler::Condition(run), spec)) => run(self, &Ports::new(args, spec)),
            _ => false,
        }
    }

    fn action(&mut self, id: NativeId, args: Args) -> Status {
        let natives = self.natives;
        match natives.get(id) {
            Some((Handler::Action(run), spec)) => run(self, &Ports::new(args, spec)),
            _ => Status::Failure,
        }
    }
}

#[cfg(test)]
mod tests;
