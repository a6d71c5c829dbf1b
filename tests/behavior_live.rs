//! Hot reload during a match, live: a real server, a player running its tree from files on
//! disk, and edits to those files while it plays.

use libero_agent::{build, AgentConfig, AgentStats, LibrarySource, ParamsEvent, SkillSource, Team};
use libero_behavior::ReloadEvent;
use libero_server::{ServerOptions, ServerProcess};
use libero_tests::{
    copy_of_shipped_data, fast_server, init_logging, t1, wait_sim_seconds, wait_until,
};
use std::path::Path;
use std::sync::atomic::AtomicBool;
use std::sync::Arc;
use std::time::{Duration, Instant};

/// Write a file the way many editors do: a temporary file renamed over the old one.
fn save(path: &Path, text: &str) {
    let tmp = path.with_extension("ron.tmp~");
    std::fs::write(&tmp, text).unwrap();
    std::fs::rename(&tmp, path).unwrap();
}

fn events(source: &LibrarySource) -> Vec<ReloadEvent> {
    match source {
        LibrarySource::Live(live) => live.drain_events(),
        LibrarySource::Fixed(_) => Vec::new(),
    }
}

#[test]
fn tree_edits_take_effect_within_three_cycles_and_broken_edits_keep_the_old_tree() {
    init_logging();
    // Real-time mode: cycles are 20 ms of wall time, so "three cycles" means what it means in
    // a match.
    let server = ServerProcess::start(ServerOptions {
        sync: false,
        realtime: true,
        ..ServerOptions::default()
    })
    .expect("starting rcssservermj");
    let dirs = copy_of_shipped_data("trees");
    let common = dirs[0].join("common.ron");
    let original = std::fs::read_to_string(&common).unwrap();
    let source = build::load_library(&dirs, true).expect("shipped files load");
    let mut player = build::tree_player(&t1(), "Home", 2, &source, &SkillSource::Builtin).unwrap();
    player.share_trace = true;
    let stats = Arc::clone(player.stats());
    let stop = Arc::new(AtomicBool::new(false));
    let team = Team::start(
        &AgentConfig::new("127.0.0.1", server.agent_port),
        vec![player],
        Arc::clone(&stop),
    );
    let trace = || stats.trace().unwrap_or_default();
    wait_until(Duration::from_secs(20), || {
        trace().contains("Action LookAround=Running")
    })
    .unwrap_or_else(|| {
        panic!(
            "before kick-off the player stands and looks around; trace: {}",
            trace()
        )
    });
    assert!(trace().contains("Action Stand=Running"), "{}", trace());

    // 1. A good edit: hold position without scanning.
    let edited = original.replace(
        r#"Action(name: "LookAround", amplitude: 1.2, period: 4.0),"#,
        r#"Wait(seconds: 1000.0),"#,
    );
    assert_ne!(edited, original, "the edit must change the file");
    let written = Instant::now();
    save(&common, &edited);
    std::thread::sleep(Duration::from_millis(150)); // the debounce window
    let cycles_at_window_end = AgentStats::get(&stats.percepts);
    wait_until(Duration::from_secs(5), || !trace().contains("LookAround"))
        .unwrap_or_else(|| panic!("the edited tree never ran; trace: {}", trace()));
    let cycles_after_window = AgentStats::get(&stats.percepts) - cycles_at_window_end;
    eprintln!(
        "edit active {:?} after the write, {cycles_after_window} cycles after the debounce window",
        written.elapsed()
    );
    assert!(
        cycles_after_window <= 3,
        "new tree active only {cycles_after_window} cycles after the debounce window"
    );
    assert!(trace().contains("Action Stand=Running"), "{}", trace());
    assert!(events(&source).iter().any(|e| matches!(
        e,
        ReloadEvent::Reloaded {
            recovered: false,
            ..
        }
    )));

    // 2. A broken edit: the team keeps playing the last good tree and the error is reported.
    let percepts_before = AgentStats::get(&stats.percepts);
    save(
        &common,
        &edited.replace(r#"Action("Stand")"#, r#"Action("Stnd")"#),
    );
    let rejected = wait_until(Duration::from_secs(3), || {
        events(&source).iter().any(|e| matches!(e, ReloadEvent::Rejected { report } if report.render_text().contains("Stnd")))
    });
    assert!(rejected.is_some(), "the broken edit was not reported");
    std::thread::sleep(Duration::from_millis(300));
    assert!(
        trace().contains("Action Stand=Running") && !trace().contains("LookAround"),
        "old tree kept: {}",
        trace()
    );
    assert!(
        AgentStats::get(&stats.percepts) > percepts_before + 10,
        "the player kept playing"
    );

    // 3. The fix: the original tree runs again and the recovery is reported.
    save(&common, &original);
    wait_until(Duration::from_secs(3), || {
        trace().contains("Action LookAround=Running")
    })
    .unwrap_or_else(|| panic!("the fixed tree never ran; trace: {}", trace()));
    let recovered = wait_until(Duration::from_secs(1), || {
        events(&source).iter().any(|e| {
            matches!(
                e,
                ReloadEvent::Reloaded {
                    recovered: true,
                    ..
                }
            )
        })
    });
    assert!(recovered.is_some(), "the recovery was not reported");
    // 4. An edit visible in ground truth: hold position by walking 3 m up the field.
    let start = stats.truth_position().expect("ground truth");
    let target = format!(
        "Action(name: \"WalkTo\", target: ({:.1}, {:.1})),",
        start[0] + 3.0,
        start[1]
    );
    let hold = r#"children: [
            Action("Stand"),"#;
    assert!(
        original.contains(hold),
        "HoldPosition's layout changed; update this test"
    );
    save(
        &common,
        &original.replace(hold, &format!("children: [\n            {target}")),
    );
    wait_until(Duration::from_secs(3), || {
        trace().contains("Action WalkTo=Running")
    })
    .unwrap_or_else(|| panic!("the walking tree never ran; trace: {}", trace()));
    let walked = wait_until(Duration::from_secs(15), || {
        stats
            .truth_position()
            .is_some_and(|p| p[0] > start[0] + 0.5 && p[2] > 0.5)
    });
    let now = stats.truth_position().unwrap();
    assert!(
        walked.is_some(),
        "the player did not walk towards the new target: {start:?} → {now:?}"
    );
    assert_eq!(AgentStats::get(&stats.connections), 1);
    assert_eq!(AgentStats::get(&stats.unreadable), 0);
    stop.store(true, std::sync::atomic::Ordering::Relaxed);
    team.join();
}

/// The stand posture's torso height [m] in ground truth, averaged over half a second.
fn settled_torso_z(stats: &AgentStats) -> f64 {
    let mut sum = 0.0;
    for _ in 0..25 {
        wait_sim_seconds(stats, 0.02);
        sum += stats.truth_position().expect("ground truth")[2];
    }
    sum / 25.0
}

#[test]
fn skill_parameter_edits_change_the_running_robot_and_broken_ones_are_refused() {
    let server = fast_server();
    let model = t1();
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("t1.ron");
    let shipped = Path::new(env!("CARGO_MANIFEST_DIR")).join("../engine/skills/params/t1.ron");
    let original = std::fs::read_to_string(shipped).unwrap();
    std::fs::write(&file, &original).unwrap();
    let skills = SkillSource::from_file(&file, &model, true).expect("shipped parameters load");
    let SkillSource::Live(live) = &skills else {
        panic!("a watched file gives live parameters")
    };
    let source = build::load_library(&build::default_data_dirs(), false).unwrap();
    let player = build::tree_player(&model, "Home", 2, &source, &skills).unwrap();
    let stats = Arc::clone(player.stats());
    let stop = Arc::new(AtomicBool::new(false));
    let team = Team::start(
        &AgentConfig::new("127.0.0.1", server.agent_port),
        vec![player],
        Arc::clone(&stop),
    );
    wait_until(Duration::from_secs(30), || stats.truth_position().is_some())
        .expect("the player joined");
    wait_sim_seconds(&stats, 2.0);
    let upright_z = settled_torso_z(&stats);

    // 1. A deeper crouch in the stand pose: the torso sinks.
    let stand = r#""left_hip_pitch": -12.0, "left_knee": 24.0, "left_ankle_pitch": -12.0,
        "right_hip_pitch": -12.0, "right_knee": 24.0, "right_ankle_pitch": -12.0,"#;
    assert!(
        original.contains(stand),
        "t1.ron's stand layout changed; update this test"
    );
    let crouch = original.replace(
        stand,
        r#""left_hip_pitch": -30.0, "left_knee": 60.0, "left_ankle_pitch": -30.0,
        "right_hip_pitch": -30.0, "right_knee": 60.0, "right_ankle_pitch": -30.0,"#,
    );
    save(&file, &crouch);
    assert_eq!(
        live.next_event(Duration::from_secs(5)),
        Some(ParamsEvent::Reloaded {
            generation: 2,
            recovered: false
        })
    );
    wait_sim_seconds(&stats, 1.5);
    let crouched_z = settled_torso_z(&stats);
    eprintln!("torso z: stand {upright_z:.3} m, edited crouch {crouched_z:.3} m");
    assert!(
        crouched_z < upright_z - 0.04,
        "the edited stand pose did not reach the robot: {upright_z:.3} → {crouched_z:.3} m"
    );

    // 2. A broken edit (a knee beyond its limit): refused with the field named, the robot keeps
    //    the crouch and keeps playing.
    let percepts = AgentStats::get(&stats.percepts);
    save(
        &file,
        &crouch.replace(r#""left_knee": 60.0"#, r#""left_knee": 600.0"#),
    );
    match live.next_event(Duration::from_secs(5)) {
        Some(ParamsEvent::Rejected { message }) => {
            assert!(message.contains("left_knee"), "{message}")
        }
        other => panic!("the broken edit was not refused: {other:?}"),
    }
    wait_sim_seconds(&stats, 1.0);
    let kept_z = settled_torso_z(&stats);
    assert!(
        (kept_z - crouched_z).abs() < 0.01,
        "a refused edit changed the robot: {crouched_z:.3} → {kept_z:.3} m"
    );
    assert!(AgentStats::get(&stats.percepts) > percepts + 50);

    // 3. The fix: back to the original stand, reported as a recovery.
    save(&file, &original);
    assert_eq!(
        live.next_event(Duration::from_secs(5)),
        Some(ParamsEvent::Reloaded {
            generation: 3,
            recovered: true
        })
    );
    wait_sim_seconds(&stats, 1.5);
    let back_z = settled_torso_z(&stats);
    assert!(
        (back_z - upright_z).abs() < 0.01,
        "the fixed file did not restore the stand: {upright_z:.3} vs {back_z:.3} m"
    );
    assert_eq!(AgentStats::get(&stats.connections), 1);
    stop.store(true, std::sync::atomic::Ordering::Relaxed);
    team.join();
}

/// Put the ball where the keeper must cover it and start play (`dropBall` is rcsssmj's PlayOn),
/// resending until the ground truth shows it.
fn drop_ball_at(server: &mut ServerProcess, x: f64, y: f64) {
    for _ in 0..20 {
        let monitor = server.monitor();
        monitor.send("(dropBall)").unwrap();
        monitor.place_ball([x, y, 0.11], [0.0; 3]).unwrap();
        std::thread::sleep(Duration::from_millis(300));
        let snapshot = server.monitor().snapshot();
        let placed = snapshot
            .ball
            .is_some_and(|b| (b[0] - x).hypot(b[1] - y) < 0.2);
        if placed && snapshot.play_mode == "PlayOn" {
            return;
        }
    }
    panic!("the ball could not be placed at ({x}, {y})");
}

#[test]
fn goalkeeper_file_edits_move_where_the_keeper_stands() {
    init_logging();
    // Real time: "within a second of the write" means a second of play.
    let mut server = ServerProcess::start(ServerOptions {
        sync: false,
        realtime: true,
        ..ServerOptions::default()
    })
    .expect("starting rcssservermj");
    let dirs = copy_of_shipped_data("keeper");
    let keeper_file = dirs[1].join("goalkeeper.ron");
    let original = std::fs::read_to_string(&keeper_file).unwrap();
    let source = build::load_library(&dirs, true).expect("shipped files load");
    let player = build::tree_player(&t1(), "Home", 1, &source, &SkillSource::Builtin).unwrap();
    let stats = Arc::clone(player.stats());
    let stop = Arc::new(AtomicBool::new(false));
    let team = Team::start(
        &AgentConfig::new("127.0.0.1", server.agent_port),
        vec![player],
        Arc::clone(&stop),
    );
    wait_until(Duration::from_secs(20), || stats.truth_position().is_some())
        .expect("the keeper joined");
    std::thread::sleep(Duration::from_secs(3));
    // The ball 12 m out on the left of our goal (we play left: own frame = global frame).
    drop_ball_at(&mut server, -16.0, 5.0);
    let strategy = |text: &str| {
        let files = [("goalkeeper.ron", text)];
        let library = libero_behavior::Library::from_texts(
            &files,
            &libero_strategy::vocabulary(),
            &libero_strategy::StrategyFiles,
        )
        .unwrap();
        libero_strategy::strategy_of(&library).goalkeeper.unwrap()
    };
    let field = libero_strategy::Field::by_name("fifa7vs7").unwrap();
    let ball = libero_world::Own::new(-16.0, 5.0);
    let near = strategy(&original).defense_point(ball, &field);
    let distance_to = |p: libero_world::Own| {
        stats
            .truth_position()
            .map_or(f64::INFINITY, |t| (t[0] - p.x).hypot(t[1] - p.y))
    };
    let reached = wait_until(Duration::from_secs(25), || distance_to(near) < 0.3);
    assert!(
        reached.is_some(),
        "the keeper never reached the defense point {near:?}: {:?}",
        stats.truth_position()
    );
    std::thread::sleep(Duration::from_secs(1));

    // Farther out: the point moves about 1.2 m towards the ball.
    let edited = original
        .replace("min_distance_m: 0.5,", "min_distance_m: 2.5,")
        .replace("max_distance_m: 1.6,", "max_distance_m: 3.0,");
    assert_ne!(edited, original, "the edit must change the file");
    let far = strategy(&edited).defense_point(ball, &field);
    assert!(far.distance(near) > 1.0, "{near:?} -> {far:?}");
    let before = distance_to(far);
    let generation = || match &source {
        LibrarySource::Live(live) => live.generation(),
        LibrarySource::Fixed(_) => 0,
    };
    let old_generation = generation();
    save(&keeper_file, &edited);
    let written = Instant::now();
    // The decision changes at the first cycle after the reload ...
    let reloaded = wait_until(Duration::from_secs(1), || generation() > old_generation);
    assert!(reloaded.is_some(), "the edit was not live within a second");
    // ... and the torso follows once the walk has started from standing (1.2-1.5 s measured:
    // the gait's first steps, see NOTES.md).
    let moving = wait_until(Duration::from_secs(2), || distance_to(far) < before - 0.03);
    assert!(
        moving.is_some(),
        "within 2 s of the write the keeper did not move towards the new point {far:?}: {:?}",
        stats.truth_position()
    );
    eprintln!(
        "edit live {reloaded:?}, keeper moving towards the new point {:?} after the write",
        written.elapsed()
    );
    let arrived = wait_until(Duration::from_secs(20), || distance_to(far) < 0.3);
    assert!(
        arrived.is_some(),
        "the keeper never reached the edited point {far:?}: {:?}",
        stats.truth_position()
    );

    // A broken edit keeps the running point.
    save(
        &keeper_file,
        &edited.replace("line: \"post_bisector\"", "line: \"nowhere\""),
    );
    let rejected = wait_until(Duration::from_secs(3), || {
        events(&source)
            .iter()
            .any(|e| matches!(e, ReloadEvent::Rejected { .. }))
    });
    assert!(rejected.is_some(), "the broken edit was not reported");
    std::thread::sleep(Duration::from_secs(2));
    assert!(
        distance_to(far) < 0.4,
        "the keeper left its point after a broken edit"
    );
    stop.store(true, std::sync::atomic::Ordering::Relaxed);
    team.join();
}
