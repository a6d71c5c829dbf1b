//! The shipped `behaviors/` and `formations/` validate cleanly and drive the reference host.

use libero_behavior::testing::ScriptedHost;
use libero_behavior::{
    validate_paths, Library, Situation, Status, TreeRunner, Value, Vec2, Vocabulary,
};
use std::path::PathBuf;
use std::sync::Arc;

fn shipped() -> Vec<PathBuf> {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..");
    vec![root.join("behaviors"), root.join("formations")]
}

fn library() -> Arc<Library> {
    Arc::new(
        Library::load(&shipped(), &Vocabulary::reference())
            .unwrap_or_else(|report| panic!("{}", report.render_text())),
    )
}

#[test]
fn shipped_files_have_no_errors_or_warnings() {
    let report = validate_paths(&shipped(), &Vocabulary::reference());
    assert_eq!(report.diagnostics.len(), 0, "{}", report.render_text());
}

#[test]
fn team_file_assigns_roots_and_formations() {
    let library = library();
    let strategy = library.strategy();
    assert_eq!(strategy.tree_for(1), Some("Goalkeeper"));
    assert_eq!(strategy.tree_for(5), Some("FieldPlayer"));
    for situation in Situation::ALL {
        let formation = strategy
            .formation_for(situation)
            .expect("every situation has a formation");
        for unum in 1..=7 {
            for ball in [
                Vec2::new(0.0, 0.0),
                Vec2::new(20.0, -15.0),
                Vec2::new(-27.5, 18.0),
                Vec2::new(60.0, 0.0),
            ] {
                let p = formation
                    .position(unum, ball)
                    .expect("every player has a position");
                assert!(
                    p.x.abs() <= 27.5 && p.y.abs() <= 18.0,
                    "{situation:?} {unum} {ball:?} -> {p:?}"
                );
            }
        }
    }
    assert!(
        strategy.goalkeeper.is_some() && strategy.shot.is_some() && strategy.avoidance.is_some()
    );
}

#[test]
fn formation_reproduces_its_samples_and_interpolates_between_them() {
    let library = library();
    let defence = library.strategy().formation("defence").unwrap();
    for sample in &defence.samples {
        for unum in 2..=6u8 {
            let p = defence.position(unum, sample.ball).unwrap();
            let expected = sample.positions[unum as usize - 1];
            assert!(
                p.distance(expected) < 1e-9,
                "unum {unum} at {:?}: {p:?} != {expected:?}",
                sample.ball
            );
        }
    }
    // Halfway between two neighbouring samples on an edge lies halfway between their positions.
    let (a, b) = (&defence.samples[0], &defence.samples[1]);
    let mid = a.ball.lerp(b.ball, 0.5);
    let p = defence.position(3, mid).unwrap();
    assert!(p.distance(a.positions[2].lerp(b.positions[2], 0.5)) < 1e-9);
}

#[test]
fn field_player_beams_before_kick_off_and_kicks_towards_the_goal_when_closest() {
    let library = library();
    let vocabulary = Vocabulary::reference();
    let mut host = ScriptedHost::new(&vocabulary);
    let mut runner = TreeRunner::new(&library, "FieldPlayer").unwrap();
    host.queries
        .insert("play_mode".into(), Value::String("BeforeKickOff".into()));
    host.conditions.insert("CanBeam".into(), true);
    assert_eq!(runner.tick(&mut host, &library), Status::Running);
    assert_eq!(host.action_names(), ["BeamToFormation"]);

    host.calls.clear();
    host.queries
        .insert("play_mode".into(), Value::String("PlayOn".into()));
    host.queries
        .insert("am_closest_to_ball".into(), Value::Bool(true));
    host.queries
        .insert("ball_position".into(), Value::Vec2(Vec2::new(3.0, 4.0)));
    runner.tick(&mut host, &library);
    assert_eq!(
        host.calls.last().unwrap(),
        &(
            "KickTo".to_string(),
            vec![
                Value::Vec2(Vec2::new(14.0, 0.0)),
                Value::Float(0.0),
                Value::Float(4.0)
            ]
        )
    );
    assert_eq!(
        host.halts,
        ["BeamToFormation"],
        "the abandoned beam is halted"
    );
    let leaves = runner.trace().last().unwrap().leaves();
    assert!(
        leaves.contains(&("Action KickTo", Status::Running)),
        "{leaves:?}"
    );
}

#[test]
fn goalkeeper_walks_to_its_formation_position() {
    let library = library();
    let vocabulary = Vocabulary::reference();
    let mut host = ScriptedHost::new(&vocabulary);
    host.queries
        .insert("play_mode".into(), Value::String("PlayOn".into()));
    let mut runner = TreeRunner::new(&library, "Goalkeeper").unwrap();
    runner.tick(&mut host, &library);
    assert_eq!(host.calls[0].1[0], Value::Vec2(Vec2::new(-8.0, 2.0)));
}
