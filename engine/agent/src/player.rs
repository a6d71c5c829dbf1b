//! One agent's per-cycle pipeline, free of I/O.

use crate::actuate::{write_actions, VelocityServo};
use crate::decide::Decider;
use crate::skill_source::SkillSource;
use crate::stats::AgentStats;
use crate::view::{DecisionView, TreeShape, ViewSlot, ViewTap};
use libero_model::RobotModel;
use libero_protocol::{parse_percept, ActionWriter};
use libero_skills::{Intent, JointTargets, Skills};
use libero_world::eval_log::EvalLogger;
use libero_world::{PlayMode, World};
use std::sync::atomic::Ordering;
use std::sync::Arc;

/// Server cycle length [s] (both servers).
pub const CYCLE_S: f64 = 0.02;

/// Everything one agent carries from cycle to cycle.
pub struct Player {
    pub model: Arc<RobotModel>,
    pub world: World,
    skills: Skills,
    decider: Box<dyn Decider>,
    writer: ActionWriter,
    targets: JointTargets,
    servo: VelocityServo,
    intent: Intent,
    stats: Arc<AgentStats>,
    /// The play mode in which we last beamed: beam once per beam-allowing mode, because a
    /// beam resets the joints and repeated beams would never let the robot settle.
    beamed_in: Option<PlayMode>,
    /// Publish each cycle's decision trace in the stats (for tests and live inspection).
    pub share_trace: bool,
    eval_log: Option<EvalLog>,
    /// Where new skill parameters come from while playing, and the version in use.
    skill_source: SkillSource,
    skill_generation: u64,
    /// Percept payloads still to be recorded into the stats.
    to_record: usize,
    /// Where a field view reads this player's beliefs and decision, if one watches.
    view: Option<ViewTap>,
    /// The latest decision as a view or the log shows it (its room reused).
    decision: DecisionView,
    /// Ground truth from outside the percept (SimSpark's monitor), for trials and evaluation.
    truth_feed: Option<TruthFeed>,
}

/// Ground truth for a player by side (left?), uniform number and the play time of the percept
/// just read, where the server does not put it in the percept: SimSpark's monitor scene graph
/// (the time lets a feed hand out the truth of that same moment). Tests and evaluation only —
/// it goes to `World::truth`, which no estimate or decision reads.
pub type TruthFeed = Arc<dyn Fn(bool, u32, f64) -> Option<libero_world::GroundTruth> + Send + Sync>;

/// Where the evaluation log goes and whether it carries decision traces.
struct EvalLog {
    logger: EvalLogger,
    with_trace: bool,
    /// The tree (generation and pointer) whose shape the log last carried.
    shape_logged: Option<(u64, usize)>,
}

/// What a traced log line adds for a replayed view.
#[derive(serde::Serialize)]
struct LoggedDecision<'a> {
    decision: &'a DecisionView,
    #[serde(skip_serializing_if = "Option::is_none")]
    tree_shape: Option<TreeShape>,
}

impl Player {
    pub fn new(
        model: Arc<RobotModel>,
        skills: Skills,
        decider: Box<dyn Decider>,
        team: &str,
        unum: u32,
        stats: Arc<AgentStats>,
    ) -> Self {
        let world = World::new(&model, team, unum);
        let mut targets = JointTargets::default();
        targets.hold_pose(&model, skills.stand_pose());
        // The first decision already sees what the skills report of themselves (the kicking
        // place a first-cycle beam puts the kick-off taker on).
        let mut decider = decider;
        decider.observe(&skills.status());
        let servo = VelocityServo::new(model.joints.len());
        Self {
            writer: ActionWriter::new(model.server),
            model,
            world,
            skills,
            decider,
            targets,
            servo,
            intent: Intent::default(),
            stats,
            beamed_in: None,
            share_trace: false,
            eval_log: None,
            skill_source: SkillSource::Builtin,
            skill_generation: 0,
            to_record: 0,
            view: None,
            decision: DecisionView::default(),
            truth_feed: None,
        }
    }

    /// Take ground truth from `feed` each cycle (SimSpark: the monitor's scene graph).
    pub fn set_truth_feed(&mut self, feed: TruthFeed) {
        self.truth_feed = Some(feed);
    }

    /// Copy this player's view into `slot` (at most once per the slot's period).
    pub fn show_in(&mut self, slot: Arc<ViewSlot>) {
        self.view = Some(ViewTap::new(slot));
    }

    /// Keep the next `limit` percept payloads in the stats ([`AgentStats::take_recording`]).
    /// A fresh player built the same way and fed them through [`Player::on_percept`] replays
    /// this one's cycles offline (benchmarks, allocation counts, debugging a decision).
    /// The room is taken at once, so recording does not allocate in the cycles it records.
    pub fn record_frames(&mut self, limit: usize) {
        self.to_record = limit;
        if let Ok(mut recorded) = self.stats.recorded.lock() {
            recorded.reserve(limit);
        }
    }

    fn record(&mut self, payload: &[u8]) {
        if self.to_record == 0 {
            return;
        }
        self.to_record -= 1;
        let kept = self
            .stats
            .recorded
            .lock()
            .is_ok_and(|mut recorded| recorded.push(payload));
        if !kept {
            // Out of the room reserved: the recording ends here.
            self.to_record = 0;
        }
    }

    /// Take new skill parameters from `source` whenever it has a new version (checked once per
    /// cycle, before the skills run).
    pub fn follow_skill_params(&mut self, source: SkillSource) {
        self.skill_generation = source.generation();
        self.skill_source = source;
    }

    fn pick_up_skill_params(&mut self) {
        let generation = self.skill_source.generation();
        if generation == self.skill_generation {
            return;
        }
        self.skill_generation = generation;
        let Some(params) = self.skill_source.current() else {
            return;
        };
        match self
            .skills
            .set_params(&self.model, params.for_type(&self.model))
        {
            Ok(()) => log::debug!(
                "agent {}: skill parameters version {generation} in use",
                self.world.game.unum
            ),
            // Validated against the file's model already; a different robot type of the same
            // family may still refuse them, and then keeps its running parameters.
            Err(e) => log::error!(
                "agent {} ({}): new skill parameters refused, keeping the running ones: {e}",
                self.world.game.unum,
                self.model.name
            ),
        }
    }

    /// Write one evaluation-log line per cycle (estimates, ground truth, optionally the
    /// decision trace) to `logger`.
    pub fn log_to(&mut self, logger: EvalLogger, with_trace: bool) {
        self.eval_log = Some(EvalLog {
            logger,
            with_trace,
            shape_logged: None,
        });
    }

    pub fn stats(&self) -> &Arc<AgentStats> {
        &self.stats
    }

    /// The intent chosen in the latest cycle.
    pub fn intent(&self) -> &Intent {
        &self.intent
    }

    /// The message that opens a connection (rcssservermj `init`; SimSpark `scene`).
    pub fn greeting(&mut self) -> Result<Vec<u8>, libero_protocol::action::ActionError> {
        self.writer.clear();
        match self.model.server {
            libero_model::ServerKind::RcssMj => {
                self.writer
                    .init(&self.model, &self.world.game.team, self.world.game.unum)?
            }
            libero_model::ServerKind::SimSpark => self.writer.scene(&self.model)?,
        }
        let mut out = Vec::new();
        self.writer.frame_into(&mut out);
        Ok(out)
    }

    /// Forget per-connection state (after a reconnect the server knows nothing of us).
    pub fn reset_connection(&mut self) {
        let (team, unum) = (self.world.game.team.clone(), self.world.game.unum);
        self.world = World::new(&self.model, &team, unum);
        self.beamed_in = None;
        self.servo.reset();
    }

    /// One cycle: read `payload`, decide, and append exactly one reply frame to `out`. A
    /// message that cannot be read still gets a reply (the previous targets again), because
    /// a missing reply stalls a sync-mode server.
    pub fn on_percept(&mut self, payload: &[u8], out: &mut Vec<u8>) {
        AgentStats::bump(&self.stats.percepts);
        self.record(payload);
        let mut stopwatch = Stopwatch::start();
        self.writer.clear();
        let first = self.world.cycle == 0;
        let parsed = parse_percept(payload, self.model.server);
        let stages = &self.stats.stages;
        stopwatch.lap(&stages.parse_ns);
        match parsed {
            Ok(percept) => {
                let before = self.world.time;
                self.world.update(&self.model, &percept);
                if let (Some(feed), Some(side)) = (&self.truth_feed, self.world.game.side) {
                    let left = side == libero_world::Side::Left;
                    if let Some(truth) = feed(left, self.world.game.unum, self.world.game.play_time)
                    {
                        self.world.truth = truth;
                    }
                }
                self.count_missed(before);
                if !percept.skipped.is_empty() && self.world.cycle % 500 == 1 {
                    log::debug!("unread percept items: {:?}", percept.skipped);
                }
            }
            Err(e) => {
                AgentStats::bump(&self.stats.unreadable);
                log::warn!(
                    "agent {}: unreadable percept ({e}); holding the previous targets",
                    self.world.game.unum
                );
            }
        }
        if first && self.model.server == libero_model::ServerKind::SimSpark {
            // The robot exists now; `init` goes with the first reply (with `syn`, or a
            // sync-mode server waits forever).
            let (team, unum) = (self.world.game.team.clone(), self.world.game.unum);
            if let Err(e) = self.writer.init(&self.model, &team, unum) {
                log::error!("init not sent: {e}");
            }
        }
        stopwatch.lap(&self.stats.stages.world_ns);
        let view_due = self.view.as_mut().is_some_and(ViewTap::due);
        let log_decision = self.eval_log.as_ref().is_some_and(|l| l.with_trace);
        if view_due || log_decision {
            self.decider.note_next();
        }
        self.intent = self.decider.decide(&self.world);
        if view_due || log_decision {
            let detail = log_decision || self.view.as_ref().is_some_and(|v| v.slot.detailed());
            self.decider
                .describe(&self.skills.status(), detail, &mut self.decision);
            self.decision
                .note_intent(&self.intent.body, &self.world.pose());
        }
        self.tell_teammates();
        if self.share_trace {
            if let Ok(mut trace) = self.stats.trace.lock() {
                *trace = self.decider.trace_line();
            }
        }
        if let Some(log) = &mut self.eval_log {
            let trace = if log.with_trace {
                self.decider.trace_line()
            } else {
                None
            };
            let extra = log.with_trace.then(|| {
                let running = self.decider.running_tree();
                let key = running
                    .as_ref()
                    .map(|(g, tree)| (*g, Arc::as_ptr(tree) as usize));
                let tree_shape = (key.is_some() && key != log.shape_logged)
                    .then(|| running.map(|(g, tree)| TreeShape::of(&tree, g)))
                    .flatten();
                log.shape_logged = key;
                LoggedDecision {
                    decision: &self.decision,
                    tree_shape,
                }
            });
            if let Err(e) = log
                .logger
                .write_record(&self.world, trace.as_deref(), extra.as_ref())
            {
                log::error!(
                    "agent {}: evaluation log stopped: {e}",
                    self.world.game.unum
                );
                self.eval_log = None;
            }
        }
        // After the log, which writes the same decision: the slot takes it over.
        if view_due {
            if let Some(view) = &self.view {
                if let Some((generation, tree)) = self.decider.running_tree() {
                    view.slot.publish_shape(generation, &tree);
                }
                view.slot.publish(&self.world, &mut self.decision);
            }
        }
        stopwatch.lap(&self.stats.stages.decide_ns);
        self.pick_up_skill_params();
        self.skills
            .act(&self.model, &self.world, &self.intent, &mut self.targets);
        let status = self.skills.status();
        self.decider.observe(&status);
        self.stats.in_motion.store(
            matches!(
                status.active,
                libero_skills::ActiveSkill::GetUp | libero_skills::ActiveSkill::Save
            ),
            Ordering::Relaxed,
        );
        let mode = self.world.game.play_mode;
        // Once per beam-allowing mode *each time it comes*: the second goal of a half is
        // another `Goal_Left` and must beam again (it did not, and the referee lined the
        // players up outside the touchline, 20 m from their places: NOTES.md session 16).
        if !mode.allows_beam() {
            self.beamed_in = None;
        }
        // The side must be known: the server ignores a beam from a robot whose init has not
        // taken effect (SimSpark), and the right team's beam is mirrored (rcssservermj).
        let beam_now = self.intent.beam.is_some()
            && mode.allows_beam()
            && self.world.game.side.is_some()
            && self.beamed_in != Some(mode);
        if beam_now {
            self.beamed_in = Some(mode);
            self.skills.beamed();
        }
        stopwatch.lap(&self.stats.stages.skills_ns);
        write_actions(
            &self.model,
            &self.world,
            &self.intent,
            &self.targets,
            beam_now,
            &mut self.servo,
            &mut self.writer,
        );
        self.writer.frame_into(out);
        stopwatch.lap(&self.stats.stages.write_ns);
        AgentStats::bump(&self.stats.replies);
    }

    /// In this player's turn on the channel (and unless the decision said something of its
    /// own), tell the team what this player knows: its position, whether it is down, the ball.
    fn tell_teammates(&mut self) {
        let world = &self.world;
        let server = self.model.server;
        if self.intent.say.is_some()
            || world.game.side.is_none()
            || !world.me.localized
            || !libero_world::team_message::may_speak(server, world.time, world.game.unum)
        {
            return;
        }
        let message = world.team_message(self.intent.time_to_ball_s, self.intent.going_for_ball);
        self.intent.say = Some(message.encode(&world.game.team, &world.field, server));
    }

    fn count_missed(&mut self, before: f64) {
        let now = self.world.time;
        if self.world.cycle > 1 && now > before {
            // Server times are truncated to 2 decimals, so one cycle can read as 0.01–0.03 s;
            // only a step of 0.04 s or more is a skipped cycle.
            let gap = ((now - before + 0.005) / CYCLE_S).floor() as u64;
            if gap > 1 {
                log::debug!(
                    "agent {}: server time jumped {before:.2} → {now:.2}",
                    self.world.game.unum
                );
                self.stats
                    .missed_cycles
                    .fetch_add(gap - 1, Ordering::Relaxed);
            }
        }
        self.stats
            .last_time_ms
            .store((now * 1000.0) as u64, Ordering::Relaxed);
        if let Ok(mut truth) = self.stats.truth_position.lock() {
            *truth = self.world.truth.torso_position;
        }
        let side = match self.world.game.side {
            Some(libero_world::Side::Left) => 1,
            Some(libero_world::Side::Right) => 2,
            None => 0,
        };
        self.stats.side.store(side, Ordering::Relaxed);
        if let Ok(mut estimate) = self.stats.self_estimate.lock() {
            *estimate = Some(self.world.me.position);
        }
    }
}

/// Laps of one cycle's stages, each added to its counter.
struct Stopwatch(std::time::Instant);

impl Stopwatch {
    fn start() -> Self {
        Self(std::time::Instant::now())
    }

    fn lap(&mut self, total_ns: &std::sync::atomic::AtomicU64) {
        let now = std::time::Instant::now();
        AgentStats::add(total_ns, (now - self.0).as_nanos() as u64);
        self.0 = now;
    }
}

#[cfg(test)]
mod tests;
