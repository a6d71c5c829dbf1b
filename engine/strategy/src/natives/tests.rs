use super::*;
use std::collections::HashSet;

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
