//! The decision stage: from beliefs to this cycle's intent.

use crate::view::DecisionView;
use libero_behavior::{Library, LiveLibrary, TreeRunner};
use libero_skills::{BodyIntent, HeadIntent, Intent, SkillStatus};
use libero_strategy::{strategy_of, AgentHost, DecisionNotes, Natives, PlayerMemory};
use libero_world::World;
use std::sync::Arc;

/// Chooses what the skills should do this cycle.
pub trait Decider: Send {
    fn decide(&mut self, world: &World) -> Intent;

    /// What the skills made of the latest intent (called after every `decide`): e.g. a kick
    /// node succeeds once the kick is done.
    fn observe(&mut self, _status: &SkillStatus) {}

    /// The active path of the latest decision, one line (for traces and tests).
    fn trace_line(&self) -> Option<String> {
        None
    }

    /// Keep the strategy's notes of the next decision, for [`Decider::describe`].
    fn note_next(&mut self) {}

    /// The latest decision as a view shows it.
    /// `detail`: the tree's statuses and blackboard too.
    fn describe(&self, _skills: &SkillStatus, _detail: bool, out: &mut DecisionView) {
        out.tree = None;
    }

    /// The tree being run and its library generation (for a view's drawing of it).
    fn running_tree(&self) -> Option<(u64, Arc<libero_behavior::CompiledTree>)> {
        None
    }
}

/// Beam to a fixed own-frame pose when the play mode allows, then stand and look around.
/// Used when no behavior tree is loaded.
pub struct StandAndBeam {
    pub beam_pose: [f64; 3],
}

impl Decider for StandAndBeam {
    fn decide(&mut self, world: &World) -> Intent {
        Intent {
            body: BodyIntent::Stand,
            head: HeadIntent::LookAround {
                amplitude_deg: None,
                period_s: None,
            },
            beam: world.game.play_mode.allows_beam().then_some(self.beam_pose),
            ..Intent::default()
        }
    }
}

/// Where a process's behavior files come from: loaded once, or watched and hot-reloaded.
/// Shared by every agent of the process.
#[derive(Clone)]
pub enum LibrarySource {
    Fixed(Arc<Library>),
    Live(Arc<LiveLibrary>),
}

impl LibrarySource {
    /// The newest good library (a broken edit never replaces it).
    pub fn current(&self) -> Arc<Library> {
        match self {
            LibrarySource::Fixed(l) => Arc::clone(l),
            LibrarySource::Live(l) => l.current(),
        }
    }
}

/// Decides by ticking this player's behavior tree from the team file.
pub struct TreeDecider {
    source: LibrarySource,
    natives: Natives,
    runner: Option<TreeRunner>,
    memory: PlayerMemory,
    /// The library generation whose field was last checked against the server's.
    field_checked: Option<u64>,
    unum: u32,
    /// What the skills made of the previous cycle's intent (a kick node waits for `Done`).
    skills: SkillStatus,
    /// The active path last logged (`RUST_LOG=libero_agent::decide=debug` logs each change).
    logged_path: Option<String>,
    /// Whether the next decision keeps its notes, and the notes kept.
    want_notes: bool,
    notes: Option<DecisionNotes>,
}

impl TreeDecider {
    pub fn new(source: LibrarySource, natives: Natives, unum: u32) -> Self {
        Self {
            source,
            natives,
            runner: None,
            memory: PlayerMemory::default(),
            field_checked: None,
            unum,
            skills: SkillStatus::default(),
            logged_path: None,
            want_notes: false,
            notes: None,
        }
    }

    /// Make the runner for this player's root tree on first use. A library whose team file
    /// names no tree for us leaves the player standing.
    fn ensure_runner(&mut self, library: &Arc<Library>) {
        if self.runner.is_some() {
            return;
        }
        let unum = u8::try_from(self.unum).unwrap_or(u8::MAX);
        let Some(root) = strategy_of(library).tree_for(unum) else {
            return;
        };
        match TreeRunner::new(library, root) {
            Ok(runner) => self.runner = Some(runner),
            Err(e) => log::error!("player {}: tree `{root}` cannot run: {e}", self.unum),
        }
    }
}

impl Decider for TreeDecider {
    fn decide(&mut self, world: &World) -> Intent {
        let library = self.source.current();
        let mut intent = Intent::default();
        self.ensure_runner(&library);
        if self.field_checked != Some(library.generation()) {
            self.field_checked = Some(library.generation());
            let strategy = strategy_of(&library);
            let team_field = strategy.field();
            // The path planner's room for any plan on this field, now rather than during play.
            self.memory
                .avoidance
                .reserve(&strategy.avoidance.unwrap_or_default(), &team_field);
            if team_field.name() != world.field.name {
                log::error!(
                    "player {}: team.ron plays on the `{}` field but the server's is `{}`: formations and strategy files are for another field",
                    self.unum,
                    team_field.name(),
                    world.field.name
                );
            }
        }
        if let Some(runner) = self.runner.as_mut() {
            let mut host = AgentHost::new(
                world,
                strategy_of(&library),
                &self.natives,
                &self.skills,
                &mut self.memory,
                &mut intent,
            );
            runner.tick(&mut host, &library);
            if std::mem::take(&mut self.want_notes) {
                self.notes = Some(host.notes());
            }
            intent.time_to_ball_s = self.memory.time_to_ball.take();
            intent.going_for_ball =
                intent.time_to_ball_s.is_some() && self.memory.ball_winner.get();
        }
        if log::log_enabled!(log::Level::Debug) {
            let path = self.trace_line();
            if path != self.logged_path {
                log::debug!(
                    "t {:.2} {} {} [{:?}]: {}",
                    world.time,
                    world.game.team,
                    self.unum,
                    world.game.play_mode,
                    path.as_deref().unwrap_or("-")
                );
                self.logged_path = path;
            }
        }
        intent
    }

    fn observe(&mut self, status: &SkillStatus) {
        self.skills = *status;
    }

    fn note_next(&mut self) {
        self.want_notes = true;
    }

    fn describe(&self, skills: &SkillStatus, detail: bool, out: &mut DecisionView) {
        out.fill(self.notes.as_ref(), self.runner.as_ref(), skills, detail);
    }

    fn running_tree(&self) -> Option<(u64, Arc<libero_behavior::CompiledTree>)> {
        let runner = self.runner.as_ref()?;
        Some((runner.generation(), Arc::clone(runner.tree())))
    }

    fn trace_line(&self) -> Option<String> {
        let record = self.runner.as_ref()?.trace().last()?;
        let leaves: Vec<String> = record
            .leaves()
            .iter()
            .map(|(label, status)| format!("{label}={status:?}"))
            .collect();
        Some(leaves.join(" "))
    }
}
