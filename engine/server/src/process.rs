//! Starting and stopping one server process (rcssservermj or SimSpark rcssserver3d).

use crate::monitor::Monitor;
use crate::ports::choose_ports;
use crate::simspark::{ensure_simspark_installed, run_files, RunSettings, SimSparkInstall};
use crate::venv::{ensure_installed, Installation};
use crate::ServerError;
pub use libero_model::ServerKind;
use std::io::Read;
use std::path::PathBuf;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

/// The server's rule set (`--rules`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Rules {
    /// 7 players a side on the 55 × 36 m `fifa7vs7` field, 300 s halves.
    #[default]
    Ssim,
    /// 11 a side on the 105 × 68 m `fifa` field, 2700 s halves.
    Fifa,
}

impl Rules {
    pub fn as_arg(self) -> &'static str {
        match self {
            Rules::Ssim => "ssim",
            Rules::Fifa => "fifa",
        }
    }

    /// Play time of one half [s] (the referee's `GameOver`).
    pub fn half_time_s(self) -> f64 {
        match self {
            Rules::Ssim => 300.0,
            Rules::Fifa => 2700.0,
        }
    }

    pub fn players_per_team(self) -> u32 {
        match self {
            Rules::Ssim => 7,
            Rules::Fifa => 11,
        }
    }
}

impl std::str::FromStr for Rules {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "ssim" | "ssim26" => Ok(Rules::Ssim),
            "fifa" => Ok(Rules::Fifa),
            other => Err(format!("unknown rules `{other}`: use `ssim` or `fifa`")),
        }
    }
}

/// How to run the server.
#[derive(Debug, Clone)]
pub struct ServerOptions {
    /// Which server: rcssservermj (T1, the league's) or SimSpark (NAO, the thesis's).
    pub server: ServerKind,
    /// Wait for every agent's answer each cycle.
    pub sync: bool,
    /// Keep 20 ms cycles; `false` runs as fast as the agents answer (and implies sync).
    pub realtime: bool,
    pub rules: Rules,
    /// The field (`--field`, e.g. `fifa7vs7`); `None` plays on the rule book's own. The FIFA
    /// rules on the 7-a-side field give one 2700 s half: rcssservermj ends play for good at
    /// the end of a half, so a longer stretch of play needs a longer half.
    pub field: Option<&'static str>,
    /// Agent port; `None` picks a free one.
    pub agent_port: Option<u16>,
    /// Monitor port; `None` picks a free one.
    pub monitor_port: Option<u16>,
    /// Where the server runs (it writes `console.log` there) and where `server.log` goes;
    /// `None` makes a fresh temporary directory.
    pub work_dir: Option<PathBuf>,
}

impl Default for ServerOptions {
    /// The fast mode used by tests and matches: `--sync --no-realtime`.
    fn default() -> Self {
        Self {
            server: ServerKind::RcssMj,
            sync: true,
            realtime: false,
            rules: Rules::Ssim,
            field: None,
            agent_port: None,
            monitor_port: None,
            work_dir: None,
        }
    }
}

/// What runs: the rcssservermj virtualenv or a SimSpark build.
#[derive(Debug, Clone)]
enum Program {
    RcssMj(Installation),
    SimSpark(SimSparkInstall),
}

impl Program {
    fn path(&self) -> PathBuf {
        match self {
            Program::RcssMj(install) => install.server_program(),
            Program::SimSpark(install) => install.server_program(),
        }
    }
}

/// A running server that this process started. Dropping it stops the server.
pub struct ServerProcess {
    child: Option<Child>,
    monitor: Option<Monitor>,
    program: Program,
    options: ServerOptions,
    pub agent_port: u16,
    pub monitor_port: u16,
    pub work_dir: PathBuf,
    /// The run folder is ours (a fresh temporary one) and goes when the server is dropped,
    /// unless `keep_files` says its log explains something.
    own_work_dir: bool,
    /// The server failed to start or ended on its own: its log is named in an error.
    keep_files: bool,
}

const START_TIMEOUT: Duration = Duration::from_secs(60);

impl ServerProcess {
    /// Install the server if needed and start it; returns once it accepts connections.
    pub fn start(options: ServerOptions) -> Result<Self, ServerError> {
        let program = match options.server {
            ServerKind::RcssMj => Program::RcssMj(ensure_installed()?),
            ServerKind::SimSpark => Program::SimSpark(ensure_simspark_installed(None)?),
        };
        let (agent_port, monitor_port) = choose_ports(options.agent_port, options.monitor_port)?;
        let own_work_dir = options.work_dir.is_none();
        let work_dir = match &options.work_dir {
            Some(dir) => dir.clone(),
            None => fresh_dir()?,
        };
        std::fs::create_dir_all(&work_dir)
            .map_err(|e| ServerError::Io(work_dir.display().to_string(), e))?;
        let mut server = Self {
            child: None,
            monitor: None,
            program,
            options,
            agent_port,
            monitor_port,
            work_dir,
            own_work_dir,
            keep_files: false,
        };
        let chosen_by_us =
            server.options.agent_port.is_none() && server.options.monitor_port.is_none();
        let mut attempt = 1;
        loop {
            match server.spawn() {
                // Another process took a port between our check and the server's bind.
                Err(ServerError::PortTaken(p)) if chosen_by_us && attempt < START_ATTEMPTS => {
                    log::warn!("port {p} was taken as the server started; trying other ports");
                    (server.agent_port, server.monitor_port) = choose_ports(None, None)?;
                    attempt += 1;
                }
                Err(e) => {
                    server.keep_files = true;
                    return Err(e);
                }
                Ok(()) => return Ok(server),
            }
        }
    }

    /// The server's process id while it runs (fault injection: stopping and continuing it).
    pub fn pid(&self) -> Option<u32> {
        self.child.as_ref().map(Child::id)
    }

    pub fn log_path(&self) -> PathBuf {
        self.work_dir.join("server.log")
    }

    fn spawn(&mut self) -> Result<(), ServerError> {
        let log_path = self.log_path();
        let log = std::fs::File::create(&log_path)
            .map_err(|e| ServerError::Io(log_path.display().to_string(), e))?;
        let err = log
            .try_clone()
            .map_err(|e| ServerError::Io(log_path.display().to_string(), e))?;
        let mut cmd = Command::new(self.program.path());
        cmd.current_dir(&self.work_dir)
            .stdin(Stdio::null())
            .stdout(log)
            .stderr(err);
        match &self.program {
            Program::RcssMj(_) => self.rcssmj_arguments(&mut cmd),
            Program::SimSpark(install) => {
                run_files(
                    install,
                    &self.work_dir,
                    RunSettings {
                        agent_port: self.agent_port,
                        monitor_port: self.monitor_port,
                        sync: self.options.sync || !self.options.realtime,
                        realtime: self.options.realtime,
                    },
                )?;
                // The server reads and writes `$HOME/.simspark`: the run folder, never the
                // user's home.
                cmd.env("HOME", &self.work_dir)
                    .env("LD_LIBRARY_PATH", install.library_path());
            }
        }
        let child = spawn_tied_to_this_process(cmd)
            .map_err(|e| ServerError::Io(self.program.path().display().to_string(), e))?;
        log::info!(
            "{} pid {} on 127.0.0.1 agent port {} monitor port {} (log {})",
            self.name(),
            child.id(),
            self.agent_port,
            self.monitor_port,
            log_path.display()
        );
        self.child = Some(child);
        self.monitor = None;
        self.wait_ready()
    }

    /// The server's name for messages.
    pub fn name(&self) -> &'static str {
        match self.program {
            Program::RcssMj(_) => "rcssservermj",
            Program::SimSpark(_) => "rcssserver3d",
        }
    }

    fn is_simspark(&self) -> bool {
        self.options.server == ServerKind::SimSpark
    }

    fn rcssmj_arguments(&self, cmd: &mut Command) {
        cmd.args(["--no-render", "--host", "127.0.0.1"])
            .args(["--aport", &self.agent_port.to_string()])
            .args(["--mport", &self.monitor_port.to_string()])
            .args(["--rules", self.options.rules.as_arg()])
            .arg(if self.options.realtime {
                "--realtime"
            } else {
                "--no-realtime"
            })
            .env("PYTHONUNBUFFERED", "1");
        if self.options.sync {
            cmd.arg("--sync");
        }
        if let Some(field) = self.options.field {
            cmd.args(["--field", field]);
        }
    }

    fn wait_ready(&mut self) -> Result<(), ServerError> {
        let start = Instant::now();
        loop {
            let log = read_text(&self.log_path());
            // SimSpark logs nothing at start-up: its monitor's first frame says it is up.
            if self.is_simspark() || log.contains("Starting server... DONE") {
                return self.wait_first_step(start);
            }
            if let Some(child) = self.child.as_mut() {
                if let Ok(Some(status)) = child.try_wait() {
                    self.child = None;
                    let tail: Vec<&str> = log.lines().rev().take(12).collect();
                    let tail = tail.into_iter().rev().collect::<Vec<_>>().join("\n");
                    if tail.contains("Address already in use") {
                        return Err(ServerError::PortTaken(self.agent_port));
                    }
                    return Err(ServerError::EarlyExit {
                        status: status.to_string(),
                        log: self.log_path().display().to_string(),
                        tail,
                    });
                }
            }
            if start.elapsed() > START_TIMEOUT {
                return Err(ServerError::StartTimeout(
                    START_TIMEOUT.as_secs(),
                    self.log_path().display().to_string(),
                ));
            }
            std::thread::sleep(Duration::from_millis(50));
        }
    }

    /// rcsssmj 0.2.1 crashes (audio engine, `a_forward`) when an agent is activated before
    /// the simulation's first step. A monitor frame is sent only after a step, so the first
    /// one proves it is safe to let agents in. The monitor connection then stays open for the
    /// server's whole life: closing a monitor socket can kill the server's simulation thread
    /// (it keeps writing to the closed socket).
    fn wait_first_step(&mut self, start: Instant) -> Result<(), ServerError> {
        while start.elapsed() < START_TIMEOUT {
            if self.monitor.is_none() {
                self.monitor = Monitor::connect_to(self.options.server, self.monitor_port).ok();
            }
            if let Some(monitor) = &self.monitor {
                if monitor.snapshot().frames > 0 {
                    return Ok(());
                }
            }
            if self.is_simspark() && read_text(&self.log_path()).contains("Address already in use")
            {
                // SimSpark keeps running without the socket it could not bind.
                self.kill();
                return Err(ServerError::PortTaken(self.agent_port));
            }
            if !self.is_running() {
                break;
            }
            std::thread::sleep(Duration::from_millis(10));
        }
        Err(ServerError::StartTimeout(
            START_TIMEOUT.as_secs(),
            self.log_path().display().to_string(),
        ))
    }

    /// The server's monitor connection (kick-off, ball placement, game state).
    pub fn monitor(&mut self) -> &mut Monitor {
        self.monitor
            .as_mut()
            .expect("a started server has a monitor")
    }

    /// Whether the process is still running.
    pub fn is_running(&mut self) -> bool {
        self.child
            .as_mut()
            .is_some_and(|c| matches!(c.try_wait(), Ok(None)))
    }

    /// Stop the server: SIGINT (its clean shutdown), then SIGKILL if it lingers. Only the
    /// process we started is signalled.
    pub fn stop(&mut self) {
        let Some(mut child) = self.child.take() else {
            return;
        };
        if let Ok(Some(_)) = child.try_wait() {
            // It ended before we asked: its log may say why.
            self.keep_files = true;
            return;
        }
        if let Ok(pid) = i32::try_from(child.id()) {
            // SAFETY: `pid` is our own child, not yet reaped (we hold its `Child`), so the
            // number cannot have been reused by another process.
            unsafe { libc::kill(pid, libc::SIGINT) };
        }
        let deadline = Instant::now() + Duration::from_secs(5);
        while Instant::now() < deadline {
            if let Ok(Some(_)) = child.try_wait() {
                return;
            }
            std::thread::sleep(Duration::from_millis(20));
        }
        let _ = child.kill();
        let _ = child.wait();
    }

    /// Kill the server abruptly (to test recovery), as a crash would.
    pub fn kill(&mut self) {
        if let Some(mut child) = self.child.take() {
            let _ = child.kill();
            let _ = child.wait();
        }
    }

    /// Start it again on the same ports after `stop` or `kill`.
    pub fn restart(&mut self) -> Result<(), ServerError> {
        self.stop();
        self.spawn()
    }
}

impl Drop for ServerProcess {
    fn drop(&mut self) {
        self.stop();
        if self.own_work_dir && !self.keep_files {
            let _ = std::fs::remove_dir_all(&self.work_dir);
        }
    }
}

fn read_text(path: &PathBuf) -> String {
    let mut s = String::new();
    if let Ok(mut f) = std::fs::File::open(path) {
        let _ = f.read_to_string(&mut s);
    }
    s
}

fn fresh_dir() -> Result<PathBuf, ServerError> {
    crate::scratch::fresh_dir(RUN_DIR_PREFIX)
        .map_err(|e| ServerError::Io(std::env::temp_dir().display().to_string(), e))
}

/// Run folders are `$TMPDIR/libero-server-<pid>-<n>`.
const RUN_DIR_PREFIX: &str = "libero-server";

/// How often `start` chooses new ports when the server finds one taken after all.
const START_ATTEMPTS: usize = 5;

/// Make the child `cmd` starts get SIGKILL when the thread that starts it exits (with the
/// process, if that thread lives as long). Call it from a thread that does.
pub fn die_with_parent(cmd: &mut Command) {
    use std::os::unix::process::CommandExt;
    // SAFETY: between fork and exec only async-signal-safe calls are allowed; prctl is one.
    unsafe {
        cmd.pre_exec(|| {
            if libc::prctl(libc::PR_SET_PDEATHSIG, libc::SIGKILL) != 0 {
                return Err(std::io::Error::last_os_error());
            }
            Ok(())
        });
    }
}

/// Start `cmd` so that it dies with this process, however this process ends (a killed test
/// or benchmark would otherwise leave a server running, and rcsssmj 0.2.1 grows by gigabytes
/// over a long life). Linux delivers the parent-death signal when the *thread* that forked
/// exits, so every server is forked from one thread that lives as long as the process.
fn spawn_tied_to_this_process(mut cmd: Command) -> std::io::Result<Child> {
    use std::sync::mpsc;
    use std::sync::Mutex;
    type Request = (Command, mpsc::Sender<std::io::Result<Child>>);
    static SPAWNER: Mutex<Option<mpsc::Sender<Request>>> = Mutex::new(None);

    die_with_parent(&mut cmd);
    let requests = {
        let mut spawner = SPAWNER.lock().unwrap_or_else(|p| p.into_inner());
        spawner
            .get_or_insert_with(|| {
                let (tx, rx) = mpsc::channel::<Request>();
                let started = std::thread::Builder::new()
                    .name("server-spawner".into())
                    .spawn(move || {
                        for (mut cmd, reply) in rx {
                            let _ = reply.send(cmd.spawn());
                        }
                    });
                if let Err(e) = started {
                    log::warn!("no spawner thread ({e}); servers fork from their caller");
                }
                tx
            })
            .clone()
    };
    let (reply_tx, reply_rx) = mpsc::channel();
    match requests.send((cmd, reply_tx)) {
        Ok(()) => reply_rx
            .recv()
            .unwrap_or_else(|_| Err(std::io::Error::other("the server spawner thread ended"))),
        Err(mpsc::SendError((mut cmd, _))) => cmd.spawn(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::BufRead;

    const PROBE: &str = "LIBERO_SPAWN_PROBE";

    fn alive(pid: i32) -> bool {
        // A zombie still answers kill(0); it has ended for our purposes.
        std::fs::read_to_string(format!("/proc/{pid}/stat"))
            .is_ok_and(|stat| stat.split_whitespace().nth(2).is_none_or(|s| s != "Z"))
    }

    #[test]
    fn a_spawned_program_dies_when_the_process_that_started_it_is_killed() {
        let _turn = crate::PORT_TESTS.lock().unwrap_or_else(|p| p.into_inner());
        if std::env::var_os(PROBE).is_some() {
            // The child role: start a long sleep from a short-lived thread (as the optimizer's
            // workers do), report its pid and wait to be killed.
            let mut child = std::thread::spawn(|| {
                let mut cmd = Command::new("sleep");
                cmd.arg("60");
                spawn_tied_to_this_process(cmd).unwrap()
            })
            .join()
            .unwrap();
            println!("spawned {}", child.id());
            let _ = child.wait(); // until this process is killed

            return;
        }
        let mut probe = Command::new(std::env::current_exe().unwrap())
            .args([
                "--exact",
                "process::tests::a_spawned_program_dies_when_the_process_that_started_it_is_killed",
                "--nocapture",
            ])
            .env(PROBE, "1")
            .stdout(Stdio::piped())
            .spawn()
            .unwrap();
        let stdout = std::io::BufReader::new(probe.stdout.take().unwrap());
        let pid: i32 = stdout
            .lines()
            .map_while(Result::ok)
            .find_map(|l| {
                l.strip_prefix("spawned ")
                    .and_then(|p| p.trim().parse().ok())
            })
            .expect("the probe reports its child");
        std::thread::sleep(Duration::from_millis(200));
        assert!(
            alive(pid),
            "the spawned program outlived only its spawning thread"
        );
        probe.kill().unwrap();
        let _ = probe.wait();
        let deadline = Instant::now() + Duration::from_secs(5);
        while alive(pid) && Instant::now() < deadline {
            std::thread::sleep(Duration::from_millis(20));
        }
        assert!(
            !alive(pid),
            "pid {pid} survived the process that started it"
        );
    }
}
