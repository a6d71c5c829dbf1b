//! The joint gains the skills override, resolved to joint indices once per parameter set.
//!
//! Every cycle of a walk, kick or save sets some of them; resolving the names each cycle
//! (formatting `left_…`/`right_…` names, looking them up in the model) allocated and compared
//! strings on the per-cycle path.

use crate::kick::KickParams;
use crate::params::SkillParams;
use crate::pose::JointTargets;
use crate::save::DiveSide;
use crate::walk::gait::Foot;
use libero_model::{Gains, RobotModel};
use std::collections::BTreeMap;

/// (joint index, gains) pairs of joints the model has.
type Resolved = Vec<(usize, Gains)>;

#[derive(Debug, Clone, Default)]
pub struct GainTable {
    /// The walk's leg gains, both legs.
    walk_legs: Resolved,
    /// The kick's swing-leg gains by [short, long] and [left, right] kicking foot.
    kick_swing: [[Resolved; 2]; 2],
    /// The save's gains by [left, right, centre] dive.
    save: [Resolved; 3],
    get_up: Resolved,
}

fn both_legs(model: &RobotModel, per_leg: &BTreeMap<String, Gains>) -> [Resolved; 2] {
    ["left", "right"].map(|side| {
        per_leg
            .iter()
            .filter_map(|(joint, g)| Some((model.joint_id(&format!("{side}_{joint}"))?, *g)))
            .collect()
    })
}

fn by_name(model: &RobotModel, gains: impl IntoIterator<Item = (String, Gains)>) -> Resolved {
    gains
        .into_iter()
        .filter_map(|(joint, g)| Some((model.joint_id(&joint)?, g)))
        .collect()
}

impl GainTable {
    pub fn new(model: &RobotModel, params: &SkillParams) -> Self {
        let [left, right] = both_legs(model, &params.walk.leg_gains);
        let kick = |k: &KickParams| {
            [
                both_legs(model, &k.short.swing_gains),
                both_legs(model, &k.long.swing_gains),
            ]
        };
        Self {
            walk_legs: left.into_iter().chain(right).collect(),
            kick_swing: kick(&params.kick),
            save: [DiveSide::Left, DiveSide::Right, DiveSide::Centre]
                .map(|side| by_name(model, params.save.gains_for(side))),
            get_up: by_name(
                model,
                params.get_up.gains.iter().map(|(j, g)| (j.clone(), *g)),
            ),
        }
    }

    pub fn walk(&self, out: &mut JointTargets) {
        out.set_gains_of(&self.walk_legs);
    }

    pub fn kick_swing(&self, foot: Foot, long: bool, out: &mut JointTargets) {
        let foot = match foot {
            Foot::Left => 0,
            Foot::Right => 1,
        };
        out.set_gains_of(&self.kick_swing[usize::from(long)][foot]);
    }

    pub fn get_up(&self, out: &mut JointTargets) {
        out.set_gains_of(&self.get_up);
    }

    pub fn save(&self, side: DiveSide, out: &mut JointTargets) {
        let side = match side {
            DiveSide::Left => 0,
            DiveSide::Right => 1,
            DiveSide::Centre => 2,
        };
        out.set_gains_of(&self.save[side]);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_named_gain_lands_on_its_joint_and_only_there() {
        let model = RobotModel::builtin("T1").unwrap();
        let params = SkillParams::builtin(&model).unwrap();
        let table = GainTable::new(&model, &params);
        let stand = vec![0.0; model.joints.len()];
        let fresh = || {
            let mut t = JointTargets::default();
            t.hold_pose(&model, &stand);
            t
        };
        let mut walking = fresh();
        table.walk(&mut walking);
        for (joint, g) in &params.walk.leg_gains {
            for side in ["left", "right"] {
                let id = model.joint_id(&format!("{side}_{joint}")).unwrap();
                assert_eq!((walking.joints[id].kp, walking.joints[id].kd), (g.kp, g.kd));
            }
        }
        let untouched = fresh();
        let changed = |t: &JointTargets| {
            t.joints
                .iter()
                .zip(&untouched.joints)
                .filter(|(a, b)| (a.kp, a.kd) != (b.kp, b.kd))
                .count()
        };
        assert!(changed(&walking) <= 2 * params.walk.leg_gains.len());
        for long in [false, true] {
            let swing = if long {
                &params.kick.long.swing_gains
            } else {
                &params.kick.short.swing_gains
            };
            let mut kicking = fresh();
            table.kick_swing(Foot::Right, long, &mut kicking);
            for (joint, g) in swing.iter() {
                let id = model.joint_id(&format!("right_{joint}")).unwrap();
                assert_eq!(kicking.joints[id].kp, g.kp);
            }
            assert!(changed(&kicking) <= swing.len());
        }
    }
}
