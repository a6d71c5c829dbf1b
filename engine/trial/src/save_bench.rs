//! Goalkeeper saves measured from the ground truth: the robot stands on its goal line facing
//! the field, is asked to dive (or block), and the body's lateral coverage of the line is
//! followed cycle by cycle until it has got up again.
//!
//! The body is approximated by points from forward kinematics of the measured joint angles on
//! the torso's ground-truth pose: torso, head top, shoulders, elbows, hands, hips, knees,
//! ankles and soles, each widened by [`LIMB_RADIUS_M`]. Coverage is the lateral span (along the
//! goal line, i.e. perpendicular to the start heading) of those points, relative to the start
//! position; all heights count (a goal is 1.8–2.4 m high).

use crate::episode::{Episode, Recording, Trial, TrialError};
use crate::getup_bench;
use libero_model::kinematics::{BodyPoses, Kinematics};
use libero_model::RobotModel;
use libero_skills::{BodyIntent, DiveSide, Intent, SaveState, SkillParams};
use libero_world::World;
use nalgebra::{Isometry3, Point3, Quaternion, Translation3, UnitQuaternion, Vector3};
use std::sync::{Arc, Mutex};

/// Half the thickness of a limb or the torso around its points [m].
pub const LIMB_RADIUS_M: f64 = 0.05;
/// Where the goalkeeper stands: on its goal line, facing the field.
pub const KEEPER_START: [f64; 3] = [-26.0, 0.0, 0.0];
/// Forearm from the elbow-yaw joint to the hand point [m]: with [`LIMB_RADIUS_M`] 0.25 m, where
/// robot.xml's hand capsule ends (centre 0.13 m along the forearm, half-length 0.0875, radius
/// 0.03: 0.2475 m).
pub const FOREARM_M: f64 = 0.2;
/// Body points below this height count for the low coverage [m].
pub const LOW_M: f64 = 0.3;
/// Head point above the head-pitch joint [m]: with [`LIMB_RADIUS_M`] 0.20 m (robot.xml: head
/// sphere of radius 0.08 centred 0.11 m above it, top at 0.19 m).
pub const HEAD_TOP_M: f64 = 0.15;

/// The lateral span of the body at one cycle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Coverage {
    /// Seconds since the save was asked for.
    pub t: f64,
    /// Lateral extent [m], + to the robot's start left: from `lo` to `hi`.
    pub lo: f64,
    pub hi: f64,
    /// The same for the body points below [`LOW_M`] (what stops a ball along the ground);
    /// NaN when there are none.
    pub low_lo: f64,
    pub low_hi: f64,
    /// Torso height [m] and tilt from vertical [deg] (ground truth).
    pub torso_z: f64,
    pub tilt_deg: f64,
    /// Torso roll [deg], + right side down (ground truth), and pitch, + nose down.
    pub roll_deg: f64,
    pub pitch_deg: f64,
    /// What the skills reported.
    pub save: SaveState,
}

/// Body points in the world from FK on the ground-truth torso pose.
#[derive(Clone)]
pub struct BodyPoints {
    kin: Kinematics,
    poses: BodyPoses,
    /// Joint ids and the point's offset in that joint's frame.
    points: Vec<(usize, Vector3<f64>)>,
    frames: Vec<usize>,
}

impl BodyPoints {
    pub fn new(model: &RobotModel) -> Self {
        let kin = Kinematics::new(model);
        let mut points = Vec::new();
        let mut add = |name: &str, offset: [f64; 3]| {
            if let Some(id) = model.joint_id(name) {
                points.push((id, Vector3::from(offset)));
            }
        };
        add("head_pitch", [0.0, 0.0, HEAD_TOP_M]);
        for side in ["left", "right"] {
            let y = if side == "left" { 1.0 } else { -1.0 };
            add(&format!("{side}_shoulder_pitch"), [0.0; 3]);
            add(&format!("{side}_elbow_yaw"), [0.0; 3]);
            add(&format!("{side}_elbow_yaw"), [0.0, y * FOREARM_M, 0.0]);
            add(&format!("{side}_hip_pitch"), [0.0; 3]);
            add(&format!("{side}_knee"), [0.0; 3]);
            add(&format!("{side}_ankle_roll"), [0.0; 3]);
        }
        let frames = ["left_sole", "right_sole"]
            .iter()
            .filter_map(|f| kin.frame_id(f))
            .collect();
        Self {
            poses: kin.new_poses(),
            kin,
            points,
            frames,
        }
    }

    /// The points in the world frame (torso origin first); empty without ground truth.
    pub fn world_points(&mut self, world: &World) -> Vec<Point3<f64>> {
        let (Some(p), Some(q)) = (world.truth.torso_position, world.truth.torso_orientation) else {
            return Vec::new();
        };
        if self
            .kin
            .forward(&world.body.joint_angles, &mut self.poses)
            .is_err()
        {
            return Vec::new();
        }
        let torso = Isometry3::from_parts(
            Translation3::new(p[0], p[1], p[2]),
            UnitQuaternion::from_quaternion(Quaternion::new(q[0], q[1], q[2], q[3])),
        );
        let mut out = vec![torso * Point3::origin()];
        for (joint, offset) in &self.points {
            if let Some(j) = self.poses.joint_in_torso(*joint) {
                out.push(torso * (j * Point3::from(*offset)));
            }
        }
        for &f in &self.frames {
            if let Some(frame) = self.poses.frame_in_torso(f) {
                out.push(torso * (frame * Point3::origin()));
            }
        }
        out
    }
}

/// One save and what followed.
#[derive(Debug, Clone)]
pub struct SaveRun {
    pub side: DiveSide,
    /// Coverage at every cycle from the request on.
    pub coverage: Vec<Coverage>,
    /// Seconds from the request until the torso is 30° from vertical.
    pub tilt_30_s: Option<f64>,
    /// Seconds from the request until the robot stood again for good (torso ≥ 0.60 m,
    /// ≤ 20° from vertical, for 1.5 s), counted only after it had been down.
    pub stood_at: Option<f64>,
    /// Whether the robot fell (torso low or detector) at all.
    pub fell: bool,
    pub recording: Recording,
}

impl SaveRun {
    /// The coverage of the side the save goes to: a span reaching `offset_m` on that side
    /// (+ left of the start for `Left` and `Centre`, + right for `Right`).
    fn reach(&self, c: &Coverage) -> f64 {
        match self.side {
            DiveSide::Right => -c.lo,
            _ => c.hi,
        }
    }

    /// The span on the near side (towards the start point) for the side the save goes to.
    fn near(&self, c: &Coverage) -> f64 {
        match self.side {
            DiveSide::Right => -c.hi,
            _ => c.lo,
        }
    }

    /// Seconds from the request until the body first covers the goal line `offset_m` beside
    /// the start point on the save's side (both sides for a block: the smaller reach counts).
    pub fn covers_at(&self, offset_m: f64) -> Option<f64> {
        self.coverage
            .iter()
            .find(|c| self.covered(c, offset_m))
            .map(|c| c.t)
    }

    fn covered(&self, c: &Coverage, offset_m: f64) -> bool {
        match self.side {
            DiveSide::Centre => c.hi >= offset_m && -c.lo >= offset_m,
            _ => self.reach(c) >= offset_m,
        }
    }

    /// Seconds from the request until the body covers the whole stretch from `near_m` to
    /// `far_m` beside the start point at one time (dives).
    pub fn covers_span_at(&self, near_m: f64, far_m: f64) -> Option<f64> {
        self.coverage
            .iter()
            .find(|c| self.near(c) <= near_m && self.reach(c) >= far_m)
            .map(|c| c.t)
    }

    /// The furthest lateral reach on the save's side [m] (for a block, the smaller side).
    pub fn max_reach(&self) -> f64 {
        self.coverage
            .iter()
            .map(|c| match self.side {
                DiveSide::Centre => c.hi.min(-c.lo),
                _ => self.reach(c),
            })
            .fold(f64::NEG_INFINITY, f64::max)
    }

    /// The coverage at about `t` seconds (the first sample at or after it).
    pub fn at(&self, t: f64) -> Option<&Coverage> {
        self.coverage.iter().find(|c| c.t >= t - 1e-6)
    }
}

/// Stand at `start` (world x, y, heading), settle, ask for the save once and keep asking until
/// the skills report it done; then stand (the get-up follows on its own) until `until_s`
/// seconds after the request.
pub fn save(
    trial: &mut Trial,
    params: &SkillParams,
    side: DiveSide,
    start: [f64; 3],
    until_s: f64,
) -> Result<SaveRun, TrialError> {
    save_after(trial, params, side, start, None, 0.0, until_s)
}

/// [`save`] after `lead_in`: that intent for that many seconds first (e.g. walking sideways),
/// the save asked for straight out of it. Coverage is measured from where the torso is at the
/// request, along the start heading's lateral axis; all times count from the request. The
/// request is held until the save is done and at least `hold_s` after the request (after a
/// dive the robot then stays down that long).
pub fn save_after(
    trial: &mut Trial,
    params: &SkillParams,
    side: DiveSide,
    start: [f64; 3],
    lead_in: Option<(BodyIntent, f64)>,
    hold_s: f64,
    until_s: f64,
) -> Result<SaveRun, TrialError> {
    let (lead_intent, lead_s) = lead_in.unwrap_or((BodyIntent::Stand, 0.0));
    let status = trial.skill_status();
    let model = trial.model().clone();
    let coverage = Arc::new(Mutex::new(Vec::<Coverage>::new()));
    let tracer = BodyPoints::new(&model);
    let cov = Arc::clone(&coverage);
    let heading = start[2].to_radians();
    // Lateral: the start frame's y axis.
    let lateral = Vector3::new(-heading.sin(), heading.cos(), 0.0);
    let mut origin: Option<Vector3<f64>> = None;
    let mut tracer_state = tracer;
    let mut done = false;
    let script = move |w: &World, t: f64| {
        if t < lead_s {
            return Some(Intent {
                body: lead_intent,
                ..Intent::default()
            });
        }
        let t = t - lead_s;
        let origin = *origin.get_or_insert_with(|| match w.truth.torso_position {
            Some([x, y, _]) => Vector3::new(x, y, 0.0),
            None => Vector3::new(start[0], start[1], 0.0),
        });
        let state = status.lock().map(|s| s.save).unwrap_or_default();
        done |= matches!(state, SaveState::Done(_));
        let points = tracer_state.world_points(w);
        if let Some(torso) = points.first() {
            let span = |low_only: bool| {
                points
                    .iter()
                    .filter(|p| !low_only || p.z < LOW_M)
                    .map(|p| (p.coords - origin).dot(&lateral))
                    .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), y| {
                        (lo.min(y), hi.max(y))
                    })
            };
            let (lo, hi) = span(false);
            let (low_lo, low_hi) = match span(true) {
                (lo, hi) if lo <= hi => (lo - LIMB_RADIUS_M, hi + LIMB_RADIUS_M),
                _ => (f64::NAN, f64::NAN),
            };
            let [qw, qx, qy, qz] = w.truth.torso_orientation.unwrap_or([f64::NAN; 4]);
            let tilt = (1.0 - 2.0 * (qx * qx + qy * qy))
                .clamp(-1.0, 1.0)
                .acos()
                .to_degrees();
            let roll = -(2.0 * (qw * qx + qy * qz))
                .atan2(1.0 - 2.0 * (qx * qx + qy * qy))
                .to_degrees();
            let pitch = (2.0 * (qw * qy - qz * qx))
                .clamp(-1.0, 1.0)
                .asin()
                .to_degrees();
            if let Ok(mut c) = cov.lock() {
                c.push(Coverage {
                    t,
                    lo: lo - LIMB_RADIUS_M,
                    hi: hi + LIMB_RADIUS_M,
                    low_lo,
                    low_hi,
                    torso_z: torso.z,
                    tilt_deg: tilt,
                    roll_deg: roll,
                    pitch_deg: pitch,
                    save: state,
                });
            }
        }
        if t >= until_s {
            return None;
        }
        // After the save: stand; the fall detector starts the get-up once the body has lain
        // still for `get_up.rest_s`.
        let body = if !done || t < hold_s {
            BodyIntent::Dive { side }
        } else {
            BodyIntent::Stand
        };
        Some(Intent {
            body,
            ..Intent::default()
        })
    };
    let recording = trial.run(
        params,
        Episode {
            start,
            lying: None,
            settle_s: 1.0,
            script,
        },
    )?;
    let coverage = std::mem::take(&mut *coverage.lock().expect("coverage lock"));
    let tilt_30_s = coverage.iter().find(|c| c.tilt_deg >= 30.0).map(|c| c.t);
    // From the request on, with its times.
    let from_request = Recording {
        samples: recording
            .samples
            .iter()
            .filter(|s| s.t >= lead_s)
            .map(|s| crate::Sample {
                t: s.t - lead_s,
                ..*s
            })
            .collect(),
        intents: Vec::new(),
    };
    let fell = from_request.fell();
    let first_down = from_request.first_fall_s();
    let stood_at = first_down.and_then(|down| {
        let after = Recording {
            samples: from_request
                .samples
                .iter()
                .filter(|s| s.t >= down)
                .copied()
                .collect(),
            intents: Vec::new(),
        };
        getup_bench::stood_up_at(&after, getup_bench::STANDING_HOLD_S)
    });
    Ok(SaveRun {
        side,
        coverage,
        tilt_30_s,
        stood_at,
        fell,
        recording,
    })
}
