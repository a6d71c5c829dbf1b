//! The agent runtime: one cycle per percept, one reply per cycle.
//!
//! ```text
//! bytes → frame → S-expression → Percept → World → decide → Intent → Skills → JointTargets → actions → bytes
//! ```
//! [`player`] is that pipeline without any I/O (so it is tested on recorded messages);
//! [`seats`] puts agents on sockets with reconnects, answering several from one thread;
//! [`run`] runs one, [`team`] hosts a team in one process; [`connection`] is a plain
//! blocking connection for tools.

pub mod actuate;
pub mod build;
pub mod connection;
pub mod decide;
pub mod player;
pub mod run;
pub mod seats;
pub mod skill_source;
pub mod stats;
pub mod team;
pub mod view;

pub use decide::{Decider, LibrarySource, StandAndBeam, TreeDecider};
pub use libero_model::team_types::{check_simspark_types, simspark_team_types};
pub use player::{Player, TruthFeed};
pub use run::{run_agent, AgentConfig, AgentError, JoinGate};
pub use skill_source::{LiveSkillParams, ParamsEvent, SkillSource};
pub use stats::AgentStats;
pub use team::Team;
pub use view::{AgentView, DecisionView, TreeShape, ViewSlot};
