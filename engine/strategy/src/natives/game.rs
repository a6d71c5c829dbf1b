//! The game as trees see it: play modes from the team's point of view, beaming, falls.

use super::{AgentHost, Native, Ports};
use crate::Situation;
use libero_behavior::{NodeSpec, ParamSpec, ValueType};
use libero_world::{PlayMode, Posture, Side};

pub(super) const NODES: &[Native] = &[
    Native::condition(play_mode_is_ports, play_mode_is),
    Native::condition(can_beam_ports, can_beam),
    Native::condition(is_fallen_ports, is_fallen),
];

/// Play modes as seen from the team (own/theirs rather than left/right).
pub const PLAY_MODES: &[&str] = &[
    "BeforeKickOff",
    "KickOffOwn",
    "KickOffTheirs",
    "PlayOn",
    "ThrowInOwn",
    "ThrowInTheirs",
    "CornerKickOwn",
    "CornerKickTheirs",
    "GoalKickOwn",
    "GoalKickTheirs",
    "FreeKickOwn",
    "FreeKickTheirs",
    "GoalOwn",
    "GoalTheirs",
    "GameOver",
];

fn play_mode_is_ports() -> NodeSpec {
    NodeSpec::condition("PlayModeIs", "True when the current play mode is `mode`.").param(
        ParamSpec::new("mode", ValueType::String)
            .choices(PLAY_MODES)
            .doc("team-relative play mode"),
    )
}

fn play_mode_is(host: &AgentHost, ports: &Ports) -> bool {
    host.team_play_mode() == ports.str("mode")
}

fn can_beam_ports() -> NodeSpec {
    NodeSpec::condition(
        "CanBeam",
        "True when the server accepts a beam (before kick-off, after a goal).",
    )
}

fn can_beam(host: &AgentHost, _: &Ports) -> bool {
    host.world.game.play_mode.allows_beam()
}

fn is_fallen_ports() -> NodeSpec {
    NodeSpec::condition("IsFallen", "True when the robot is lying on the ground.")
}

fn is_fallen(host: &AgentHost, _: &Ports) -> bool {
    host.world.body.posture != Posture::Upright
}

impl AgentHost<'_> {
    fn ours(&self, side: Side) -> bool {
        self.world.game.side == Some(side)
    }

    /// The play mode as the team sees it (`PlayModeIs` choices).
    pub(crate) fn team_play_mode(&self) -> &'static str {
        let own =
            |s: Side, yes: &'static str, no: &'static str| if self.ours(s) { yes } else { no };
        match self.world.game.play_mode {
            PlayMode::BeforeKickOff => "BeforeKickOff",
            PlayMode::PlayOn => "PlayOn",
            PlayMode::GameOver => "GameOver",
            PlayMode::KickOff(s) => own(s, "KickOffOwn", "KickOffTheirs"),
            PlayMode::KickIn(s) => own(s, "ThrowInOwn", "ThrowInTheirs"),
            PlayMode::CornerKick(s) => own(s, "CornerKickOwn", "CornerKickTheirs"),
            PlayMode::GoalKick(s) => own(s, "GoalKickOwn", "GoalKickTheirs"),
            PlayMode::FreeKick(s)
            | PlayMode::DirectFreeKick(s)
            | PlayMode::PenaltyKick(s)
            | PlayMode::PenaltyShoot(s) => own(s, "FreeKickOwn", "FreeKickTheirs"),
            // `offside_left`: the left team was offside, so the right team takes the kick.
            PlayMode::Offside(s) => own(s, "FreeKickTheirs", "FreeKickOwn"),
            PlayMode::Goal(s) => own(s, "GoalOwn", "GoalTheirs"),
            PlayMode::Unknown => "",
        }
    }

    /// The situation that picks the formation.
    pub(crate) fn situation(&self) -> Situation {
        match self.team_play_mode() {
            // Before the first kick-off the team file may say who kicks off; otherwise take the
            // positions that are legal either way (the referee relocates defenders inside the
            // centre circle).
            "BeforeKickOff" => {
                let first = self
                    .strategy
                    .team
                    .as_ref()
                    .and_then(|t| t.left_kicks_off_first);
                match (first, self.world.game.side) {
                    (Some(true), Some(Side::Left)) | (Some(false), Some(Side::Right)) => {
                        Situation::KickOffOwn
                    }
                    _ => Situation::KickOffTheirs,
                }
            }
            "KickOffTheirs" | "GoalOwn" => Situation::KickOffTheirs,
            "KickOffOwn" | "GoalTheirs" => Situation::KickOffOwn,
            m if m.ends_with("Own") => Situation::SetPlayOwn,
            m if m.ends_with("Theirs") => Situation::SetPlayTheirs,
            _ => Situation::play_on(super::host::value(self.ball())),
        }
    }
}
