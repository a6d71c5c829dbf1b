//! Scenario files on the real server: shots are launched and measured, outcomes come from the
//! ground truth, and the JSON summary carries the figures.

use libero_agent::build::{default_data_dirs, load_library};
use libero_agent::SkillSource;
use libero_scenario::{load_text, run_series, Report, RunData, Scenario};
use libero_tests::live_turn;
use std::path::Path;
use std::time::Instant;

/// Shots from 6–8 m at varied angles at a point 0.5 m inside our goal; `ours` decides who is
/// in the way.
fn shots(ours: &str) -> Scenario {
    let text = format!(
        r#"Scenario(
    name: "short_shots",
    field: "fifa7vs7",
    ours: [{ours}],
    ball: Ball(
        at: (x: Range(-21.5, -19.5), y: Range(-4.0, 4.0)),
        launch: Some(Towards(target: (x: -28.0, y: Range(-1.0, 1.0)), speed_m_s: Range(6.0, 6.5))),
    ),
    settle_s: 0.5,
    time_limit_s: 4.0,
    success: BallKeptOut,
)"#
    );
    let mut report = Report::default();
    let scenario = load_text(Path::new("short_shots.ron"), text, &mut report);
    assert!(!report.has_errors(), "{}", report.render_text());
    scenario.unwrap()
}

fn data() -> RunData {
    RunData {
        library: load_library(&default_data_dirs(), false).unwrap(),
        skills: SkillSource::Builtin,
        interrupt: Default::default(),
    }
}

#[test]
fn shots_are_launched_measured_and_judged_from_ground_truth() {
    let _turn = live_turn();
    let wall = Instant::now();
    // Nobody in goal (our only robot stands at the centre): every shot must go in.
    let empty = shots("Robot(unum: 5, at: (x: 0.0, y: 10.0), play: Stand)");
    let (summary, error) = run_series(&empty, Path::new("short_shots.ron"), &data(), 2, 3, |_| {});
    assert!(error.is_none(), "{error:?}");
    assert_eq!(summary.runs.len(), 2);
    for r in &summary.runs {
        let line = libero_scenario::Summary::run_line(r);
        let launch = r
            .launch
            .unwrap_or_else(|| panic!("the ball was not seen moving: {line}"));
        // Launched where it was aimed (field direction roughly −x, towards our goal).
        let aimed = r.setup.launch_direction_deg();
        let off = (launch.direction_deg - aimed + 540.0).rem_euclid(360.0) - 180.0;
        assert!(
            off.abs() < 5.0,
            "launch {launch:?} against aimed {aimed:.1}°: {line}"
        );
        assert!(launch.mean_speed_m_s > 3.0, "{line}");
        assert!(r.setup.ball_velocity[0] < -4.0, "{line}");
        // On target and in: the goal is counted by the server and seen in the ball's path.
        let y = r
            .goal_line_y
            .unwrap_or_else(|| panic!("never crossed the goal line: {line}"));
        assert!(y.abs() < 1.83, "{line}");
        assert_eq!(r.goals_against, 1, "{line}");
        assert!(!r.success && r.why.as_deref().is_some_and(|w| w.contains("goal against")));
    }
    // Our keeper in goal: whatever happens, the verdict follows the ground truth.
    let keeper = shots("Robot(unum: 1, at: (x: -26.0, y: 0.0), heading_deg: 0.0)");
    let (summary, error) = run_series(&keeper, Path::new("short_shots.ron"), &data(), 2, 4, |_| {});
    assert!(error.is_none(), "{error:?}");
    for r in &summary.runs {
        let line = libero_scenario::Summary::run_line(r);
        assert!(r.launch.is_some(), "{line}");
        assert_eq!(r.success, r.goals_against == 0, "{line}");
        assert_eq!(r.success, r.time_s.is_some(), "{line}");
        if r.success {
            assert!(r.time_s.unwrap() <= 4.0 + 1e-9, "{line}");
            assert!(r.goal_line_y.is_none_or(|y| y.abs() > 1.5), "{line}");
        }
    }
    let json: serde_json::Value = serde_json::from_str(&summary.render_json()).unwrap();
    for field in [
        "scenario",
        "seed",
        "runs",
        "successes",
        "success_rate",
        "median_time_s",
        "mean_time_s",
        "per_run",
    ] {
        assert!(json.get(field).is_some(), "no `{field}` in {json}");
    }
    assert_eq!(json["runs"], 2);
    let run = &json["per_run"][0];
    for field in [
        "success",
        "time_s",
        "ball",
        "launch_velocity",
        "measured_launch",
        "goals_against",
        "robots",
        "ours",
    ] {
        assert!(run.get(field).is_some(), "no `{field}` in {run}");
    }
    assert!(run["measured_launch"]["direction_deg"].is_number());
    assert!(wall.elapsed().as_secs() < 120, "took {:?}", wall.elapsed());
}
