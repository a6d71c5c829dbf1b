use super::*;
use crate::decide::StandAndBeam;
use libero_protocol::sexp;
use libero_skills::SkillParams;

fn t1_player() -> Player {
    let model = Arc::new(RobotModel::builtin("T1").unwrap());
    let skills = Skills::new(&model, SkillParams::builtin(&model).unwrap()).unwrap();
    let decider = Box::new(StandAndBeam {
        beam_pose: [-5.0, 1.0, 0.0],
    });
    // The recorded messages name the team `Probe`: that is how the player learns its side.
    Player::new(model, skills, decider, "Probe", 3, Arc::default())
}

fn sample(name: &str) -> Vec<u8> {
    let path = format!(
        "{}/../../../shared/samples/rcssservermj/{name}",
        env!("CARGO_MANIFEST_DIR")
    );
    std::fs::read(path).unwrap()
}

fn reply_items(out: &[u8]) -> Vec<String> {
    let text = std::str::from_utf8(&out[4..]).unwrap();
    sexp::top_level(text)
        .map(|i| i.unwrap().as_list().unwrap().head().unwrap().to_string())
        .collect()
}

#[test]
fn a_beam_goes_out_in_every_goal_mode_not_only_the_first() {
    let mut player = t1_player();
    let base = String::from_utf8(sample("T1_sync_msg0001.txt")).unwrap();
    let mut beams = Vec::new();
    for mode in [
        "BeforeKickOff",
        "KickOff_Left",
        "PlayOn",
        "Goal_Left",
        "Goal_Left",
        "KickOff_Right",
        "PlayOn",
        "Goal_Left",
        "Goal_Left",
    ] {
        let percept = base.replace("(pm BeforeKickOff)", &format!("(pm {mode})"));
        let mut out = Vec::new();
        player.on_percept(percept.as_bytes(), &mut out);
        beams.push(reply_items(&out).last().map(String::as_str) == Some("beam"));
    }
    assert_eq!(
        beams,
        [true, false, false, true, false, false, false, true, false]
    );
}

#[test]
fn every_percept_gets_one_reply_with_all_joints_and_one_beam() {
    let mut player = t1_player();
    let mut out = Vec::new();
    player.on_percept(&sample("T1_sync_msg0000.txt"), &mut out);
    let items = reply_items(&out);
    assert_eq!(items.len(), 24, "{items:?}");
    assert_eq!(items.last().unwrap(), "beam");
    assert_eq!(
        u32::from_be_bytes(out[..4].try_into().unwrap()) as usize,
        out.len() - 4
    );
    out.clear();
    player.on_percept(&sample("T1_sync_msg0001.txt"), &mut out);
    assert_eq!(
        reply_items(&out).len(),
        23,
        "beam is sent once per beam-allowing play mode"
    );
    out.clear();
    player.on_percept(b"\xff\xfe garbage (((", &mut out);
    assert_eq!(
        reply_items(&out).len(),
        23,
        "unreadable input still gets a full reply"
    );
    assert_eq!(AgentStats::get(&player.stats.replies), 3);
    assert_eq!(AgentStats::get(&player.stats.unreadable), 1);
}

#[test]
fn time_gaps_count_as_missed_cycles() {
    let mut player = t1_player();
    let mut out = Vec::new();
    for t in ["1.00", "1.02", "1.05", "1.06", "1.11"] {
        player.on_percept(format!("(time (now {t}))").as_bytes(), &mut out);
    }
    // 1.02 → 1.05 is one truncated cycle; 1.06 → 1.11 skips one.
    assert_eq!(AgentStats::get(&player.stats.missed_cycles), 1);
}

#[test]
fn the_evaluation_log_has_one_json_line_per_cycle_with_ground_truth() {
    let path = std::env::temp_dir().join(format!("libero-eval-{}.jsonl", std::process::id()));
    let mut player = t1_player();
    player.log_to(EvalLogger::create(&path).unwrap(), true);
    let mut out = Vec::new();
    player.on_percept(&sample("T1_sync_msg0000.txt"), &mut out);
    player.on_percept(&sample("T1_sync_msg0001.txt"), &mut out);
    drop(player);
    let text = std::fs::read_to_string(&path).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines.len(), 2);
    assert!(lines[0].starts_with("{\"time\":667.31,"), "{}", lines[0]);
    assert!(
        lines[1].contains("\"truth\":{\"position\":[-2.999,21.0,0.672]"),
        "{}",
        lines[1]
    );
    let _ = std::fs::remove_file(path);
}

#[test]
fn a_view_slot_and_the_traced_log_show_the_same_cycle_alike() {
    let path = std::env::temp_dir().join(format!("libero-view-{}.jsonl", std::process::id()));
    let model = Arc::new(RobotModel::builtin("T1").unwrap());
    let source = crate::build::load_library(&crate::build::default_data_dirs(), false).unwrap();
    let mut player =
        crate::build::tree_player(&model, "Probe", 3, &source, &SkillSource::Builtin).unwrap();
    player.log_to(EvalLogger::create(&path).unwrap(), true);
    // A period of zero: a copy in every cycle.
    let slot = ViewSlot::new(std::time::Duration::ZERO);
    player.show_in(Arc::clone(&slot));
    let mut out = Vec::new();
    for name in [
        "T1_sync_msg0000.txt",
        "T1_sync_msg0001.txt",
        "T1_sync_msg0002.txt",
    ] {
        player.on_percept(&sample(name), &mut out);
    }
    drop(player);
    let text = std::fs::read_to_string(&path).unwrap();
    let _ = std::fs::remove_file(&path);
    let lines: Vec<&str> = text.lines().collect();
    assert!(
        lines[0].contains("\"tree_shape\":{"),
        "the first line carries the tree"
    );
    assert!(!lines[1].contains("\"tree_shape\""), "and only the first");
    let logged: crate::view::AgentView = serde_json::from_str(lines[2]).unwrap();
    let live = slot.latest().unwrap();
    assert_eq!(slot.copies(), 3);
    assert_eq!(
        (logged.time, logged.cycle, logged.unum),
        (live.time, live.cycle, 3)
    );
    assert_eq!(logged.me.position, live.me.position);
    assert_eq!(
        logged.truth.map(|t| t.position),
        live.truth.map(|t| t.position)
    );
    let (l, v) = (logged.decision.unwrap(), live.decision.unwrap());
    assert_eq!(l.formation_target, v.formation_target);
    assert!(v.formation_target.is_some(), "the notes were kept");
    let (lt, vt) = (l.tree.unwrap(), v.tree.unwrap());
    assert_eq!(lt.ticked, vt.ticked);
    assert!(!vt.ticked.is_empty() && vt.name == "FieldPlayer", "{vt:?}");
    let shape = slot.shape(vt.generation).unwrap();
    assert_eq!(shape.labels.len(), shape.parents.len());
    assert!(vt
        .ticked
        .iter()
        .all(|(n, _)| (*n as usize) < shape.labels.len()));
}

#[test]
fn simspark_handshake_init_then_velocities_and_syn_every_cycle() {
    let model = Arc::new(RobotModel::builtin("NAO_type2").unwrap());
    let source = crate::build::load_library(&crate::build::default_data_dirs(), false).unwrap();
    let mut player =
        crate::build::tree_player(&model, "Libero", 4, &source, &SkillSource::Builtin).unwrap();
    let hello = player.greeting().unwrap();
    assert_eq!(&hello[4..], b"(scene rsg/agent/nao/nao_hetero.rsg 2)");
    let path = format!(
        "{}/../../../shared/samples/simspark/agent_first20.txt",
        env!("CARGO_MANIFEST_DIR")
    );
    let messages: Vec<String> = std::fs::read_to_string(path)
        .unwrap()
        .lines()
        .filter(|l| l.starts_with("(time"))
        .map(str::to_string)
        .collect();
    let mut beams = Vec::new();
    for (i, message) in messages.iter().enumerate() {
        let mut out = Vec::new();
        player.on_percept(message.as_bytes(), &mut out);
        let text = std::str::from_utf8(&out[4..]).unwrap();
        if text.contains("(beam ") {
            beams.push(i);
        }
        assert!(
            text.ends_with("(syn)"),
            "cycle {i}: every reply syncs: {text}"
        );
        assert_eq!(
            text.matches("(init ").count(),
            usize::from(i == 0),
            "cycle {i}: init exactly once: {text}"
        );
        for joint in &model.joints {
            assert!(
                text.contains(&format!("({} ", joint.effector)),
                "cycle {i}: {} missing",
                joint.effector
            );
        }
        if i == 0 {
            assert!(
                text.starts_with("(init (unum 4)(teamname Libero))"),
                "{text}"
            );
        }
    }
    // The third message announced our side and number; the beam waits for it (an earlier one
    // would be ignored by the server) and is sent once.
    assert_eq!(player.world.game.side, Some(libero_world::Side::Left));
    assert_eq!(beams, [2]);
}
