//! Behavior trees and strategy files in RON: language, validation, interpretation and hot reload.
//!
//! The agent describes its native nodes in a [`Vocabulary`], implements [`Host`], loads a
//! [`Library`] (or starts a [`LiveLibrary`] for hot reload) and gives each player a
//! [`TreeRunner`]. `libero validate` calls [`validate_paths`]; `libero nodes` prints
//! [`Vocabulary::to_markdown`] or [`Vocabulary::to_json`].

mod blackboard;
mod check;
mod compile;
mod decode;
pub mod diagnostics;
mod host;
mod library;
mod live;
mod runtime;
pub mod strategy;
pub mod syntax;
pub mod testing;
mod trace;
pub mod tree;
mod value;
mod vocabulary;

pub use compile::CompiledTree;
pub use diagnostics::{Diagnostic, Report, Severity};
pub use library::{validate_paths, Library};
pub use live::{LiveLibrary, ReloadEvent, ReloadOptions};
pub use runtime::{Args, Blackboard, Host, RunnerError, TreeRunner};
pub use strategy::{Field, Formation, Situation, Strategy};
pub use trace::{TickRecord, Trace, TraceEntry};
pub use value::{Status, Value, ValueType, Vec2};
pub use vocabulary::{NativeId, NativeKind, NodeSpec, ParamSpec, Vocabulary};
