use super::*;
use std::collections::HashSet;

/// The repository's behavior and formation files, loaded as a team would load them.
fn shipped_library() -> libero_behavior::Library {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    crate::load(&[root.join("behaviors"), root.join("formations")]).unwrap()
}

/// The skills' status with the T1's measured long kick spread (`t1.ron` `kick.measured`).
fn t1_kick_skills() -> libero_skills::SkillStatus {
    libero_skills::SkillStatus {
        kick_spread: libero_skills::kick::KickSpread {
            direction_sd_deg: 2.6,
            distance_m: 11.1,
            distance_sd_m: 1.3,
            diagonal_extra_m: 0.0,
        },
        ..libero_skills::SkillStatus::default()
    }
}

/// One call of the action `name` with `args` on the shipped files, with the skills reporting
/// `skills`: its status and the intent it wrote.
fn run_action(
    world: &libero_world::World,
    name: &str,
    args: &[Value],
    skills: libero_skills::SkillStatus,
) -> (Status, libero_skills::Intent) {
    let library = shipped_library();
    let natives = Natives::new();
    let mut memory = PlayerMemory::default();
    let mut intent = libero_skills::Intent::default();
    let mut host = AgentHost::new(
        world,
        crate::strategy_of(&library),
        &natives,
        &skills,
        &mut memory,
        &mut intent,
    );
    let id = vocabulary()
        .find(libero_behavior::NativeKind::Action, name)
        .unwrap();
    let status = host.action(id, Args(args));
    (status, intent)
}

#[test]
fn every_node_declares_a_unique_name_its_kind_and_documents_its_ports() {
    let mut names = HashSet::new();
    for native in catalogue() {
        let spec = (native.declare)();
        assert_eq!(spec.kind, native.run.kind(), "{}", spec.name);
        assert!(
            names.insert((spec.kind, spec.name.clone())),
            "{} twice",
            spec.name
        );
        assert!(!spec.doc.is_empty(), "{} has no doc", spec.name);
        for port in &spec.params {
            assert!(
                !port.doc.is_empty(),
                "{}.{} has no doc",
                spec.name,
                port.name
            );
        }
    }
    // The vocabulary and the dispatch table come from the same list, in the same order.
    let vocabulary = vocabulary();
    let natives = Natives::new();
    assert_eq!(vocabulary.nodes().len(), natives.by_id.len());
    for (i, spec) in vocabulary.nodes().iter().enumerate() {
        assert_eq!(natives.by_id[i].1.name, spec.name);
    }
}

#[test]
fn ports_are_read_by_name_whatever_their_order() {
    let spec = NodeSpec::action("A", "a")
        .param(libero_behavior::ParamSpec::new("first", libero_behavior::ValueType::Float).doc("1"))
        .param(
            libero_behavior::ParamSpec::new("second", libero_behavior::ValueType::Vec2).doc("2"),
        );
    let values = [Value::Float(2.5), Value::Vec2(Vec2::new(1.0, -1.0))];
    let ports = Ports::new(Args(&values), &spec);
    assert_eq!(ports.float("first"), 2.5);
    assert_eq!(ports.vec2("second"), Vec2::new(1.0, -1.0));
}

mod kick_to;

mod dribble_to;

mod shot_is_good;

mod search_ball;

/// One evaluation of the query `name` with `args` on the shipped files, with `memory` kept
/// between calls.
fn run_query(
    world: &libero_world::World,
    name: &str,
    args: &[Value],
    memory: &mut PlayerMemory,
) -> Value {
    let library = shipped_library();
    let natives = Natives::new();
    let skills = libero_skills::SkillStatus::default();
    let mut intent = libero_skills::Intent::default();
    let host = AgentHost::new(
        world,
        crate::strategy_of(&library),
        &natives,
        &skills,
        memory,
        &mut intent,
    );
    let id = vocabulary()
        .find(libero_behavior::NativeKind::Query, name)
        .unwrap();
    host.query(id, Args(args))
}

mod team_play;

mod anticipation;

mod beam;
