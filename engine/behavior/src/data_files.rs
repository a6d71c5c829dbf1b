//! Data files beside the trees: the tree engine knows only `Behaviors(..)` files; a domain (the
//! soccer strategy layer) registers the other file kinds it reads, checks them against the trees
//! and keeps what it read inside the [`crate::Library`], so they load, validate and hot-reload
//! with the trees as one unit.

use crate::check::Definitions;
use crate::decode::Decoder;
use crate::diagnostics::{Diagnostic, Report, SourceFile};
use crate::syntax::{Node, Span};
use crate::tree::{NodeDef, NodeDefKind};
use std::any::Any;
use std::collections::{BTreeSet, HashMap};
use std::path::Path;
use std::sync::Arc;

/// The reader of a domain's data files.
pub trait DataFiles: Send + Sync {
    /// The top-level names (`Formation`, `Team`, ...) of the files this reader takes.
    fn kinds(&self) -> &[&'static str];
    /// A fresh collection for one load of the whole directory set.
    fn collector(&self) -> Box<dyn DataCollector>;
}

/// Collects the data files of one load.
pub trait DataCollector {
    /// Reads one file whose top-level name `kind` (at `head`) is one of [`DataFiles::kinds`];
    /// errors go to the decoder with their location.
    fn read(&mut self, kind: &str, head: Span, node: &Node, decoder: &mut Decoder);
    /// Cross-checks what was read against the trees and returns the data the library keeps.
    fn finish(
        self: Box<Self>,
        trees: &TreeIndex,
        report: &mut Report,
    ) -> Arc<dyn Any + Send + Sync>;
}

/// No data files: a library of trees alone.
#[derive(Debug, Clone, Copy, Default)]
pub struct NoDataFiles;

impl DataFiles for NoDataFiles {
    fn kinds(&self) -> &[&'static str] {
        &[]
    }
    fn collector(&self) -> Box<dyn DataCollector> {
        Box::new(NoDataFiles)
    }
}

impl DataCollector for NoDataFiles {
    fn read(&mut self, _: &str, _: Span, _: &Node, _: &mut Decoder) {}
    fn finish(self: Box<Self>, _: &TreeIndex, _: &mut Report) -> Arc<dyn Any + Send + Sync> {
        Arc::new(())
    }
}

/// What a data collector may ask about the trees of the same load.
pub struct TreeIndex<'a> {
    pub(crate) defs: &'a Definitions<'a>,
}

impl TreeIndex<'_> {
    /// `Some(true)` when tree `name` exists and every parameter has a default (it can be a
    /// root), `Some(false)` when it has required parameters, `None` when there is no such tree.
    pub fn can_be_root(&self, name: &str) -> Option<bool> {
        let (_, tree) = self.defs.trees.get(name)?;
        Some(tree.params.iter().all(|p| p.default.is_some()))
    }

    pub fn names(&self) -> impl Iterator<Item = &str> {
        self.defs.trees.keys().copied()
    }

    /// Warns about every behavior file none of whose trees the `roots` reach: probably
    /// forgotten or misnamed.
    pub fn warn_unreachable_files(&self, roots: &[&str], report: &mut Report) {
        let reachable = self.reachable(roots);
        let mut files_seen: HashMap<&Path, (bool, &Arc<SourceFile>, Span)> = HashMap::new();
        for (name, (file, tree)) in &self.defs.trees {
            let entry =
                files_seen
                    .entry(file.path.as_path())
                    .or_insert((false, file, tree.name_span));
            entry.0 |= reachable.contains(name);
        }
        for (used, file, span) in files_seen.values() {
            if !used {
                let message = format!(
                    "no tree in {} is used by the team's root trees",
                    file.path.display()
                );
                report.push(Diagnostic::warning("unused-file", message).at(file, *span));
            }
        }
    }

    /// The trees reachable from `roots` through subtree calls.
    pub fn reachable(&self, roots: &[&str]) -> BTreeSet<&str> {
        fn calls<'n>(node: &'n NodeDef, out: &mut Vec<&'n str>) {
            match &node.kind {
                NodeDefKind::SubTree(call) => out.push(&call.name),
                NodeDefKind::Composite(_, children) | NodeDefKind::Parallel { children, .. } => {
                    children.iter().for_each(|c| calls(c, out))
                }
                NodeDefKind::Decorator(_, child)
                | NodeDefKind::Counted(_, _, child)
                | NodeDefKind::Timed(_, _, child) => calls(child, out),
                NodeDefKind::Utility { choices, .. } => {
                    choices.iter().for_each(|c| calls(&c.child, out))
                }
                _ => {}
            }
        }
        let mut seen = BTreeSet::new();
        let mut stack: Vec<&str> = roots.to_vec();
        while let Some(name) = stack.pop() {
            let Some((key, (_, tree))) = self.defs.trees.get_key_value(name) else {
                continue;
            };
            if seen.insert(*key) {
                let mut found = Vec::new();
                calls(&tree.root, &mut found);
                stack.extend(found);
            }
        }
        seen
    }
}
