//! The real servers on this machine, installed and run by the project itself.
//!
//! [`venv`] creates a git-ignored virtualenv and pip-installs the pinned rcssservermj there on
//! first use; [`simspark`] builds SimSpark rcssserver3d from source into a per-user cache;
//! [`process`] starts either headless on free loopback ports and stops exactly the process it
//! started; [`monitor`] speaks the monitor port (kick-off, ball placement, game state).

pub mod fouls;
pub mod monitor;
mod ports;
pub mod process;
pub mod scratch;
pub mod simspark;
pub mod simspark_scene;
pub mod venv;

pub use fouls::{Foul, FoulTally, FOUL_KINDS};
pub use monitor::{GameSnapshot, Monitor};
pub use process::{Rules, ServerKind, ServerOptions, ServerProcess};
pub use simspark::{ensure_simspark_installed, SimSparkInstall};
pub use simspark_scene::RobotTruth;
pub use venv::{
    ensure_installed, ensure_ray_installed, Installation, RAY_VERSION, RCSSSMJ_VERSION,
};

/// Why the server could not be provided.
#[derive(Debug, thiserror::Error)]
pub enum ServerError {
    #[error("python3 was not found on PATH: install Python 3.10 or newer (Debian: `apt-get install python3 python3-venv`)")]
    NoPython,
    #[error("could not create the virtualenv at {path}: {detail}\nhint: on Debian install `python3-venv`; or set LIBERO_VENV to an existing virtualenv")]
    Venv { path: String, detail: String },
    #[error("pip could not install {version} into {path}: {detail}\nhint: check that the package registry is reachable, or pre-install it and set LIBERO_VENV")]
    Pip {
        version: String,
        path: String,
        detail: String,
    },
    #[error("port {0} on 127.0.0.1 is already taken: stop whatever listens there or pick another port (or leave ports unset to use free ones)")]
    PortTaken(u16),
    #[error("the server exited during start-up ({status}); its log {log} ends with:\n{tail}")]
    EarlyExit {
        status: String,
        log: String,
        tail: String,
    },
    #[error("the server did not report ready within {0} s; see its log {1}")]
    StartTimeout(u64, String),
    #[error("{0}")]
    SimSpark(String),
    #[error("{0}: {1}")]
    Io(String, std::io::Error),
}

/// The port tests and the spawn test take turns: a fork in the spawn test copies every open
/// socket into the child until its exec closes them, so a port a port test has just let go is
/// still bound there for a moment (the requested-port test failed 14 of 60 runs so).
#[cfg(test)]
static PORT_TESTS: std::sync::Mutex<()> = std::sync::Mutex::new(());
