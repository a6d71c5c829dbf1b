//! Every real server message in `../shared/samples` reads into the expected typed percept.

use libero_model::ServerKind;
use libero_protocol::parse_percept_str;
use libero_protocol::percept::{HeardFrom, Percept};
use std::path::PathBuf;

fn samples_dir(server: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../../shared/samples")
        .join(server)
}

fn read(server: &str, name: &str) -> String {
    let path = samples_dir(server).join(name);
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// The SimSpark sample files hold several messages, each after a `### recv` header line.
fn simspark_messages(name: &str) -> Vec<String> {
    read("simspark", name)
        .lines()
        .filter(|l| l.starts_with("(time"))
        .map(str::to_string)
        .collect()
}

fn parse_mj(text: &str) -> Percept<'_> {
    let p = parse_percept_str(text.trim_end(), ServerKind::RcssMj).unwrap();
    assert!(p.skipped.is_empty(), "skipped {:?}", p.skipped);
    p
}

#[test]
fn every_rcssservermj_agent_sample_parses_completely() {
    let mut with_vision = 0;
    for entry in std::fs::read_dir(samples_dir("rcssservermj")).unwrap() {
        let path = entry.unwrap().path();
        let name = path.file_name().unwrap().to_string_lossy().to_string();
        if name.starts_with("monitor") {
            continue;
        }
        let text = std::fs::read_to_string(&path).unwrap();
        let p = parse_mj(&text);
        let expected_joints = if name.starts_with("K1") { 22 } else { 23 };
        assert_eq!(p.joints.len(), expected_joints, "{name}");
        assert!(
            p.time.is_some() && p.gyro.is_some() && p.accel.is_some(),
            "{name}"
        );
        assert!(
            p.truth_position.is_some() && p.truth_orientation.is_some(),
            "{name}"
        );
        assert!(p.joints.iter().all(|j| j.velocity_deg.is_some()), "{name}");
        with_vision += p.vision.is_some() as usize;
    }
    assert!(with_vision >= 10, "only {with_vision} samples had vision");
}

#[test]
fn rcssservermj_first_message_values() {
    let text = read("rcssservermj", "T1_sync_msg0000.txt");
    let p = parse_mj(&text);
    assert_eq!(p.time, Some(667.31));
    assert_eq!(p.game.play_mode, Some("BeforeKickOff"));
    assert_eq!(p.game.team_left, Some("Probe"));
    assert_eq!(p.game.team_right, None);
    assert_eq!((p.game.score_left, p.game.score_right), (Some(0), Some(0)));
    assert_eq!(p.truth_orientation, Some([0.707, 0.0, 0.0, -0.707]));
    assert_eq!(p.truth_position, Some([-3.0, 21.0, 0.673]));
    assert_eq!(p.joints[0].perceptor, "q_hj1");
    assert_eq!(p.joints[22].perceptor, "q_rlj6");
    let vision = p.vision.unwrap();
    assert_eq!(vision.landmarks.len(), 21);
    assert_eq!(vision.landmarks[0].name, "l_llf");
    assert_eq!(vision.landmarks[0].at.distance, 45.97);
    assert_eq!(vision.landmarks[0].at.azimuth_deg, -32.21);
    assert_eq!(vision.landmarks[0].at.elevation_deg, -1.36);
    let ball = vision.ball.unwrap();
    assert_eq!(
        (ball.distance, ball.azimuth_deg, ball.elevation_deg),
        (21.12, 8.17, -2.68)
    );
}

#[test]
fn rcssservermj_hearing_and_players() {
    let text = read("rcssservermj", "T1_two_agents_B_with_MIC_012.txt");
    let p = parse_mj(&text);
    assert_eq!(p.game.team_right, Some("Other"));
    assert_eq!(p.heard.len(), 1);
    assert_eq!(p.heard[0].from, HeardFrom::Direction(-11.0));
    assert_eq!(p.heard[0].message, "aGVsbG8xMA==");
    let vision = p.vision.unwrap();
    assert_eq!(vision.players.len(), 1);
    let player = &vision.players[0];
    assert_eq!((player.team, player.unum), ("Probe", 2));
    let parts: Vec<_> = player.parts.iter().map(|s| s.name).collect();
    assert_eq!(parts, ["head", "lfoot", "rfoot"]);
}

#[test]
fn simspark_messages_parse_with_robot_frame_vectors() {
    let messages = simspark_messages("agent_first20.txt");
    assert_eq!(messages.len(), 20);
    for text in &messages {
        let p = parse_percept_str(text, ServerKind::SimSpark).unwrap();
        assert!(p.skipped.is_empty(), "skipped {:?} in {text}", p.skipped);
        assert_eq!(p.joints.len(), 22);
        assert!(p.joints.iter().all(|j| j.velocity_deg.is_none()));
    }
    let first = parse_percept_str(&messages[0], ServerKind::SimSpark).unwrap();
    // (GYR (n torso) (rt 112.20 -656.15 -3218.40)): x right, y forward → forward, left.
    assert_eq!(first.gyro, Some([-656.15, -112.20, -3218.40]));
    assert_eq!(
        first.vision,
        Some(Default::default()),
        "`(See )` is an empty vision frame"
    );
    assert_eq!(first.foot_contacts.len(), 2);
    assert_eq!(first.foot_contacts[0].name, "rf");
    assert_eq!(first.foot_contacts[0].force, [-729.71, -330.53, 337.17]);
    let third = parse_percept_str(&messages[2], ServerKind::SimSpark).unwrap();
    assert_eq!(third.game.unum, Some(1));
    assert_eq!(third.game.side, Some("left"));
    let with_vision = messages
        .iter()
        .filter(|m| {
            parse_percept_str(m, ServerKind::SimSpark)
                .unwrap()
                .vision
                .is_some()
        })
        .count();
    assert_eq!(with_vision, 7, "vision every 3rd message: #1, #4, … #19");
}

#[test]
fn simspark_vision_flags_goals_lines_players_and_hearing() {
    let all = simspark_messages("agent_hear.txt");
    let opp = all
        .iter()
        .find(|m| m.contains("-6.59 hello42"))
        .expect("opponent's hear sample");
    let p = parse_percept_str(opp, ServerKind::SimSpark).unwrap();
    assert!(p.skipped.is_empty(), "{:?}", p.skipped);
    assert_eq!(p.heard.len(), 1);
    assert_eq!(p.heard[0].team, Some("Probe"));
    assert_eq!(p.heard[0].time, Some(0.36));
    assert_eq!(p.heard[0].from, HeardFrom::Direction(-6.59));
    assert_eq!(p.heard[0].message, "hello42");
    let vision = p.vision.unwrap();
    let names: Vec<_> = vision.landmarks.iter().map(|l| l.name).collect();
    assert!(
        names.starts_with(&["G1L", "G2L", "F1L", "F2L"]),
        "{names:?}"
    );
    assert_eq!(vision.ball.unwrap().distance, 3.45);
    let probe = vision.players.iter().find(|pl| pl.team == "Probe").unwrap();
    assert_eq!(probe.parts.len(), 5);
    assert!(!vision.lines.is_empty(), "SimSpark reports field lines");

    let own = all.iter().find(|m| m.contains("self hello42")).unwrap();
    let p = parse_percept_str(own, ServerKind::SimSpark).unwrap();
    assert_eq!(p.heard[0].from, HeardFrom::Myself);
}

#[test]
fn simspark_playon_vision_sample() {
    let messages = simspark_messages("agent_vision_playon.txt");
    assert!(!messages.is_empty());
    for text in &messages {
        let p = parse_percept_str(text, ServerKind::SimSpark).unwrap();
        assert!(p.skipped.is_empty(), "{:?}", p.skipped);
        assert_eq!(p.game.play_mode, Some("PlayOn"));
    }
}

/// A percept lives on the stack with fixed capacities: more items than fit are dropped, and
/// the block they came in is named in `skipped`, never a panic or a heap list.
#[test]
fn items_beyond_the_capacities_are_dropped_and_named() {
    use libero_protocol::percept::{MAX_JOINTS, MAX_LANDMARKS};
    let mut text = String::from("(time (now 1.0))");
    for i in 0..MAX_JOINTS + 5 {
        text.push_str(&format!("(HJ (n j{i}) (ax 1.0))"));
    }
    text.push_str("(See");
    for i in 0..MAX_LANDMARKS + 3 {
        text.push_str(&format!("(f{i} (pol 1 2 3))"));
    }
    text.push_str("(B (pol 1 2 3)))");
    let p = parse_percept_str(&text, ServerKind::RcssMj).unwrap();
    assert_eq!(p.joints.len(), MAX_JOINTS);
    assert_eq!(
        p.joints[MAX_JOINTS - 1].perceptor,
        format!("j{}", MAX_JOINTS - 1)
    );
    let vision = p.vision.as_ref().unwrap();
    assert_eq!(vision.landmarks.len(), MAX_LANDMARKS);
    assert!(
        vision.ball.is_some(),
        "the ball after the overflow is still read"
    );
    assert!(vision.overflowed);
    assert_eq!(p.skipped.iter().filter(|s| **s == "HJ").count(), 5);
    assert!(p.skipped.contains(&"See"));
}
