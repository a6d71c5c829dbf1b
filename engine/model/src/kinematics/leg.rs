//! Six-joint leg IK: a closed-form solution of the leg's main geometry, polished on the exact chain.
//!
//! Closed form (both leg kinds): the hip point is fixed by the hip joints above the yaw axis; the
//! ankle roll follows from the hip direction seen from the foot, the knee from the law of cosines on
//! thigh and shank (knee offsets included), the ankle pitch from the hip direction in the shank
//! plane, and the three hip angles from the remaining rotation (Booster: Ry·Rx·Rz Euler angles; NAO:
//! the 45° yaw-pitch axis turned onto z, then Rz·Rx·Ry). The few sub-millimetre offsets this ignores
//! (ankle roll 0.25 mm sideways, ankle pitch/roll axes 5–12 mm apart, Booster hip pitch/roll 20–26
//! mm apart, handled by re-solving with the updated hip point) are removed by a few damped
//! Gauss–Newton steps on the exact chain, which start next to the answer and converge in 1–3 steps.

use super::chain::{check_len, Chain};
use super::forward::Kinematics;
use super::numeric::{IkOptions, IkReport, IkTarget, NumericIk};
use super::KinematicsError;
use crate::robot::{JointId, RobotModel};
use nalgebra::{Isometry3, Matrix3, Rotation3, Vector3};
use std::f64::consts::PI;

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Side {
    Left,
    Right,
}

impl Side {
    fn prefix(self) -> &'static str {
        match self {
            Side::Left => "left",
            Side::Right => "right",
        }
    }
}

/// The hip arrangements the closed form knows.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LegKind {
    /// Booster T1/K1: hip pitch (y) → roll (x) → yaw (z) → knee → ankle pitch → ankle roll.
    Booster,
    /// NAO: hip yaw-pitch (45° in the y-z plane) → roll (x) → pitch (y) → knee → ankle pitch → roll.
    Nao,
}

/// Which of the two law-of-cosines knee solutions to take.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum KneeBranch {
    /// Flexed the ordinary way (the larger flexion).
    Bent,
    /// The mirror solution about the hip–ankle line.
    Straighter,
}

const JOINTS_BOOSTER: [&str; 6] = [
    "hip_pitch",
    "hip_roll",
    "hip_yaw",
    "knee",
    "ankle_pitch",
    "ankle_roll",
];
const JOINTS_NAO: [&str; 6] = [
    "hip_yaw_pitch",
    "hip_roll",
    "hip_pitch",
    "knee",
    "ankle_pitch",
    "ankle_roll",
];

/// Leg IK for one leg of one model. Targets are the pose of the `<side>_sole` frame in the torso
/// frame; joints above the hip (the T1 waist) are read from the angle vector and kept.
#[derive(Debug, Clone)]
pub struct LegIk {
    kind: LegKind,
    joints: [JointId; 6],
    /// Joint origins in the parent joint frame (index 0: in the leg's base frame).
    origins: [Vector3<f64>; 6],
    /// ±1: the sign relating each joint angle to a rotation about the positive principal axis.
    signs: [f64; 6],
    /// NAO: the yaw-pitch axis.
    hip_axis: Vector3<f64>,
    limits_deg: [(f64, f64); 6],
    /// Sole frame → ankle-roll frame.
    sole_to_ankle: Isometry3<f64>,
    polish: NumericIk,
}

/// A joint axis that must be ±`principal`; returns the sign.
fn principal_sign(axis: &[f64; 3], principal: usize, joint: &str) -> Result<f64, KinematicsError> {
    let v = Vector3::from(*axis);
    let s = v[principal];
    if (s.abs() - 1.0).abs() < 1e-9 {
        Ok(s.signum())
    } else {
        Err(KinematicsError::UnsupportedLeg(format!(
            "joint `{joint}` must turn about ±{} (axis {v:?})",
            ["x", "y", "z"][principal]
        )))
    }
}

impl LegIk {
    /// The solvers for both legs, left first.
    pub fn both(model: &RobotModel, kin: &Kinematics) -> Result<[Self; 2], KinematicsError> {
        Ok([
            Self::new(model, kin, Side::Left)?,
            Self::new(model, kin, Side::Right)?,
        ])
    }

    /// Build the solver for `side` of `model` (T1, K1 or any NAO type).
    pub fn new(model: &RobotModel, kin: &Kinematics, side: Side) -> Result<Self, KinematicsError> {
        let prefix = side.prefix();
        let nao = model.joint_id(&format!("{prefix}_hip_yaw_pitch")).is_some();
        let (kind, names) = if nao {
            (LegKind::Nao, JOINTS_NAO)
        } else {
            (LegKind::Booster, JOINTS_BOOSTER)
        };
        let mut joints = [0; 6];
        let mut origins = [Vector3::zeros(); 6];
        for (k, short) in names.iter().enumerate() {
            let name = format!("{prefix}_{short}");
            let id = model
                .joint_id(&name)
                .ok_or_else(|| KinematicsError::UnknownJoint(name.clone()))?;
            let joint = &model.joints[id];
            if joint.rotation != [1.0, 0.0, 0.0, 0.0] {
                return Err(KinematicsError::UnsupportedLeg(format!(
                    "joint `{name}` has a fixed rotation"
                )));
            }
            if k > 0 && joint.parent.as_deref() != Some(&format!("{prefix}_{}", names[k - 1])) {
                return Err(KinematicsError::UnsupportedLeg(format!(
                    "joint `{name}` is not mounted on `{prefix}_{}`",
                    names[k - 1]
                )));
            }
            joints[k] = id;
            origins[k] = Vector3::from(joint.origin);
        }
        let axis = |k: usize| &model.joints[joints[k]].axis;
        let name = |k: usize| model.joints[joints[k]].name.as_str();
        let principal = match kind {
            LegKind::Booster => [1, 0, 2, 1, 1, 0],
            LegKind::Nao => [usize::MAX, 0, 1, 1, 1, 0],
        };
        let mut signs = [1.0; 6];
        for k in 0..6 {
            if principal[k] != usize::MAX {
                signs[k] = principal_sign(axis(k), principal[k], name(k))?;
            }
        }
        let hip_axis = Vector3::from(*axis(0));
        if kind == LegKind::Nao && (hip_axis.x.abs() > 1e-9 || hip_axis.z.abs() < 1e-3) {
            return Err(KinematicsError::UnsupportedLeg(format!(
                "joint `{}` must turn about an axis in the y-z plane",
                name(0)
            )));
        }
        let sole = format!("{prefix}_sole");
        let frame = model
            .frame(&sole)
            .ok_or_else(|| KinematicsError::UnknownFrame(sole.clone()))?;
        if frame.parent.as_deref() != Some(name(5)) {
            return Err(KinematicsError::UnsupportedLeg(format!(
                "frame `{sole}` must be fixed to `{}`",
                name(5)
            )));
        }
        let sole_to_ankle = super::forward::isometry(&frame.origin, &frame.rotation).inverse();
        let chain = Chain::to_frame(kin, Some(name(0)), &sole)?;
        let options = IkOptions {
            max_iterations: 200,
            position_tolerance: 1e-6,
            orientation_tolerance: 1e-5,
            ..IkOptions::default()
        };
        let limits_deg = joints.map(|j| model.joints[j].limits_deg);
        Ok(Self {
            kind,
            limits_deg,
            joints,
            origins,
            signs,
            hip_axis,
            sole_to_ankle,
            polish: NumericIk::new(chain, options),
        })
    }

    pub fn kind(&self) -> LegKind {
        self.kind
    }

    /// The six leg joints, hip first.
    pub fn joints(&self) -> &[JointId; 6] {
        &self.joints
    }

    /// Set the six leg joints in `angles_deg` so that the sole reaches `sole_in_torso`. Joints
    /// outside the leg are read (the waist) and left unchanged. Unreachable targets give the closest
    /// pose found within the joint limits with `reached == false`; no angle is ever NaN.
    pub fn solve(
        &self,
        kin: &Kinematics,
        sole_in_torso: &Isometry3<f64>,
        angles_deg: &mut [f64],
    ) -> Result<IkReport, KinematicsError> {
        check_len(kin, angles_deg)?;
        let target = IkTarget::Pose(*sole_in_torso);
        let base = self.polish.chain().base_pose(kin, angles_deg);
        let foot = base.inverse() * sole_in_torso * self.sole_to_ankle;
        if !foot.translation.vector.iter().all(|v| v.is_finite())
            || !foot.rotation.coords.iter().all(|v| v.is_finite())
        {
            return Err(KinematicsError::NonFiniteTarget);
        }
        let start = self.joints.map(|j| angles_deg[j]);
        let mut best: Option<(IkReport, [f64; 6])> = None;
        // The closed form starts its hip-point iteration from a guess of hip pitch and roll. From
        // (0, 0) it lands on the answer except near the Booster hip's gimbal lock (|roll| ≈ 90°),
        // where other guesses do. The caller's own angles (usually last cycle's) are the last resort.
        for guess in self.guesses() {
            let attempt = match guess {
                Some((hip, knee)) => self.closed_form_from(&foot, hip, knee),
                None => Some(start),
            };
            let Some(attempt) = attempt else { continue };
            self.write(angles_deg, &attempt);
            let report = self.polish.solve(kin, &target, angles_deg)?;
            let result = self.joints.map(|j| angles_deg[j]);
            if report.reached {
                return Ok(report);
            }
            if best
                .as_ref()
                .is_none_or(|(b, _)| cost(&report, &self.polish) < cost(b, &self.polish))
            {
                best = Some((report, result));
            }
        }
        let (report, result) = best.ok_or(KinematicsError::NonFiniteTarget)?;
        self.write(angles_deg, &result);
        Ok(report)
    }

    /// Closed-form starts: (hip pitch, hip roll) guesses [rad] and knee branch; `None` = the
    /// caller's angles.
    fn guesses(&self) -> impl Iterator<Item = Option<((f64, f64), KneeBranch)>> {
        let extra: &[(f64, f64)] = match self.kind {
            LegKind::Booster => &[
                (-1.5, 1.4),
                (-1.5, -1.4),
                (1.5, 1.4),
                (1.5, -1.4),
                (-2.5, 1.4),
                (-2.5, -1.4),
                (0.8, 1.5),
                (0.8, -1.5),
                (-0.8, 1.5),
                (-0.8, -1.5),
                // A leg swung far forward (K1 hip pitch reaches −172°).
                (-2.6, 0.4),
                (-2.6, -0.4),
                (-3.0, 0.0),
            ],
            LegKind::Nao => &[],
        };
        let bent = |hip| Some((hip, KneeBranch::Bent));
        let straighter = |hip| Some((hip, KneeBranch::Straighter));
        // The knee axis sits slightly behind the thigh line, so a nearly straight knee has two
        // solutions (a few degrees either side of the thigh line); each start is tried with both.
        [bent((0.0, 0.0)), straighter((0.0, 0.0))]
            .into_iter()
            .chain(extra.iter().copied().map(bent))
            .chain(extra.iter().copied().map(straighter))
            .chain(std::iter::once(None))
    }

    fn write(&self, angles_deg: &mut [f64], leg: &[f64; 6]) {
        for (k, &j) in self.joints.iter().enumerate() {
            angles_deg[j] = leg[k];
        }
    }

    /// Leg angles [deg] for the ankle-roll frame pose `foot` in the leg's base frame, from the
    /// closed form alone; `None` when the target is not finite.
    pub fn closed_form(&self, foot: &Isometry3<f64>) -> Option<[f64; 6]> {
        self.closed_form_from(foot, (0.0, 0.0), KneeBranch::Bent)
    }

    fn closed_form_from(
        &self,
        foot: &Isometry3<f64>,
        hip_guess: (f64, f64),
        knee: KneeBranch,
    ) -> Option<[f64; 6]> {
        let r_foot = foot.rotation.to_rotation_matrix();
        let p_foot = foot.translation.vector;
        let o = &self.origins;
        let (thigh, shank) = (o[3], o[4]);
        let mut rho = [hip_guess.0, hip_guess.1, 0.0, 0.0, 0.0, 0.0];
        // Fixed-point passes: the Booster hip point depends on the hip pitch/roll of the previous
        // pass (2 suffice for ordinary poses, legs swung far forward need more).
        for _ in 0..4 {
            let hip = match self.kind {
                LegKind::Booster => {
                    o[0] + Rotation3::from_axis_angle(&Vector3::y_axis(), rho[0])
                        * (o[1] + Rotation3::from_axis_angle(&Vector3::x_axis(), rho[1]) * o[2])
                }
                LegKind::Nao => o[0] + o[1] + o[2],
            };
            let v = r_foot.inverse() * (hip - p_foot);
            // Of the two rolls that put the hip in the ankle-pitch plane, the one within ±90°:
            // the other turns the foot upside down, beyond every ankle's limits.
            rho[5] = half_turn_range(v.y.atan2(v.z));
            let w = Rotation3::from_axis_angle(&Vector3::x_axis(), rho[5]) * v + o[5];
            let reach = (w.x * w.x + w.z * w.z).sqrt();
            let (lt, ls) = (planar_len(&thigh), planar_len(&shank));
            let cos_inner =
                ((reach * reach - lt * lt - ls * ls) / (2.0 * lt * ls)).clamp(-1.0, 1.0);
            let inner = match knee {
                KneeBranch::Bent => cos_inner.acos(),
                KneeBranch::Straighter => -cos_inner.acos(),
            };
            rho[3] = wrap(planar_angle(&thigh) - planar_angle(&shank)) + inner;
            let u = -(shank + Rotation3::from_axis_angle(&Vector3::y_axis(), -rho[3]) * thigh);
            rho[4] = wrap(planar_angle(&u) - planar_angle(&w));
            let hip_rotation = r_foot.matrix()
                * Rotation3::from_axis_angle(&Vector3::x_axis(), rho[5])
                    .matrix()
                    .transpose()
                * Rotation3::from_axis_angle(&Vector3::y_axis(), rho[3] + rho[4])
                    .matrix()
                    .transpose();
            let (r0, r1, r2) = match self.kind {
                LegKind::Booster => euler_yxz(&hip_rotation),
                LegKind::Nao => self.nao_hip(&hip_rotation),
            };
            rho[0] = r0;
            rho[1] = r1;
            rho[2] = r2;
        }
        let mut angles = [0.0; 6];
        for k in 0..6 {
            let (lo, hi) = self.limits_deg[k];
            angles[k] = into_limits((self.signs[k] * rho[k]).to_degrees(), lo, hi);
        }
        angles.iter().all(|a| a.is_finite()).then_some(angles)
    }

    /// NAO hip: R = Rot(axis, a1)·Rx(ρ2)·Ry(ρ3). Turning the yaw-pitch axis onto ±z with Rx(ψ)
    /// leaves Rx(ψ)ᵀ·R = Rz(κ·a1)·Rx(ρ2 − ψ)·Ry(ρ3), a plain Z-X-Y Euler decomposition.
    fn nao_hip(&self, r: &Matrix3<f64>) -> (f64, f64, f64) {
        let kappa = self.hip_axis.z.signum();
        let psi = (-kappa * self.hip_axis.y).atan2(kappa * self.hip_axis.z);
        let m = Rotation3::from_axis_angle(&Vector3::x_axis(), psi)
            .matrix()
            .transpose()
            * r;
        let beta = m[(2, 1)].clamp(-1.0, 1.0).asin();
        let alpha = (-m[(0, 1)]).atan2(m[(1, 1)]);
        let gamma = (-m[(2, 0)]).atan2(m[(2, 2)]);
        (kappa * alpha, wrap(beta + psi), gamma)
    }
}

fn cost(report: &IkReport, ik: &NumericIk) -> f64 {
    let w = ik.options().orientation_weight;
    report.position_error.powi(2) + (w * report.orientation_error).powi(2)
}

/// R = Ry(a)·Rx(b)·Rz(c) → (a, b, c).
fn euler_yxz(r: &Matrix3<f64>) -> (f64, f64, f64) {
    let b = (-r[(1, 2)]).clamp(-1.0, 1.0).asin();
    let a = r[(0, 2)].atan2(r[(2, 2)]);
    let c = r[(1, 0)].atan2(r[(1, 1)]);
    (a, b, c)
}

/// Direction of a vector in the x-z plane, measured from +z towards +x (a rotation about +y adds
/// to it).
fn planar_angle(v: &Vector3<f64>) -> f64 {
    v.x.atan2(v.z)
}

fn planar_len(v: &Vector3<f64>) -> f64 {
    (v.x * v.x + v.z * v.z).sqrt()
}

/// `angle` or a whole turn away from it, whichever lies within [lo, hi] (or is nearest to it).
fn into_limits(angle: f64, lo: f64, hi: f64) -> f64 {
    let outside = |a: f64| (lo - a).max(a - hi).max(0.0);
    [angle, angle - 360.0, angle + 360.0]
        .into_iter()
        .min_by(|a, b| outside(*a).total_cmp(&outside(*b)))
        .unwrap_or(angle)
}

fn half_turn_range(angle: f64) -> f64 {
    if angle > PI / 2.0 {
        angle - PI
    } else if angle < -PI / 2.0 {
        angle + PI
    } else {
        angle
    }
}

fn wrap(angle: f64) -> f64 {
    (angle + PI).rem_euclid(2.0 * PI) - PI
}
