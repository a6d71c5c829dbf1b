//! The field view in a real browser: headless Chromium opens the page that `libero match
//! --view` / `libero team --view --edit` / `libero view LOG…` serve on a real fast-mode
//! server, and the page's DOM is checked against what the agents wrote in their evaluation
//! logs and what the server's monitor says — not against what the page was sent.
//!
//! Chromium comes from the Debian package (`.ci/run` installs it); `LIBERO_CHROMIUM` names
//! another binary. `LIBERO_SCREENSHOTS=DIR` saves the screenshots the README shows.

use headless_chrome::protocol::cdp::{Input, Page};
use headless_chrome::{Browser, LaunchOptions, Tab};
use serde_json::Value;
use std::collections::HashMap;
use std::io::{BufRead, BufReader, Read, Write};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

/// Both tests run matches: one at a time on two cores.
static ONE_AT_A_TIME: Mutex<()> = Mutex::new(());

fn repository() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

fn find_chromium() -> Option<PathBuf> {
    if let Ok(path) = std::env::var("LIBERO_CHROMIUM") {
        return Some(PathBuf::from(path));
    }
    ["chromium", "chromium-browser", "google-chrome"]
        .iter()
        .flat_map(|name| {
            ["/usr/bin", "/usr/local/bin", "/snap/bin"].map(|dir| Path::new(dir).join(name))
        })
        .find(|path| path.is_file())
}

/// Chromium, installed from the Debian package when it is missing and we may (root), as the
/// live tests install the server themselves.
fn chromium() -> PathBuf {
    static INSTALL: Mutex<()> = Mutex::new(());
    let _once = INSTALL.lock().unwrap_or_else(|p| p.into_inner());
    if let Some(path) = find_chromium() {
        return path;
    }
    const INSTALL_COMMAND: &str = "apt-get install -y chromium";
    let root = Command::new("id")
        .arg("-u")
        .output()
        .is_ok_and(|o| String::from_utf8_lossy(&o.stdout).trim() == "0");
    if root {
        eprintln!("view_live: Chromium is missing; `{INSTALL_COMMAND}`…");
        let installed = Command::new("sh")
            .args(["-c", &format!("DEBIAN_FRONTEND=noninteractive {INSTALL_COMMAND} >/dev/null || (apt-get update >/dev/null && DEBIAN_FRONTEND=noninteractive {INSTALL_COMMAND} >/dev/null)")])
            .status()
            .is_ok_and(|s| s.success());
        if let (true, Some(path)) = (installed, find_chromium()) {
            return path;
        }
    }
    panic!(
        "the field view's browser tests need Chromium: run `{INSTALL_COMMAND}` as root (.ci/run does), or set LIBERO_CHROMIUM=/path/to/chrome"
    );
}

fn browser() -> Browser {
    Browser::new(LaunchOptions {
        headless: true,
        sandbox: false,
        window_size: Some((1400, 820)),
        path: Some(chromium()),
        idle_browser_timeout: Duration::from_secs(600),
        ..LaunchOptions::default()
    })
    .expect("Chromium starts")
}

/// A `libero` child whose output lines are collected as they come.
struct Running {
    child: Child,
    lines: Arc<Mutex<Vec<String>>>,
}

impl Running {
    fn start(args: &[&str]) -> Running {
        let mut child = Command::new(env!("CARGO_BIN_EXE_libero"))
            .current_dir(repository())
            .args(args)
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        let lines = Arc::new(Mutex::new(Vec::new()));
        for stream in [
            Box::new(child.stdout.take().unwrap()) as Box<dyn Read + Send>,
            Box::new(child.stderr.take().unwrap()),
        ] {
            let lines = Arc::clone(&lines);
            std::thread::spawn(move || {
                for line in BufReader::new(stream).lines().map_while(Result::ok) {
                    lines.lock().unwrap().push(line);
                }
            });
        }
        Running { child, lines }
    }

    /// The first output line containing `pattern`.
    fn wait_for(&mut self, pattern: &str, timeout: Duration) -> String {
        let deadline = Instant::now() + timeout;
        loop {
            if let Some(line) = self
                .lines
                .lock()
                .unwrap()
                .iter()
                .find(|l| l.contains(pattern))
            {
                return line.clone();
            }
            if let Ok(Some(status)) = self.child.try_wait() {
                panic!(
                    "libero ended ({status}) before `{pattern}`:\n{}",
                    self.output()
                );
            }
            assert!(
                Instant::now() < deadline,
                "no `{pattern}` in:\n{}",
                self.output()
            );
            std::thread::sleep(Duration::from_millis(50));
        }
    }

    fn output(&self) -> String {
        self.lines.lock().unwrap().join("\n")
    }

    fn wait(mut self, timeout: Duration) {
        let deadline = Instant::now() + timeout;
        loop {
            if let Some(status) = self.child.try_wait().unwrap() {
                assert!(status.success(), "libero failed:\n{}", self.output());
                return;
            }
            assert!(
                Instant::now() < deadline,
                "libero did not end:\n{}",
                self.output()
            );
            std::thread::sleep(Duration::from_millis(100));
        }
    }
}

impl Drop for Running {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

fn url_in(line: &str) -> String {
    line[line.find("http://").unwrap()..]
        .split_whitespace()
        .next()
        .unwrap()
        .to_string()
}

/// Evaluate `js` (an expression giving a JSON string) in the page.
fn eval(tab: &Tab, js: &str) -> Value {
    let result = tab.evaluate(js, false).unwrap();
    match result.value {
        Some(Value::String(s)) => serde_json::from_str(&s).unwrap_or(Value::String(s)),
        Some(v) => v,
        None => Value::Null,
    }
}

fn wait_until(tab: &Tab, js: &str, timeout: Duration) {
    let deadline = Instant::now() + timeout;
    while eval(tab, js) != Value::Bool(true) {
        assert!(Instant::now() < deadline, "the page never met `{js}`");
        std::thread::sleep(Duration::from_millis(100));
    }
}

/// Where the page drew each robot, in field metres, from the elements' boxes on screen and the
/// field outline's box (the page's own scale), with the cycle each robot's copy is from.
const DRAWN: &str = r#"(() => {
  const o = document.getElementById('outline').getBoundingClientRect();
  const L = info.field.length / 2, W = info.field.width / 2;
  const at = (r) => [(r.left + r.width / 2 - o.left) / o.width * 2 * L - L, W - (r.top + r.height / 2 - o.top) / o.height * 2 * W];
  return JSON.stringify([...document.querySelectorAll('g.robot')].map((g) => {
    const [x, y] = at(g.querySelector('circle.body').getBoundingClientRect());
    return { team: g.dataset.team, unum: +g.dataset.unum, cycle: +g.dataset.cycle, x, y };
  }));
})()"#;

/// Where the page drew the selected agent's ball estimate, in field metres (null if not).
const BALL_DRAWN: &str = r#"(() => {
  const o = document.getElementById('outline').getBoundingClientRect();
  const L = info.field.length / 2, W = info.field.width / 2;
  const b = document.getElementById('ball-estimate');
  if (!b) return JSON.stringify([null, null]);
  const r = b.getBoundingClientRect();
  return JSON.stringify([(r.left + r.width / 2 - o.left) / o.width * 2 * L - L, W - (r.top + r.height / 2 - o.top) / o.height * 2 * W]);
})()"#;

/// An evaluation log's records by cycle.
fn log_by_cycle(path: &Path) -> HashMap<u64, Value> {
    std::fs::read_to_string(path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .lines()
        .filter_map(|l| serde_json::from_str::<Value>(l).ok())
        .map(|v| (v["cycle"].as_u64().unwrap(), v))
        .collect()
}

fn screenshot(tab: &Tab, name: &str) {
    let Ok(dir) = std::env::var("LIBERO_SCREENSHOTS") else {
        return;
    };
    let png = tab
        .capture_screenshot(Page::CaptureScreenshotFormatOption::Png, None, None, true)
        .unwrap();
    std::fs::write(Path::new(&dir).join(name), png).unwrap();
}

fn assert_drawn_as_logged(drawn: &Value, logs: &Path, prefix: &str) -> usize {
    let mut checked = 0;
    for robot in drawn.as_array().unwrap() {
        let (team, unum) = (
            robot["team"].as_str().unwrap(),
            robot["unum"].as_u64().unwrap(),
        );
        let log = log_by_cycle(&logs.join(format!("{prefix}.{team}.{unum}")));
        let cycle = robot["cycle"].as_u64().unwrap();
        let line = log
            .get(&cycle)
            .unwrap_or_else(|| panic!("{team} {unum} logged no cycle {cycle}"));
        let (x, y) = (robot["x"].as_f64().unwrap(), robot["y"].as_f64().unwrap());
        let logged = &line["me"]["position"];
        let (lx, ly) = (logged[0].as_f64().unwrap(), logged[1].as_f64().unwrap());
        let off = (x - lx).hypot(y - ly);
        assert!(
            off <= 0.2,
            "{team} {unum} drawn at ({x:.2}, {y:.2}), logged at ({lx:.2}, {ly:.2}) in cycle {cycle}"
        );
        checked += 1;
    }
    checked
}

#[test]
fn the_live_view_draws_the_match_as_logged_and_a_replay_steps_through_the_logs() {
    let _turn = ONE_AT_A_TIME.lock().unwrap_or_else(|p| p.into_inner());
    let dir = tempfile::tempdir().unwrap();
    let logs = dir.path().to_path_buf();
    let prefix = logs.join("l");
    let mut game = Running::start(&[
        "match",
        "--players",
        "3",
        "--away",
        "tools/teams/standing",
        "--away-name",
        "Standing",
        "--duration",
        "25",
        "--no-watch",
        "--view",
        "--log",
        prefix.to_str().unwrap(),
        "--trace",
    ]);
    let url = url_in(&game.wait_for("field view: http://", Duration::from_secs(60)));
    let port_line = game.wait_for("monitor port", Duration::from_secs(120));
    let port: u16 = port_line
        .split("monitor port ")
        .nth(1)
        .and_then(|r| r.split_whitespace().next())
        .and_then(|p| p.parse().ok())
        .unwrap();
    // The test's own monitor connection: the score and play mode to compare with the page's.
    // (The line comes as the server starts; it listens a moment later.)
    let deadline = Instant::now() + Duration::from_secs(60);
    let monitor = loop {
        match libero_server::Monitor::connect(port) {
            Ok(monitor) => break monitor,
            Err(e) if Instant::now() < deadline => {
                let _ = e;
                std::thread::sleep(Duration::from_millis(200));
            }
            Err(e) => panic!("no monitor on port {port}: {e}"),
        }
    };

    let browser = browser();
    let tab = browser.new_tab().unwrap();
    tab.navigate_to(&format!("{url}?agent=Libero/3")).unwrap();
    tab.wait_until_navigated().unwrap();
    wait_until(
        &tab,
        "document.querySelectorAll('g.robot').length === 6 && document.getElementById('mode').dataset.mode === 'PlayOn' && frame.monitor.time > 6",
        Duration::from_secs(180),
    );
    eval(&tab, "document.getElementById('freeze').click(), true");
    let truth = monitor.snapshot();
    let page = eval(
        &tab,
        r#"JSON.stringify({ left: +document.getElementById('score').dataset.left, right: +document.getElementById('score').dataset.right,
            mode: document.getElementById('mode').dataset.mode, time: frame.monitor.time, selected: document.getElementById('agent').value,
            tree_cycle: +document.getElementById('tree').dataset.cycle,
            running: [...document.querySelectorAll('#tree .node[data-status=running]')].map((n) => n.firstChild.textContent) })"#,
    );
    let drawn = eval(&tab, DRAWN);
    let ball = eval(&tab, BALL_DRAWN);
    screenshot(&tab, "view-live.png");
    assert_eq!(page["left"], truth.score_left, "{page}");
    assert_eq!(page["right"], truth.score_right, "{page}");
    assert_eq!(page["mode"], truth.play_mode.as_str(), "{page}");
    let lag = truth.time - page["time"].as_f64().unwrap();
    assert!(
        lag.abs() < 2.0,
        "the page is {lag} s of play behind the monitor"
    );
    assert_eq!(page["selected"], "Libero/3");
    // Started without --edit: the view is read-only.
    let address = url
        .trim_start_matches("http://")
        .trim_end_matches('/')
        .to_string();
    let (status, response) = post(
        &address,
        "/api/formation/move",
        &[],
        r#"{"file":"kickoff.ron","sample":0,"unum":2,"x":1.0,"y":1.0}"#,
    );
    assert_eq!(status, 403, "{response}");
    assert!(response.contains("read-only"), "{response}");
    game.wait(Duration::from_secs(240));

    // Every robot drawn where its agent's log says it believed it was in that cycle.
    assert_eq!(assert_drawn_as_logged(&drawn, &logs, "l"), 6, "{drawn}");
    // The selected agent's ball estimate too.
    let log = log_by_cycle(&logs.join("l.Libero.3"));
    let selected_cycle = drawn
        .as_array()
        .unwrap()
        .iter()
        .find(|r| r["team"] == "Libero" && r["unum"] == 3)
        .unwrap()["cycle"]
        .as_u64()
        .unwrap();
    let logged_ball = &log[&selected_cycle]["ball"]["position"];
    let (bx, by) = (
        ball[0].as_f64().expect("the ball is drawn"),
        ball[1].as_f64().unwrap(),
    );
    let (lx, ly) = (
        logged_ball[0].as_f64().unwrap(),
        logged_ball[1].as_f64().unwrap(),
    );
    assert!(
        (bx - lx).hypot(by - ly) <= 0.2,
        "ball drawn at ({bx:.2}, {by:.2}), logged at ({lx:.2}, {ly:.2})"
    );
    // The selected agent's tree: the leaves the page shows running are the trace's.
    let cycle = page["tree_cycle"].as_u64().unwrap();
    let trace = log[&cycle]["trace"].as_str().unwrap().to_string();
    let running_leaves: Vec<&str> = page["running"]
        .as_array()
        .unwrap()
        .iter()
        .filter_map(Value::as_str)
        .filter(|l| l.starts_with("Action ") || l.starts_with("Condition "))
        .collect();
    assert!(!running_leaves.is_empty(), "{page}");
    for leaf in running_leaves {
        assert!(
            trace.contains(&format!("{leaf}=Running")),
            "the page shows `{leaf}` running in cycle {cycle}; the trace: {trace}"
        );
    }

    // Replay of the six logs (a 3 v 3 match).
    let mut files: Vec<String> = std::fs::read_dir(&logs)
        .unwrap()
        .map(|e| e.unwrap().path().display().to_string())
        .collect();
    files.sort();
    assert_eq!(files.len(), 6, "{files:?}");
    let mut args = vec!["view"];
    args.extend(files.iter().map(String::as_str));
    let mut replay = Running::start(&args);
    let url = url_in(&replay.wait_for("field view: http://", Duration::from_secs(30)));
    tab.navigate_to(&url).unwrap();
    tab.wait_until_navigated().unwrap();
    wait_until(
        &tab,
        "frame !== null && frame.step === 0",
        Duration::from_secs(30),
    );
    // Scrub to the middle of the half, then step cycle by cycle.
    eval(
        &tab,
        "(() => { const t = document.getElementById('timeline'); t.value = Math.floor(info.steps / 2); t.dispatchEvent(new Event('input')); return true; })()",
    );
    wait_until(
        &tab,
        "frame.step === Math.floor(info.steps / 2)",
        Duration::from_secs(10),
    );
    let mut last_cycle: Option<u64> = None;
    for k in 0..5 {
        let before = eval(&tab, "frame.step").as_u64().unwrap();
        if k > 0 {
            eval(&tab, "document.getElementById('step').click(), true");
            wait_until(
                &tab,
                &format!("frame.step === {}", before + 1),
                Duration::from_secs(10),
            );
        }
        let drawn = eval(&tab, DRAWN);
        assert_eq!(assert_drawn_as_logged(&drawn, &logs, "l"), 6, "{drawn}");
        let ours = drawn
            .as_array()
            .unwrap()
            .iter()
            .find(|r| r["team"] == "Libero" && r["unum"] == 1)
            .unwrap()["cycle"]
            .as_u64()
            .unwrap();
        if let Some(last) = last_cycle {
            assert_eq!(ours, last + 1, "one step is one cycle");
        }
        last_cycle = Some(ours);
    }
    drop(replay);
}

/// A raw HTTP request to the view (a page of another origin would send it like this).
fn post(address: &str, path: &str, headers: &[(&str, &str)], body: &str) -> (u16, String) {
    let mut stream = std::net::TcpStream::connect(address).unwrap();
    let mut request = format!(
        "POST {path} HTTP/1.1\r\nHost: {address}\r\nContent-Type: application/json\r\nContent-Length: {}\r\nConnection: close\r\n",
        body.len()
    );
    for (k, v) in headers {
        request.push_str(&format!("{k}: {v}\r\n"));
    }
    request.push_str("\r\n");
    request.push_str(body);
    stream.write_all(request.as_bytes()).unwrap();
    let mut response = String::new();
    stream.read_to_string(&mut response).unwrap();
    let status = response
        .split_whitespace()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(0);
    (status, response)
}

/// Press at `from`, move in steps to `to`, release: a real drag through the browser's input.
fn drag(tab: &Tab, from: (f64, f64), to: (f64, f64)) {
    let event = |kind, (x, y): (f64, f64), buttons| Input::DispatchMouseEvent {
        Type: kind,
        x,
        y,
        modifiers: None,
        timestamp: None,
        button: Some(Input::MouseButton::Left),
        buttons: Some(buttons),
        click_count: Some(1),
        force: None,
        tangential_pressure: None,
        tilt_x: None,
        tilt_y: None,
        twist: None,
        delta_x: None,
        delta_y: None,
        pointer_Type: None,
    };
    use Input::DispatchMouseEventTypeOption::{MouseMoved, MousePressed, MouseReleased};
    tab.call_method(event(MouseMoved, from, 0)).unwrap();
    tab.call_method(event(MousePressed, from, 1)).unwrap();
    for k in 1..=10 {
        let t = f64::from(k) / 10.0;
        let at = (from.0 + t * (to.0 - from.0), from.1 + t * (to.1 - from.1));
        tab.call_method(event(MouseMoved, at, 1)).unwrap();
    }
    tab.call_method(event(MouseReleased, to, 0)).unwrap();
}

/// The screen centre of the editor's marker for `unum` and the screen pixels per metre.
fn marker(tab: &Tab, unum: u32) -> ((f64, f64), f64) {
    let m = eval(
        tab,
        &format!(
            "(() => {{ const r = document.querySelector('.edit-player[data-unum=\"{unum}\"]').getBoundingClientRect();
               const o = document.getElementById('outline').getBoundingClientRect();
               return JSON.stringify([r.left + r.width / 2, r.top + r.height / 2, o.width / info.field.length]); }})()"
        ),
    );
    let m = m.as_array().unwrap();
    (
        (m[0].as_f64().unwrap(), m[1].as_f64().unwrap()),
        m[2].as_f64().unwrap(),
    )
}

#[test]
fn the_formation_editor_writes_the_file_by_span_and_the_running_player_follows() {
    let _turn = ONE_AT_A_TIME.lock().unwrap_or_else(|p| p.into_inner());
    let team = tempfile::tempdir().unwrap();
    for folder in ["behaviors", "formations"] {
        std::fs::create_dir(team.path().join(folder)).unwrap();
        for entry in std::fs::read_dir(repository().join(folder)).unwrap() {
            let path = entry.unwrap().path();
            std::fs::copy(
                &path,
                team.path().join(folder).join(path.file_name().unwrap()),
            )
            .unwrap();
        }
    }
    let kickoff = team.path().join("formations/kickoff.ron");
    let original = std::fs::read_to_string(&kickoff).unwrap();
    let server =
        libero_server::ServerProcess::start(libero_server::ServerOptions::default()).unwrap();
    let port = server.agent_port.to_string();
    let behaviors = team.path().join("behaviors");
    let formations = team.path().join("formations");
    let mut running = Running::start(&[
        "team",
        "--players",
        "2",
        "--port",
        &port,
        "--behaviors",
        behaviors.to_str().unwrap(),
        "--formations",
        formations.to_str().unwrap(),
        "--view",
        "--edit",
    ]);
    let url = url_in(&running.wait_for("field view: http://", Duration::from_secs(60)));
    assert!(url.contains("token="), "{url}");
    let address = url
        .trim_start_matches("http://")
        .split('/')
        .next()
        .unwrap()
        .to_string();
    let token = url.split("token=").nth(1).unwrap().to_string();

    let browser = browser();
    let tab = browser.new_tab().unwrap();
    tab.navigate_to(&format!("{url}&agent=Libero/2")).unwrap();
    tab.wait_until_navigated().unwrap();
    // Player 2 stands in its kick-off formation; the editor shows kickoff.ron's centre sample.
    wait_until(
        &tab,
        "formations.length > 0 && frame !== null && frame.agents.some((a) => a.unum === 2 && a.decision && a.decision.formation_target)",
        Duration::from_secs(120),
    );
    let sample = eval(
        &tab,
        "(() => { const f = document.getElementById('formation'); f.value = 'kickoff.ron'; f.dispatchEvent(new Event('change'));
           const d = formations.find((d) => d.file === 'kickoff.ron'); const i = d.samples.findIndex((s) => s.ball[0] === 0 && s.ball[1] === 0);
           const s = document.getElementById('sample'); s.value = i; s.dispatchEvent(new Event('change'));
           return JSON.stringify({ index: i, at: d.samples[i].positions.find((p) => p[0] === 2)[1] }); })()",
    );
    let at = sample["at"].as_array().unwrap();
    let (x0, y0) = (at[0].as_f64().unwrap(), at[1].as_f64().unwrap());
    let target_before = eval(
        &tab,
        "JSON.stringify(frame.agents.find((a) => a.team === 'Libero' && a.unum === 2).decision.formation_target)",
    );
    let tb = target_before.as_array().unwrap();
    assert!(
        (tb[0].as_f64().unwrap() - x0).hypot(tb[1].as_f64().unwrap() - y0) < 0.3,
        "player 2's target {target_before} is the sample's ({x0}, {y0})"
    );

    // A drag 2 m towards the halfway line and 1 m to the side.
    let (centre, per_metre) = marker(&tab, 2);
    drag(
        &tab,
        centre,
        (centre.0 + 2.0 * per_metre, centre.1 - 1.0 * per_metre),
    );
    wait_until(
        &tab,
        "document.getElementById('edit-status').textContent.includes('written')",
        Duration::from_secs(10),
    );
    let status = eval(
        &tab,
        "JSON.stringify(document.getElementById('edit-status').textContent)",
    );
    screenshot(&tab, "view-editor.png");
    let edited = std::fs::read_to_string(&kickoff).unwrap();
    let doc = libero_view::FormationDoc::parse("kickoff.ron", &edited).unwrap();
    let index = sample["index"].as_u64().unwrap() as usize;
    let (_, moved) = doc.samples[index]
        .positions
        .iter()
        .find(|(u, _)| *u == 2)
        .unwrap();
    assert!(
        (moved[0] - (x0 + 2.0)).abs() <= 0.15 && (moved[1] - (y0 + 1.0)).abs() <= 0.15,
        "dragged to {moved:?} from ({x0}, {y0}); {status}"
    );
    // Only that tuple changed: every other line, comments included, is as it was.
    let changed: Vec<(&str, &str)> = original
        .lines()
        .zip(edited.lines())
        .filter(|(a, b)| a != b)
        .collect();
    assert_eq!(changed.len(), 1, "{changed:?}");
    assert_eq!(original.lines().count(), edited.lines().count());
    let expected_line = changed[0].0.replace(
        &libero_view::edit::tuple([x0, y0]).replacen('(', "2: (", 1),
        &libero_view::edit::tuple(*moved).replacen('(', "2: (", 1),
    );
    assert_eq!(changed[0].1, expected_line);
    let report = libero_strategy::validate_paths(&[behaviors.clone(), formations.clone()]);
    assert!(!report.has_errors(), "{}", report.render_text());
    // The running player takes the new target through hot reload.
    wait_until(
        &tab,
        &format!(
            "(() => {{ const t = frame.agents.find((a) => a.team === 'Libero' && a.unum === 2).decision.formation_target;
                return Math.hypot(t[0] - {}, t[1] - {}) < 0.3; }})()",
            moved[0], moved[1]
        ),
        Duration::from_secs(10),
    );

    // The files panel names the reload that took the edit up.
    wait_until(
        &tab,
        "[...document.querySelectorAll('#files tr.accepted')].some((r) => r.textContent.includes('kickoff.ron') && r.textContent.includes('taken'))",
        Duration::from_secs(10),
    );
    // A broken edit made by hand is shown refused, with the diagnostic naming the file.
    let shot = team.path().join("formations/shot.ron");
    let shot_text = std::fs::read_to_string(&shot).unwrap();
    std::fs::write(&shot, format!("{shot_text}\n)) not RON\n")).unwrap();
    wait_until(
        &tab,
        "[...document.querySelectorAll('#files tr.rejected')].some((r) => r.textContent.includes('shot.ron') && r.textContent.includes('refused')) && document.getElementById('files').textContent.includes('error')",
        Duration::from_secs(10),
    );
    std::fs::write(&shot, &shot_text).unwrap();
    wait_until(
        &tab,
        "[...document.querySelectorAll('#files tr.accepted')].some((r) => r.textContent.includes('shot.ron'))",
        Duration::from_secs(10),
    );

    // Without the token: the page's drag is refused and the file stays as it is.
    let no_token = browser.new_tab().unwrap();
    no_token.navigate_to(&format!("http://{address}/")).unwrap();
    no_token.wait_until_navigated().unwrap();
    wait_until(&no_token, "formations.length > 0", Duration::from_secs(30));
    eval(
        &no_token,
        &format!(
            "(() => {{ const f = document.getElementById('formation'); f.value = 'kickoff.ron'; f.dispatchEvent(new Event('change'));
               const s = document.getElementById('sample'); s.value = {index}; s.dispatchEvent(new Event('change')); return true; }})()"
        ),
    );
    let (centre, per_metre) = marker(&no_token, 3);
    drag(&no_token, centre, (centre.0 + 2.0 * per_metre, centre.1));
    wait_until(
        &no_token,
        "document.getElementById('edit-status').textContent.includes('token')",
        Duration::from_secs(10),
    );
    assert_eq!(std::fs::read_to_string(&kickoff).unwrap(), edited);
    // Another origin, even with the token, and a request without it: refused.
    let body = format!(r#"{{"file":"kickoff.ron","sample":{index},"unum":3,"x":1.0,"y":1.0}}"#);
    let (status, response) = post(
        &address,
        "/api/formation/move",
        &[
            ("X-Libero-Token", &token),
            ("Origin", "http://evil.example"),
        ],
        &body,
    );
    assert_eq!(status, 403, "{response}");
    let (status, response) = post(&address, "/api/formation/move", &[], &body);
    assert_eq!(status, 403, "{response}");
    let (status, response) = post(
        &address,
        "/api/formation/move",
        &[("X-Libero-Token", &token)],
        &body.replace("kickoff.ron", "../behaviors/common.ron"),
    );
    assert_eq!(status, 400, "{response}");
    // An edit `libero validate` refuses (a position off the field, inside the border the
    // editor lets a drag reach): the diagnostic comes back, nothing is written.
    let (status, response) = post(
        &address,
        "/api/formation/move",
        &[("X-Libero-Token", &token)],
        &body.replace(r#""x":1.0"#, r#""x":29.0"#),
    );
    assert_eq!(status, 422, "{response}");
    assert!(
        response.contains("off-field") && response.contains("kickoff.ron"),
        "{response}"
    );
    assert_eq!(std::fs::read_to_string(&kickoff).unwrap(), edited);
    drop(running);
    drop(server);
}
