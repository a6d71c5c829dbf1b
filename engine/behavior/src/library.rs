//! Loading a set of directories into a validated [`Library`]: every tree compiled and every
//! data file handed to the domain's reader, with cross-file checks (subtrees, unused files).

use crate::check::{check_trees, collect_definitions, LoadedBehaviors};
use crate::compile::{compile_tree, BlackboardLayout, CompiledTree};
use crate::data_files::{DataFiles, TreeIndex};
use crate::decode::Decoder;
use crate::diagnostics::{did_you_mean, Diagnostic, Report, SourceFile};
use crate::files::{read_text, ron_files, ReadError};
use crate::syntax;
use crate::tree::parse_behavior_file;
use crate::vocabulary::Vocabulary;
use std::any::Any;
use std::collections::hash_map::DefaultHasher;
use std::collections::HashMap;
use std::hash::{Hash, Hasher};
use std::path::PathBuf;
use std::sync::Arc;

/// All trees and strategy of a directory set, validated and compiled; shared by every agent.
#[derive(Debug)]
pub struct Library {
    generation: u64,
    trees: HashMap<String, Arc<CompiledTree>>,
    layout: BlackboardLayout,
    /// What the domain's data-file reader kept (see [`Library::data`]).
    data: Arc<dyn Any + Send + Sync>,
    warnings: Report,
    files: Vec<PathBuf>,
}

impl Library {
    /// Loads and validates `.ron` files under `paths` (directories are searched recursively).
    /// Fails with every error found; warnings of a successful load are in [`Library::warnings`].
    pub fn load(
        paths: &[PathBuf],
        vocabulary: &Vocabulary,
        data_files: &dyn DataFiles,
    ) -> Result<Library, Report> {
        let (sources, report) = read_sources(paths);
        finish(&sources, vocabulary, data_files, report)
    }

    /// Builds a library from in-memory files `(path, text)`, as if read from disk.
    pub fn from_texts(
        files: &[(&str, &str)],
        vocabulary: &Vocabulary,
        data_files: &dyn DataFiles,
    ) -> Result<Library, Report> {
        let sources: Vec<Arc<SourceFile>> = files
            .iter()
            .map(|(path, text)| Arc::new(SourceFile::new(PathBuf::from(path), text.to_string())))
            .collect();
        finish(&sources, vocabulary, data_files, Report::default())
    }

    /// A number that increases with each reload published by a [`crate::LiveLibrary`].
    pub fn generation(&self) -> u64 {
        self.generation
    }

    pub(crate) fn set_generation(&mut self, generation: u64) {
        self.generation = generation;
    }

    /// A compiled tree without required parameters, by name.
    pub fn tree(&self, name: &str) -> Option<&Arc<CompiledTree>> {
        self.trees.get(name)
    }

    pub fn tree_names(&self) -> impl Iterator<Item = &str> {
        self.trees.keys().map(String::as_str)
    }

    /// The domain data read from the non-tree files, when it is a `T`.
    pub fn data<T: Any>(&self) -> Option<&T> {
        self.data.downcast_ref()
    }

    pub fn warnings(&self) -> &Report {
        &self.warnings
    }

    pub fn files(&self) -> &[PathBuf] {
        &self.files
    }

    pub(crate) fn blackboard_layout(&self) -> &BlackboardLayout {
        &self.layout
    }
}

/// Validates files and directories without keeping the result: what `libero validate` runs.
pub fn validate_paths(
    paths: &[PathBuf],
    vocabulary: &Vocabulary,
    data_files: &dyn DataFiles,
) -> Report {
    match Library::load(paths, vocabulary, data_files) {
        Ok(library) => library.warnings,
        Err(report) => report,
    }
}

/// Every `.ron` file under `paths`, read with bounded cost (see [`crate::files`]). Files that
/// cannot be read are errors in the report; one removed since listing is simply gone.
pub(crate) fn read_sources(paths: &[PathBuf]) -> (Vec<Arc<SourceFile>>, Report) {
    let mut report = Report::default();
    let mut sources = Vec::new();
    for path in ron_files(paths, &mut report) {
        match read_text(&path) {
            Ok(text) => sources.push(Arc::new(SourceFile::new(path, text))),
            // An editor's save by rename: the next event brings the new file.
            Err(ReadError::Missing) => {}
            Err(error) => report.push(Diagnostic::error("io", error.describe(&path))),
        }
    }
    (sources, report)
}

/// Identifies a set of file contents and of problems reading files, to skip reloading (and
/// reporting again) when nothing really changed: a file refused unread is in no source, so
/// without its problem a new unreadable file would look like no change at all.
pub(crate) fn fingerprint(sources: &[Arc<SourceFile>], read_problems: &Report) -> u64 {
    let mut hasher = DefaultHasher::new();
    for source in sources {
        source.path.hash(&mut hasher);
        source.text.hash(&mut hasher);
    }
    for problem in &read_problems.diagnostics {
        problem.message.hash(&mut hasher);
    }
    hasher.finish()
}

pub(crate) fn build(
    sources: &[Arc<SourceFile>],
    vocabulary: &Vocabulary,
    data_files: &dyn DataFiles,
    report: &mut Report,
) -> Option<Library> {
    let mut behaviors = Vec::new();
    let mut collector = data_files.collector();
    let kinds = data_files.kinds();
    for source in sources {
        let node = match syntax::parse(&source.text) {
            Ok(node) => node,
            Err(error) => {
                report.push(
                    Diagnostic::error("syntax", error.message)
                        .at(source, error.span)
                        .maybe_hint(error.hint),
                );
                continue;
            }
        };
        let Some((head, head_span)) = Decoder::head(&node) else {
            let message = format!(
                "expected a file such as `Behaviors(..)`, found {}",
                node.describe()
            );
            report.push(Diagnostic::error("unknown-file-kind", message).at(source, node.span));
            continue;
        };
        let mut decoder = Decoder::new(source.clone(), report);
        if head == "Behaviors" {
            behaviors.push(LoadedBehaviors {
                source: source.clone(),
                file: parse_behavior_file(&mut decoder, &node),
            });
        } else if kinds.contains(&head) {
            collector.read(head, head_span, &node, &mut decoder);
        } else {
            let all: Vec<&str> = std::iter::once("Behaviors")
                .chain(kinds.iter().copied())
                .collect();
            let hint = did_you_mean(head, all.iter().copied())
                .or_else(|| Some(format!("files are one of: {}", all.join(", "))));
            decoder
                .error(
                    "unknown-file-kind",
                    head_span,
                    format!("unknown file kind `{head}`"),
                )
                .hint = hint;
        }
    }
    let defs = collect_definitions(&behaviors, report);
    check_trees(&behaviors, &defs, vocabulary, report);
    let data = collector.finish(&TreeIndex { defs: &defs }, report);
    if report.has_errors() {
        return None;
    }
    let layout = BlackboardLayout::from_definitions(&defs);
    let mut trees = HashMap::new();
    for (name, (_, tree)) in &defs.trees {
        if tree.params.iter().all(|p| p.default.is_some()) {
            let compiled = compile_tree(name, &defs, &layout, vocabulary)?;
            trees.insert(name.to_string(), Arc::new(compiled));
        }
    }
    Some(Library {
        generation: 0,
        trees,
        layout,
        data,
        warnings: Report::default(),
        files: sources.iter().map(|s| s.path.clone()).collect(),
    })
}

/// Build from read sources; every error in `report` (reading or building) fails the load, and a
/// successful library keeps the warnings.
fn finish(
    sources: &[Arc<SourceFile>],
    vocabulary: &Vocabulary,
    data_files: &dyn DataFiles,
    mut report: Report,
) -> Result<Library, Report> {
    let library = build(sources, vocabulary, data_files, &mut report);
    report.sort();
    match library {
        Some(mut library) if !report.has_errors() => {
            library.warnings = report;
            Ok(library)
        }
        _ => Err(report),
    }
}
