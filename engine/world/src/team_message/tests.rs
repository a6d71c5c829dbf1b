use super::*;
use base64::Engine;

fn field() -> FieldGeometry {
    FieldGeometry::builtin("fifa7vs7").unwrap()
}

fn message() -> TeamMessage {
    TeamMessage {
        unum: 7,
        position: [-12.34, 5.67],
        fallen: true,
        ball: Some(([3.21, -8.76], 0.73)),
        time_to_ball_s: Some(4.2),
        going_for_ball: true,
    }
}

fn on_the_wire(bytes: &[u8], server: ServerKind) -> String {
    match server {
        ServerKind::RcssMj => base64::engine::general_purpose::STANDARD.encode(bytes),
        ServerKind::SimSpark => String::from_utf8(bytes.to_vec()).unwrap(),
    }
}

#[test]
fn a_message_comes_back_within_the_grid_on_both_servers() {
    let m = message();
    for server in [ServerKind::RcssMj, ServerKind::SimSpark] {
        let bytes = m.encode("Libero", &field(), server);
        match server {
            ServerKind::RcssMj => assert!(bytes.len() <= 10),
            ServerKind::SimSpark => {
                assert!(bytes.len() <= 20);
                assert!(bytes
                    .iter()
                    .all(|b| b.is_ascii_alphanumeric() || *b == b'+' || *b == b'/'));
            }
        }
        let back = TeamMessage::decode(&on_the_wire(&bytes, server), "Libero", &field()).unwrap();
        assert_eq!(back.unum, 7);
        assert!(back.fallen);
        let close =
            |a: [f64; 2], b: [f64; 2]| (a[0] - b[0]).abs() < 0.04 && (a[1] - b[1]).abs() < 0.05;
        assert!(close(back.position, m.position), "{back:?}");
        let (ball, age) = back.ball.unwrap();
        assert!(close(ball, [3.21, -8.76]), "{back:?}");
        assert!((age - 0.7).abs() < 1e-9);
        assert!((back.time_to_ball_s.unwrap() - 4.2).abs() < 1e-9);
        assert!(back.going_for_ball);
    }
}

#[test]
fn no_ball_and_no_claim_stay_absent_and_long_values_saturate() {
    let m = TeamMessage {
        ball: None,
        time_to_ball_s: None,
        going_for_ball: false,
        fallen: false,
        position: [100.0, -100.0],
        ..message()
    };
    let bytes = m.encode("Libero", &field(), ServerKind::RcssMj);
    let back =
        TeamMessage::decode(&on_the_wire(&bytes, ServerKind::RcssMj), "Libero", &field()).unwrap();
    assert_eq!(
        (
            back.ball,
            back.time_to_ball_s,
            back.fallen,
            back.going_for_ball
        ),
        (None, None, false, false)
    );
    // Off the field: clamped to the grid's edge, not wrapped round.
    assert!((back.position[0] - 29.5).abs() < 0.1 && (back.position[1] + 20.0).abs() < 0.1);
    let slow = TeamMessage {
        time_to_ball_s: Some(1e6),
        ball: Some(([0.0, 0.0], 99.0)),
        ..message()
    };
    let bytes = slow.encode("Libero", &field(), ServerKind::RcssMj);
    let back =
        TeamMessage::decode(&on_the_wire(&bytes, ServerKind::RcssMj), "Libero", &field()).unwrap();
    assert!((back.time_to_ball_s.unwrap() - TIME_TO_BALL_MAX_S).abs() < 1e-9);
    assert!((TIME_TO_BALL_MAX_S - 19.0).abs() < 1e-9);
    assert!((back.ball.unwrap().1 - 3.1).abs() < 1e-9);
}

#[test]
fn the_other_teams_messages_and_garbage_are_rejected() {
    let bytes = message().encode("Libero", &field(), ServerKind::RcssMj);
    let wire = on_the_wire(&bytes, ServerKind::RcssMj);
    assert_eq!(
        TeamMessage::decode(&wire, "Other", &field()),
        Err(Rejected::Foreign)
    );
    // One bit flipped.
    let mut flipped = bytes.clone();
    flipped[3] ^= 0x10;
    let wire = on_the_wire(&flipped, ServerKind::RcssMj);
    assert_eq!(
        TeamMessage::decode(&wire, "Libero", &field()),
        Err(Rejected::Foreign)
    );
    for garbage in [
        "",
        "hello",
        "!!!!",
        "aGVsbG8xMA==",
        "AAAAAAAAAAAA",
        &"A".repeat(10_000),
    ] {
        assert!(
            TeamMessage::decode(garbage, "Libero", &field()).is_err(),
            "{garbage:.20}"
        );
    }
}

#[test]
fn every_player_gets_the_channel_and_few_speak_at_once() {
    for server in [ServerKind::RcssMj, ServerKind::SimSpark] {
        let mut spoke = [0u32; 11];
        for cycle in 0..220 {
            let time = 100.0 + cycle as f64 * 0.02;
            let speakers: Vec<u32> = (1..=11).filter(|u| may_speak(server, time, *u)).collect();
            let most = match server {
                ServerKind::RcssMj => 2,
                ServerKind::SimSpark => 1,
            };
            assert!(speakers.len() <= most, "{server:?} {cycle}: {speakers:?}");
            for u in speakers {
                spoke[u as usize - 1] += 1;
            }
        }
        let least = *spoke.iter().min().unwrap();
        let expected = match server {
            ServerKind::RcssMj => 40,
            ServerKind::SimSpark => 10,
        };
        assert_eq!(least, expected, "{server:?}: {spoke:?}");
    }
}

#[test]
fn times_to_the_ball_are_told_finely_while_short_and_coarsely_beyond() {
    for (time, told) in [
        (0.0, 0.0),
        (0.09, 0.0),
        (0.11, 0.2),
        (4.23, 4.2),
        (8.0, 8.0),
        (8.2, 8.0),
        (8.3, 8.5),
        (13.1, 13.0),
        (18.9, 19.0),
    ] {
        let m = TeamMessage {
            time_to_ball_s: Some(time),
            ..message()
        };
        let bytes = m.encode("Libero", &field(), ServerKind::RcssMj);
        let back =
            TeamMessage::decode(&on_the_wire(&bytes, ServerKind::RcssMj), "Libero", &field())
                .unwrap();
        assert!(
            (back.time_to_ball_s.unwrap() - told).abs() < 1e-9,
            "{time}: {back:?}"
        );
        assert!((told_time_to_ball(time) - told).abs() < 1e-9, "{time}");
    }
    // Beyond the ceiling a player still compares its own time in the coarse steps.
    assert!((told_time_to_ball(30.2) - 30.0).abs() < 1e-9);
}
