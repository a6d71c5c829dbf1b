//! Scenario files on the real server: shots are launched and measured, outcomes come from the
//! ground truth, and the JSON summary carries the figures.

use libero_agent::build::{default_data_dirs, load_library};
use libero_agent::SkillSource;
use libero_scenario::{load_text, run_series, Report, RunData, Scenario};
use libero_tests::{copy_of_shipped_data, live_turn};
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
        watcher: None,
        log: None,
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

/// `runs` runs of the shipped `scenarios/<name>.ron`, with one line per run for messages.
fn shipped_series(name: &str, runs: usize, seed: u64) -> (libero_scenario::Summary, Vec<String>) {
    let file = Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("../scenarios/{name}.ron"));
    let text = std::fs::read_to_string(&file).unwrap();
    let mut report = Report::default();
    let scenario = load_text(&file, text, &mut report).expect("the shipped file loads");
    let (summary, error) = run_series(&scenario, &file, &data(), runs, seed, |_| {});
    assert!(error.is_none(), "{error:?}");
    let lines = summary
        .runs
        .iter()
        .map(libero_scenario::Summary::run_line)
        .collect();
    (summary, lines)
}

/// How many of `runs` runs of the shipped `scenarios/<name>.ron` succeeded, and the run lines.
fn shipped_successes(name: &str, runs: usize, seed: u64) -> (usize, String) {
    let (summary, lines) = shipped_series(name, runs, seed);
    let n = summary.runs.iter().filter(|r| r.success).count();
    (n, lines.join("\n"))
}

/// The shipped keeper scenario, shortened for CI: our keeper keeps most shots out. With the
/// keeper of the previous wave (walking to its formation spot) about 1 in 20 was kept out;
/// this one keeps 80-85 % (NOTES.md), so 6 of 10 fails only when the keeper breaks.
#[test]
fn the_keeper_keeps_most_shots_out() {
    let _turn = live_turn();
    let (summary, lines) = shipped_series("keeper_shots", 10, 11);
    let kept = summary.runs.iter().filter(|r| r.success).count();
    assert!(kept >= 6, "kept out {kept} of 10:\n{}", lines.join("\n"));
    // Every shot was a real one: launched towards the goal.
    for r in &summary.runs {
        assert!(
            r.launch.is_some(),
            "{}",
            libero_scenario::Summary::run_line(r)
        );
    }
}

/// The global direction (deg) the striker aimed its shot at, from its evaluation log: the
/// median over the cycles whose decision was a kick at `best_shot` (the trace shows the
/// `ShotIsGood` condition holding). `None` when it never decided to shoot.
fn shot_aim_deg(log: &Path) -> Option<f64> {
    let text = std::fs::read_to_string(log).ok()?;
    let mut aims: Vec<f64> = text
        .lines()
        .filter_map(|line| serde_json::from_str::<serde_json::Value>(line).ok())
        .filter(|record| {
            record["trace"]
                .as_str()
                .is_some_and(|t| t.contains("ShotIsGood=Success"))
        })
        .filter_map(|record| record["decision"]["intent_direction_deg"].as_f64())
        .collect();
    if aims.is_empty() {
        return None;
    }
    aims.sort_by(f64::total_cmp);
    Some(aims[aims.len() / 2])
}

/// Editing `shot.ron` while the scenario series runs changes where the striker shoots: 8 m
/// out in front of a keeper standing 0.7 m left of the goal's centre, the shipped file's best
/// point lies towards the far (right) post (an aim 6-9 deg right of straight on); with one
/// target only (the centre: `targets: 1`) and a threshold low enough to take that chance
/// beside the keeper, the striker shoots straight at the middle. The aim is the decision the
/// file drives (read from the evaluation log); the kick's own spread (3-5 deg, up to 0.7 m
/// at 8 m) makes where the ball crosses the line a noisy witness of it, so the ball is only
/// asked to have been kicked at the goal.
#[test]
fn shot_file_edits_change_where_the_striker_shoots() {
    let _turn = live_turn();
    let text = r#"Scenario(
    name: "shot_edit",
    field: "fifa7vs7",
    ours: [Robot(unum: 7, at: FromBall(dx: -0.7, dy: 0.0), heading_deg: 0.0)],
    theirs: [Robot(unum: 1, at: (x: 27.0, y: 0.7), heading_deg: 180.0, play: Stand)],
    ball: Ball(at: (x: 19.5, y: 0.0), launch: None),
    settle_s: 2.0,
    // Never met: the run goes on until the ball is in the goal (play stops) or time is up, so
    // the ball's whole travel is measured. Time for one kick (5-8 s from the start) and the
    // shot's roll, not for a second approach (pushes add up to a goal in 25 s).
    time_limit_s: 13.0,
    success: BallMoved(min_m: 40.0),
)"#;
    let mut report = Report::default();
    let scenario = load_text(Path::new("shot_edit.ron"), text.to_string(), &mut report).unwrap();
    let dirs = copy_of_shipped_data("shot");
    let shot_file = dirs[1].join("shot.ron");
    let original = std::fs::read_to_string(&shot_file).unwrap();
    let library = load_library(&dirs, true).unwrap();
    let logs = tempfile::tempdir().unwrap();
    let kick = |name: &str| {
        let log = logs.path().join(name);
        let data = RunData {
            library: library.clone(),
            skills: SkillSource::Builtin,
            watcher: None,
            log: Some(log.clone()),
            interrupt: Default::default(),
        };
        let (summary, error) =
            run_series(&scenario, Path::new("shot_edit.ron"), &data, 1, 1, |_| {});
        assert!(error.is_none(), "{error:?}");
        let striker_log = std::fs::read_dir(logs.path())
            .unwrap()
            .filter_map(|e| e.ok().map(|e| e.path()))
            .find(|p| {
                let file = p.file_name().unwrap().to_string_lossy().into_owned();
                file.starts_with(&format!("{name}.")) && file.ends_with(".7")
            })
            .expect("the striker's evaluation log");
        (summary.runs[0].clone(), shot_aim_deg(&striker_log))
    };
    let (shot, aim) = kick("shipped");
    let line = libero_scenario::Summary::run_line(&shot);
    assert!(
        aim.is_some_and(|a| a < -4.0) && shot.ball_travel_m > 6.0,
        "the striker did not shoot towards the far post (aim {aim:?} deg): {line}"
    );
    let edited = original
        .replace("targets: 9,", "targets: 1,")
        .replace("threshold: 0.3,", "threshold: 0.05,");
    assert_eq!(
        edited.matches("targets: 1,").count() + edited.matches("threshold: 0.05,").count(),
        2,
        "the edit must change the file's targets and threshold"
    );
    let generation = || match &library {
        libero_agent::LibrarySource::Live(live) => live.generation(),
        libero_agent::LibrarySource::Fixed(_) => 0,
    };
    let old = generation();
    std::fs::write(&shot_file, &edited).unwrap();
    let written = Instant::now();
    while generation() == old && written.elapsed().as_secs_f64() < 1.0 {
        std::thread::sleep(std::time::Duration::from_millis(10));
    }
    assert!(generation() > old, "the edit was not live within a second");
    let (centre, aim) = kick("edited");
    let line = libero_scenario::Summary::run_line(&centre);
    assert!(
        aim.is_some_and(|a| a.abs() < 2.0) && centre.ball_travel_m > 3.0,
        "with the centre as the only target the striker did not shoot at the middle (aim \
         {aim:?} deg): {line}"
    );
}

/// The shipped wall scenario, shortened for CI: the striker walks round three standing robots
/// to the ball and kicks it without coming within 0.45 m of any of them. Without avoidance it
/// walks into the wall in every run; with it (NOTES.md) 18-20 of 20 runs succeed, and about 1 run
/// in 15 ends in a brush with the wall's end robot, so this asks for half of 4.
#[test]
fn the_striker_walks_round_a_wall_to_the_ball() {
    let _turn = live_turn();
    let (clean, runs) = shipped_successes("striker_wall", 4, 7);
    assert!(
        clean >= 2,
        "reached and kicked without a collision in {clean} of 4:\n{runs}"
    );
}

/// The shipped striker scenario, shortened for CI: alone with the ball 8-14 m out, the striker
/// scores within 20 s, shooting from within the long kick's reach and walking the ball in from
/// beyond it. 19 of 40 runs (seeds 12 and 13, NOTES.md session 29), 4 of this seed's first 10.
/// Series of 10 scatter widely (2 to 4 of seed 13's first 10 in four series), so this only
/// asks for a goal: none in 10 when shooting breaks, one series in 400 by chance.
#[test]
fn the_striker_alone_scores() {
    let _turn = live_turn();
    let (goals, runs) = shipped_successes("striker_alone", 10, 12);
    assert!(goals >= 1, "scored in {goals} of 10 runs:\n{runs}");
}

/// The shipped dribble scenario, shortened for CI: from midfield, where no shot is on, the
/// field player plays the ball on towards their goal — since session 15 by a long kick at the
/// goal's front (8 of 10 got it 5 m in 20 s; the session-14 dribble 9 of 10). With the first
/// wave's 2 m short kicks none of 20 runs did, so 2 of 6 fails only when playing on breaks.
#[test]
fn the_field_player_plays_the_ball_on_from_midfield() {
    let _turn = live_turn();
    let (moved, runs) = shipped_successes("dribble", 6, 3);
    assert!(moved >= 2, "the ball got 5 m in {moved} of 6 runs:\n{runs}");
}

/// The shipped pass scenario, shortened for CI: player 7 passes long where the pass utility
/// sends it and player 4 gets the ball where it stops (first touch within 1 m of the stop point
/// the world model's tracker predicts). 16 and 15 of 20 runs (seeds 1, 2; NOTES.md session 16);
/// seed 2's first five all did. A receiver standing in the path, or none going, gets none, so
/// 2 of 5 fails only when passing breaks.
#[test]
fn a_pass_reaches_the_free_teammate_where_it_stops() {
    let _turn = live_turn();
    let (received, runs) = shipped_successes("pass", 5, 2);
    assert!(
        received >= 2,
        "received where it stopped in {received} of 5 runs:\n{runs}"
    );
}

/// The shipped ball-handling scenario, shortened for CI: from 2-6 m on any side of the ball,
/// facing anywhere, the player touches the ball and shoots 6 m or more on target (19 of 20 on
/// seed 1, median first touch 9.8 s, shot 14.5 s; NOTES.md session 34). A player that never
/// shoots, or a judge that takes a dribble for a shot, fails it.
#[test]
fn from_any_side_of_the_ball_the_player_touches_it_and_shoots_on_target() {
    let _turn = live_turn();
    let (summary, lines) = shipped_series("ball_handling", 4, 1);
    let lines = lines.join("\n");
    let shots = summary.runs.iter().filter(|r| r.success).count();
    assert!(shots >= 2, "shot on target in {shots} of 4 runs:\n{lines}");
    for r in summary.runs.iter().filter(|r| r.success) {
        let (touch, shot) = (r.first_touch_s, r.time_s.unwrap());
        assert!(
            touch.is_some_and(|t| t < shot),
            "a shot without an earlier touch:\n{lines}"
        );
        assert!(r.ball_travel_m >= 6.0, "{lines}");
    }
    assert!(summary.median_first_touch_s().is_some(), "{lines}");
}
