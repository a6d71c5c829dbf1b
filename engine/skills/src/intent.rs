//! What the decision layer asks the skills for, each cycle.

/// The body's task this cycle.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum BodyIntent {
    /// Hold the stand posture in balance.
    #[default]
    Stand,
}

/// The head's task this cycle.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum HeadIntent {
    /// Keep the head where the body skill puts it.
    #[default]
    Hold,
    /// Pan left and right to see more landmarks.
    LookAround,
}

/// One cycle's request to the skill layer.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Intent {
    pub body: BodyIntent,
    pub head: HeadIntent,
    /// Beam to (x, y, θ°) in the team's own frame (own goal at −x), when the play mode allows.
    pub beam: Option<[f64; 3]>,
    /// A message to broadcast.
    pub say: Option<Vec<u8>>,
}
