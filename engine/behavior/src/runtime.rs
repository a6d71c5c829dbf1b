//! Running a compiled tree for one agent: node state, blackboard, the host interface and trace.

pub use crate::blackboard::Blackboard;
use crate::compile::{CExpr, CNode, CompiledTree, Op};
pub use crate::host::{Args, Host};
use crate::library::Library;
use crate::trace::{TickRecord, Trace};
use crate::tree::{CompareOp, CompositeKind, CountKind, DecoratorKind, TimedKind};
use crate::value::{Status, Value};
use std::collections::HashMap;
use std::sync::Arc;

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Phase {
    Idle,
    Running,
    Success,
    Failure,
}

impl From<Status> for Phase {
    fn from(status: Status) -> Phase {
        match status {
            Status::Running => Phase::Running,
            Status::Success => Phase::Success,
            Status::Failure => Phase::Failure,
        }
    }
}

const NO_CHOICE: u32 = u32::MAX;

#[derive(Debug, Clone, Copy)]
struct NodeState {
    phase: Phase,
    cursor: u32,
    count: u32,
    started: f64,
    last_success: f64,
    choice: u32,
    /// The score this node last had as a choice of a `Utility` parent (NaN otherwise), for
    /// views of the running tree.
    utility_score: f64,
}

impl NodeState {
    const FRESH: NodeState = NodeState {
        phase: Phase::Idle,
        cursor: 0,
        count: 0,
        started: f64::NAN,
        last_success: f64::NEG_INFINITY,
        choice: NO_CHOICE,
        utility_score: f64::NAN,
    };
}

/// Why a runner could not be created or could not switch to a new library.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum RunnerError {
    #[error("no tree named `{0}` without required parameters in the library")]
    UnknownTree(String),
}

/// One agent's instance of a tree: node state, blackboard and trace.
pub struct TreeRunner {
    root: String,
    library: Arc<Library>,
    tree: Arc<CompiledTree>,
    states: Vec<NodeState>,
    blackboard: Blackboard,
    trace: Trace,
    scratch: Vec<Value>,
    ticks: u64,
    missing_root_reported: bool,
}

impl TreeRunner {
    pub const DEFAULT_TRACE_CAPACITY: usize = 256;

    pub fn new(library: &Arc<Library>, root: &str) -> Result<Self, RunnerError> {
        let tree = library
            .tree(root)
            .ok_or_else(|| RunnerError::UnknownTree(root.to_string()))?
            .clone();
        Ok(Self {
            root: root.to_string(),
            library: library.clone(),
            states: vec![NodeState::FRESH; tree.nodes.len()],
            tree,
            blackboard: Blackboard::new(library),
            trace: Trace::new(Self::DEFAULT_TRACE_CAPACITY),
            scratch: Vec::with_capacity(32),
            ticks: 0,
            missing_root_reported: false,
        })
    }

    /// Keeps the last `capacity` ticks (0 turns tracing off).
    pub fn with_trace_capacity(mut self, capacity: usize) -> Self {
        self.trace = Trace::new(capacity);
        self
    }

    pub fn root(&self) -> &str {
        &self.root
    }
    pub fn trace(&self) -> &Trace {
        &self.trace
    }
    pub fn blackboard(&self) -> &Blackboard {
        &self.blackboard
    }
    pub fn blackboard_mut(&mut self) -> &mut Blackboard {
        &mut self.blackboard
    }
    pub fn library(&self) -> &Arc<Library> {
        &self.library
    }
    /// The compiled tree being run (node labels and shape, for views).
    pub fn tree(&self) -> &Arc<CompiledTree> {
        &self.tree
    }
    /// The score `node` had in its `Utility` parent's last choice (hysteresis included), if it
    /// is such a choice and was scored.
    pub fn utility_score(&self, node: u32) -> Option<f64> {
        self.states
            .get(node as usize)
            .map(|s| s.utility_score)
            .filter(|s| !s.is_nan())
    }
    pub fn generation(&self) -> u64 {
        self.library.generation()
    }

    /// Ticks the tree once, first switching to `library` if it is a newer version. Call at the
    /// start of each cycle with the newest library; switching is one pointer comparison when
    /// nothing changed.
    pub fn tick<H: Host>(&mut self, host: &mut H, library: &Arc<Library>) -> Status {
        if !Arc::ptr_eq(&self.library, library) {
            self.adopt(host, library);
        }
        let Self {
            tree,
            states,
            blackboard,
            trace,
            scratch,
            ticks,
            library,
            ..
        } = self;
        *ticks += 1;
        let now = host.now();
        let record = trace.begin(*ticks, now, library.generation(), tree);
        let mut ticker = Ticker {
            nodes: &tree.nodes,
            states,
            blackboard: &mut blackboard.values,
            scratch,
            record,
            host,
            now,
        };
        let status = ticker.tick(0);
        if let Some(record) = ticker.record {
            record.status = status;
        }
        status
    }

    /// Switches to a new library version: node states of unchanged subtrees and the blackboard
    /// carry over; running actions that no longer exist are halted.
    fn adopt<H: Host>(&mut self, host: &mut H, library: &Arc<Library>) {
        let Some(new_tree) = library.tree(&self.root).cloned() else {
            if !self.missing_root_reported {
                log::error!(
                    "tree `{}` is missing from library generation {}; keeping the running version",
                    self.root,
                    library.generation()
                );
                self.missing_root_reported = true;
            }
            return;
        };
        self.missing_root_reported = false;
        let old = &self.tree;
        let mut by_hash: HashMap<u64, Vec<u32>> = HashMap::new();
        for (index, node) in old.nodes.iter().enumerate() {
            by_hash.entry(node.hash).or_default().push(index as u32);
        }
        let mut old_used = vec![false; old.nodes.len()];
        let mut states = vec![NodeState::FRESH; new_tree.nodes.len()];
        let mut carried = vec![false; new_tree.nodes.len()];
        let mut index = 0usize;
        while index < new_tree.nodes.len() {
            let node = &new_tree.nodes[index];
            let size = node.end as usize - index;
            let candidate = by_hash.get(&node.hash).and_then(|candidates| {
                candidates.iter().copied().find(|&o| {
                    !old_used[o as usize] && old.nodes[o as usize].end as usize - o as usize == size
                })
            });
            match candidate {
                Some(o) => {
                    let o = o as usize;
                    states[index..index + size].copy_from_slice(&self.states[o..o + size]);
                    old_used[o..o + size].iter_mut().for_each(|u| *u = true);
                    carried[index..index + size]
                        .iter_mut()
                        .for_each(|c| *c = true);
                    index += size;
                }
                None => index += 1,
            }
        }
        // Running actions left behind are halted before the old blackboard goes away.
        let mut ticker = Ticker {
            nodes: &old.nodes,
            states: &mut self.states,
            blackboard: &mut self.blackboard.values,
            scratch: &mut self.scratch,
            record: None,
            host,
            now: f64::NAN,
        };
        for (o, used) in old_used.iter().enumerate() {
            if !used
                && ticker.states[o].phase == Phase::Running
                && matches!(ticker.nodes[o].op, Op::Action(..))
            {
                ticker.halt_action(o as u32);
            }
        }
        // New ancestors of carried running nodes count as running so that abandoning the branch
        // later halts what runs inside it.
        for i in 0..new_tree.nodes.len() {
            if carried[i] && states[i].phase == Phase::Running {
                let mut parent = new_tree.nodes[i].parent;
                while let Some(p) = parent {
                    if carried[p as usize] || states[p as usize].phase == Phase::Running {
                        break;
                    }
                    states[p as usize].phase = Phase::Running;
                    parent = new_tree.nodes[p as usize].parent;
                }
            }
        }
        self.blackboard = self.blackboard.migrate(library);
        self.states = states;
        self.tree = new_tree;
        self.library = library.clone();
    }

    /// Halts everything running (e.g. when the agent stops or switches roots).
    pub fn halt<H: Host>(&mut self, host: &mut H) {
        let mut ticker = Ticker {
            nodes: &self.tree.nodes,
            states: &mut self.states,
            blackboard: &mut self.blackboard.values,
            scratch: &mut self.scratch,
            record: None,
            host,
            now: f64::NAN,
        };
        if ticker.states[0].phase == Phase::Running {
            ticker.halt(0);
        }
    }
}

struct Ticker<'a, H: Host> {
    nodes: &'a [CNode],
    states: &'a mut [NodeState],
    blackboard: &'a mut [Value],
    scratch: &'a mut Vec<Value>,
    record: Option<&'a mut TickRecord>,
    host: &'a mut H,
    now: f64,
}

impl<H: Host> Ticker<'_, H> {
    fn eval(&mut self, expr: &CExpr) -> Value {
        match expr {
            CExpr::Const(value) => value.clone(),
            CExpr::Blackboard(slot, _) => self.blackboard[slot.0 as usize].clone(),
            CExpr::Query(id, args) => {
                let base = self.push_args(args);
                let value = self.host.query(*id, Args(&self.scratch[base..]));
                self.scratch.truncate(base);
                value
            }
        }
    }

    fn push_args(&mut self, args: &[CExpr]) -> usize {
        let base = self.scratch.len();
        for arg in args {
            let value = self.eval(arg);
            self.scratch.push(value);
        }
        base
    }

    fn tick(&mut self, index: u32) -> Status {
        let slot = self.record.as_mut().map(|r| r.enter(index));
        let nodes = self.nodes;
        let node = &nodes[index as usize];
        let status = match &node.op {
            Op::Composite(kind) => self.composite(index, node, *kind),
            Op::Parallel { success, failure } => self.parallel(index, node, *success, *failure),
            Op::Decorator(kind) => match (kind, self.tick(node.children[0])) {
                (_, Status::Running) => Status::Running,
                (DecoratorKind::Invert, Status::Success) => Status::Failure,
                (DecoratorKind::Invert, _) => Status::Success,
                (DecoratorKind::ForceSuccess, _) => Status::Success,
                (DecoratorKind::ForceFailure, _) => Status::Failure,
            },
            Op::Counted(kind, n) => self.counted(index, node, *kind, *n),
            Op::Timed(TimedKind::Timeout, seconds) => self.timeout(index, node, *seconds),
            Op::Timed(TimedKind::Cooldown, seconds) => {
                let state = self.states[index as usize];
                if self.now < state.last_success + seconds {
                    Status::Failure
                } else {
                    let status = self.tick(node.children[0]);
                    if status == Status::Success {
                        self.states[index as usize].last_success = self.now;
                    }
                    status
                }
            }
            Op::Utility {
                hysteresis,
                choices,
            } => {
                let state = self.states[index as usize];
                let current = if state.phase == Phase::Running {
                    state.choice
                } else {
                    NO_CHOICE
                };
                let mut best = (NO_CHOICE, f64::NEG_INFINITY);
                for (k, choice) in choices.iter().enumerate() {
                    let (mut total, mut weights) = (0.0, 0.0);
                    for consideration in &choice.considerations {
                        let input = self.eval(&consideration.input).as_f64();
                        total += consideration.weight * consideration.curve.score(input);
                        weights += consideration.weight;
                    }
                    let mut score =
                        choice.weight * if weights > 0.0 { total / weights } else { 1.0 };
                    if k as u32 == current {
                        score += hysteresis;
                    }
                    self.states[node.children[k] as usize].utility_score = score;
                    if score > best.1 {
                        best = (k as u32, score);
                    }
                }
                let child = node.children[best.0 as usize];
                self.halt_others(node, Some(child));
                let status = self.tick(child);
                self.states[index as usize].choice = if status == Status::Running {
                    best.0
                } else {
                    NO_CHOICE
                };
                status
            }
            Op::Condition(id, args) => {
                let base = self.push_args(args);
                let ok = self.host.condition(*id, Args(&self.scratch[base..]));
                self.scratch.truncate(base);
                Status::from_bool(ok)
            }
            Op::Action(id, args) => {
                let base = self.push_args(args);
                let status = self.host.action(*id, Args(&self.scratch[base..]));
                self.scratch.truncate(base);
                status
            }
            Op::SubTree(_) => self.tick(node.children[0]),
            Op::Compare { left, op, right } => {
                let (l, r) = (self.eval(left), self.eval(right));
                Status::from_bool(compare(&l, *op, &r))
            }
            Op::Set { slot, value, .. } => {
                let value = self.eval(value);
                let target = &mut self.blackboard[slot.0 as usize];
                *target = value.coerce(target.value_type());
                Status::Success
            }
            Op::Wait(seconds) => {
                let state = &mut self.states[index as usize];
                if state.phase != Phase::Running || state.started.is_nan() {
                    state.started = self.now;
                }
                if self.now - state.started >= *seconds {
                    Status::Success
                } else {
                    Status::Running
                }
            }
            Op::Succeed => Status::Success,
            Op::Fail => Status::Failure,
        };
        self.states[index as usize].phase = status.into();
        if let (Some(record), Some(slot)) = (self.record.as_mut(), slot) {
            record.exit(slot, status);
        }
        status
    }

    fn composite(&mut self, index: u32, node: &CNode, kind: CompositeKind) -> Status {
        let state = self.states[index as usize];
        let reactive = matches!(
            kind,
            CompositeKind::ReactiveSequence | CompositeKind::ReactiveFallback
        );
        let sequence = matches!(
            kind,
            CompositeKind::Sequence | CompositeKind::ReactiveSequence
        );
        let start = if reactive || state.phase != Phase::Running {
            0
        } else {
            state.cursor as usize
        };
        let (done, other) = if sequence {
            (Status::Failure, Status::Success)
        } else {
            (Status::Success, Status::Failure)
        };
        let mut result = (other, None);
        for k in start..node.children.len() {
            let child = node.children[k];
            match self.tick(child) {
                Status::Running => {
                    self.states[index as usize].cursor = k as u32;
                    result = (Status::Running, Some(child));
                    break;
                }
                status if status == done => {
                    result = (done, None);
                    break;
                }
                _ => {}
            }
        }
        self.halt_others(node, result.1);
        if result.0 != Status::Running {
            self.states[index as usize].cursor = 0;
        }
        result.0
    }

    fn parallel(&mut self, index: u32, node: &CNode, success: u32, failure: u32) -> Status {
        if self.states[index as usize].phase != Phase::Running {
            for &child in node.children.iter() {
                self.states[child as usize].phase = Phase::Idle;
            }
        }
        let (mut succeeded, mut failed) = (0u32, 0u32);
        for &child in node.children.iter() {
            let status = match self.states[child as usize].phase {
                Phase::Success => Status::Success,
                Phase::Failure => Status::Failure,
                Phase::Idle | Phase::Running => self.tick(child),
            };
            match status {
                Status::Success => succeeded += 1,
                Status::Failure => failed += 1,
                Status::Running => {}
            }
        }
        let children = node.children.len() as u32;
        let status = if succeeded >= success {
            Status::Success
        } else if failed >= failure || children - failed < success {
            Status::Failure
        } else {
            return Status::Running;
        };
        self.halt_others(node, None);
        status
    }

    fn counted(&mut self, index: u32, node: &CNode, kind: CountKind, n: u32) -> Status {
        if self.states[index as usize].phase != Phase::Running {
            self.states[index as usize].count = 0;
        }
        // One attempt per tick keeps the cost of a tick bounded whatever n is.
        let (repeat_on, finish_on) = match kind {
            CountKind::Repeat => (Status::Success, Status::Failure),
            CountKind::RetryUntilSuccess => (Status::Failure, Status::Success),
        };
        match self.tick(node.children[0]) {
            Status::Running => Status::Running,
            status if status == finish_on => status,
            _ => {
                let state = &mut self.states[index as usize];
                state.count += 1;
                if state.count >= n {
                    repeat_on
                } else {
                    Status::Running
                }
            }
        }
    }

    fn timeout(&mut self, index: u32, node: &CNode, seconds: f64) -> Status {
        let state = &mut self.states[index as usize];
        if state.phase != Phase::Running || state.started.is_nan() {
            state.started = self.now;
        }
        if self.now - state.started >= seconds {
            self.halt_others(node, None);
            return Status::Failure;
        }
        self.tick(node.children[0])
    }

    /// Halts running children other than `active`.
    fn halt_others(&mut self, node: &CNode, active: Option<u32>) {
        for &child in node.children.iter() {
            if Some(child) != active && self.states[child as usize].phase == Phase::Running {
                self.halt(child);
            }
        }
    }

    fn halt(&mut self, index: u32) {
        let nodes = self.nodes;
        let node = &nodes[index as usize];
        self.halt_others(node, None);
        if matches!(node.op, Op::Action(..)) && self.states[index as usize].phase == Phase::Running
        {
            self.halt_action(index);
        }
        let state = &mut self.states[index as usize];
        *state = NodeState {
            last_success: state.last_success,
            ..NodeState::FRESH
        };
    }

    fn halt_action(&mut self, index: u32) {
        if let Op::Action(id, args) = &self.nodes[index as usize].op {
            let base = self.push_args(args);
            self.host.halt(*id, Args(&self.scratch[base..]));
            self.scratch.truncate(base);
        }
        self.states[index as usize].phase = Phase::Idle;
    }
}

fn compare(left: &Value, op: CompareOp, right: &Value) -> bool {
    match (left, right) {
        (Value::Vec2(a), Value::Vec2(b)) => (a == b) == (op == CompareOp::Eq),
        (Value::String(a), Value::String(b)) => (a == b) == (op == CompareOp::Eq),
        _ => {
            let (l, r) = (left.as_f64(), right.as_f64());
            match op {
                CompareOp::Lt => l < r,
                CompareOp::Le => l <= r,
                CompareOp::Gt => l > r,
                CompareOp::Ge => l >= r,
                CompareOp::Eq => l == r,
                CompareOp::Ne => l != r,
            }
        }
    }
}
