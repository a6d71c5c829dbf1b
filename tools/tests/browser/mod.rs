//! Driving headless Chromium and `libero` children for the field view's tests.

use headless_chrome::protocol::cdp::{Input, Page};
use headless_chrome::{Browser, LaunchOptions, Tab};
use serde_json::Value;
use std::collections::HashMap;
use std::io::{BufRead, BufReader, Read, Write};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

pub fn repository() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

pub fn find_chromium() -> Option<PathBuf> {
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
pub fn chromium() -> PathBuf {
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

pub fn browser() -> Browser {
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
pub struct Running {
    child: Child,
    lines: Arc<Mutex<Vec<String>>>,
}

impl Running {
    pub fn start(args: &[&str]) -> Running {
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
    pub fn wait_for(&mut self, pattern: &str, timeout: Duration) -> String {
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

    pub fn output(&self) -> String {
        self.lines.lock().unwrap().join("\n")
    }

    pub fn wait(mut self, timeout: Duration) {
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

pub fn url_in(line: &str) -> String {
    line[line.find("http://").unwrap()..]
        .split_whitespace()
        .next()
        .unwrap()
        .to_string()
}

/// Evaluate `js` (an expression giving a JSON string) in the page.
pub fn eval(tab: &Tab, js: &str) -> Value {
    let result = tab.evaluate(js, false).unwrap();
    match result.value {
        Some(Value::String(s)) => serde_json::from_str(&s).unwrap_or(Value::String(s)),
        Some(v) => v,
        None => Value::Null,
    }
}

pub fn wait_until(tab: &Tab, js: &str, timeout: Duration) {
    let deadline = Instant::now() + timeout;
    while eval(tab, js) != Value::Bool(true) {
        assert!(Instant::now() < deadline, "the page never met `{js}`");
        std::thread::sleep(Duration::from_millis(100));
    }
}

/// Where the page drew each robot, in field metres, from the elements' boxes on screen and the
/// field outline's box (the page's own scale), with the cycle each robot's copy is from.
pub const DRAWN: &str = r#"(() => {
  const o = document.getElementById('outline').getBoundingClientRect();
  const L = info.field.length / 2, W = info.field.width / 2;
  const at = (r) => [(r.left + r.width / 2 - o.left) / o.width * 2 * L - L, W - (r.top + r.height / 2 - o.top) / o.height * 2 * W];
  return JSON.stringify([...document.querySelectorAll('g.robot')].map((g) => {
    const [x, y] = at(g.querySelector('circle.body').getBoundingClientRect());
    return { team: g.dataset.team, unum: +g.dataset.unum, cycle: +g.dataset.cycle, x, y };
  }));
})()"#;

/// Where the page drew the selected agent's ball estimate, in field metres (null if not).
pub const BALL_DRAWN: &str = r#"(() => {
  const o = document.getElementById('outline').getBoundingClientRect();
  const L = info.field.length / 2, W = info.field.width / 2;
  const b = document.getElementById('ball-estimate');
  if (!b) return JSON.stringify([null, null]);
  const r = b.getBoundingClientRect();
  return JSON.stringify([(r.left + r.width / 2 - o.left) / o.width * 2 * L - L, W - (r.top + r.height / 2 - o.top) / o.height * 2 * W]);
})()"#;

/// An evaluation log's records by cycle.
pub fn log_by_cycle(path: &Path) -> HashMap<u64, Value> {
    std::fs::read_to_string(path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .lines()
        .filter_map(|l| serde_json::from_str::<Value>(l).ok())
        .map(|v| (v["cycle"].as_u64().unwrap(), v))
        .collect()
}

pub fn screenshot(tab: &Tab, name: &str) {
    let Ok(dir) = std::env::var("LIBERO_SCREENSHOTS") else {
        return;
    };
    let png = tab
        .capture_screenshot(Page::CaptureScreenshotFormatOption::Png, None, None, true)
        .unwrap();
    std::fs::write(Path::new(&dir).join(name), png).unwrap();
}

pub fn assert_drawn_as_logged(drawn: &Value, logs: &Path, prefix: &str) -> usize {
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

/// A raw HTTP request to the view (a page of another origin would send it like this).
pub fn post(address: &str, path: &str, headers: &[(&str, &str)], body: &str) -> (u16, String) {
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
pub fn drag(tab: &Tab, from: (f64, f64), to: (f64, f64)) {
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
pub fn marker(tab: &Tab, unum: u32) -> ((f64, f64), f64) {
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
