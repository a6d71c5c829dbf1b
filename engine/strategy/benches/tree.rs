//! Tick cost of the shipped field-player tree (vs the same decisions hand-written in Rust),
//! validation time of all shipped files, and reload latency beyond the debounce window.

use criterion::{criterion_group, criterion_main, Criterion};
use libero_behavior::testing::ScriptedHost;
use libero_behavior::{
    Args, Host, LiveLibrary, ReloadOptions, Status, TreeRunner, Value, Vec2, Vocabulary,
};
use libero_strategy::{validate_paths, vocabulary, StrategyFiles};
use std::hint::black_box;
use std::path::PathBuf;
use std::sync::Arc;
use std::time::{Duration, Instant};

fn shipped() -> Vec<PathBuf> {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..");
    vec![root.join("behaviors"), root.join("formations")]
}

/// A host that answers from constants and does no bookkeeping, so the bench measures the engine.
struct BenchHost {
    ids: Vocabulary,
}

impl Host for BenchHost {
    fn now(&self) -> f64 {
        1.0
    }
    fn query(&self, id: libero_behavior::NativeId, _args: Args) -> Value {
        match self.ids.spec(id).name.as_str() {
            "am_ball_winner" => Value::Bool(true),
            "ball_distance" => Value::Float(3.0),
            // Within 4 m of their goal (no shot): the dribble branch.
            "distance" => Value::Float(3.0),
            "ball_position" => Value::Vec2(Vec2::new(1.0, 2.0)),
            _ => Value::Vec2(Vec2::new(-5.0, 0.0)),
        }
    }
    fn condition(&self, id: libero_behavior::NativeId, args: Args) -> bool {
        match self.ids.spec(id).name.as_str() {
            "PlayModeIs" => args.str(0) == "PlayOn",
            "MayPlayBall" => true,
            _ => false,
        }
    }
    fn action(&mut self, _id: libero_behavior::NativeId, args: Args) -> Status {
        black_box(args.vec2(0));
        Status::Running
    }
}

/// The field player's play-on decisions written directly in Rust: the baseline.
fn hand_written(
    host: &mut BenchHost,
    ids: &[libero_behavior::NativeId; 11],
    modes: &[Value; 1],
) -> Status {
    let [can_beam, fallen, mode, may_play, winner, distance, ball, shot_is_good, far, goal, dribble] =
        *ids;
    if host.condition(can_beam, Args(&[])) {
        return Status::Running;
    }
    if host.condition(fallen, Args(&[])) {
        return Status::Running;
    }
    if !host.condition(mode, Args(&modes[..1])) {
        return Status::Running;
    }
    if !host.condition(may_play, Args(&[])) {
        return Status::Running;
    }
    let chase = 0.5 * f64::from(u8::from(host.query(winner, Args(&[])).as_bool()))
        + 0.5 * (1.0 - host.query(distance, Args(&[])).as_f64() / 20.0);
    if chase + 0.1 <= 0.6 {
        return host.action(dribble, Args(&[Value::Vec2(Vec2::new(-5.0, 0.0))]));
    }
    if host.condition(shot_is_good, Args(&[])) {
        return Status::Running;
    }
    let target = host.query(ball, Args(&[]));
    let to_goal = host.query(goal, Args(&[]));
    // Beyond 4 m of their goal the tree kicks long at its front.
    if host.query(far, Args(&[target.clone(), to_goal])).as_f64() >= 4.0 {
        return Status::Running;
    }
    host.action(
        dribble,
        Args(&[target, Value::Float(0.5), Value::Float(4.0)]),
    )
}

fn tick(c: &mut Criterion) {
    let vocabulary = vocabulary();
    let library = Arc::new(libero_strategy::load(&shipped()).expect("shipped files are valid"));
    let mut host = BenchHost {
        ids: vocabulary.clone(),
    };
    let mut runner = TreeRunner::new(&library, "FieldPlayer").unwrap();
    runner.tick(&mut host, &library);
    assert!(runner
        .trace()
        .last()
        .unwrap()
        .leaves()
        .contains(&("Action DribbleTo", Status::Running)));
    c.bench_function("tick field player (engine)", |b| {
        b.iter(|| runner.tick(&mut host, &library))
    });
    let mut untraced = TreeRunner::new(&library, "FieldPlayer")
        .unwrap()
        .with_trace_capacity(0);
    c.bench_function("tick field player (engine, no trace)", |b| {
        b.iter(|| untraced.tick(&mut host, &library))
    });
    use libero_behavior::NativeKind::*;
    let ids = [
        vocabulary.find(Condition, "CanBeam").unwrap(),
        vocabulary.find(Condition, "IsFallen").unwrap(),
        vocabulary.find(Condition, "PlayModeIs").unwrap(),
        vocabulary.find(Condition, "MayPlayBall").unwrap(),
        vocabulary.find(Query, "am_ball_winner").unwrap(),
        vocabulary.find(Query, "ball_distance").unwrap(),
        vocabulary.find(Query, "ball_position").unwrap(),
        vocabulary.find(Condition, "ShotIsGood").unwrap(),
        vocabulary.find(Query, "distance").unwrap(),
        vocabulary.find(Query, "opponent_goal").unwrap(),
        vocabulary.find(Action, "DribbleTo").unwrap(),
    ];
    let modes = [Value::String("PlayOn".into())];
    c.bench_function("tick field player (hand-written baseline)", |b| {
        b.iter(|| hand_written(&mut host, black_box(&ids), &modes))
    });
    let mut scripted = ScriptedHost::new(&vocabulary);
    scripted
        .queries
        .insert("play_mode".into(), Value::String("PlayOn".into()));
    black_box(runner.tick(&mut scripted, &library));
}

fn validate(c: &mut Criterion) {
    let paths = shipped();
    assert_eq!(validate_paths(&paths).error_count(), 0);
    c.bench_function("validate all shipped files", |b| {
        b.iter(|| validate_paths(black_box(&paths)))
    });
}

fn reload(c: &mut Criterion) {
    let dir = tempfile::tempdir().unwrap();
    for sub in ["behaviors", "formations"] {
        std::fs::create_dir_all(dir.path().join(sub)).unwrap();
        for entry in std::fs::read_dir(
            PathBuf::from(env!("CARGO_MANIFEST_DIR"))
                .join("../..")
                .join(sub),
        )
        .unwrap()
        {
            let entry = entry.unwrap();
            // Files only: formations/simspark/ is another team's set.
            if entry.path().is_file() {
                std::fs::copy(entry.path(), dir.path().join(sub).join(entry.file_name())).unwrap();
            }
        }
    }
    let debounce = Duration::from_millis(50);
    let paths = vec![dir.path().join("behaviors"), dir.path().join("formations")];
    let live = LiveLibrary::start(
        paths,
        Arc::new(vocabulary()),
        Arc::new(StrategyFiles),
        ReloadOptions { debounce },
    )
    .unwrap();
    let file = dir.path().join("behaviors/goalkeeper.ron");
    let original = std::fs::read_to_string(&file).unwrap();
    let mut counter = 0u64;
    let mut group = c.benchmark_group("reload");
    group.sample_size(10);
    group.bench_function("file write to swap, beyond the debounce window", |b| {
        b.iter_custom(|iterations| {
            let mut beyond = Duration::ZERO;
            for _ in 0..iterations {
                counter += 1;
                let before = live.generation();
                let start = Instant::now();
                std::fs::write(&file, format!("{original}\n// edit {counter}\n")).unwrap();
                while live.generation() == before {
                    std::thread::sleep(Duration::from_micros(200));
                    assert!(
                        start.elapsed() < Duration::from_secs(5),
                        "reload never happened"
                    );
                }
                beyond += start.elapsed().saturating_sub(debounce);
                live.drain_events();
            }
            beyond
        })
    });
    group.finish();
}

criterion_group!(benches, tick, validate, reload);
criterion_main!(benches);
