//! The step generator: where each sole is, step by step, in the level walk frame.
//!
//! The walk frame is level (gravity along −z), moves with the torso origin, and faces the
//! torso's heading. Each foot is described by its offset from its neutral place (x, y, yaw).
//! A step moves the swing foot from where it was to where the step command puts it, lifting it
//! on the way, while the support foot slides the opposite way at constant speed: that slide is
//! the torso moving over the support foot. A new command only changes where the next step ends,
//! so commands change smoothly step by step.

use super::kick_step::KickStepParams;
use super::params::WalkParams;
use std::f64::consts::PI;

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Foot {
    Left,
    Right,
}

impl Foot {
    pub fn other(self) -> Foot {
        match self {
            Foot::Left => Foot::Right,
            Foot::Right => Foot::Left,
        }
    }

    /// +1 for the left foot (at +y), −1 for the right.
    pub fn sign(self) -> f64 {
        match self {
            Foot::Left => 1.0,
            Foot::Right => -1.0,
        }
    }

    pub fn index(self) -> usize {
        match self {
            Foot::Left => 0,
            Foot::Right => 1,
        }
    }
}

/// A foot's displacement from its neutral place [m, m, deg].
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct FootOffset {
    pub x: f64,
    pub y: f64,
    pub yaw_deg: f64,
}

impl FootOffset {
    fn lerp(a: FootOffset, b: FootOffset, s: f64) -> FootOffset {
        FootOffset {
            x: a.x + (b.x - a.x) * s,
            y: a.y + (b.y - a.y) * s,
            yaw_deg: a.yaw_deg + (b.yaw_deg - a.yaw_deg) * s,
        }
    }

    pub fn is_neutral(&self, tolerance: f64) -> bool {
        self.x.abs() < tolerance
            && self.y.abs() < tolerance
            && self.yaw_deg.abs() < tolerance * 100.0
    }
}

/// How far the torso moves relative to the support foot during one step [m, m, deg].
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Step {
    pub x: f64,
    pub y: f64,
    pub yaw_deg: f64,
}

/// Where a sole is in the level walk frame: position [m] and yaw [deg].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SolePlacement {
    pub x: f64,
    pub y: f64,
    pub z: f64,
    pub yaw_deg: f64,
}

/// The state of the stepping pattern.
#[derive(Debug, Clone)]
pub struct Gait {
    /// Progress through the current step [0, 1).
    pub phase: f64,
    pub swing: Foot,
    start: [FootOffset; 2],
    end: [FootOffset; 2],
    /// Share of the full lift this step gets (0 for the weight shift that starts a walk).
    lift_scale: f64,
    /// The swing of this step when it is a kick step, and the shift of the swing foot across
    /// (+ left) [m] that puts it behind the ball for the strike.
    kick: Option<(KickStepParams, f64)>,
}

impl Default for Gait {
    fn default() -> Self {
        Self {
            phase: 0.0,
            swing: Foot::Left,
            start: [FootOffset::default(); 2],
            end: [FootOffset::default(); 2],
            lift_scale: 0.0,
            kick: None,
        }
    }
}

impl Gait {
    /// Start a step of `swing` that moves the torso by `step` over the other foot.
    ///
    /// Sideways steps and turns are made by the foot on the side of the motion (the leading
    /// leg) and followed by a closing step, so the feet never cross or collide; forward steps
    /// are shared evenly between both feet.
    pub fn begin_step(&mut self, swing: Foot, step: Step, lift_scale: f64) {
        let support = swing.other();
        self.start = self.current_offsets();
        self.swing = swing;
        self.phase = 0.0;
        self.lift_scale = lift_scale;
        let leads = |amount: f64| amount * swing.sign() > 0.0;
        let mut swing_end = FootOffset {
            x: step.x / 2.0,
            ..Default::default()
        };
        let mut support_end = FootOffset {
            x: -step.x / 2.0,
            ..Default::default()
        };
        if leads(step.y) {
            swing_end.y = step.y;
            support_end.y = -step.y;
        }
        if leads(step.yaw_deg) {
            swing_end.yaw_deg = step.yaw_deg;
            support_end.yaw_deg = -step.yaw_deg;
        }
        self.end[swing.index()] = swing_end;
        self.end[support.index()] = support_end;
        self.kick = None;
    }

    /// Start a step like [`Gait::begin_step`] whose swing is the kick step `kick`.
    /// The swing foot moves `across_m` sideways (+ left) for the strike and back to land.
    pub fn begin_kick_step(
        &mut self,
        swing: Foot,
        step: Step,
        kick: KickStepParams,
        across_m: f64,
    ) {
        self.begin_step(swing, step, 1.0);
        self.kick = Some((kick, across_m));
    }

    /// The kick step under way, if this step is one.
    pub fn kick(&self) -> Option<&KickStepParams> {
        self.kick.as_ref().map(|(k, _)| k)
    }

    /// How long the current step lasts [s].
    pub fn period_s(&self, p: &WalkParams) -> f64 {
        self.kick.map_or(p.step_period_s, |(k, _)| k.period_s)
    }

    /// Offsets of both feet at the current phase (no lift, no sway).
    pub fn current_offsets(&self) -> [FootOffset; 2] {
        let swing = self.swing.index();
        let mut out = [FootOffset::default(); 2];
        for (k, slot) in out.iter_mut().enumerate() {
            let s = if k == swing {
                swing_progress(self.phase)
            } else {
                self.phase
            };
            *slot = FootOffset::lerp(self.start[k], self.end[k], s);
        }
        if let Some((kick, across)) = &self.kick {
            out[swing].x = kick.swing_x(self.start[swing].x, self.end[swing].x, self.phase);
            out[swing].y += across * kick.strike_share(self.phase);
        }
        out
    }

    /// Advance by `dt` seconds; true when the step has just ended.
    pub fn advance(&mut self, dt: f64, period: f64) -> bool {
        self.phase += dt / period;
        if self.phase >= 1.0 {
            self.phase = 1.0;
            true
        } else {
            false
        }
    }

    /// Both soles in the level walk frame (index 0 left, 1 right).
    pub fn placements(&self, p: &WalkParams) -> [SolePlacement; 2] {
        let offsets = self.current_offsets();
        // The torso shifts towards the support foot and back once per step; a positive shift
        // towards +y moves both soles to −y in the torso-centred frame.
        let support_sign = self.swing.other().sign();
        let sway_phase = (self.phase + p.sway_phase_lead).min(1.0);
        let sway = p.sway_m * support_sign * (PI * sway_phase).sin();
        let lift = match &self.kick {
            Some((kick, _)) => kick.swing_z(self.phase),
            None => self.lift_scale * p.step_height_m * lift_profile(self.phase),
        };
        let mut out = [SolePlacement {
            x: 0.0,
            y: 0.0,
            z: 0.0,
            yaw_deg: 0.0,
        }; 2];
        for foot in [Foot::Left, Foot::Right] {
            let o = offsets[foot.index()];
            out[foot.index()] = SolePlacement {
                x: p.foot_x_offset_m + o.x,
                y: foot.sign() * p.foot_y_offset_m + o.y - sway,
                z: -p.torso_height_m + if foot == self.swing { lift } else { 0.0 },
                yaw_deg: o.yaw_deg,
            };
        }
        out
    }

    /// True when both feet are at their neutral places.
    pub fn feet_together(&self) -> bool {
        self.current_offsets().iter().all(|o| o.is_neutral(1e-3))
    }
}

/// Horizontal progress of the swing foot: slow start and landing, so it lifts before moving
/// and sets down without sliding.
fn swing_progress(phase: f64) -> f64 {
    let s = phase.clamp(0.0, 1.0);
    0.5 - 0.5 * (PI * s).cos()
}

/// Swing-foot height profile: 0 at lift-off and touch-down, 1 at mid-step.
fn lift_profile(phase: f64) -> f64 {
    (PI * phase.clamp(0.0, 1.0)).sin()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn forward_steps_alternate_and_move_the_torso_by_the_step() {
        let mut g = Gait::default();
        let step = Step {
            x: 0.1,
            ..Default::default()
        };
        g.begin_step(Foot::Left, step, 1.0);
        g.phase = 1.0;
        let o = g.current_offsets();
        assert!((o[0].x - 0.05).abs() < 1e-12 && (o[1].x + 0.05).abs() < 1e-12);
        g.begin_step(Foot::Right, step, 1.0);
        g.phase = 1.0;
        let o = g.current_offsets();
        // The left (support) foot slid back by a whole step: the torso moved 0.1 m over it.
        assert!((o[0].x + 0.05).abs() < 1e-12 && (o[1].x - 0.05).abs() < 1e-12);
    }

    #[test]
    fn sideways_steps_open_with_the_leading_foot_and_close_with_the_other() {
        let mut g = Gait::default();
        let step = Step {
            y: 0.04,
            ..Default::default()
        };
        g.begin_step(Foot::Left, step, 1.0);
        g.phase = 1.0;
        let o = g.current_offsets();
        assert_eq!((o[0].y, o[1].y), (0.04, -0.04));
        g.begin_step(Foot::Right, step, 1.0);
        g.phase = 1.0;
        assert!(g.feet_together());
    }

    #[test]
    fn a_kick_step_swings_past_its_landing_place_and_lands_where_a_step_would() {
        let kick = crate::walk::kick_step::example();
        let model = libero_model::RobotModel::builtin("T1").unwrap();
        let p = crate::SkillParams::builtin(&model).unwrap().walk;
        let step = Step {
            x: 0.1,
            ..Default::default()
        };
        let (mut walking, mut kicking) = (Gait::default(), Gait::default());
        walking.begin_step(Foot::Left, step, 1.0);
        kicking.begin_kick_step(Foot::Left, step, kick, -0.03);
        assert_eq!(kicking.period_s(&p), 0.4);
        assert_eq!(walking.period_s(&p), p.step_period_s);
        let mid_strike = 0.5 * (kick.strike_from + kick.strike_to);
        kicking.phase = mid_strike;
        walking.phase = mid_strike;
        let (k, w) = (kicking.placements(&p)[0], walking.placements(&p)[0]);
        // Up at the strike's height, and moved across by the asked shift.
        assert!(
            (k.z + p.torso_height_m - kick.lift_m).abs() < 1e-12,
            "{k:?}"
        );
        assert!((k.y - (w.y - 0.03)).abs() < 1e-12, "{k:?} {w:?}");
        kicking.phase = kick.strike_to;
        assert!((kicking.current_offsets()[0].x - (0.05 + kick.reach_m)).abs() < 1e-12);
        // Landing: where the plain step lands, and the support foot is where it would be.
        kicking.phase = 1.0;
        walking.phase = 1.0;
        let near = |a: SolePlacement, b: SolePlacement| {
            [a.x - b.x, a.y - b.y, a.z - b.z, a.yaw_deg - b.yaw_deg]
                .iter()
                .all(|d| d.abs() < 1e-12)
        };
        let (k, w) = (kicking.placements(&p), walking.placements(&p));
        assert!(near(k[0], w[0]) && near(k[1], w[1]), "{k:?} {w:?}");
        // The next step is a plain one again.
        kicking.begin_step(Foot::Right, step, 1.0);
        assert!(kicking.kick().is_none());
    }
}
