//! Play mode, sides, score and time.

use libero_protocol::percept::GameStatePercept;

#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
pub enum Side {
    Left,
    Right,
}

impl Side {
    pub fn opposite(self) -> Side {
        match self {
            Side::Left => Side::Right,
            Side::Right => Side::Left,
        }
    }
}

/// The referee's play mode, with the side it favours where it has one.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PlayMode {
    BeforeKickOff,
    KickOff(Side),
    PlayOn,
    KickIn(Side),
    CornerKick(Side),
    GoalKick(Side),
    Offside(Side),
    FreeKick(Side),
    DirectFreeKick(Side),
    PenaltyKick(Side),
    PenaltyShoot(Side),
    Goal(Side),
    GameOver,
    /// A mode this engine does not know (kept so that decisions can stay conservative).
    Unknown,
}

impl PlayMode {
    /// Both servers' play-mode strings.
    pub fn from_server(name: &str) -> Self {
        let (base, side) = match name.rsplit_once('_') {
            Some((b, s)) if s.eq_ignore_ascii_case("left") => (b, Some(Side::Left)),
            Some((b, s)) if s.eq_ignore_ascii_case("right") => (b, Some(Side::Right)),
            _ => (name, None),
        };
        // Compared without case in place: lower-casing a copy allocated at every mode change.
        type Named = (&'static str, fn(Side) -> PlayMode);
        const NAMED: [Named; 10] = [
            ("kickoff", PlayMode::KickOff),
            ("kickin", PlayMode::KickIn),
            ("corner_kick", PlayMode::CornerKick),
            ("goal_kick", PlayMode::GoalKick),
            ("offside", PlayMode::Offside),
            ("free_kick", PlayMode::FreeKick),
            ("direct_free_kick", PlayMode::DirectFreeKick),
            ("penalty_kick", PlayMode::PenaltyKick),
            ("penalty_shoot", PlayMode::PenaltyShoot),
            ("goal", PlayMode::Goal),
        ];
        match side {
            None if base.eq_ignore_ascii_case("beforekickoff") => PlayMode::BeforeKickOff,
            None if base.eq_ignore_ascii_case("playon") => PlayMode::PlayOn,
            None if base.eq_ignore_ascii_case("gameover") => PlayMode::GameOver,
            Some(side) => NAMED
                .iter()
                .find(|(name, _)| base.eq_ignore_ascii_case(name))
                .map_or(PlayMode::Unknown, |(_, mode)| mode(side)),
            None => PlayMode::Unknown,
        }
    }

    /// Beam is honoured only before kick-off and after a goal (both servers).
    pub fn allows_beam(self) -> bool {
        matches!(self, PlayMode::BeforeKickOff | PlayMode::Goal(_))
    }
}

/// Longer than any play mode name either server sends.
const PLAY_MODE_NAME_ROOM: usize = 64;

/// What the agent knows about the game.
#[derive(Debug, Clone)]
pub struct GameState {
    pub team: String,
    pub unum: u32,
    pub play_mode: PlayMode,
    /// The play-mode string as last sent (for logs and traces).
    pub play_mode_name: String,
    /// Play time [s].
    pub play_time: f64,
    /// Our side, once the server has told us (team names on rcssservermj, `team` on SimSpark).
    pub side: Option<Side>,
    pub score_left: u32,
    pub score_right: u32,
}

impl GameState {
    pub fn new(team: &str, unum: u32) -> Self {
        Self {
            team: team.to_string(),
            unum,
            play_mode: PlayMode::Unknown,
            play_mode_name: String::with_capacity(PLAY_MODE_NAME_ROOM),
            play_time: 0.0,
            side: None,
            score_left: 0,
            score_right: 0,
        }
    }

    pub fn update(&mut self, gs: &GameStatePercept<'_>) {
        if let Some(pm) = gs.play_mode {
            if pm != self.play_mode_name {
                self.play_mode = PlayMode::from_server(pm);
                // Into the string's own room (reserved at start): no allocation per change.
                self.play_mode_name.clear();
                self.play_mode_name.push_str(pm);
            }
        }
        if let Some(t) = gs.play_time {
            self.play_time = t;
        }
        self.score_left = gs.score_left.unwrap_or(self.score_left);
        self.score_right = gs.score_right.unwrap_or(self.score_right);
        if let Some(side) = gs.side {
            self.side = match side {
                "left" => Some(Side::Left),
                "right" => Some(Side::Right),
                _ => self.side,
            };
        } else if gs.team_left == Some(self.team.as_str()) {
            self.side = Some(Side::Left);
        } else if gs.team_right == Some(self.team.as_str()) {
            self.side = Some(Side::Right);
        }
        if let Some(unum) = gs.unum {
            self.unum = unum;
        }
    }

    /// (ours, theirs), once our side is known.
    pub fn score(&self) -> Option<(u32, u32)> {
        self.side.map(|s| match s {
            Side::Left => (self.score_left, self.score_right),
            Side::Right => (self.score_right, self.score_left),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn play_modes_of_both_servers() {
        assert_eq!(
            PlayMode::from_server("BeforeKickOff"),
            PlayMode::BeforeKickOff
        );
        assert_eq!(
            PlayMode::from_server("KickOff_Left"),
            PlayMode::KickOff(Side::Left)
        );
        assert_eq!(
            PlayMode::from_server("corner_kick_right"),
            PlayMode::CornerKick(Side::Right)
        );
        assert_eq!(
            PlayMode::from_server("direct_free_kick_left"),
            PlayMode::DirectFreeKick(Side::Left)
        );
        assert_eq!(
            PlayMode::from_server("Goal_Right"),
            PlayMode::Goal(Side::Right)
        );
        assert_eq!(PlayMode::from_server("nonsense_left"), PlayMode::Unknown);
        assert!(PlayMode::Goal(Side::Left).allows_beam());
        assert!(!PlayMode::PlayOn.allows_beam());
    }

    #[test]
    fn side_from_team_names_or_simspark_announcement() {
        let mut g = GameState::new("Libero", 2);
        g.update(&GameStatePercept {
            team_left: Some("Other"),
            team_right: Some("Libero"),
            score_left: Some(1),
            ..Default::default()
        });
        assert_eq!(g.side, Some(Side::Right));
        assert_eq!(g.score(), Some((0, 1)));
        let mut g = GameState::new("Libero", 0);
        g.update(&GameStatePercept {
            unum: Some(4),
            side: Some("left"),
            ..Default::default()
        });
        assert_eq!((g.side, g.unum), (Some(Side::Left), 4));
    }
}
