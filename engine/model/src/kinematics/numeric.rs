//! Damped least-squares IK for any chain (Levenberg–Marquardt damping, joint limits by projection).

use super::chain::{check_len, Chain, ChainState, MAX_CHAIN_JOINTS};
use super::forward::Kinematics;
use super::KinematicsError;
use nalgebra::{Isometry3, Matrix6, Unit, Vector3, Vector6};

/// What the chain's tip should do, in the torso frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum IkTarget {
    /// Reach this pose exactly.
    Pose(Isometry3<f64>),
    /// Reach this point; orientation is free.
    Position(Vector3<f64>),
    /// Point the tip-frame direction `axis` at `point` (e.g. the camera's x axis at the ball).
    LookAt {
        point: Vector3<f64>,
        axis: Unit<Vector3<f64>>,
    },
}

/// Solver settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct IkOptions {
    pub max_iterations: usize,
    /// Done when the position error is at most this [m].
    pub position_tolerance: f64,
    /// Done when the orientation (or pointing) error is at most this [rad].
    pub orientation_tolerance: f64,
    /// Metres of position error worth one radian of orientation error.
    pub orientation_weight: f64,
    /// Initial Levenberg–Marquardt damping λ [m].
    pub initial_damping: f64,
}

impl Default for IkOptions {
    fn default() -> Self {
        Self {
            max_iterations: 100,
            position_tolerance: 1e-5,
            orientation_tolerance: 1e-4,
            orientation_weight: 0.2,
            initial_damping: 1e-3,
        }
    }
}

/// How a solve ended. `reached == false` means the angles written are the closest found (within
/// limits), not a solution.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct IkReport {
    pub reached: bool,
    pub iterations: usize,
    /// Remaining tip position error [m] (0 for `LookAt`).
    pub position_error: f64,
    /// Remaining orientation or pointing error [rad] (0 for `Position`).
    pub orientation_error: f64,
}

/// Numeric IK on one chain.
#[derive(Debug, Clone)]
pub struct NumericIk {
    chain: Chain,
    options: IkOptions,
}

struct Residual {
    weighted: Vector6<f64>,
    position: f64,
    orientation: f64,
}

impl Residual {
    fn cost(&self) -> f64 {
        self.weighted.norm_squared()
    }
}

fn residual(state: &ChainState, target: &IkTarget, weight: f64) -> Residual {
    let tip = &state.tip;
    match target {
        IkTarget::Pose(goal) => {
            let dp = goal.translation.vector - tip.translation.vector;
            let dr = (goal.rotation * tip.rotation.inverse()).scaled_axis();
            Residual {
                weighted: Vector6::new(
                    dp.x,
                    dp.y,
                    dp.z,
                    weight * dr.x,
                    weight * dr.y,
                    weight * dr.z,
                ),
                position: dp.norm(),
                orientation: dr.norm(),
            }
        }
        IkTarget::Position(goal) => {
            let dp = goal - tip.translation.vector;
            Residual {
                weighted: Vector6::new(dp.x, dp.y, dp.z, 0.0, 0.0, 0.0),
                position: dp.norm(),
                orientation: 0.0,
            }
        }
        IkTarget::LookAt { point, axis } => {
            let current = tip.rotation * axis.into_inner();
            let wanted = (point - tip.translation.vector)
                .try_normalize(1e-9)
                .unwrap_or(current);
            let cross = current.cross(&wanted);
            let angle = cross.norm().atan2(current.dot(&wanted));
            let dr = cross
                .try_normalize(1e-12)
                .map_or(Vector3::zeros(), |a| a * angle);
            Residual {
                weighted: Vector6::new(0.0, 0.0, 0.0, weight * dr.x, weight * dr.y, weight * dr.z),
                position: 0.0,
                orientation: angle,
            }
        }
    }
}

impl NumericIk {
    pub fn new(chain: Chain, options: IkOptions) -> Self {
        Self { chain, options }
    }

    pub fn chain(&self) -> &Chain {
        &self.chain
    }

    pub fn options(&self) -> &IkOptions {
        &self.options
    }

    /// Move the chain's joints in `angles_deg` (whole-body vector, read as the start guess) towards
    /// `target`. Other joints are left alone. Never writes a non-finite angle.
    pub fn solve(
        &self,
        kin: &Kinematics,
        target: &IkTarget,
        angles_deg: &mut [f64],
    ) -> Result<IkReport, KinematicsError> {
        check_len(kin, angles_deg)?;
        if !target_is_finite(target) {
            return Err(KinematicsError::NonFiniteTarget);
        }
        let joints = self.chain.joints();
        if joints.iter().any(|&j| !angles_deg[j].is_finite()) {
            return Err(KinematicsError::NonFiniteAngles);
        }
        for &j in joints {
            let (lo, hi) = kin.joints[j].limits_rad;
            angles_deg[j] = angles_deg[j].to_radians().clamp(lo, hi).to_degrees();
        }
        let base = self.chain.base_pose(kin, angles_deg);
        let weight = self.options.orientation_weight;
        let mut state = self.chain.evaluate_from(kin, base, angles_deg);
        let mut current = residual(&state, target, weight);
        let mut damping = self.options.initial_damping;
        let mut previous = [0.0; MAX_CHAIN_JOINTS];
        let mut iterations = 0;
        let mut stalled_steps = 0;
        while iterations < self.options.max_iterations && !self.done(&current) {
            iterations += 1;
            let jacobian = weighted_jacobian(&state, joints.len(), target, weight);
            let Some(step) = damped_step(&jacobian, joints.len(), &current.weighted, damping)
            else {
                break;
            };
            for (k, &j) in joints.iter().enumerate() {
                let (lo, hi) = kin.joints[j].limits_rad;
                previous[k] = angles_deg[j];
                angles_deg[j] = (angles_deg[j].to_radians() + step[k])
                    .clamp(lo, hi)
                    .to_degrees();
            }
            let next_state = self.chain.evaluate_from(kin, base, angles_deg);
            let next = residual(&next_state, target, weight);
            if next.cost() < current.cost() && next.cost().is_finite() {
                // Converging steps shrink the cost by orders of magnitude; a creep means a target
                // out of reach (or held by a limit), where more iterations buy nothing.
                if next.cost() > current.cost() * (1.0 - 1e-4) {
                    stalled_steps += 1;
                } else {
                    stalled_steps = 0;
                }
                state = next_state;
                current = next;
                damping = (damping * 0.3).max(1e-9);
                if stalled_steps >= 5 {
                    break;
                }
            } else {
                for (k, &j) in joints.iter().enumerate() {
                    angles_deg[j] = previous[k];
                }
                damping *= 10.0;
                if damping > 1e6 {
                    break;
                }
            }
        }
        Ok(IkReport {
            reached: self.done(&current),
            iterations,
            position_error: current.position,
            orientation_error: current.orientation,
        })
    }

    fn done(&self, r: &Residual) -> bool {
        r.position <= self.options.position_tolerance
            && r.orientation <= self.options.orientation_tolerance
    }
}

fn target_is_finite(target: &IkTarget) -> bool {
    match target {
        IkTarget::Pose(p) => {
            p.translation.vector.iter().all(|v| v.is_finite())
                && p.rotation.coords.iter().all(|v| v.is_finite())
        }
        IkTarget::Position(p) => p.iter().all(|v| v.is_finite()),
        IkTarget::LookAt { point, axis } => {
            point.iter().all(|v| v.is_finite()) && axis.iter().all(|v| v.is_finite())
        }
    }
}

/// Columns: one per chain joint, rows: position (m/rad) then weighted rotation.
fn weighted_jacobian(
    state: &ChainState,
    n: usize,
    target: &IkTarget,
    weight: f64,
) -> [Vector6<f64>; MAX_CHAIN_JOINTS] {
    let mut columns = [Vector6::zeros(); MAX_CHAIN_JOINTS];
    let tip = state.tip.translation.vector;
    for (k, column) in columns.iter_mut().enumerate().take(n) {
        let axis = state.axes[k];
        let linear = axis.cross(&(tip - state.points[k]));
        let (p, w) = match target {
            IkTarget::Pose(_) => (linear, axis * weight),
            IkTarget::Position(_) => (linear, Vector3::zeros()),
            IkTarget::LookAt { .. } => (Vector3::zeros(), axis * weight),
        };
        *column = Vector6::new(p.x, p.y, p.z, w.x, w.y, w.z);
    }
    columns
}

/// Δq = Jᵀ (J Jᵀ + λ² I)⁻¹ e, always through a 6×6 system whatever the chain length.
fn damped_step(
    columns: &[Vector6<f64>; MAX_CHAIN_JOINTS],
    n: usize,
    error: &Vector6<f64>,
    damping: f64,
) -> Option<[f64; MAX_CHAIN_JOINTS]> {
    let mut jjt = Matrix6::identity() * (damping * damping);
    for c in &columns[..n] {
        jjt += c * c.transpose();
    }
    let y = jjt.cholesky()?.solve(error);
    let mut step = [0.0; MAX_CHAIN_JOINTS];
    for k in 0..n {
        // Large steps leave the region where the linearisation holds; cap at ~17°.
        step[k] = columns[k].dot(&y).clamp(-0.3, 0.3);
    }
    step[..n].iter().all(|s| s.is_finite()).then_some(step)
}
