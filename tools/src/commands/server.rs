//! `libero server …`: a local rcssservermj or SimSpark.

use super::setup::ctrl_c_flag;
use super::CliResult;
use clap::{Args, Subcommand};
use libero_server::{
    ensure_installed, ensure_simspark_installed, Rules, ServerKind, ServerOptions, ServerProcess,
};
use std::path::PathBuf;
use std::process::ExitCode;
use std::sync::atomic::Ordering;

#[derive(Subcommand)]
pub enum ServerCommand {
    /// Install the pinned rcssservermj into the project's virtualenv, or build SimSpark into
    /// the per-user cache (first use does it too).
    Install {
        /// Also the pinned Ray (`--ray` and `ray start` need it; first use does it too).
        #[arg(long)]
        with_ray: bool,
        /// `rcssservermj` or `simspark`.
        #[arg(long, default_value = "rcssservermj")]
        server: ServerKind,
        /// SimSpark only: a source folder (spark/ and rcssserver3d/ side by side) or its archive
        /// [default: ../shared/simspark/SIMSPARK-f6934a6.tar.xz beside the checkout].
        #[arg(long, value_name = "DIR|ARCHIVE")]
        source: Option<PathBuf>,
    },
    /// Start a headless server on 127.0.0.1 and keep it running until Ctrl-C.
    Start(StartArgs),
}

#[derive(Args, Clone)]
pub struct StartArgs {
    /// `rcssservermj` (T1) or `simspark` (NAO).
    #[arg(long, default_value = "rcssservermj")]
    pub server: ServerKind,
    /// Wait for every agent each cycle.
    #[arg(long)]
    pub sync: bool,
    /// Run as fast as the agents answer (implies sync).
    #[arg(long)]
    pub no_realtime: bool,
    #[arg(long, default_value = "ssim")]
    pub rules: Rules,
    /// Agent port (default: a free one).
    #[arg(long)]
    pub agent_port: Option<u16>,
    /// Monitor port (default: a free one).
    #[arg(long)]
    pub monitor_port: Option<u16>,
}

impl StartArgs {
    pub fn options(&self) -> ServerOptions {
        ServerOptions {
            server: self.server,
            sync: self.sync || self.no_realtime,
            realtime: !self.no_realtime,
            rules: self.rules,
            field: None,
            agent_port: self.agent_port,
            monitor_port: self.monitor_port,
            work_dir: None,
        }
    }
}

pub fn run(cmd: ServerCommand) -> CliResult {
    match cmd {
        ServerCommand::Install {
            server: ServerKind::SimSpark,
            source,
            ..
        } => {
            let install = ensure_simspark_installed(source.as_deref())?;
            println!(
                "SimSpark rcssserver3d installed: {}",
                install.server_program().display()
            );
        }
        ServerCommand::Install {
            source: Some(_), ..
        } => return Err("--source is for `--server simspark`".into()),
        ServerCommand::Install { with_ray, .. } => {
            let install = ensure_installed()?;
            println!(
                "rcssservermj installed: {}",
                install.server_program().display()
            );
            if with_ray {
                let install = libero_server::ensure_ray_installed()?;
                println!(
                    "ray {} installed: {}",
                    libero_server::RAY_VERSION,
                    install.venv.join("bin/ray").display()
                );
            }
        }
        ServerCommand::Start(args) => {
            let shutdown = ctrl_c_flag();
            let mut server = ServerProcess::start(args.options())?;
            println!(
                "{} running: agent port {} monitor port {} (log {}); Ctrl-C stops it",
                server.name(),
                server.agent_port,
                server.monitor_port,
                server.log_path().display()
            );
            while !shutdown.load(Ordering::Relaxed) {
                if !server.is_running() {
                    return Err(format!(
                        "the server stopped on its own; see {}",
                        server.log_path().display()
                    )
                    .into());
                }
                std::thread::sleep(std::time::Duration::from_millis(100));
            }
            server.stop();
        }
    }
    Ok(ExitCode::SUCCESS)
}
