//! Low-level skills. Each turns an [`Intent`] and the world state into joint targets for the
//! next cycle; none of them decides *what* to do (that is the behavior tree's job).
//!
//! Switching between skills blends the joint targets over the walk's `settle_s`, so no skill
//! has to start from an exact posture.

pub mod dribble;
mod gains;
pub mod getup;
#[cfg(test)]
mod handover_tests;
pub mod intent;
pub mod kick;
mod motion;
pub mod params;
pub mod pose;
pub mod save;
#[cfg(test)]
mod stand_tests;
mod status;
pub mod walk;

pub use dribble::{DribbleParams, DribbleState};
pub use intent::{BodyIntent, HeadIntent, Intent};
pub use kick::{KickGeometry, KickParams, KickState};
pub use motion::MotionId;
pub use params::{ParamsError, SkillParams};
pub use pose::{JointTarget, JointTargets};
pub use save::{DiveSide, SaveParams, SaveState};
pub use status::{ActiveSkill, SkillStatus};
pub use walk::{Velocity, Walk, WalkParams};

use libero_model::RobotModel;
use libero_world::World;

/// A blend from the previous skill's last pose into the current skill's output.
#[derive(Debug, Clone)]
struct Blend {
    start_s: f64,
    duration_s: f64,
}

/// The skill layer of one agent.
pub struct Skills {
    params: SkillParams,
    stand: Vec<f64>,
    walk: Walk,
    kick: kick::Kick,
    dribble: dribble::Dribble,
    get_up: getup::GetUp,
    save: save::Save,
    motion: motion::MotionPlayer,
    /// The pose a dive ended in, held while the robot lies and the request is still held
    /// (covering the line). Once it is dropped the stand pose is blended into while the body
    /// lies until the get-up starts: holding the end pose there instead stood 19 and 15 of 20
    /// (end pose with straight legs / with the stand's legs) against 40 of 40 (NOTES.md).
    after_dive: Option<(DiveSide, Vec<f64>)>,
    /// Standing after a get-up until the body has settled (`get_up.settle`).
    settling: Option<getup::Settling>,
    /// The robot has walked since it was last put down (a beam, a placement, a get-up): it
    /// stands in the walk's posture (`stand_in_walk_posture`).
    walked: bool,
    active: ActiveSkill,
    blend: Option<Blend>,
    /// The pose the blend starts from (kept: a blend starts at every change of skill).
    blend_from: Vec<f64>,
    /// The pose sent last cycle [deg per joint].
    last_pose: Vec<f64>,
    /// New parameters changed the stand pose: blend into it from the next cycle on.
    stand_changed: bool,
    pose: Vec<f64>,
    gains: gains::GainTable,
    save_motions: save::SaveMotions,
    /// The key-frame kicks per foot, built when the parameters load.
    kick_frames: kick::KickFrames,
}

impl Skills {
    pub fn new(model: &RobotModel, params: SkillParams) -> Result<Self, ParamsError> {
        params.validate(model)?;
        let stand = params.stand_pose(model)?;
        Ok(Self {
            walk: Walk::new(model)?,
            kick: kick::Kick::new(model)?,
            dribble: dribble::Dribble::default(),
            get_up: getup::GetUp::new().with_room(model.joints.len()),
            save: save::Save::new().with_room(model.joints.len()),
            motion: motion::MotionPlayer::new(model.joints.len()),
            after_dive: None,
            settling: None,
            walked: false,
            gains: gains::GainTable::new(model, &params),
            save_motions: params.save.motions(),
            kick_frames: kick::KickFrames::of(&params.kick),
            params,
            last_pose: stand.clone(),
            pose: stand.clone(),
            stand,
            active: ActiveSkill::Stand,
            blend: None,
            blend_from: Vec::new(),
            stand_changed: false,
        })
    }

    pub fn params(&self) -> &SkillParams {
        &self.params
    }

    /// Swap in new parameters (hot reload, optimizer trials). A changed stand pose is blended
    /// into over the walk's `settle_s` (a jump in every leg joint at once throws the robot);
    /// the walk picks the new numbers up from its next cycle.
    pub fn set_params(
        &mut self,
        model: &RobotModel,
        params: SkillParams,
    ) -> Result<(), ParamsError> {
        params.validate(model)?;
        let stand = params.stand_pose(model)?;
        self.stand_changed |= stand != self.stand;
        self.stand = stand;
        self.gains = gains::GainTable::new(model, &params);
        self.save_motions = params.save.motions();
        self.kick_frames = kick::KickFrames::of(&params.kick);
        self.params = params;
        Ok(())
    }

    /// The stand posture [deg per joint].
    pub fn stand_pose(&self) -> &[f64] {
        &self.stand
    }

    /// The skill that produced the latest targets.
    pub fn active(&self) -> ActiveSkill {
        self.active
    }

    /// The walk engine (for its executed command and state).
    pub fn walk(&self) -> &Walk {
        &self.walk
    }

    /// Where the current kick request stands (`Idle` when no kick is requested).
    pub fn kick_state(&self) -> KickState {
        self.kick.state()
    }

    /// The active skill and the kick's state after the latest [`Self::act`].
    pub fn status(&self) -> SkillStatus {
        SkillStatus {
            active: self.active,
            kick: self.kick.state(),
            dribble: self.dribble.state(),
            kick_spread: self.params.kick.measured,
            kick_geometry: kick::KickGeometry::of(&self.params.kick),
            save: self.save.state(),
            kick_steps: self.walk.kick_steps(),
        }
    }

    /// A beam was sent: the robot will stand where it lands, so a walk, kick or dribble
    /// under way ends here (carried on, a walk lifted a foot of a robot the server had just
    /// put down on straightened legs, and it fell).
    pub fn beamed(&mut self) {
        self.walked = false;
        self.walk.reset();
        self.kick.reset();
        self.dribble.reset();
    }

    /// Where the save stands (`Idle` when none is asked for).
    pub fn save_state(&self) -> SaveState {
        self.save.state()
    }

    /// Joint targets realising `intent` this cycle.
    pub fn act(
        &mut self,
        model: &RobotModel,
        world: &World,
        intent: &Intent,
        out: &mut JointTargets,
    ) {
        self.pose.copy_from_slice(&self.stand);
        // A save goes first: it starts in the cycle it is asked for and nothing interrupts it.
        let save_request = match intent.body {
            BodyIntent::Dive { side } => Some(side),
            _ => None,
        };
        let saving = self.save.update(
            world,
            save_request,
            !self.get_up.is_running() && world.body.posture == libero_world::Posture::Upright,
            &self.save_motions,
            model,
            &mut self.pose,
        );
        // The save's last cycle (it wrote its end pose and is over).
        let ended = saving && !self.save.is_running();
        if let (true, SaveState::Done(side)) = (ended, self.save.state()) {
            if side != DiveSide::Centre {
                self.after_dive = Some((side, self.pose.clone()));
            }
        }
        let motion_request = match intent.body {
            BodyIntent::Motion { id } if !saving => Some(id),
            _ => None,
        };
        let playing_motion = self.motion.update(
            world,
            motion_request,
            &self.params.motions,
            model,
            &mut self.pose,
        );
        let saving = saving || playing_motion;
        // The get-up played out last cycle: stand until the body has settled.
        if self.active == ActiveSkill::GetUp && !self.get_up.is_running() {
            self.settling = self
                .params
                .get_up
                .settle
                .map(|_| getup::Settling::new(world.time));
        }
        let settling = match (self.settling.as_mut(), self.params.get_up.settle.as_ref()) {
            (Some(s), Some(p)) if !saving => {
                s.goes_on(p, &getup::Sensed::from_body(&world.body), world.time)
            }
            _ => false,
        };
        if !settling {
            self.settling = None;
        }
        let walk_params = &self.params.walk;
        let kick = match intent.body {
            _ if saving || settling => {
                self.kick.reset();
                None
            }
            BodyIntent::Kick {
                ball,
                direction_deg,
                distance_m,
            } => Some(self.kick.update(
                kick::KickRequest {
                    ball,
                    direction_deg: kick::aimed_for_curve(
                        direction_deg,
                        distance_m,
                        world,
                        &self.params.kick,
                    ),
                    distance_m,
                },
                world.time,
                kick::BodyNow {
                    walk_stepping: self.walk.is_stepping(),
                    walk_velocity: self.walk.executed(),
                    rate_deg_s: world.body.gyro[0].abs().max(world.body.gyro[1].abs()),
                },
                &self.params.kick,
                walk_params,
            )),
            _ => self.kick.carry_on(world.time),
        };
        let dribble = match intent.body {
            BodyIntent::Dribble {
                ball,
                direction_deg,
                ..
            } if !saving && !settling => {
                Some(
                    self.dribble
                        .update(ball, direction_deg, &self.params.dribble, walk_params),
                )
            }
            _ => {
                self.dribble.reset();
                None
            }
        };
        if let Some(v) = dribble {
            log::trace!(
                "t {:.2} dribble {:?} asks {:.2} {:.2} {:.0} executes {:?}",
                world.time,
                self.dribble.state(),
                v.forward_m_s,
                v.sideways_m_s,
                v.turn_deg_s,
                self.walk.executed()
            );
        }
        let request = match intent.body {
            _ if settling => None,
            BodyIntent::Stand
            | BodyIntent::GetUp
            | BodyIntent::Dive { .. }
            | BodyIntent::Motion { .. } => None,
            BodyIntent::Dribble { .. } => dribble,
            BodyIntent::Kick { .. } => match kick {
                Some(kick::KickOutput::Walk(v)) => v,
                _ => None,
            },
            BodyIntent::Walk {
                forward_m_s,
                sideways_m_s,
                turn_deg_s,
            } => Some(Velocity {
                forward_m_s,
                sideways_m_s,
                turn_deg_s,
            }),
            BodyIntent::WalkTo {
                target,
                heading_deg,
                max_speed_m_s,
            } => if self.walk.is_stepping() {
                walk::walk_to::velocity_towards(target, heading_deg, walk_params)
            } else {
                walk::walk_to::velocity_from_rest(target, heading_deg, walk_params)
            }
            .map(|v| v.capped(max_speed_m_s)),
        };
        // A dive played out while the request is still held: stay down in its end pose, on
        // the line, until the decision layer lets go (then the get-up starts after `rest_s`).
        let held_down = !saving
            && save_request.is_some()
            && matches!(self.save.state(), SaveState::Done(_))
            && self.after_dive.is_some();
        let getting_up = !saving
            && !held_down
            && self.get_up.update(
                world,
                intent.body == BodyIntent::GetUp,
                &self.params.get_up,
                model,
                &mut self.pose,
            );
        // Held until the get-up starts, or the robot turns out not to be lying after all.
        if getting_up
            || getup::Condition::UprightWithin(30.0).holds(&getup::Sensed::from_body(&world.body))
        {
            self.after_dive = None;
        }
        // Standing in the walk's posture, balanced (`stand_in_walk_posture`), once it walked;
        // a robot the server put down (its joints straightened: a beam, a placement) or one
        // getting up starts again from the stand pose, which it lands in without a drop.
        if getting_up || saving || joints_were_reset(world, &self.last_pose) {
            self.walked = false;
        } else if self.walk.is_stepping() {
            self.walked = true;
        }
        let mut stand_balanced = false;
        let active = if playing_motion {
            self.walk.reset();
            ActiveSkill::Motion
        } else if saving {
            self.walk.reset();
            ActiveSkill::Save
        } else if getting_up {
            self.walk.reset();
            self.kick.reset();
            ActiveSkill::GetUp
        } else if let Some((_, held)) = self.after_dive.as_ref().filter(|_| held_down) {
            self.walk.reset();
            self.pose.copy_from_slice(held);
            ActiveSkill::Save
        } else if kick == Some(kick::KickOutput::Motion) {
            self.kick.write_pose(
                world,
                &self.params.kick,
                &self.kick_frames,
                model,
                &mut self.pose,
            );
            ActiveSkill::Kick
        } else if request.is_some()
            || self.walk.is_stepping()
            || matches!(kick, Some(kick::KickOutput::Walk(None)))
        {
            // Near the kicking place the robot stops and looks in the walk's own posture, the
            // one the kick motion starts from: changing to the taller standing pose there
            // (and back when the kick starts) tips a robot that has just stopped walking
            // over backwards.
            let kick_steps =
                matches!(intent.body, BodyIntent::Dribble { kick_steps, .. } if kick_steps);
            self.walk
                .ask_kick_step(self.dribble.kick_foot().filter(|_| kick_steps));
            self.walk
                .update(world, request, walk_params, &mut self.pose);
            if dribble.is_some() {
                ActiveSkill::Dribble
            } else {
                ActiveSkill::Walk
            }
        } else if self.params.stand_in_walk_posture && self.walked && !settling {
            self.walk.update(world, None, walk_params, &mut self.pose);
            stand_balanced = true;
            ActiveSkill::Stand
        } else {
            ActiveSkill::Stand
        };
        let watched_ball = match intent.body {
            BodyIntent::Kick { ball, .. } if kick.is_some() => Some(ball),
            BodyIntent::Dribble { ball, .. } if dribble.is_some() => Some(ball),
            _ => None,
        };
        if let Some(ball) = watched_ball {
            // Keep the ball in view: while walking round it, it is beside the robot, and an
            // estimate not refreshed by sightings drifts (a bump, a phantom chase). During the
            // kick motion the head stays still, looking down at the feet.
            let a = &self.params.kick.approach;
            let (yaw, pitch) = if self.kick.state() == KickState::Kicking {
                (0.0, a.look_down_deg)
            } else {
                let distance = ball[0].hypot(ball[1]).max(0.01);
                (
                    ball[1].atan2(ball[0]).to_degrees(),
                    a.eye_height_m
                        .atan2(distance)
                        .to_degrees()
                        .min(a.look_down_deg),
                )
            };
            if let Some(id) = model.joint_id("head_yaw") {
                self.pose[id] = model.clamp_deg(id, yaw);
            }
            if let Some(id) = model.joint_id("head_pitch") {
                self.pose[id] = model.clamp_deg(id, pitch);
            }
        }
        self.switch_to(active, world.time);
        if std::mem::take(&mut self.stand_changed) && self.blend.is_none() {
            self.start_blend(world.time);
        }
        let keyframed_kick = active == ActiveSkill::Kick && self.kick.playing_keyframes();
        if !keyframed_kick
            && !matches!(
                active,
                ActiveSkill::GetUp | ActiveSkill::Save | ActiveSkill::Motion
            )
        {
            // The get-up and save motions start from the measured angles and must not be
            // softened.
            self.apply_blend(world.time);
        } else {
            self.blend = None;
        }
        out.hold_pose(model, &self.pose);
        if active == ActiveSkill::GetUp {
            self.gains.get_up(out);
        }
        if active == ActiveSkill::Save {
            let side = self
                .save
                .side()
                .or(self.after_dive.as_ref().map(|(side, _)| *side))
                .unwrap_or(DiveSide::Centre);
            self.gains.save(side, out);
        }
        // A key-frame kick plays with the model's gains, as named motions do (the frames
        // were found that way).
        if stand_balanced
            || matches!(self.active, ActiveSkill::Walk | ActiveSkill::Dribble)
            || (self.active == ActiveSkill::Kick && !keyframed_kick)
        {
            self.gains.walk(out);
        }
        if self.active == ActiveSkill::Kick {
            if let Some((foot, long)) = self.kick.swinging_with(world.time) {
                self.gains.kick_swing(foot, long, out);
            }
        }
        self.last_pose.copy_from_slice(&self.pose);
        match intent.head {
            HeadIntent::Hold => {}
            HeadIntent::LookAt { target } => {
                // The same aim as while approaching a kick: yaw to the bearing, pitch down to a
                // point on the ground from the eye height.
                let a = &self.params.kick.approach;
                let distance = target[0].hypot(target[1]).max(0.01);
                let pitch = a
                    .eye_height_m
                    .atan2(distance)
                    .to_degrees()
                    .min(a.look_down_deg);
                out.set_angle(model, "head_yaw", target[1].atan2(target[0]).to_degrees());
                out.set_angle(model, "head_pitch", pitch);
            }
            HeadIntent::LookAround {
                amplitude_deg,
                period_s,
            } => {
                let la = &self.params.look_around;
                let period = period_s.unwrap_or(la.period_s).max(0.1);
                let amplitude = amplitude_deg.unwrap_or(la.yaw_amplitude_deg);
                let phase = world.time * std::f64::consts::TAU / period;
                out.set_angle(model, "head_yaw", amplitude * phase.sin());
                out.set_angle(model, "head_pitch", la.pitch_deg);
            }
        }
    }

    fn switch_to(&mut self, active: ActiveSkill, now: f64) {
        if active != self.active {
            // Walking and dribbling are one gait, one pose after the other: a blend from the
            // pose sent last held the legs back mid-stride for `settle_s` at every hand-over
            // between the walk to the ball and the dribble (or the kick's approach), and the
            // robot at speed pitched forward over its feet (striker_alone, 16 falls in 20
            // runs from 11-14 m out; NOTES.md session 29).
            let one_gait = |s: ActiveSkill| matches!(s, ActiveSkill::Walk | ActiveSkill::Dribble);
            if !(one_gait(active) && one_gait(self.active)) {
                self.start_blend(now);
            }
            self.active = active;
        }
    }

    /// Blend from the pose sent last into what the skills produce, from `now` on.
    fn start_blend(&mut self, now: f64) {
        self.blend_from.clear();
        self.blend_from.extend_from_slice(&self.last_pose);
        self.blend = Some(Blend {
            start_s: now,
            duration_s: self.params.walk.settle_s,
        });
    }

    fn apply_blend(&mut self, now: f64) {
        let Some(blend) = &self.blend else { return };
        let t = if blend.duration_s > 0.0 {
            ((now - blend.start_s) / blend.duration_s).clamp(0.0, 1.0)
        } else {
            1.0
        };
        if t >= 1.0 {
            self.blend = None;
            return;
        }
        // Smoothstep: no jump in joint velocity at either end of the blend.
        let w = t * t * (3.0 - 2.0 * t);
        for (q, from) in self.pose.iter_mut().zip(&self.blend_from) {
            *q = from + (*q - from) * w;
        }
    }
}

/// Mean difference between the measured and the last commanded joint angles beyond which the
/// server, not the robot, has moved the joints [deg]: a beam or a monitor placement sets every
/// joint to 0 (rcssservermj), while tracking errors average a few degrees.
const JOINTS_RESET_MEAN_DEG: f64 = 10.0;

fn joints_were_reset(world: &World, last_pose: &[f64]) -> bool {
    let measured = &world.body.joint_angles;
    let n = measured.len().min(last_pose.len());
    if n == 0 {
        return false;
    }
    let total: f64 = measured
        .iter()
        .zip(last_pose)
        .map(|(m, c)| (m - c).abs())
        .sum();
    total / n as f64 > JOINTS_RESET_MEAN_DEG
}
