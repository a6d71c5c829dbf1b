//! Scenario files: a good one, and each kind of error at its place.

use crate::load::{is_scenario_text, load_text};
use crate::spec::{path_point, shortfall};
use crate::spec::{Launch, Num, Play, Success};
use libero_behavior::Report;
use libero_world::WorldParams;
use std::path::Path;

const GOOD: &str = r#"// Shots on goal against our keeper alone.
Scenario(
    name: "keeper_shots",
    field: "fifa7vs7",
    ours: [Robot(unum: 1, at: (x: -26.0, y: 0.0), heading_deg: 0.0)],
    theirs: [Robot(unum: 4, at: (-14.0, Range(-2.0, 2.0)), heading_deg: 180, play: Tree)],
    ball: Ball(
        at: (x: Range(-21.5, -15.5), y: Range(-4.0, 4.0)),
        launch: Some(Towards(target: (x: -27.5, y: Range(-1.2, 1.2)), speed_m_s: Range(6.5, 7.5))),
    ),
    time_limit_s: 8.0,
    success: All([BallKeptOut, NoCollision(min_distance_m: 0.45)]),
)
"#;

fn check(text: &str) -> (Option<crate::Scenario>, Report) {
    let mut report = Report::default();
    let s = load_text(Path::new("s.ron"), text.to_string(), &mut report);
    (s, report)
}

/// The one error of `text`: its code and `line:column`.
fn one_error(text: &str) -> (String, String) {
    let (s, report) = check(text);
    assert!(s.is_none(), "expected an error in:\n{text}");
    let errors: Vec<_> = report
        .diagnostics
        .iter()
        .filter(|d| d.severity == libero_behavior::Severity::Error)
        .collect();
    assert_eq!(errors.len(), 1, "{}", report.render_text());
    let d = errors[0];
    let loc = d.location.as_ref().expect("located");
    let (line, col) = loc.file.line_col(loc.span.start);
    (d.code.to_string(), format!("{line}:{col}"))
}

#[test]
fn a_good_file_reads_with_defaults() {
    let (s, report) = check(GOOD);
    assert!(!report.has_errors(), "{}", report.render_text());
    assert_eq!(report.warning_count(), 0, "{}", report.render_text());
    let s = s.unwrap();
    assert_eq!(s.name, "keeper_shots");
    assert_eq!(s.ours[0].play, Play::Tree);
    assert_eq!(s.theirs[0].unum, 4);
    assert!(matches!(s.theirs[0].at, crate::spec::Place::At(p) if p.y == Num::Range(-2.0, 2.0)));
    assert_eq!(s.settle_s, 1.0);
    assert!(matches!(s.ball.launch, Some(Launch::Towards { .. })));
    assert!(matches!(&s.success, Success::All(p) if p.len() == 2));
    assert!(is_scenario_text(GOOD));
    assert!(!is_scenario_text("// a tree\n{ \"A\": Action(\"Stand\") }"));
}

#[test]
fn runs_are_reproducible_and_varied() {
    let (s, _) = check(GOOD);
    let s = s.unwrap();
    let ball = WorldParams::builtin().ball;
    let a = s.draw(7, 3, &ball);
    assert_eq!(a, s.draw(7, 3, &ball));
    assert_ne!(a.ball, s.draw(7, 4, &ball).ball);
    assert_ne!(a.ball, s.draw(8, 3, &ball).ball);
    for i in 0..50 {
        let r = s.draw(1, i, &ball);
        assert!((-21.5..=-15.5).contains(&r.ball[0]));
        // Every shot is aimed to reach its target in the goal.
        let t = r.target.unwrap();
        assert!(shortfall(&ball, r.ball, t, r.launch_speed()) <= 0.0);
        // ... and its modelled path goes through the target.
        let h = r.ball_velocity[1].atan2(r.ball_velocity[0]);
        let d = (t[0] - r.ball[0]).hypot(t[1] - r.ball[1]);
        let closest = (0..=400)
            .map(|k| {
                path_point(
                    &ball,
                    r.ball,
                    r.launch_speed(),
                    h,
                    d * 1.2 * k as f64 / 400.0,
                )
            })
            .map(|p| (p[0] - t[0]).hypot(p[1] - t[1]))
            .fold(f64::INFINITY, f64::min);
        assert!(
            closest < 0.05,
            "run {i}: the path passes {closest:.3} m from the target"
        );
        assert!(r.ball_velocity[0] < 0.0);
    }
}

#[test]
fn syntax_errors_are_located() {
    let text = GOOD.replace("time_limit_s: 8.0,", "time_limit_s: 8.0 oops");
    assert_eq!(one_error(&text).0, "syntax");
}

#[test]
fn unknown_and_missing_fields() {
    let text = GOOD.replace("time_limit_s:", "time_limt_s:");
    let (s, report) = check(&text);
    assert!(s.is_none());
    let text_out = report.render_text();
    assert!(
        text_out.contains("missing field `time_limit_s`"),
        "{text_out}"
    );
    assert!(
        text_out.contains("unknown field `time_limt_s`"),
        "{text_out}"
    );
    assert!(
        text_out.contains("did you mean `time_limit_s`?"),
        "{text_out}"
    );
    assert!(text_out.contains("s.ron:11:5"), "{text_out}");
}

#[test]
fn an_unknown_field_geometry() {
    let text = GOOD.replace("\"fifa7vs7\"", "\"fifa7v7\"");
    assert_eq!(
        one_error(&text),
        ("unknown-field-geometry".into(), "4:12".into())
    );
}

#[test]
fn uniform_numbers_in_range_and_unique() {
    let text = GOOD.replace("Robot(unum: 1,", "Robot(unum: 8,");
    assert_eq!(one_error(&text), ("out-of-range".into(), "5:24".into()));
    let text = GOOD.replace(
        "ours: [Robot(unum: 1, at: (x: -26.0, y: 0.0), heading_deg: 0.0)],",
        "ours: [Robot(unum: 1, at: (-26.0, 0.0)), Robot(unum: 1, at: (-20.0, 0.0))],",
    );
    assert_eq!(one_error(&text), ("duplicate-unum".into(), "5:58".into()));
}

#[test]
fn positions_off_the_field_and_empty_ranges() {
    let text = GOOD.replace("(x: -26.0, y: 0.0)", "(x: -28.0, y: 0.0)");
    assert_eq!(one_error(&text), ("off-field".into(), "5:31".into()));
    let text = GOOD.replace("y: Range(-4.0, 4.0)", "y: Range(4.0, -4.0)");
    assert_eq!(one_error(&text), ("empty-range".into(), "8:41".into()));
    let text = GOOD.replace("y: Range(-4.0, 4.0)", "y: Range(-4.0, 19.0)");
    assert_eq!(one_error(&text).0, "off-field");
}

#[test]
fn a_shot_that_stops_short_is_not_on_target() {
    let text = GOOD.replace("Range(6.5, 7.5)", "Range(2.0, 7.5)");
    let (code, at) = one_error(&text);
    assert_eq!((code.as_str(), at.as_str()), ("launch-short", "9:22"));
}

#[test]
fn bad_conditions_and_choices() {
    let text = GOOD.replace("BallKeptOut,", "BallKeptOot,");
    assert_eq!(
        one_error(&text),
        ("unknown-condition".into(), "12:19".into())
    );
    let text = GOOD.replace(
        "All([BallKeptOut, NoCollision(min_distance_m: 0.45)])",
        "BallReached(unum: 4, within_m: 0.5)",
    );
    assert_eq!(one_error(&text), ("unknown-robot".into(), "12:32".into()));
    let text = GOOD.replace(
        "All([BallKeptOut, NoCollision(min_distance_m: 0.45)])",
        "PassReceived(receiver: 4, within_m: 1.0)",
    );
    assert_eq!(one_error(&text), ("unknown-robot".into(), "12:37".into()));
    let text = GOOD.replace(
        "All([BallKeptOut, NoCollision(min_distance_m: 0.45)])",
        "PassReceived(receiver: 1, within_m: 9.0)",
    );
    assert_eq!(one_error(&text).0, "out-of-range");
    let text = GOOD.replace("play: Tree", "play: Walk");
    assert_eq!(one_error(&text), ("invalid-choice".into(), "6:84".into()));
    let text = GOOD.replace("Some(Towards(", "Some(Toward(");
    assert_eq!(one_error(&text).0, "invalid-choice");
    let text = GOOD.replace(
        "All([BallKeptOut, NoCollision(min_distance_m: 0.45)])",
        "All([])",
    );
    assert_eq!(one_error(&text).0, "empty-composite");
}

#[test]
fn robots_placed_from_the_ball() {
    let text = GOOD.replace(
        "at: (-14.0, Range(-2.0, 2.0))",
        "at: FromBall(dx: Range(0.8, 1.2), dy: 0.0)",
    );
    let (s, report) = check(&text);
    assert!(!report.has_errors(), "{}", report.render_text());
    let s = s.unwrap();
    let r = s.draw(3, 0, &WorldParams::builtin().ball);
    let gap = r.theirs[0].pose[0] - r.ball[0];
    assert!((0.8..=1.2).contains(&gap) && r.theirs[0].pose[1] == r.ball[1]);
    let text = GOOD.replace(
        "at: (-14.0, Range(-2.0, 2.0))",
        "at: FromBall(dx: -15.0, dy: 0.0)",
    );
    assert_eq!(one_error(&text), ("off-field".into(), "6:33".into()));
}

#[test]
fn only_play_on_can_be_set() {
    let (_, report) = check(&GOOD.replace(
        "time_limit_s: 8.0,",
        "play_mode: PlayOn,\n    time_limit_s: 8.0,",
    ));
    assert!(!report.has_errors(), "{}", report.render_text());
    let text = GOOD.replace(
        "time_limit_s: 8.0,",
        "play_mode: KickOff_Left,\n    time_limit_s: 8.0,",
    );
    assert_eq!(
        one_error(&text),
        ("unsupported-play-mode".into(), "11:16".into())
    );
}

#[test]
fn an_empty_team_of_ours() {
    let text = GOOD.replace(
        "ours: [Robot(unum: 1, at: (x: -26.0, y: 0.0), heading_deg: 0.0)],",
        "ours: [],",
    );
    assert_eq!(one_error(&text).0, "empty-team");
}

#[test]
fn not_utf8_and_hostile_input_do_not_panic() {
    let mut report = Report::default();
    for text in [
        "",
        "Scenario(",
        "Scenario(name: [[[[",
        "((((((((",
        "Scenario(ours: 1e999)",
    ] {
        let _ = load_text(Path::new("x.ron"), text.to_string(), &mut report);
    }
    assert!(report.has_errors());
}

#[test]
fn a_file_with_a_byte_order_mark_is_a_scenario_and_loads() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("bom.ron");
    std::fs::write(&path, format!("\u{feff}{GOOD}")).unwrap();
    assert!(crate::is_scenario_file(&path));
    let mut report = Report::default();
    let scenario = crate::load_file(&path, &mut report);
    assert!(scenario.is_some(), "{}", report.render_text());
    assert!(is_scenario_text(&format!("\u{feff}{GOOD}")));
}

#[test]
fn a_huge_file_is_refused_unread() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("huge.ron");
    std::fs::File::create(&path)
        .unwrap()
        .set_len(50 << 20)
        .unwrap();
    assert!(!crate::is_scenario_file(&path));
    let start = std::time::Instant::now();
    let mut report = Report::default();
    assert!(crate::load_file(&path, &mut report).is_none());
    assert!(start.elapsed() < std::time::Duration::from_secs(1));
    let text = report.render_text();
    assert!(text.len() < 2048 && text.contains("huge.ron"), "{text}");
}

#[test]
#[ignore]
fn print_rest_distances() {
    let ball = WorldParams::builtin().ball;
    for v in [3.0, 4.0, 4.5, 5.0, 5.5, 6.0, 6.5, 7.0, 8.0] {
        let d0 = ball.launch_table.stop_offset(v, 0.0).norm();
        let d30 = ball.launch_table.stop_offset(v, 0.5).norm();
        println!("{v} m/s: rest {d0:.2} m along an axis, {d30:.2} m at 29°");
    }
    for d in [10.0, 11.0, 12.0] {
        println!(
            "{d} m: {:.2} m/s",
            ball.launch_table.speed_for_distance(d, 0.0)
        );
    }
}

#[test]
fn the_shipped_scenarios_are_valid() {
    let dir = crate::default_scenarios_dir();
    let mut files: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .flatten()
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|e| e == "ron"))
        .collect();
    files.sort();
    assert!(files.len() >= 4, "{files:?}");
    for f in &files {
        assert!(crate::is_scenario_file(f), "{}", f.display());
    }
    let report = crate::validate_files(&files);
    assert!(report.diagnostics.is_empty(), "{}", report.render_text());
}

#[test]
fn robots_placed_round_the_ball_and_a_shot_on_target_condition() {
    let text = GOOD
        .replace(
            "at: (-14.0, Range(-2.0, 2.0))",
            "at: AroundBall(distance_m: Range(2.0, 6.0), bearing_deg: Range(-180.0, 180.0))",
        )
        .replace(
            "success: All([BallKeptOut, NoCollision(min_distance_m: 0.45)])",
            "success: ShotOnTarget(min_m: 6.0)",
        );
    let (s, report) = check(&text);
    assert!(!report.has_errors(), "{}", report.render_text());
    let s = s.unwrap();
    assert_eq!(s.success, Success::ShotOnTarget { min_m: 6.0 });
    assert_eq!(s.success.describe(), "ShotOnTarget(min_m: 6)");
    let ball = WorldParams::builtin().ball;
    let mut sides = [false; 4];
    for i in 0..40 {
        let r = s.draw(5, i, &ball);
        let (dx, dy) = (
            r.theirs[0].pose[0] - r.ball[0],
            r.theirs[0].pose[1] - r.ball[1],
        );
        let d = dx.hypot(dy);
        assert!((2.0 - 1e-9..=6.0 + 1e-9).contains(&d), "{d}");
        sides[usize::from(dx > 0.0) * 2 + usize::from(dy > 0.0)] = true;
    }
    assert_eq!(sides, [true; 4], "drawn on every side of the ball");
    // A ring that reaches off the field is refused where it is written.
    let text = GOOD.replace(
        "at: (-14.0, Range(-2.0, 2.0))",
        "at: AroundBall(distance_m: 8.0, bearing_deg: 180.0)",
    );
    assert_eq!(one_error(&text), ("off-field".into(), "6:33".into()));
}
