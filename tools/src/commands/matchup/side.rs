//! The two teams of a match: ours (in this process, from a folder of files) or an external one
//! (a start command).

use super::super::setup::{
    build_player, load_robot, robot_for_unum, team_robot_types, DataArgs, LogArgs,
};
use super::observer::RobotSample;
use libero_agent::{AgentConfig, AgentStats, Team};
use libero_server::{RobotTruth, ServerKind};
use std::process::{Child, Command};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

/// How long an external team gets to connect its first player before ours joins [s].
const EXTERNAL_FIRST_JOIN: Duration = Duration::from_secs(5);

pub enum Kind {
    Ours(DataArgs),
    External(String),
}

/// The robot name a team of ours fields on `server` (`NAO`: each number's type by the team
/// rules, `robot_for_unum`).
pub fn team_robot(server: ServerKind) -> &'static str {
    match server {
        ServerKind::RcssMj => "T1",
        ServerKind::SimSpark => "NAO",
    }
}

pub struct TeamSetup {
    pub name: String,
    pub kind: Kind,
}

impl TeamSetup {
    pub fn ours(name: &str, data: DataArgs) -> Self {
        Self {
            name: name.to_string(),
            kind: Kind::Ours(data),
        }
    }

    pub fn external(name: &str, command: &str) -> Self {
        Self {
            name: name.to_string(),
            kind: Kind::External(command.to_string()),
        }
    }

    /// Start the team against the server's agent port.
    pub fn start(
        &self,
        port: u16,
        server: ServerKind,
        players: u32,
        log: &LogArgs,
        // This half's own flag: stopping the team must not stop the match.
        shutdown: &Arc<AtomicBool>,
        view: Option<&super::super::view::LiveView>,
    ) -> Result<TeamEntry, Box<dyn std::error::Error>> {
        let running = match &self.kind {
            Kind::Ours(data) => {
                let source = data.source_for(server)?;
                if let Some(view) = view {
                    view.watch_library(&self.name, &source);
                }
                let robot = team_robot(server);
                let types = team_robot_types(&source);
                // One skill parameter file for the team (every NAO type shares nao.ron).
                let mut skills = None;
                let mut team = Vec::new();
                for unum in 1..=players {
                    let model = load_robot(&robot_for_unum(robot, unum, types.as_deref()), None)?;
                    let skills = match &skills {
                        Some(s) => s,
                        None => skills.insert(data.skills(&model)?),
                    };
                    let mut player = build_player(&model, &self.name, unum, &source, skills)?;
                    log.attach(&mut player, &self.name, unum, true)?;
                    if let Some(view) = view {
                        view.show(&mut player);
                    }
                    team.push(player);
                }
                println!("team {}: {players} players joining…", self.name);
                let config = AgentConfig::new("127.0.0.1", port);
                Running::Ours(Team::start(&config, team, shutdown.clone()))
            }
            Kind::External(command) => {
                println!("team {}: starting `{command} 127.0.0.1 {port}`", self.name);
                use std::os::unix::process::CommandExt;
                let mut command_line = Command::new("sh");
                // A script that runs `$LIBERO` gets this binary unless told otherwise.
                if std::env::var_os("LIBERO").is_none() {
                    if let Ok(exe) = std::env::current_exe() {
                        command_line.env("LIBERO", exe);
                    }
                }
                command_line
                    .arg("-c")
                    // `exec`: the command takes the shell's place, so the death signal below
                    // reaches the team (a script that `exec`s its agents, as ours do).
                    .arg(format!("exec {command} 127.0.0.1 {port}"))
                    // The start script's conventional knobs (tools/teams/standing/start.sh).
                    .env("PLAYERS", players.to_string())
                    .env("TEAM", &self.name)
                    .process_group(0);
                // It dies with this process even when that is killed (a cancelled series job).
                libero_server::process::die_with_parent(&mut command_line);
                let child = command_line
                    .spawn()
                    .map_err(|e| format!("cannot start the away team `{command}`: {e}"))?;
                Running::External(child)
            }
        };
        Ok(TeamEntry {
            name: self.name.clone(),
            running,
        })
    }
}

enum Running {
    Ours(Team),
    External(Child),
}

/// The monitor's robots on the sides our teams play, each with its agent's self-estimate.
pub fn with_estimates(robots: &[RobotTruth], entries: &[TeamEntry]) -> Vec<RobotSample> {
    robots
        .iter()
        .filter_map(|robot| {
            let team = entries.iter().find_map(|entry| match &entry.running {
                Running::Ours(team) if entry.plays_left() == Some(robot.left) => Some(team),
                _ => None,
            })?;
            let estimate = team
                .stats
                .iter()
                .find(|(unum, _)| *unum == robot.unum)
                .and_then(|(_, stats)| stats.self_estimate());
            Some(RobotSample {
                left: robot.left,
                unum: robot.unum,
                torso: robot.torso,
                estimate,
            })
        })
        .collect()
}

/// A team taking part in a half.
pub struct TeamEntry {
    pub name: String,
    running: Running,
}

impl TeamEntry {
    /// Wait until every player of ours has joined (each joins after the one before it), or an
    /// external team has had time for its first.
    pub fn wait_joined(&self, timeout: Duration, shutdown: &AtomicBool) {
        let deadline = Instant::now() + timeout;
        match &self.running {
            Running::Ours(team) => {
                while Instant::now() < deadline && !shutdown.load(Ordering::Relaxed) {
                    let joined = team.stats.iter().all(|(_, s)| s.plays_left().is_some());
                    if joined {
                        return;
                    }
                    std::thread::sleep(Duration::from_millis(20));
                }
                log::warn!("team {}: not every player joined in {timeout:?}", self.name);
            }
            Running::External(_) => std::thread::sleep(EXTERNAL_FIRST_JOIN),
        }
    }

    /// The side the server gave our team (`None` for an external team).
    pub fn plays_left(&self) -> Option<bool> {
        match &self.running {
            Running::Ours(team) => team.stats.iter().find_map(|(_, s)| s.plays_left()),
            Running::External(_) => None,
        }
    }

    /// Our robots' ground truth and self-estimates (none for an external team).
    pub fn robots(&self) -> Vec<RobotSample> {
        let Running::Ours(team) = &self.running else {
            return Vec::new();
        };
        team.stats
            .iter()
            .filter_map(|(unum, stats)| {
                Some(RobotSample {
                    left: stats.plays_left()?,
                    unum: *unum,
                    torso: stats.truth_position()?,
                    estimate: stats.self_estimate(),
                })
            })
            .collect()
    }

    pub fn missed_cycles(&self) -> u64 {
        match &self.running {
            Running::Ours(team) => team
                .stats
                .iter()
                .map(|(_, s)| AgentStats::get(&s.missed_cycles))
                .sum(),
            Running::External(_) => 0,
        }
    }

    /// Stop the team: our agents leave; an external team's process group is terminated.
    pub fn stop(self) {
        match self.running {
            Running::Ours(team) => {
                team.stop();
            }
            Running::External(mut child) => {
                let group = format!("-{}", child.id());
                for signal in ["-TERM", "-KILL"] {
                    let _ = Command::new("kill").args([signal, "--", &group]).status();
                    let deadline = Instant::now() + Duration::from_secs(2);
                    while Instant::now() < deadline {
                        if let Ok(Some(_)) = child.try_wait() {
                            return;
                        }
                        std::thread::sleep(Duration::from_millis(50));
                    }
                }
                let _ = child.wait();
            }
        }
    }
}
