//! The field view in a real browser: headless Chromium opens the page that `libero match
//! --view` / `libero team --view --edit` / `libero view LOG…` serve on a real fast-mode
//! server, and the page's DOM is checked against what the agents wrote in their evaluation
//! logs and what the server's monitor says — not against what the page was sent.
//!
//! Chromium comes from the Debian package (`.ci/run` installs it); `LIBERO_CHROMIUM` names
//! another binary. `LIBERO_SCREENSHOTS=DIR` saves the screenshots the README shows.

mod browser;

use browser::*;
use serde_json::Value;
use std::sync::Mutex;
use std::time::{Duration, Instant};

/// Both tests run matches: one at a time on two cores.
static ONE_AT_A_TIME: Mutex<()> = Mutex::new(());

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
    tab.navigate_to(&url).unwrap();
    tab.wait_until_navigated().unwrap();
    wait_until(
        &tab,
        "document.querySelectorAll('g.robot').length === 6 && document.getElementById('mode').dataset.mode === 'PlayOn' && frame.monitor.time > 4",
        Duration::from_secs(180),
    );
    // Select Libero 3 by clicking its robot on the field, as a user does.
    let at = eval(
        &tab,
        r#"(() => { const r = document.querySelector('g.robot[data-team="Libero"][data-unum="3"] circle.body').getBoundingClientRect();
            return JSON.stringify([r.left + r.width / 2, r.top + r.height / 2]); })()"#,
    );
    tab.click_point(headless_chrome::browser::tab::point::Point {
        x: at[0].as_f64().unwrap(),
        y: at[1].as_f64().unwrap(),
    })
    .unwrap();
    wait_until(
        &tab,
        "document.getElementById('agent').value === 'Libero/3' && frame.monitor.time > 6 && frame.agents.some((a) => a.team === 'Libero' && a.unum === 3 && a.decision && a.decision.tree)",
        Duration::from_secs(60),
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

#[test]
fn the_formation_editor_writes_the_file_by_span_and_the_running_player_follows() {
    let _turn = ONE_AT_A_TIME.lock().unwrap_or_else(|p| p.into_inner());
    let team = tempfile::tempdir().unwrap();
    for folder in ["behaviors", "formations"] {
        std::fs::create_dir(team.path().join(folder)).unwrap();
        for entry in std::fs::read_dir(repository().join(folder)).unwrap() {
            let path = entry.unwrap().path();
            // Files only: formations/simspark/ is another team's set.
            if path.is_file() {
                std::fs::copy(
                    &path,
                    team.path().join(folder).join(path.file_name().unwrap()),
                )
                .unwrap();
            }
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
    eval(
        &tab,
        "document.getElementById('editor').scrollIntoView(), true",
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
