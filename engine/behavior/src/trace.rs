//! Per-tick records of which nodes ran and what they returned, kept in a ring buffer.

use crate::compile::CompiledTree;
use crate::value::Status;
use std::fmt::Write as _;
use std::sync::Arc;

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct TraceEntry {
    pub node: u32,
    pub status: Status,
}

/// Everything ticked in one cycle, in preorder (the active path and every node visited on it).
#[derive(Debug, Clone)]
pub struct TickRecord {
    pub tick: u64,
    pub time: f64,
    /// The library generation the tick ran on.
    pub generation: u64,
    pub status: Status,
    tree: Option<Arc<CompiledTree>>,
    entries: Vec<TraceEntry>,
}

impl TickRecord {
    pub fn entries(&self) -> &[TraceEntry] {
        &self.entries
    }

    pub fn label(&self, node: u32) -> &str {
        self.tree.as_ref().map_or("?", |tree| tree.label(node))
    }

    pub fn tree_name(&self) -> &str {
        self.tree.as_ref().map_or("", |tree| &tree.name)
    }

    /// Labels and statuses of every ticked node, in order.
    pub fn visited(&self) -> impl Iterator<Item = (&str, Status)> {
        self.entries.iter().map(|e| (self.label(e.node), e.status))
    }

    /// Native actions and conditions ticked this cycle, e.g. `("Action WalkTo", Running)`.
    pub fn leaves(&self) -> Vec<(&str, Status)> {
        self.visited()
            .filter(|(label, _)| label.starts_with("Action ") || label.starts_with("Condition "))
            .collect()
    }

    /// The status of the first ticked node with this label.
    pub fn status_of(&self, label: &str) -> Option<Status> {
        self.visited().find(|(l, _)| *l == label).map(|(_, s)| s)
    }

    /// An indented, one-node-per-line rendering for the evaluation log.
    pub fn render(&self) -> String {
        let mut out = format!(
            "tick {} t={:.3}s gen {} {} → {}\n",
            self.tick,
            self.time,
            self.generation,
            self.tree_name(),
            self.status
        );
        if let Some(tree) = &self.tree {
            for entry in &self.entries {
                let depth = tree.nodes[entry.node as usize].depth as usize;
                let _ = writeln!(
                    out,
                    "{}{} → {}",
                    "  ".repeat(depth + 1),
                    tree.label(entry.node),
                    entry.status
                );
            }
        }
        out
    }
}

/// A fixed-size ring of tick records; recording reuses buffers so a tick does not allocate.
#[derive(Debug)]
pub struct Trace {
    records: Vec<TickRecord>,
    capacity: usize,
    next: usize,
}

impl Trace {
    pub fn new(capacity: usize) -> Self {
        Self {
            records: Vec::with_capacity(capacity),
            capacity,
            next: 0,
        }
    }

    pub fn capacity(&self) -> usize {
        self.capacity
    }

    pub fn len(&self) -> usize {
        self.records.len()
    }

    pub fn is_empty(&self) -> bool {
        self.records.is_empty()
    }

    /// Oldest to newest.
    pub fn iter(&self) -> impl Iterator<Item = &TickRecord> {
        let (newer, older) = self.records.split_at(self.next.min(self.records.len()));
        older.iter().chain(newer.iter())
    }

    pub fn last(&self) -> Option<&TickRecord> {
        if self.records.is_empty() {
            return None;
        }
        let index = (self.next + self.records.len() - 1) % self.records.len();
        self.records.get(index)
    }

    /// Starts a record for a new tick and returns its entry buffer.
    pub(crate) fn begin(
        &mut self,
        tick: u64,
        time: f64,
        generation: u64,
        tree: &Arc<CompiledTree>,
    ) -> Option<&mut TickRecord> {
        if self.capacity == 0 {
            return None;
        }
        if self.records.len() < self.capacity {
            self.records.push(TickRecord {
                tick,
                time,
                generation,
                status: Status::Running,
                tree: None,
                entries: Vec::with_capacity(64),
            });
            self.next = self.records.len() % self.capacity;
            let last = self.records.len() - 1;
            let record = &mut self.records[last];
            record.tree = Some(tree.clone());
            return Some(record);
        }
        let record = &mut self.records[self.next];
        self.next = (self.next + 1) % self.capacity;
        record.tick = tick;
        record.time = time;
        record.generation = generation;
        record.entries.clear();
        if !record.tree.as_ref().is_some_and(|t| Arc::ptr_eq(t, tree)) {
            record.tree = Some(tree.clone());
        }
        Some(record)
    }
}

impl TickRecord {
    pub(crate) fn enter(&mut self, node: u32) -> usize {
        self.entries.push(TraceEntry {
            node,
            status: Status::Running,
        });
        self.entries.len() - 1
    }

    pub(crate) fn exit(&mut self, slot: usize, status: Status) {
        self.entries[slot].status = status;
    }
}
