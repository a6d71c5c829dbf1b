//! Behavior trees in RON: language, validation, interpretation and hot reload. Knows nothing of
//! soccer.
//!
//! A domain describes its native nodes in a [`Vocabulary`], implements [`Host`], reads its own
//! data files through [`DataFiles`], loads a [`Library`] (or starts a [`LiveLibrary`] for hot
//! reload) and gives each player a [`TreeRunner`]. [`validate_paths`] is what `libero validate`
//! runs; [`Vocabulary::to_markdown`] and [`Vocabulary::to_json`] are what `libero nodes` prints.

mod blackboard;
mod check;
mod compile;
mod data_files;
pub mod decode;
pub mod diagnostics;
pub mod files;
mod host;
mod library;
mod live;
mod runtime;
pub mod syntax;
pub mod testing;
mod trace;
pub mod tree;
mod value;
mod vocabulary;

pub use compile::CompiledTree;
pub use data_files::{DataCollector, DataFiles, NoDataFiles, TreeIndex};
pub use diagnostics::{did_you_mean, Diagnostic, Report, Severity, SourceFile};
pub use library::{validate_paths, Library};
pub use live::{LiveLibrary, ReloadEvent, ReloadOptions};
pub use runtime::{Args, Blackboard, Host, RunnerError, TreeRunner};
pub use trace::{TickRecord, Trace, TraceEntry};
pub use value::{Status, Value, ValueType, Vec2};
pub use vocabulary::{NativeId, NativeKind, NodeSpec, ParamSpec, Vocabulary};
