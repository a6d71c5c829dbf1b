//! One module per subcommand; shared setup lives in [`setup`].

pub mod agent;
pub mod behavior;
pub mod bench;
pub mod bench_cycle;
pub mod bench_view;
pub mod matchup;
pub mod optimize;
pub mod scenario;
pub mod series;
pub mod server;
pub mod setup;
pub mod soak;
pub mod team;
pub mod view;

/// Errors a command reports to the user: already phrased for them.
pub type CliResult = Result<std::process::ExitCode, Box<dyn std::error::Error>>;
