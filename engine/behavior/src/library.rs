//! Loading a set of directories into a validated [`Library`]: every tree compiled and every
//! strategy file checked, with cross-file checks (subtrees, formations, unused files).

use crate::check::{check_trees, collect_definitions, LoadedBehaviors};
use crate::compile::{compile_tree, BlackboardLayout, CompiledTree};
use crate::decode::Decoder;
use crate::diagnostics::{did_you_mean, Diagnostic, Report, SourceFile};
use crate::strategy::{self, Strategy};
use crate::syntax::{self, Span};
use crate::tree::{parse_behavior_file, NodeDef, NodeDefKind};
use crate::vocabulary::Vocabulary;
use std::collections::hash_map::DefaultHasher;
use std::collections::{BTreeSet, HashMap};
use std::hash::{Hash, Hasher};
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// All trees and strategy of a directory set, validated and compiled; shared by every agent.
#[derive(Debug)]
pub struct Library {
    generation: u64,
    trees: HashMap<String, Arc<CompiledTree>>,
    layout: BlackboardLayout,
    strategy: Strategy,
    warnings: Report,
    files: Vec<PathBuf>,
}

impl Library {
    /// Loads and validates `.ron` files under `paths` (directories are searched recursively).
    /// Fails with every error found; warnings of a successful load are in [`Library::warnings`].
    pub fn load(paths: &[PathBuf], vocabulary: &Vocabulary) -> Result<Library, Report> {
        let (sources, report) = read_sources(paths);
        finish(&sources, vocabulary, report)
    }

    /// Builds a library from in-memory files `(path, text)`, as if read from disk.
    pub fn from_texts(files: &[(&str, &str)], vocabulary: &Vocabulary) -> Result<Library, Report> {
        let sources: Vec<Arc<SourceFile>> = files
            .iter()
            .map(|(path, text)| Arc::new(SourceFile::new(PathBuf::from(path), text.to_string())))
            .collect();
        finish(&sources, vocabulary, Report::default())
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

    pub fn strategy(&self) -> &Strategy {
        &self.strategy
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
pub fn validate_paths(paths: &[PathBuf], vocabulary: &Vocabulary) -> Report {
    match Library::load(paths, vocabulary) {
        Ok(library) => library.warnings,
        Err(report) => report,
    }
}

/// `.ron` files under the given paths, sorted so results do not depend on directory order.
pub(crate) fn ron_files(paths: &[PathBuf], report: &mut Report) -> Vec<PathBuf> {
    fn walk(dir: &Path, out: &mut Vec<PathBuf>, report: &mut Report) {
        match std::fs::read_dir(dir) {
            Ok(entries) => {
                for entry in entries.flatten() {
                    let path = entry.path();
                    if path.is_dir() {
                        walk(&path, out, report);
                    } else if path.extension().is_some_and(|e| e == "ron") {
                        out.push(path);
                    }
                }
            }
            Err(error) => report.push(Diagnostic::error(
                "io",
                format!("cannot read directory {}: {error}", dir.display()),
            )),
        }
    }
    let mut files = Vec::new();
    for path in paths {
        if path.is_dir() {
            walk(path, &mut files, report);
        } else if path.exists() {
            files.push(path.clone());
        } else {
            report.push(Diagnostic::error(
                "io",
                format!("{} does not exist", path.display()),
            ));
        }
    }
    files.sort();
    files.dedup();
    files
}

pub(crate) fn read_sources(paths: &[PathBuf]) -> (Vec<Arc<SourceFile>>, Report) {
    let mut report = Report::default();
    let mut sources = Vec::new();
    for path in ron_files(paths, &mut report) {
        match std::fs::read(&path) {
            Ok(bytes) => match String::from_utf8(bytes) {
                Ok(text) => sources.push(Arc::new(SourceFile::new(path, text))),
                Err(_) => report.push(Diagnostic::error(
                    "io",
                    format!("{} is not UTF-8 text", path.display()),
                )),
            },
            // A file removed between listing and reading is simply gone (an editor's rename).
            Err(error) if error.kind() == std::io::ErrorKind::NotFound => {}
            Err(error) => report.push(Diagnostic::error(
                "io",
                format!("cannot read {}: {error}", path.display()),
            )),
        }
    }
    (sources, report)
}

/// Identifies a set of file contents, to skip reloading when nothing really changed.
pub(crate) fn fingerprint(sources: &[Arc<SourceFile>]) -> u64 {
    let mut hasher = DefaultHasher::new();
    for source in sources {
        source.path.hash(&mut hasher);
        source.text.hash(&mut hasher);
    }
    hasher.finish()
}

const FILE_KINDS: &[&str] = &[
    "Behaviors",
    "Formation",
    "Team",
    "Goalkeeper",
    "ShotUtility",
    "Avoidance",
];

struct StrategyFiles {
    strategy: Strategy,
    /// Formation name → its file, for cross-checks and unused-file warnings.
    formation_files: HashMap<String, (Arc<SourceFile>, Span)>,
    team_file: Option<Arc<SourceFile>>,
}

pub(crate) fn build(
    sources: &[Arc<SourceFile>],
    vocabulary: &Vocabulary,
    report: &mut Report,
) -> Option<Library> {
    let mut behaviors = Vec::new();
    let mut strategy_files = StrategyFiles {
        strategy: Strategy::default(),
        formation_files: HashMap::new(),
        team_file: None,
    };
    let mut singletons: HashMap<&str, Arc<SourceFile>> = HashMap::new();
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
                "expected a file such as `Behaviors(..)` or `Formation(..)`, found {}",
                node.describe()
            );
            report.push(Diagnostic::error("unknown-file-kind", message).at(source, node.span));
            continue;
        };
        let mut decoder = Decoder::new(source.clone(), report);
        if head != "Behaviors" && head != "Formation" && FILE_KINDS.contains(&head) {
            if let Some(first) = singletons.get(head) {
                let message = format!("a second `{head}` file");
                decoder
                    .error("duplicate-definition", head_span, message)
                    .hint = Some(format!(
                    "`{head}` is already defined in {}",
                    first.path.display()
                ));
                continue;
            }
            singletons.insert(
                FILE_KINDS
                    .iter()
                    .find(|k| **k == head)
                    .copied()
                    .unwrap_or("?"),
                source.clone(),
            );
        }
        let s = &mut strategy_files.strategy;
        match head {
            "Behaviors" => behaviors.push(LoadedBehaviors {
                source: source.clone(),
                file: parse_behavior_file(&mut decoder, &node),
            }),
            "Formation" => {
                if let Some(formation) = strategy::parse_formation(&mut decoder, &node) {
                    if let Some((first, _)) = strategy_files.formation_files.get(&formation.name) {
                        let message = format!("formation `{}` is defined twice", formation.name);
                        decoder
                            .error("duplicate-definition", head_span, message)
                            .hint = Some(format!("also defined in {}", first.path.display()));
                    } else {
                        strategy_files
                            .formation_files
                            .insert(formation.name.clone(), (source.clone(), head_span));
                        s.formations.insert(formation.name.clone(), formation);
                    }
                }
            }
            "Team" => {
                s.team = strategy::parse_team(&mut decoder, &node);
                strategy_files.team_file = Some(source.clone());
            }
            "Goalkeeper" => s.goalkeeper = strategy::parse_goalkeeper(&mut decoder, &node),
            "ShotUtility" => s.shot = strategy::parse_shot(&mut decoder, &node),
            "Avoidance" => s.avoidance = strategy::parse_avoidance(&mut decoder, &node),
            _ => {
                let hint = did_you_mean(head, FILE_KINDS.iter().copied())
                    .or_else(|| Some(format!("files are one of: {}", FILE_KINDS.join(", "))));
                decoder
                    .error(
                        "unknown-file-kind",
                        head_span,
                        format!("unknown file kind `{head}`"),
                    )
                    .hint = hint;
            }
        }
    }
    let defs = collect_definitions(&behaviors, report);
    check_trees(&behaviors, &defs, vocabulary, report);
    check_team(&strategy_files, &defs, report);
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
        strategy: strategy_files.strategy,
        warnings: Report::default(),
        files: sources.iter().map(|s| s.path.clone()).collect(),
    })
}

fn check_team(files: &StrategyFiles, defs: &crate::check::Definitions, report: &mut Report) {
    let (Some(team), Some(team_file)) = (&files.strategy.team, &files.team_file) else {
        return;
    };
    for (name, span) in [&team.goalkeeper_tree, &team.field_player_tree] {
        match defs.trees.get(name.as_str()) {
            None => {
                let hint = did_you_mean(name, defs.trees.keys().copied());
                report.push(
                    Diagnostic::error("missing-subtree", format!("no tree named `{name}`"))
                        .at(team_file, *span)
                        .maybe_hint(hint),
                );
            }
            Some((_, tree)) if tree.params.iter().any(|p| p.default.is_none()) => {
                let message =
                    format!("tree `{name}` has required parameters and cannot be a player's root");
                report.push(Diagnostic::error("invalid-value", message).at(team_file, *span));
            }
            Some(_) => {}
        }
    }
    for (name, span) in team.formations.values() {
        match files.strategy.formations.get(name) {
            None => {
                let hint = did_you_mean(name, files.strategy.formations.keys().map(String::as_str));
                report.push(
                    Diagnostic::error("unknown-formation", format!("no formation named `{name}`"))
                        .at(team_file, *span)
                        .maybe_hint(hint),
                );
            }
            Some(formation) if formation.field != team.field => {
                let message = format!(
                    "formation `{name}` is for the {} field, the team plays on {}",
                    formation.field.name, team.field.name
                );
                report.push(Diagnostic::error("field-mismatch", message).at(team_file, *span));
            }
            Some(_) => {}
        }
    }
    // Files nothing refers to are probably forgotten or misnamed: warn, do not fail.
    let used_formations: BTreeSet<&str> =
        team.formations.values().map(|(n, _)| n.as_str()).collect();
    for (name, (file, span)) in &files.formation_files {
        if !used_formations.contains(name.as_str()) {
            let message = format!("formation `{name}` is not used by the team file");
            report.push(Diagnostic::warning("unused-file", message).at(file, *span));
        }
    }
    let reachable = reachable_trees(
        defs,
        [
            team.goalkeeper_tree.0.as_str(),
            team.field_player_tree.0.as_str(),
        ],
    );
    let mut files_seen: HashMap<&Path, (bool, &Arc<SourceFile>, Span)> = HashMap::new();
    for (name, (file, tree)) in &defs.trees {
        let entry = files_seen
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

fn reachable_trees<'a>(
    defs: &crate::check::Definitions<'a>,
    roots: [&'a str; 2],
) -> BTreeSet<&'a str> {
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
        let Some((key, (_, tree))) = defs.trees.get_key_value(name) else {
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

/// Build from read sources; every error in `report` (reading or building) fails the load, and a
/// successful library keeps the warnings.
fn finish(
    sources: &[Arc<SourceFile>],
    vocabulary: &Vocabulary,
    mut report: Report,
) -> Result<Library, Report> {
    let library = build(sources, vocabulary, &mut report);
    report.sort();
    match library {
        Some(mut library) if !report.has_errors() => {
            library.warnings = report;
            Ok(library)
        }
        _ => Err(report),
    }
}
