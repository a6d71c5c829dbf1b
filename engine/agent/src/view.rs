//! What a field view shows of one agent: its beliefs and its decision, copied out of the
//! per-cycle pipe at most every [`ViewSlot::period`] into a slot that a viewer thread reads.
//!
//! The records use the evaluation log's field names (`me.position`, `ball.predicted_stop`,
//! `players[].relation`, `truth.position`, …) so that a view reads live slots and logged lines
//! alike: a log line deserializes into an [`AgentView`].

use libero_behavior::{CompiledTree, Status, TreeRunner};
use libero_skills::SkillStatus;
use libero_strategy::DecisionNotes;
use libero_world::World;
use serde::{Deserialize, Serialize};
use std::fmt::Write as _;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

/// One agent's picture for a viewer. Every field is reused from copy to copy.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
pub struct AgentView {
    pub time: f64,
    pub cycle: u64,
    pub team: String,
    pub unum: u32,
    /// Once the server has said.
    pub side: Option<libero_world::Side>,
    pub play_mode: String,
    /// Goals (left, right) as the agent heard them.
    #[serde(default)]
    pub score: [u32; 2],
    pub me: SelfView,
    pub ball: Option<BallView>,
    #[serde(default)]
    pub players: Vec<PlayerView>,
    pub truth: Option<TruthView>,
    #[serde(default)]
    pub decision: Option<DecisionView>,
}

#[derive(Debug, Clone, Default, Serialize, Deserialize)]
pub struct SelfView {
    pub position: [f64; 2],
    pub yaw_deg: f64,
    #[serde(default)]
    pub localized: bool,
    #[serde(default)]
    pub fallen: bool,
}

#[derive(Debug, Clone, Default, Serialize, Deserialize)]
pub struct BallView {
    pub position: [f64; 2],
    pub velocity: [f64; 2],
    pub predicted_stop: [f64; 2],
    pub last_seen_time: Option<f64>,
}

#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct PlayerView {
    pub relation: libero_world::Relation,
    pub unum: u32,
    pub position: [f64; 2],
    #[serde(default)]
    pub last_update_time: f64,
    #[serde(default)]
    pub fallen: bool,
}

#[derive(Debug, Clone, Default, Serialize, Deserialize)]
pub struct TruthView {
    pub position: [f64; 3],
    pub yaw_deg: f64,
}

/// The decision of the cycle: strategy notes, the tree's statuses, blackboard and skill.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
pub struct DecisionView {
    pub slot: u8,
    pub role: String,
    pub formation_target: Option<[f64; 2]>,
    pub defense_point: Option<[f64; 2]>,
    pub shot_target: Option<[f64; 2]>,
    pub shot_probability: Option<f64>,
    pub tree: Option<TreeStatus>,
    #[serde(default)]
    pub blackboard: Vec<(String, String)>,
    /// The active skill and its state (`Kick Approaching`, `Walk`, …).
    #[serde(default)]
    pub skill: String,
    /// What the decision asked the body for this cycle (`WalkTo { target: [1.20, 0.30], … }`).
    #[serde(default)]
    pub intent: String,
    /// Where that asks the body to go, on the field: the walk's target, or the ball to kick or
    /// dribble, and the direction [deg, global] a kick or dribble goes.
    #[serde(default)]
    pub intent_target: Option<[f64; 2]>,
    #[serde(default)]
    pub intent_direction_deg: Option<f64>,
}

impl DecisionView {
    /// The body intent in words and, on the field, where it points (from the robot's believed
    /// pose: the intent is in the robot frame).
    pub fn note_intent(&mut self, body: &libero_skills::BodyIntent, pose: &libero_world::Pose) {
        use libero_skills::BodyIntent;
        self.intent.clear();
        let _ = write!(self.intent, "{body:.2?}");
        let on_field = |p: [f64; 2]| pose.global(libero_world::Robot::from_array(p)).to_array();
        let (target, direction) = match *body {
            BodyIntent::WalkTo { target, .. } => (Some(on_field(target)), None),
            BodyIntent::Kick {
                ball,
                direction_deg,
                ..
            }
            | BodyIntent::Dribble {
                ball,
                direction_deg,
                ..
            } => (
                Some(on_field(ball)),
                Some(libero_world::geometry::wrap_deg(
                    pose.yaw_deg + direction_deg,
                )),
            ),
            _ => (None, None),
        };
        self.intent_target = target;
        self.intent_direction_deg = direction;
    }
}

/// Which nodes of the running tree were ticked this cycle and what they returned.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
pub struct TreeStatus {
    pub name: String,
    /// The library generation: the shape to draw is that generation's tree of this name.
    pub generation: u64,
    /// `(node, status)` for each node ticked, preorder; nodes not listed were not ticked.
    pub ticked: Vec<(u32, Status)>,
    /// `(node, score)` of the choices that their `Utility` parent scored.
    pub scores: Vec<(u32, f64)>,
}

/// A tree's shape as a view draws it: labels and parents in preorder.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct TreeShape {
    pub name: String,
    pub generation: u64,
    pub labels: Vec<String>,
    pub parents: Vec<Option<u32>>,
}

impl TreeShape {
    pub fn of(tree: &CompiledTree, generation: u64) -> Self {
        Self {
            name: tree.name.clone(),
            generation,
            labels: tree.nodes.iter().map(|n| n.label.clone()).collect(),
            parents: tree.parents().collect(),
        }
    }
}

impl DecisionView {
    /// Fill from the strategy's notes, the runner and the skills (reusing this view's room).
    /// `detail`: also the tree's statuses and the blackboard (what a view shows only for the
    /// agent it has selected, and the log always).
    pub fn fill(
        &mut self,
        notes: Option<&DecisionNotes>,
        runner: Option<&TreeRunner>,
        skills: &SkillStatus,
        detail: bool,
    ) {
        // No notes (no tree ran): nothing to show rather than an older decision's.
        let empty = DecisionNotes::default();
        let notes = notes.unwrap_or(&empty);
        self.slot = notes.slot;
        self.role.clear();
        self.role.push_str(&notes.role);
        self.formation_target = notes.formation_target.map(|p| p.to_array());
        self.defense_point = notes.defense_point.map(|p| p.to_array());
        self.shot_target = notes.shot.map(|(p, _)| p.to_array());
        self.shot_probability = notes.shot.map(|(_, p)| p);
        self.skill.clear();
        let _ = write!(self.skill, "{:?}", skills.active);
        // A kick's approach walks (the active skill is `Walk` then): its state says more.
        if skills.kick != libero_skills::KickState::Idle {
            let _ = write!(self.skill, ", kick {:?}", skills.kick);
        }
        if skills.dribble != libero_skills::DribbleState::Idle {
            let _ = write!(self.skill, ", dribble {:?}", skills.dribble);
        }
        let Some(runner) = runner.filter(|_| detail) else {
            self.tree = None;
            self.blackboard.clear();
            return;
        };
        let tree = self.tree.get_or_insert_with(TreeStatus::default);
        tree.name.clear();
        tree.name.push_str(&runner.tree().name);
        tree.generation = runner.generation();
        tree.ticked.clear();
        tree.scores.clear();
        if let Some(record) = runner.trace().last() {
            for entry in record.entries() {
                tree.ticked.push((entry.node, entry.status));
                if let Some(score) = runner.utility_score(entry.node) {
                    tree.scores.push((entry.node, score));
                }
            }
        }
        let entries = runner.blackboard().entries();
        let mut count = 0;
        for (key, value) in entries {
            if count == self.blackboard.len() {
                self.blackboard.push((String::new(), String::new()));
            }
            let (k, v) = &mut self.blackboard[count];
            k.clear();
            k.push_str(key);
            v.clear();
            let _ = write!(v, "{value}");
            count += 1;
        }
        self.blackboard.truncate(count);
    }
}

impl AgentView {
    /// Copy the world's beliefs into this view (the decision is handed over apart).
    pub fn fill(&mut self, world: &World) {
        self.time = world.time;
        self.cycle = world.cycle;
        self.team.clear();
        self.team.push_str(&world.game.team);
        self.unum = world.game.unum;
        self.side = world.game.side;
        self.play_mode.clear();
        self.play_mode.push_str(&world.game.play_mode_name);
        self.score = [world.game.score_left, world.game.score_right];
        self.me = SelfView {
            position: world.me.position,
            yaw_deg: world.me.yaw_deg,
            localized: world.me.localized,
            fallen: world.body.posture != libero_world::Posture::Upright,
        };
        let ball_known = world.ball.last_seen_time.is_some() || world.ball.heard_time.is_some();
        self.ball = ball_known.then_some(BallView {
            position: world.ball.position,
            velocity: world.ball.velocity,
            predicted_stop: world.ball.predicted_stop,
            last_seen_time: world.ball.last_seen_time,
        });
        self.players.clear();
        self.players
            .extend(world.players.known.iter().map(|p| PlayerView {
                relation: p.relation,
                unum: p.unum,
                position: p.position,
                last_update_time: p.last_update_time,
                fallen: p.fallen,
            }));
        self.truth = world
            .truth_pose()
            .map(|(position, yaw_deg)| TruthView { position, yaw_deg });
    }
}

/// Where one agent puts its view for a viewer: the latest copy and the tree shapes it ran.
pub struct ViewSlot {
    latest: Mutex<AgentView>,
    shape: Mutex<Option<(u64, Arc<CompiledTree>)>>,
    /// Copies made so far (a viewer sends a frame only when this moved).
    copies: AtomicU64,
    period: Duration,
    /// Whether the agent copies at all (a benchmark turns it off and on in one run).
    enabled: std::sync::atomic::AtomicBool,
    /// Until when [ms after `born`] a viewer wants the whole decision (tree, blackboard): the
    /// agent it has selected. The others copy their pose and notes only.
    detail_until_ms: AtomicU64,
    born: Instant,
}

impl ViewSlot {
    /// A viewer's stream runs at most 25 frames a second: copying more often is waste.
    pub const DEFAULT_PERIOD: Duration = Duration::from_millis(40);

    pub fn new(period: Duration) -> Arc<Self> {
        Arc::new(Self {
            latest: Mutex::new(AgentView::default()),
            shape: Mutex::new(None),
            copies: AtomicU64::new(0),
            period,
            enabled: std::sync::atomic::AtomicBool::new(true),
            detail_until_ms: AtomicU64::new(0),
            born: Instant::now(),
        })
    }

    /// A viewer has this agent selected: copy its whole decision for the next `span`.
    pub fn want_detail_for(&self, span: Duration) {
        let until = (self.born.elapsed() + span).as_millis() as u64;
        self.detail_until_ms.fetch_max(until, Ordering::Relaxed);
    }

    /// Whether a viewer wants the whole decision now.
    pub fn detailed(&self) -> bool {
        (self.born.elapsed().as_millis() as u64) < self.detail_until_ms.load(Ordering::Relaxed)
    }

    /// Stop or resume copying (the agent then skips even the clock check).
    pub fn set_enabled(&self, enabled: bool) {
        self.enabled.store(enabled, Ordering::Relaxed);
    }

    /// Copies made so far.
    pub fn copies(&self) -> u64 {
        self.copies.load(Ordering::Relaxed)
    }

    /// The latest view, copied (for the viewer thread; the agent never waits long for it).
    pub fn latest(&self) -> Option<AgentView> {
        if self.copies() == 0 {
            return None;
        }
        self.latest.lock().ok().map(|v| v.clone())
    }

    /// The shape of the tree the agent runs, when it is the given generation's.
    pub fn shape(&self, generation: u64) -> Option<TreeShape> {
        let guard = self.shape.lock().ok()?;
        let (g, tree) = guard.as_ref()?;
        (*g == generation).then(|| TreeShape::of(tree, *g))
    }

    /// Copy the beliefs in and hand the decision over: it is swapped with the slot's older
    /// one, whose room the agent then refills (every field of it) the next time.
    pub(crate) fn publish(&self, world: &World, decision: &mut DecisionView) {
        if let Ok(mut latest) = self.latest.lock() {
            latest.fill(world);
            std::mem::swap(
                latest.decision.get_or_insert_with(DecisionView::default),
                decision,
            );
        }
        self.copies.fetch_add(1, Ordering::Relaxed);
    }

    /// Whether the latest copy is of this agent.
    pub fn is(&self, team: &str, unum: u32) -> bool {
        self.copies() > 0
            && self
                .latest
                .lock()
                .is_ok_and(|v| v.team == team && v.unum == unum)
    }

    pub(crate) fn publish_shape(&self, generation: u64, tree: &Arc<CompiledTree>) {
        if let Ok(mut shape) = self.shape.lock() {
            if shape
                .as_ref()
                .is_none_or(|(g, t)| *g != generation || !Arc::ptr_eq(t, tree))
            {
                *shape = Some((generation, Arc::clone(tree)));
            }
        }
    }
}

/// The agent's side of a slot: when the next copy is due.
pub(crate) struct ViewTap {
    pub slot: Arc<ViewSlot>,
    next: Instant,
}

impl ViewTap {
    pub fn new(slot: Arc<ViewSlot>) -> Self {
        Self {
            slot,
            next: Instant::now(),
        }
    }

    /// Whether this cycle copies (at most once per period of wall time).
    pub fn due(&mut self) -> bool {
        if !self.slot.enabled.load(Ordering::Relaxed) {
            return false;
        }
        let now = Instant::now();
        if now < self.next {
            return false;
        }
        self.next = now + self.slot.period;
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use libero_skills::BodyIntent;
    use libero_world::{Global, Pose};

    #[test]
    fn only_a_selected_agent_copies_its_tree_and_only_while_selected() {
        let slot = ViewSlot::new(Duration::ZERO);
        assert!(!slot.detailed());
        slot.want_detail_for(Duration::from_millis(30));
        assert!(slot.detailed());
        std::thread::sleep(Duration::from_millis(40));
        assert!(!slot.detailed(), "a selection not renewed lapses");
        let mut view = DecisionView {
            blackboard: vec![("k".into(), "v".into())],
            tree: Some(TreeStatus::default()),
            ..DecisionView::default()
        };
        view.fill(None, None, &SkillStatus::default(), false);
        assert!(view.tree.is_none() && view.blackboard.is_empty());
    }

    #[test]
    fn an_intent_is_placed_on_the_field_from_the_believed_pose() {
        let pose = Pose::new(Global::new(1.0, 2.0), 90.0);
        let mut view = DecisionView::default();
        view.note_intent(
            &BodyIntent::WalkTo {
                target: [1.0, 0.0],
                heading_deg: 0.0,
                max_speed_m_s: None,
            },
            &pose,
        );
        let [x, y] = view.intent_target.unwrap();
        assert!((x - 1.0).abs() < 1e-9 && (y - 3.0).abs() < 1e-9, "{x} {y}");
        assert!(view.intent.starts_with("WalkTo"), "{}", view.intent);
        view.note_intent(
            &BodyIntent::Kick {
                ball: [0.0, -1.0],
                direction_deg: -90.0,
                distance_m: 5.0,
            },
            &pose,
        );
        let [x, y] = view.intent_target.unwrap();
        assert!((x - 2.0).abs() < 1e-9 && (y - 2.0).abs() < 1e-9, "{x} {y}");
        assert_eq!(view.intent_direction_deg, Some(0.0));
        view.note_intent(&BodyIntent::Stand, &pose);
        assert_eq!(view.intent_target, None);
    }
}
