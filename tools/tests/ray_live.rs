//! `libero optimize --ray` and `libero series --ray` on a real local Ray cluster (`ray start
//! --head` on 127.0.0.1 and a second node, both from the project's virtualenv), each job a
//! real fast-mode rcssservermj: a killed driver's search continues from its checkpoint, a
//! killed worker node's match is run again elsewhere and the series is complete, and a node
//! with the wrong server version is refused before any job runs.

use std::os::unix::process::CommandExt;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

fn libero() -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_libero"));
    c.current_dir(root());
    c
}

/// The project's virtualenv with rcsssmj and Ray in it (installed on first use).
fn venv() -> PathBuf {
    let out = libero()
        .args(["server", "install", "--with-ray"])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    libero_server::venv::venv_path()
}

fn free_port() -> u16 {
    for port in 20_000 + (std::process::id() % 5_000) as u16..32_000 {
        if std::net::TcpListener::bind(("127.0.0.1", port)).is_ok() {
            return port;
        }
    }
    panic!("no free port");
}

/// A local Ray cluster: the head and one more node, one CPU each; stopped when dropped.
struct Cluster {
    address: String,
    temp: tempfile::TempDir,
    venv: PathBuf,
    head_env: Vec<(String, String)>,
    nodes: Vec<Child>,
}

impl Cluster {
    fn start() -> Self {
        let venv = venv();
        let temp = tempfile::Builder::new()
            .prefix("ray")
            .tempdir_in("/tmp")
            .unwrap();
        let port = free_port();
        let address = format!("127.0.0.1:{port}");
        let head_env = vec![
            ("LIBERO_VENV".to_string(), venv.display().to_string()),
            ("RAY_DISABLE_USAGE_STATS".to_string(), "1".to_string()),
        ];
        let mut cluster = Cluster {
            address,
            temp,
            venv,
            head_env,
            nodes: Vec::new(),
        };
        let head = cluster.node(
            &[
                "--head",
                &format!("--port={port}"),
                "--include-dashboard=false",
            ],
            &[],
        );
        cluster.nodes.push(head);
        cluster.wait_for_nodes(1);
        let worker = cluster.node(&[&format!("--address={}", cluster.address)], &[]);
        cluster.nodes.push(worker);
        cluster.wait_for_nodes(2);
        cluster
    }

    /// `ray start --block` in its own process group, so killing the group takes the node's
    /// raylet and its workers down at once (a lost machine).
    fn node(&self, args: &[&str], extra_env: &[(&str, &str)]) -> Child {
        let mut c = Command::new(self.venv.join("bin/ray"));
        c.arg("start")
            .args(args)
            .args([
                "--node-ip-address=127.0.0.1",
                "--num-cpus=1",
                "--block",
                "--disable-usage-stats",
            ])
            .arg(format!("--temp-dir={}", self.temp.path().display()))
            .envs(self.head_env.iter().map(|(k, v)| (k, v)))
            .envs(extra_env.iter().copied())
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .process_group(0);
        c.spawn().unwrap()
    }

    fn alive_nodes(&self) -> usize {
        let out = Command::new(self.venv.join("bin/python"))
            .args([
                "-c",
                "import ray,sys; ray.init(address=sys.argv[1], logging_level='ERROR'); \
                 print(sum(1 for n in ray.nodes() if n['Alive']))",
                &self.address,
            ])
            .env("RAY_DISABLE_USAGE_STATS", "1")
            .output()
            .unwrap();
        String::from_utf8_lossy(&out.stdout)
            .trim()
            .parse()
            .unwrap_or(0)
    }

    fn wait_for_nodes(&self, n: usize) {
        let deadline = Instant::now() + Duration::from_secs(90);
        while self.alive_nodes() < n {
            assert!(
                Instant::now() < deadline,
                "the Ray cluster did not get {n} nodes"
            );
            std::thread::sleep(Duration::from_secs(1));
        }
    }

    fn kill_node(&mut self, index: usize) {
        let pid = self.nodes[index].id() as i32;
        // SAFETY: kill(2) on the node's own process group.
        unsafe {
            libc::kill(-pid, libc::SIGKILL);
        }
        let _ = self.nodes[index].wait();
    }
}

impl Drop for Cluster {
    fn drop(&mut self) {
        for i in (0..self.nodes.len()).rev() {
            self.kill_node(i);
        }
    }
}

/// Whether process `pid` descends from `ancestor` (through /proc's parent links).
fn descends_from(mut pid: i32, ancestor: i32) -> bool {
    for _ in 0..64 {
        if pid == ancestor {
            return true;
        }
        let Ok(stat) = std::fs::read_to_string(format!("/proc/{pid}/stat")) else {
            return false;
        };
        // The fields after the command's closing parenthesis: state, then the parent's pid.
        let Some(after) = stat.rsplit_once(')').map(|(_, rest)| rest.to_string()) else {
            return false;
        };
        match after.split_whitespace().nth(1).and_then(|p| p.parse().ok()) {
            Some(parent) if parent > 1 => pid = parent,
            _ => return false,
        }
    }
    false
}

/// Pids of the `libero match` jobs running now.
fn match_jobs() -> Vec<i32> {
    let mut pids = Vec::new();
    for entry in std::fs::read_dir("/proc").unwrap().flatten() {
        let Ok(pid) = entry.file_name().to_string_lossy().parse::<i32>() else {
            continue;
        };
        let Ok(cmdline) = std::fs::read(format!("/proc/{pid}/cmdline")) else {
            continue;
        };
        let args: Vec<&[u8]> = cmdline.split(|&b| b == 0).collect();
        if args.len() > 1 && args[0].ends_with(b"/libero") && args[1] == b"match" {
            pids.push(pid);
        }
    }
    pids
}

#[test]
fn ray_runs_the_optimizer_and_a_series_through_a_killed_driver_and_a_killed_node() {
    let mut cluster = Cluster::start();
    let dir = tempfile::tempdir().unwrap();

    // 1. The optimizer: three generations; the run is killed once the first checkpoint is
    //    written, and the same command continues from it.
    let params = dir.path().join("t1.ron");
    std::fs::copy(root().join("engine/skills/params/t1.ron"), &params).unwrap();
    let checkpoint = dir.path().join("search.json");
    let optimize = |c: &mut Command| {
        c.args([
            "optimize",
            "walk",
            "--course",
            "forward",
            "--generations",
            "3",
        ])
        .args([
            "--population",
            "2",
            "--tunables",
            "step_period_s",
            "--dry-run",
        ])
        .arg("--params")
        .arg(&params)
        .arg("--checkpoint")
        .arg(&checkpoint)
        .args(["--ray", &cluster.address]);
    };
    let mut first = libero();
    optimize(&mut first);
    let mut first = first
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let deadline = Instant::now() + Duration::from_secs(600);
    while !checkpoint.exists() {
        assert!(
            first.try_wait().unwrap().is_none(),
            "the first run ended early"
        );
        assert!(Instant::now() < deadline, "no checkpoint in 10 minutes");
        std::thread::sleep(Duration::from_millis(100));
    }
    first.kill().unwrap();
    first.wait().unwrap();
    let saved: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&checkpoint).unwrap()).unwrap();
    let done_before = saved["history"].as_array().unwrap().len();
    assert!((1..3).contains(&done_before), "{saved}");
    let mut again = libero();
    optimize(&mut again);
    let out = again.output().unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{stdout}\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(
        stdout.contains(&format!(
            "continued from the checkpoint after generation {done_before}"
        )),
        "{stdout}"
    );
    assert!(stdout.contains("generation   3:"), "{stdout}");
    let evaluations = 2 * (3 - done_before);
    assert!(
        stdout.contains(&format!("{evaluations} evaluations in this run")),
        "only the generations left ran: {stdout}"
    );

    // 2. A series of four short halves; the second node is killed while it plays one of them.
    let report = dir.path().join("series.json");
    let worker_pid = cluster.nodes[1].id() as i32;
    let mut series = libero()
        .args([
            "series",
            "--matches",
            "4",
            "--half-s",
            "12",
            "--players",
            "1",
        ])
        .args(["--away", "tools/teams/standing", "--ray", &cluster.address])
        .arg("--report")
        .arg(&report)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let deadline = Instant::now() + Duration::from_secs(300);
    let on_worker = loop {
        if let Some(pid) = match_jobs()
            .into_iter()
            .find(|&p| descends_from(p, worker_pid))
        {
            break pid;
        }
        assert!(
            series.try_wait().unwrap().is_none(),
            "the series ended before the kill"
        );
        assert!(
            Instant::now() < deadline,
            "no match ever ran on the second node"
        );
        std::thread::sleep(Duration::from_millis(200));
    };
    // Let it play a little, then the node is gone.
    std::thread::sleep(Duration::from_secs(3));
    cluster.kill_node(1);
    // The node's Ray worker leaves once its raylet is gone, and the job (and its server)
    // dies with the worker that ran it.
    let killed = Instant::now();
    while Path::new(&format!("/proc/{on_worker}")).exists() {
        assert!(
            killed.elapsed() < Duration::from_secs(30),
            "the killed node's match job outlived it by 30 s"
        );
        std::thread::sleep(Duration::from_millis(100));
    }
    eprintln!(
        "the killed node's job was gone {:.1} s after the node",
        killed.elapsed().as_secs_f64()
    );
    let out = series.wait_with_output().unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{stdout}\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&report).unwrap()).unwrap();
    assert_eq!(json["played"], 4, "{json}");
    assert_eq!(json["failed"].as_array().unwrap().len(), 0, "{json}");
    let nodes: Vec<&str> = json["matches"]
        .as_array()
        .unwrap()
        .iter()
        .map(|m| m["node"].as_str().unwrap())
        .collect();
    // Every match finished on the head: the one the second node had started was run again.
    assert!(nodes.windows(2).all(|w| w[0] == w[1]), "{nodes:?}");
    assert!(
        json["cpu_s_per_match"]["mean"].as_f64().unwrap() > 1.0,
        "{json}"
    );

    // 3. A node whose virtualenv holds another rcsssmj is refused before any job runs.
    let fake = dir.path().join("other-venv");
    std::fs::create_dir_all(fake.join("bin")).unwrap();
    let python = fake.join("bin/python");
    std::fs::write(&python, "#!/bin/sh\necho 0.0.9\n").unwrap();
    std::fs::set_permissions(&python, std::os::unix::fs::PermissionsExt::from_mode(0o755)).unwrap();
    let other = cluster.node(
        &[&format!("--address={}", cluster.address)],
        &[("LIBERO_VENV", fake.to_str().unwrap())],
    );
    cluster.nodes.push(other);
    cluster.wait_for_nodes(2);
    let out = libero()
        .args([
            "series",
            "--matches",
            "1",
            "--half-s",
            "5",
            "--players",
            "1",
        ])
        .args(["--ray", &cluster.address])
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success());
    assert!(
        stderr.contains("rcsssmj 0.0.9") && stderr.contains("needs 0.2.1"),
        "{stderr}"
    );
}
