//! Hot reload with real files and the real watcher: an edit changes a running player's trace
//! within 3 cycles after the debounce window, a broken edit keeps the old tree and is reported
//! once, the fix runs; editors' save patterns all end in the right library.

use libero_behavior::testing::ScriptedHost;
use libero_behavior::{LiveLibrary, ReloadEvent, ReloadOptions, Status, TreeRunner, Value};
use libero_strategy::{vocabulary, StrategyFiles};
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::{Duration, Instant};

const DEBOUNCE: Duration = Duration::from_millis(100);
const CYCLE: Duration = Duration::from_millis(20);

fn copy_dir(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for entry in std::fs::read_dir(from).unwrap() {
        let entry = entry.unwrap();
        // Files only: formations/simspark/ is another team's set.
        if entry.path().is_file() {
            std::fs::copy(entry.path(), to.join(entry.file_name())).unwrap();
        }
    }
}

/// A copy of the shipped files in a temporary directory, watched live.
fn live_copy() -> (tempfile::TempDir, Vec<PathBuf>, LiveLibrary) {
    let repo = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..");
    let dir = tempfile::tempdir().unwrap();
    copy_dir(&repo.join("behaviors"), &dir.path().join("behaviors"));
    copy_dir(&repo.join("formations"), &dir.path().join("formations"));
    let paths = vec![dir.path().join("behaviors"), dir.path().join("formations")];
    let live = LiveLibrary::start(
        paths.clone(),
        Arc::new(vocabulary()),
        Arc::new(StrategyFiles),
        ReloadOptions { debounce: DEBOUNCE },
    )
    .unwrap_or_else(|report| panic!("{}", report.render_text()));
    (dir, paths, live)
}

struct Team {
    host: ScriptedHost,
    runner: TreeRunner,
    events: Vec<ReloadEvent>,
}

impl Team {
    fn new(live: &LiveLibrary) -> Self {
        let mut host = ScriptedHost::new(&vocabulary());
        host.queries
            .insert("play_mode".into(), Value::String("PlayOn".into()));
        let runner = TreeRunner::new(&live.current(), "FieldPlayer").unwrap();
        Self {
            host,
            runner,
            events: Vec::new(),
        }
    }

    /// One agent cycle: pick up the newest library, tick, sleep the rest of the cycle.
    fn cycle(&mut self, live: &LiveLibrary) -> Instant {
        let start = Instant::now();
        self.host.time += CYCLE.as_secs_f64();
        self.runner.tick(&mut self.host, &live.current());
        self.events.extend(live.drain_events());
        std::thread::sleep(CYCLE);
        start
    }

    fn runs(&self, action: &str) -> bool {
        let label = format!("Action {action}");
        self.runner
            .trace()
            .last()
            .unwrap()
            .leaves()
            .iter()
            .any(|(l, s)| *l == label && *s == Status::Running)
    }

    /// Cycles until `action` runs; returns how many cycles started after `window_end`.
    fn cycles_until(&mut self, live: &LiveLibrary, action: &str, window_end: Instant) -> usize {
        let mut late_cycles = 0;
        for _ in 0..200 {
            let start = self.cycle(live);
            if start >= window_end {
                late_cycles += 1;
            }
            if self.runs(action) {
                return late_cycles;
            }
        }
        panic!("`{action}` never ran; events: {:?}", self.events);
    }
}

fn replace_in(path: &Path, from: &str, to: &str) {
    let text = std::fs::read_to_string(path).unwrap();
    assert!(text.contains(from), "{from:?} not in {}", path.display());
    std::fs::write(path, text.replace(from, to)).unwrap();
}

const PLAY_ON: &str = r#"SubTree("PlayOn"),"#;

#[test]
fn edit_then_broken_edit_then_fix() {
    let (dir, _, live) = live_copy();
    let file = dir.path().join("behaviors/field_player.ron");
    let mut team = Team::new(&live);
    for _ in 0..3 {
        team.cycle(&live);
    }
    assert!(
        team.runs("WalkTo"),
        "play on walks to the formation position"
    );

    // 1. A behavior change shows in the trace within 3 cycles after the debounce window.
    let written = Instant::now();
    replace_in(
        &file,
        PLAY_ON,
        r#"Action(name: "LookAround", period: 2.0),"#,
    );
    let late = team.cycles_until(&live, "LookAround", written + DEBOUNCE);
    assert!(
        late <= 3,
        "new tree active {late} cycles after the debounce window"
    );
    assert_eq!(live.generation(), 2);
    assert!(
        matches!(
            team.events.as_slice(),
            [ReloadEvent::Reloaded {
                generation: 2,
                recovered: false,
                ..
            }]
        ),
        "{:?}",
        team.events
    );
    team.events.clear();

    // 2. A broken edit: the old tree keeps running and the error is reported once.
    let good = std::fs::read_to_string(&file).unwrap();
    let broken = good.replace(
        r#"Action(name: "LookAround", period: 2.0),"#,
        r#"Action(name: "LookAroundd", period: 2.0),"#,
    );
    std::fs::write(&file, &broken).unwrap();
    let deadline = Instant::now() + Duration::from_secs(5);
    while team.events.is_empty() && Instant::now() < deadline {
        team.cycle(&live);
        assert!(team.runs("LookAround"), "the last good tree keeps running");
    }
    let [ReloadEvent::Rejected { report }] = team.events.as_slice() else {
        panic!("expected one rejection: {:?}", team.events)
    };
    assert!(
        report.render_text().contains("did you mean `LookAround`?"),
        "{}",
        report.render_text()
    );
    // Saving the same broken content again is not reported again.
    std::fs::write(&file, &broken).unwrap();
    for _ in 0..((DEBOUNCE * 3).as_millis() / CYCLE.as_millis()) {
        team.cycle(&live);
        assert!(team.runs("LookAround"));
    }
    assert_eq!(team.events.len(), 1, "{:?}", team.events);
    assert_eq!(live.generation(), 2);
    team.events.clear();

    // 3. The fix runs, and the watcher says the error is fixed.
    let written = Instant::now();
    std::fs::write(
        &file,
        good.replace(
            r#"Action(name: "LookAround", period: 2.0),"#,
            r#"Action("BeamToFormation"),"#,
        ),
    )
    .unwrap();
    let late = team.cycles_until(&live, "BeamToFormation", written + DEBOUNCE);
    assert!(
        late <= 3,
        "fixed tree active {late} cycles after the debounce window"
    );
    assert!(
        matches!(
            team.events.as_slice(),
            [ReloadEvent::Reloaded {
                generation: 3,
                recovered: true,
                ..
            }]
        ),
        "{:?}",
        team.events
    );
}

/// Waits until the library reaches `generation` or a rejection arrives.
fn wait_generation(live: &LiveLibrary, generation: u64) -> Vec<ReloadEvent> {
    let mut events = Vec::new();
    let deadline = Instant::now() + Duration::from_secs(5);
    while live.generation() < generation && Instant::now() < deadline {
        if let Some(event) = live.next_event(Duration::from_millis(20)) {
            events.push(event);
        }
    }
    events.extend(live.drain_events());
    assert_eq!(live.generation(), generation, "events: {events:?}");
    events
}

#[test]
fn editor_save_patterns_files_added_removed_and_renamed() {
    let (dir, _, live) = live_copy();
    let behaviors = dir.path().join("behaviors");
    let field_player = behaviors.join("field_player.ron");
    let text = std::fs::read_to_string(&field_player).unwrap();

    // Write to a temporary file, then rename over the original (vim, many IDEs).
    let edited = text.replace(PLAY_ON, r#"Action("Stand"),"#);
    let temporary = behaviors.join(".field_player.ron.swp~");
    std::fs::write(&temporary, &edited).unwrap();
    std::fs::rename(&temporary, &field_player).unwrap();
    wait_generation(&live, 2);
    assert!(live
        .current()
        .tree("FieldPlayer")
        .unwrap()
        .nodes
        .iter()
        .any(|n| n.label == "Action Stand"));

    // Truncate, then write a moment later, within the debounce window: one reload, no error.
    std::fs::write(&field_player, "").unwrap();
    std::thread::sleep(DEBOUNCE / 4);
    std::fs::write(&field_player, &text).unwrap();
    let events = wait_generation(&live, 3);
    assert!(
        events
            .iter()
            .all(|e| matches!(e, ReloadEvent::Reloaded { .. })),
        "{events:?}"
    );

    // A new file with a new tree.
    std::fs::write(
        behaviors.join("extra.ron"),
        r#"Behaviors(trees: { "Extra": Action("Stand") })"#,
    )
    .unwrap();
    wait_generation(&live, 4);
    assert!(live.current().tree("Extra").is_some());

    // Renamed: the tree is still there, found at its new path.
    std::fs::rename(behaviors.join("extra.ron"), behaviors.join("renamed.ron")).unwrap();
    wait_generation(&live, 5);
    assert!(live
        .current()
        .files()
        .iter()
        .any(|f| f.ends_with("renamed.ron")));
    assert!(live.current().tree("Extra").is_some());

    // Removed: the tree is gone.
    std::fs::remove_file(behaviors.join("renamed.ron")).unwrap();
    wait_generation(&live, 6);
    assert!(live.current().tree("Extra").is_none());

    // Removing a file others depend on is a broken edit: rejected, previous version stays.
    std::fs::remove_file(behaviors.join("common.ron")).unwrap();
    let deadline = Instant::now() + Duration::from_secs(5);
    let event = loop {
        if let Some(event) = live.next_event(Duration::from_millis(20)) {
            break event;
        }
        assert!(Instant::now() < deadline, "no rejection reported");
    };
    let ReloadEvent::Rejected { report } = event else {
        panic!("expected a rejection, got {event:?}")
    };
    assert!(
        report.render_text().contains("missing-subtree"),
        "{}",
        report.render_text()
    );
    assert_eq!(live.generation(), 6);
    assert!(live.current().tree("GetUp").is_some());
}

#[test]
fn broken_files_at_start_fail_with_every_error() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("a.ron"),
        r#"Behaviors(trees: { "A": Action("Sit"), "B": SubTree("C") })"#,
    )
    .unwrap();
    let Err(report) = LiveLibrary::start(
        vec![dir.path().to_path_buf()],
        Arc::new(vocabulary()),
        Arc::new(StrategyFiles),
        ReloadOptions::default(),
    ) else {
        panic!("a broken library must not start");
    };
    assert_eq!(report.error_count(), 2, "{}", report.render_text());
}
