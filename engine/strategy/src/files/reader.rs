//! Reading the strategy files of a library load (the tree engine hands over every file that is
//! not `Behaviors(..)`), then checking them against each other and the trees.

use super::{
    parse_avoidance, parse_formation, parse_goalkeeper, parse_pass, parse_shot, parse_team,
    Strategy,
};
use libero_behavior::decode::Decoder;
use libero_behavior::syntax::{Node, Span};
use libero_behavior::{
    did_you_mean, DataCollector, DataFiles, Diagnostic, Report, SourceFile, TreeIndex,
};
use std::any::Any;
use std::collections::{BTreeSet, HashMap};
use std::sync::Arc;

/// The strategy layer's file kinds: what `formations/` holds.
#[derive(Debug, Clone, Copy, Default)]
pub struct StrategyFiles;

const KINDS: &[&str] = &[
    "Formation",
    "Team",
    "Goalkeeper",
    "ShotUtility",
    "PassUtility",
    "Avoidance",
];

impl DataFiles for StrategyFiles {
    fn kinds(&self) -> &[&'static str] {
        KINDS
    }
    fn collector(&self) -> Box<dyn DataCollector> {
        Box::<Collector>::default()
    }
}

#[derive(Default)]
struct Collector {
    strategy: Strategy,
    /// Formation name → its file, for cross-checks and unused-file warnings.
    formation_files: HashMap<String, (Arc<SourceFile>, Span)>,
    team_file: Option<Arc<SourceFile>>,
    /// The one file of each kind that may appear once.
    singletons: HashMap<&'static str, Arc<SourceFile>>,
}

impl DataCollector for Collector {
    fn read(&mut self, kind: &str, head: Span, node: &Node, decoder: &mut Decoder) {
        if kind != "Formation" {
            let kind = KINDS.iter().copied().find(|k| *k == kind).unwrap_or("?");
            if let Some(first) = self.singletons.get(kind) {
                decoder
                    .error(
                        "duplicate-definition",
                        head,
                        format!("a second `{kind}` file"),
                    )
                    .hint = Some(format!(
                    "`{kind}` is already defined in {}",
                    first.path.display()
                ));
                return;
            }
            self.singletons.insert(kind, decoder.file.clone());
        }
        let s = &mut self.strategy;
        match kind {
            "Formation" => {
                let Some(formation) = parse_formation(decoder, node) else {
                    return;
                };
                if let Some((first, _)) = self.formation_files.get(&formation.name) {
                    let message = format!("formation `{}` is defined twice", formation.name);
                    decoder.error("duplicate-definition", head, message).hint =
                        Some(format!("also defined in {}", first.path.display()));
                } else {
                    self.formation_files
                        .insert(formation.name.clone(), (decoder.file.clone(), head));
                    s.formations.insert(formation.name.clone(), formation);
                }
            }
            "Team" => {
                s.team = parse_team(decoder, node);
                self.team_file = Some(decoder.file.clone());
            }
            "Goalkeeper" => s.goalkeeper = parse_goalkeeper(decoder, node),
            "ShotUtility" => s.shot = parse_shot(decoder, node),
            "PassUtility" => s.pass = parse_pass(decoder, node),
            "Avoidance" => s.avoidance = parse_avoidance(decoder, node),
            _ => {}
        }
    }

    fn finish(
        self: Box<Self>,
        trees: &TreeIndex,
        report: &mut Report,
    ) -> Arc<dyn Any + Send + Sync> {
        self.check_team(trees, report);
        Arc::new(self.strategy)
    }
}

impl Collector {
    fn check_team(&self, trees: &TreeIndex, report: &mut Report) {
        let (Some(team), Some(team_file)) = (&self.strategy.team, &self.team_file) else {
            return;
        };
        for (name, span) in [&team.goalkeeper_tree, &team.field_player_tree] {
            match trees.can_be_root(name) {
                None => {
                    let hint = did_you_mean(name, trees.names());
                    report.push(
                        Diagnostic::error("missing-subtree", format!("no tree named `{name}`"))
                            .at(team_file, *span)
                            .maybe_hint(hint),
                    );
                }
                Some(false) => {
                    let message = format!(
                        "tree `{name}` has required parameters and cannot be a player's root"
                    );
                    report.push(Diagnostic::error("invalid-value", message).at(team_file, *span));
                }
                Some(true) => {}
            }
        }
        let formations = &self.strategy.formations;
        for (name, span) in team.formations.values() {
            match formations.get(name) {
                None => {
                    let hint = did_you_mean(name, formations.keys().map(String::as_str));
                    report.push(
                        Diagnostic::error(
                            "unknown-formation",
                            format!("no formation named `{name}`"),
                        )
                        .at(team_file, *span)
                        .maybe_hint(hint),
                    );
                }
                Some(formation) if formation.field != team.field => {
                    let message = format!(
                        "formation `{name}` is for the {} field, the team plays on {}",
                        formation.field.name(),
                        team.field.name()
                    );
                    report.push(Diagnostic::error("field-mismatch", message).at(team_file, *span));
                }
                Some(_) => {}
            }
        }
        // Files nothing refers to are probably forgotten or misnamed: warn, do not fail.
        let used: BTreeSet<&str> = team.formations.values().map(|(n, _)| n.as_str()).collect();
        for (name, (file, span)) in &self.formation_files {
            if !used.contains(name.as_str()) {
                let message = format!("formation `{name}` is not used by the team file");
                report.push(Diagnostic::warning("unused-file", message).at(file, *span));
            }
        }
        trees.warn_unreachable_files(
            &[
                team.goalkeeper_tree.0.as_str(),
                team.field_player_tree.0.as_str(),
            ],
            report,
        );
    }
}
