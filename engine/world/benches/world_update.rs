//! World-model update cost per cycle, on a real rcssservermj percept with vision (T1).
//! Baselines: the same percept without its `See` block, and parsing the message.

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use libero_model::{RobotModel, ServerKind};
use libero_protocol::parse_percept;
use libero_world::World;

fn sample(name: &str) -> Vec<u8> {
    let path = format!(
        "{}/../../../shared/samples/rcssservermj/{name}",
        env!("CARGO_MANIFEST_DIR")
    );
    std::fs::read(path).expect("sample percept")
}

fn bench(c: &mut Criterion) {
    let model = RobotModel::builtin("T1").unwrap();
    let payload = sample("T1_sync_msg0000.txt");
    let percept = parse_percept(&payload, ServerKind::RcssMj).unwrap();
    assert!(percept
        .vision
        .as_ref()
        .is_some_and(|v| !v.landmarks.is_empty()));
    let mut blind = percept.clone();
    blind.vision = None;
    let mut world = World::new(&model, "Probe", 1);
    // Localize first, so the benchmark measures the steady-state path.
    for _ in 0..10 {
        world.update(&model, &percept);
    }
    c.bench_function("world_update_with_vision", |b| {
        b.iter(|| world.update(&model, black_box(&percept)))
    });
    c.bench_function("world_update_without_vision", |b| {
        b.iter(|| world.update(&model, black_box(&blind)))
    });
    c.bench_function("parse_percept_with_vision", |b| {
        b.iter(|| parse_percept(black_box(&payload), ServerKind::RcssMj).unwrap())
    });
}

criterion_group!(benches, bench);
criterion_main!(benches);
