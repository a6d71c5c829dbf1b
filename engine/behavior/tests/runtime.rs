//! Semantics of every node kind, the blackboard, subtree parameters, traces, and state carried
//! across a library swap.

use libero_behavior::testing::{example_vocabulary, ScriptedHost};
use libero_behavior::{Library, NoDataFiles, Status, TreeRunner, Value, Vec2};
use std::sync::Arc;

fn library(trees: &str) -> Arc<Library> {
    library_with(trees, "")
}

fn library_with(trees: &str, blackboard: &str) -> Arc<Library> {
    let text = format!("Behaviors(blackboard: {{ {blackboard} }}, trees: {{ {trees} }})");
    match Library::from_texts(&[("t.ron", &text)], &example_vocabulary(), &NoDataFiles) {
        Ok(library) => Arc::new(library),
        Err(report) => panic!("{}", report.render_text()),
    }
}

struct Rig {
    host: ScriptedHost,
    runner: TreeRunner,
    library: Arc<Library>,
}

impl Rig {
    fn new(library: Arc<Library>) -> Self {
        let host = ScriptedHost::new(&example_vocabulary());
        let runner = TreeRunner::new(&library, "Main").unwrap();
        Self {
            host,
            runner,
            library,
        }
    }
    fn tick(&mut self) -> Status {
        self.runner.tick(&mut self.host, &self.library)
    }
    fn set_action(&mut self, name: &str, status: Status) {
        self.host.actions.insert(name.into(), status);
    }
    fn take_calls(&mut self) -> Vec<String> {
        std::mem::take(&mut self.host.calls)
            .into_iter()
            .map(|(n, _)| n)
            .collect()
    }
}

#[test]
fn sequence_remembers_the_running_child_and_reactive_sequence_does_not() {
    let mut rig = Rig::new(library(
        r#""Main": Sequence([Action("Stand"), Action("LookAround")])"#,
    ));
    rig.set_action("Stand", Status::Success);
    assert_eq!(rig.tick(), Status::Running);
    assert_eq!(rig.take_calls(), ["Stand", "LookAround"]);
    assert_eq!(rig.tick(), Status::Running);
    assert_eq!(
        rig.take_calls(),
        ["LookAround"],
        "memory: Stand is not re-run"
    );

    let mut rig = Rig::new(library(
        r#""Main": ReactiveSequence([Condition("IsFallen"), Action("LookAround")])"#,
    ));
    rig.host.conditions.insert("IsFallen".into(), true);
    assert_eq!(rig.tick(), Status::Running);
    rig.host.conditions.insert("IsFallen".into(), false);
    assert_eq!(rig.tick(), Status::Failure);
    assert_eq!(
        rig.host.halts,
        ["LookAround"],
        "the running action is halted when the condition turns false"
    );
}

#[test]
fn fallback_and_reactive_fallback_preempt_lower_priorities() {
    let mut rig = Rig::new(library(
        r#""Main": ReactiveFallback([Sequence([Condition("IsFallen"), Action("Stand")]), Action("LookAround")])"#,
    ));
    assert_eq!(rig.tick(), Status::Running);
    assert_eq!(rig.take_calls(), ["LookAround"]);
    rig.host.conditions.insert("IsFallen".into(), true);
    rig.tick();
    assert_eq!(rig.take_calls(), ["Stand"]);
    assert_eq!(rig.host.halts, ["LookAround"]);
    let mut rig = Rig::new(library(
        r#""Main": Fallback([Fail, Succeed, Action("Stand")])"#,
    ));
    assert_eq!(rig.tick(), Status::Success);
    assert!(rig.host.calls.is_empty());
}

#[test]
fn parallel_thresholds() {
    let text = r#""Main": Parallel(success: 2, failure: 1, children: [Action("Stand"), Action("LookAround"), Action("BeamToFormation")])"#;
    let mut rig = Rig::new(library(text));
    rig.set_action("Stand", Status::Success);
    assert_eq!(rig.tick(), Status::Running);
    assert_eq!(rig.take_calls(), ["Stand", "LookAround", "BeamToFormation"]);
    rig.set_action("LookAround", Status::Success);
    assert_eq!(rig.tick(), Status::Success);
    assert_eq!(
        rig.take_calls(),
        ["LookAround", "BeamToFormation"],
        "a finished child is not re-run"
    );
    assert_eq!(rig.host.halts, ["BeamToFormation"]);
    let mut rig = Rig::new(library(text));
    rig.set_action("BeamToFormation", Status::Failure);
    assert_eq!(rig.tick(), Status::Failure);
    assert_eq!(rig.host.halts, ["Stand", "LookAround"]);
}

#[test]
fn decorators() {
    for (tree, action, expected) in [
        (
            r#"Invert(Action("Stand"))"#,
            Status::Success,
            Status::Failure,
        ),
        (
            r#"Invert(Action("Stand"))"#,
            Status::Failure,
            Status::Success,
        ),
        (
            r#"ForceSuccess(Action("Stand"))"#,
            Status::Failure,
            Status::Success,
        ),
        (
            r#"ForceFailure(Action("Stand"))"#,
            Status::Success,
            Status::Failure,
        ),
        (
            r#"ForceFailure(Action("Stand"))"#,
            Status::Running,
            Status::Running,
        ),
    ] {
        let mut rig = Rig::new(library(&format!(r#""Main": {tree}"#)));
        rig.set_action("Stand", action);
        assert_eq!(rig.tick(), expected, "{tree} with child {action}");
    }
}

#[test]
fn repeat_and_retry_count_one_attempt_per_tick() {
    let mut rig = Rig::new(library(r#""Main": Repeat(n: 3, child: Action("Stand"))"#));
    rig.set_action("Stand", Status::Success);
    assert_eq!(
        [rig.tick(), rig.tick(), rig.tick()],
        [Status::Running, Status::Running, Status::Success]
    );
    assert_eq!(rig.take_calls().len(), 3);
    assert_eq!(
        rig.tick(),
        Status::Running,
        "a new round starts after success"
    );

    let mut rig = Rig::new(library(
        r#""Main": RetryUntilSuccess(n: 2, child: Action("Stand"))"#,
    ));
    rig.set_action("Stand", Status::Failure);
    assert_eq!([rig.tick(), rig.tick()], [Status::Running, Status::Failure]);
}

#[test]
fn timeout_halts_and_cooldown_blocks() {
    let mut rig = Rig::new(library(
        r#""Main": Timeout(seconds: 1.0, child: Action("LookAround"))"#,
    ));
    assert_eq!(rig.tick(), Status::Running);
    rig.host.time = 0.5;
    assert_eq!(rig.tick(), Status::Running);
    rig.host.time = 1.0;
    assert_eq!(rig.tick(), Status::Failure);
    assert_eq!(rig.host.halts, ["LookAround"]);

    let mut rig = Rig::new(library(
        r#""Main": Cooldown(seconds: 2.0, child: Action("Stand"))"#,
    ));
    rig.set_action("Stand", Status::Success);
    assert_eq!(rig.tick(), Status::Success);
    rig.host.time = 1.9;
    assert_eq!(rig.tick(), Status::Failure);
    assert_eq!(
        rig.take_calls().len(),
        1,
        "the child is not ticked during the cooldown"
    );
    rig.host.time = 2.0;
    assert_eq!(rig.tick(), Status::Success);
}

#[test]
fn wait_compare_and_set() {
    let trees = r#""Main": Sequence([
        Set(key: "target", value: Query("ball_position")),
        Set(key: "count", value: 3),
        Compare(left: Query("ball_distance"), op: "<", right: 2),
        Action(name: "WalkTo", target: Bb("target")),
    ])"#;
    let mut rig = Rig::new(library_with(
        trees,
        r#""target": Vec2((0.0, 0.0)), "count": Float(0.0)"#,
    ));
    rig.host
        .queries
        .insert("ball_position".into(), Value::Vec2(Vec2::new(1.0, 2.0)));
    assert_eq!(rig.tick(), Status::Failure, "ball_distance 5 is not < 2");
    assert_eq!(
        rig.runner.blackboard().get("target"),
        Some(&Value::Vec2(Vec2::new(1.0, 2.0)))
    );
    assert_eq!(
        rig.runner.blackboard().get("count"),
        Some(&Value::Float(3.0)),
        "Int widened to the declared Float"
    );
    rig.host
        .queries
        .insert("ball_distance".into(), Value::Float(1.0));
    assert_eq!(rig.tick(), Status::Running);
    assert_eq!(rig.host.calls[0].1[0], Value::Vec2(Vec2::new(1.0, 2.0)));

    let mut rig = Rig::new(library(r#""Main": Wait(seconds: 0.5)"#));
    assert_eq!(rig.tick(), Status::Running);
    rig.host.time = 0.5;
    assert_eq!(rig.tick(), Status::Success);
}

#[test]
fn subtree_parameters_are_bound_per_call() {
    let trees = r#"
        "Main": Sequence([SubTree(name: "Go", target: (1.0, 1.0)), SubTree(name: "Go", target: Query("ball_position"), speed: 1)]),
        "Go": Tree(params: { "target": Vec2, "speed": Float(0.4) }, root: Action(name: "WalkTo", target: Param("target"), speed: Param("speed"))),
    "#;
    let mut rig = Rig::new(library(trees));
    rig.set_action("WalkTo", Status::Success);
    assert_eq!(rig.tick(), Status::Success);
    let args: Vec<Vec<Value>> = rig.host.calls.iter().map(|(_, a)| a.clone()).collect();
    assert_eq!(
        args[0][..2],
        [Value::Vec2(Vec2::new(1.0, 1.0)), Value::Float(0.4)]
    );
    assert_eq!(
        args[1][..2],
        [Value::Vec2(Vec2::new(0.0, 0.0)), Value::Float(1.0)]
    );
}

#[test]
fn utility_picks_the_best_choice_with_hysteresis() {
    let trees = r#""Main": Utility(hysteresis: 0.2, choices: [
        Choice(considerations: [Consider(input: Query("ball_distance"), curve: Linear(from: 10.0, to: 0.0))], child: Action("WalkTo", )),
        Choice(weight: 0.5, child: Action("LookAround")),
    ])"#;
    let trees = trees.replace(
        r#"Action("WalkTo", )"#,
        r#"Action(name: "WalkTo", target: (0.0, 0.0))"#,
    );
    let mut rig = Rig::new(library(&trees));
    rig.host
        .queries
        .insert("ball_distance".into(), Value::Float(8.0)); // score 0.2 < 0.5
    rig.tick();
    assert_eq!(rig.take_calls(), ["LookAround"]);
    rig.host
        .queries
        .insert("ball_distance".into(), Value::Float(4.0)); // 0.6 < 0.5 + 0.2: stay
    rig.tick();
    assert_eq!(
        rig.take_calls(),
        ["LookAround"],
        "hysteresis keeps the running choice"
    );
    rig.host
        .queries
        .insert("ball_distance".into(), Value::Float(2.0)); // 0.8 > 0.7: switch
    rig.tick();
    assert_eq!(rig.take_calls(), ["WalkTo"]);
    assert_eq!(rig.host.halts, ["LookAround"]);
}

#[test]
fn trace_records_the_active_path_in_a_ring() {
    let mut rig = Rig::new(library(
        r#""Main": ReactiveSequence([Condition("CanBeam"), Action("Stand")])"#,
    ));
    rig.runner = TreeRunner::new(&rig.library, "Main")
        .unwrap()
        .with_trace_capacity(4);
    rig.host.conditions.insert("CanBeam".into(), true);
    for _ in 0..6 {
        rig.tick();
    }
    let trace = rig.runner.trace();
    assert_eq!(trace.len(), 4);
    let ticks: Vec<u64> = trace.iter().map(|r| r.tick).collect();
    assert_eq!(ticks, [3, 4, 5, 6]);
    let last = trace.last().unwrap();
    let visited: Vec<(&str, Status)> = last.visited().collect();
    assert_eq!(
        visited,
        [
            ("ReactiveSequence", Status::Running),
            ("Condition CanBeam", Status::Success),
            ("Action Stand", Status::Running)
        ]
    );
    assert!(
        last.render().contains("    Action Stand → Running"),
        "{}",
        last.render()
    );
}

#[test]
fn swap_keeps_state_of_unchanged_subtrees_and_the_blackboard() {
    let shared = r#""Count": Repeat(n: 5, child: Action("Stand")),"#;
    let v1 = library_with(
        &format!(r#"{shared} "Main": Sequence([Condition("CanBeam"), SubTree("Count")])"#),
        r#""n": Int(0)"#,
    );
    let v2 = library_with(
        &format!(
            r#"{shared} "Main": Sequence([Condition("CanBeam"), Set(key: "n", value: 1), SubTree("Count")])"#
        ),
        r#""n": Int(0), "extra": Bool(false)"#,
    );
    let mut host = ScriptedHost::new(&example_vocabulary());
    host.conditions.insert("CanBeam".into(), true);
    host.actions.insert("Stand".into(), Status::Success);
    let mut runner = TreeRunner::new(&v1, "Main").unwrap();
    runner.blackboard_mut().set("n", Value::Int(7)).unwrap();
    for _ in 0..3 {
        assert_eq!(runner.tick(&mut host, &v1), Status::Running);
    }
    // Two more repetitions finish the count only if the Repeat kept its count of 3.
    assert_eq!(runner.tick(&mut host, &v2), Status::Running);
    assert_eq!(
        runner.blackboard().get("n"),
        Some(&Value::Int(1)),
        "v2's Set ran on the carried blackboard"
    );
    assert_eq!(runner.tick(&mut host, &v2), Status::Success);
    assert_eq!(runner.blackboard().get("extra"), Some(&Value::Bool(false)));

    // Without carrying state the count would restart: check against a fresh runner.
    let mut fresh = TreeRunner::new(&v2, "Main").unwrap();
    for _ in 0..4 {
        assert_eq!(fresh.tick(&mut host, &v2), Status::Running);
    }
}

#[test]
fn swap_halts_running_actions_that_disappeared() {
    let v1 = library(r#""Main": Action("LookAround")"#);
    let v2 = library(r#""Main": Action("Stand")"#);
    let mut host = ScriptedHost::new(&example_vocabulary());
    let mut runner = TreeRunner::new(&v1, "Main").unwrap();
    runner.tick(&mut host, &v1);
    runner.tick(&mut host, &v2);
    assert_eq!(host.halts, ["LookAround"]);
    assert_eq!(host.action_names(), ["LookAround", "Stand"]);
}

#[test]
fn a_library_without_the_root_keeps_the_running_tree() {
    let v1 = library(r#""Main": Action("LookAround")"#);
    let v2 = library(r#""Other": Action("Stand")"#);
    let mut host = ScriptedHost::new(&example_vocabulary());
    let mut runner = TreeRunner::new(&v1, "Main").unwrap();
    runner.tick(&mut host, &v2);
    assert_eq!(host.action_names(), ["LookAround"]);
    assert!(TreeRunner::new(&v2, "Main").is_err());
}
