//! Named key-frame motions a decision or a script may ask for by name (`motions` in the
//! parameter file): a fall onto the front or the back that a get-up trial starts from on a
//! server that cannot lay a robot down (SimSpark), a celebration, a keeper's stretch.

use crate::getup::{step, Keyframe, Playhead, Sensed, Step};
use libero_model::RobotModel;
use libero_world::World;
use std::collections::BTreeMap;

/// A motion of the parameter file, by its place in the file's (sorted) `motions`: resolve a
/// name with [`crate::SkillParams::motion_id`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MotionId(pub u16);

/// The motion being played, if any.
#[derive(Debug, Clone)]
pub(crate) struct MotionPlayer {
    playing: Option<MotionId>,
    head: Playhead,
    /// The motion played to its end while still asked for: its last pose is held.
    ended: bool,
}

impl MotionPlayer {
    pub(crate) fn new(joints: usize) -> Self {
        Self {
            playing: None,
            head: Playhead::with_room(joints),
            ended: false,
        }
    }

    /// Play `request` (from the measured angles when it is new), writing `pose`; `false` when
    /// no motion is asked for (or the one asked for is not in `motions`).
    pub(crate) fn update(
        &mut self,
        world: &World,
        request: Option<MotionId>,
        motions: &BTreeMap<String, Vec<Keyframe>>,
        model: &RobotModel,
        pose: &mut [f64],
    ) -> bool {
        let frames = request.and_then(|id| motions.values().nth(usize::from(id.0)));
        let (Some(id), Some(frames)) = (request, frames) else {
            self.playing = None;
            return false;
        };
        if self.playing != Some(id) {
            self.playing = Some(id);
            self.ended = false;
            self.head.restart(&world.body.joint_angles, world.time);
        }
        if self.ended {
            pose.copy_from_slice(&self.head.from);
            return true;
        }
        let sensed = Sensed::from_body(&world.body);
        match step(&mut self.head, frames, world.time, &sensed, model, pose) {
            Step::Playing => {}
            // A frame whose condition never came ends the motion where it is.
            Step::Ended | Step::TimedOut(_) => self.ended = true,
        }
        true
    }
}

#[cfg(test)]
mod tests {
    use crate::{ActiveSkill, BodyIntent, Intent, JointTargets, SkillParams, Skills};
    use libero_model::RobotModel;
    use libero_world::{Posture, World};

    const BOW: &str = r#"{
        "bow": [
            Keyframe(duration_s: 0.2, pose: {"left_knee": -60.0}),
            Keyframe(duration_s: 0.2, pose: {"left_knee": -90.0}),
        ],
        "wave": [Keyframe(duration_s: 0.5, pose: {"right_shoulder_pitch": 60.0})],
    }"#;

    fn with_motions(motions: &str) -> (RobotModel, SkillParams) {
        let model = RobotModel::builtin("nao_type0").unwrap();
        let mut params = SkillParams::builtin(&model).unwrap();
        params.motions = ron::from_str(motions).unwrap();
        (model, params)
    }

    #[test]
    fn a_motion_plays_its_frames_then_holds_and_keeps_the_get_up_waiting() {
        let (model, params) = with_motions(BOW);
        let bow = params.motion_id("bow").unwrap();
        assert_eq!(params.motion_id("wave").map(|m| m.0), Some(1));
        assert_eq!(params.motion_id("dance"), None);
        let mut skills = Skills::new(&model, params).unwrap();
        let mut world = World::new(&model, "t", 1);
        let knee = model.joint_id("left_knee").unwrap();
        let mut out = JointTargets::default();
        let ask = Intent {
            body: BodyIntent::Motion { id: bow },
            ..Intent::default()
        };
        let mut knee_at = |skills: &mut Skills, world: &mut World, t: f64, intent: &Intent| {
            world.time = t;
            skills.act(&model, world, intent, &mut out);
            out.joints[knee].q_deg
        };
        assert_eq!(knee_at(&mut skills, &mut world, 10.0, &ask), 0.0);
        let halfway = knee_at(&mut skills, &mut world, 10.1, &ask);
        assert!((halfway + 30.0).abs() < 1e-6, "{halfway}");
        assert_eq!(skills.active(), ActiveSkill::Motion);
        // Lying now, as far as the fall detector knows: the motion goes on regardless.
        world.body.posture = Posture::FallenFront;
        assert!((knee_at(&mut skills, &mut world, 10.3, &ask) + 75.0).abs() < 1e-6);
        for t in [10.4, 11.0, 12.0] {
            assert!((knee_at(&mut skills, &mut world, t, &ask) + 90.0).abs() < 1e-6);
            assert_eq!(skills.active(), ActiveSkill::Motion);
        }
        // Let go: the get-up takes over once the robot has rested.
        let stand = Intent::default();
        for k in 0..100 {
            knee_at(&mut skills, &mut world, 12.02 + 0.02 * f64::from(k), &stand);
        }
        assert_eq!(skills.active(), ActiveSkill::GetUp);
    }

    #[test]
    fn a_motion_with_an_unknown_joint_is_refused_by_name() {
        let (model, params) =
            with_motions(r#"{"kneel": [Keyframe(duration_s: 0.2, pose: {"left_kneee": -60.0})]}"#);
        let err = params.validate(&model).unwrap_err().to_string();
        assert!(
            err.contains("motions.kneel") && err.contains("left_kneee"),
            "{err}"
        );
    }
}
