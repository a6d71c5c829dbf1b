//! What the decision layer asks the skills for, each cycle.

pub use crate::save::DiveSide;

/// The body's task this cycle.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum BodyIntent {
    /// Hold the stand posture in balance (a walk in progress first steps the feet together).
    #[default]
    Stand,
    /// Walk with this velocity in the robot's own frame (x forwards, y left). Values beyond the
    /// parameter file's limits are clamped; the executed command follows within its
    /// acceleration limits, so the decision layer may change it every cycle.
    Walk {
        forward_m_s: f64,
        sideways_m_s: f64,
        turn_deg_s: f64,
    },
    /// Walk to a pose given relative to the robot: `target` = (x forwards, y left) [m] and the
    /// final `heading_deg` relative to the current heading. Stops (and stands) once there.
    /// Callers holding a field pose convert it to the robot frame each cycle.
    /// `max_speed_m_s` caps the walking speed below the walk's own limits (`None`: no cap).
    WalkTo {
        target: [f64; 2],
        heading_deg: f64,
        max_speed_m_s: Option<f64>,
    },
    /// Kick the ball at `ball` = (x, y) [m] in the robot frame towards `direction_deg` (robot
    /// frame, + left) over about `distance_m`. The skill walks to its kicking place behind the
    /// ball from wherever the robot is, then kicks with the better foot.
    Kick {
        ball: [f64; 2],
        direction_deg: f64,
        distance_m: f64,
    },
    /// Dribble the ball at `ball` = (x, y) [m] in the robot frame towards `direction_deg`
    /// (robot frame, + left): line up behind it on that line (round the ball when on the wrong
    /// side), then walk on through it without stopping, steering to keep it in front of the
    /// feet. The caller recomputes the direction every cycle as the ball moves. With
    /// `kick_steps`, a ball in place before a foot is kicked on by a kick step of the walk
    /// (`walk.kick_step`, when `dribble.kick` says where the ball must be) instead of walked on.
    Dribble {
        ball: [f64; 2],
        direction_deg: f64,
        kick_steps: bool,
    },
    /// Stand up from lying. Also done automatically whenever the fall detector reports a fall.
    GetUp,
    /// Goalkeeper save: dive to a side or block straight ahead. Starts in the cycle it is
    /// first asked for (when upright and not getting up) and plays to its end whatever is
    /// asked meanwhile (`SkillStatus::save`: `Diving`, then `Done`). After a dive the robot
    /// lies; while the request is still held after `Done` it stays down in the dive's end pose
    /// (covering the line while the ball may still come), and once the request is dropped the
    /// fall detector starts the get-up. Holding the request after `Done` never dives again: a
    /// new save needs a cycle without one first.
    Dive { side: DiveSide },
    /// Play a motion of the parameter file's `motions` from the measured angles, then hold
    /// its last pose while still asked for. Nothing but a save interrupts it (the get-up
    /// waits until it is no longer asked for).
    Motion { id: crate::MotionId },
}

/// The head's task this cycle.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum HeadIntent {
    /// Keep the head where the body skill puts it.
    #[default]
    Hold,
    /// Pan left and right to see more landmarks. `None` fields take the skill parameters'
    /// values.
    LookAround {
        amplitude_deg: Option<f64>,
        period_s: Option<f64>,
    },
    /// Look at a point on the ground given in the robot frame (x forwards, y left) [m].
    LookAt { target: [f64; 2] },
}

/// One cycle's request to the skill layer.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Intent {
    pub body: BodyIntent,
    pub head: HeadIntent,
    /// Beam to (x, y, θ°) in the team's own frame (own goal at −x), when the play mode allows.
    pub beam: Option<[f64; 3]>,
    /// A message to broadcast.
    pub say: Option<libero_world::team_message::Said>,
    /// The decision's claim to the ball: this player's predicted time to reach it [s], which
    /// it tells its teammates (`None`: not claiming).
    pub time_to_ball_s: Option<f64>,
    /// The decision goes for the ball (it judged itself the ball winner), which it tells too.
    pub going_for_ball: bool,
}
