//! The foundation, live: real T1 agents on a real rcssservermj in fast mode.

use libero_agent::AgentStats;
use libero_model::kinematics::Kinematics;
use libero_skills::SkillParams;
use libero_tests::*;
use std::time::Duration;

/// Torso height above the ground that the stand posture should give: from forward kinematics,
/// the torso origin's height above the soles.
fn nominal_stand_height() -> f64 {
    let model = t1();
    let pose = SkillParams::builtin(&model)
        .unwrap()
        .stand_pose(&model)
        .unwrap();
    let kin = Kinematics::new(&model);
    let sole = kin.frame_pose("left_sole", &pose).unwrap();
    -sole.translation.vector.z
}

fn torso_heights(team: &libero_agent::Team) -> Vec<(u32, f64)> {
    team.stats
        .iter()
        .map(|(unum, s)| {
            (
                *unum,
                s.truth_position().expect("ground truth from the server")[2],
            )
        })
        .collect()
}

fn assert_all_standing(team: &libero_agent::Team, nominal: f64, when: &str) {
    let heights = torso_heights(team);
    let worst = heights
        .iter()
        .map(|(_, z)| (z - nominal).abs())
        .fold(0.0, f64::max);
    eprintln!(
        "{when}: nominal {nominal:.4} m, worst deviation {:.1} mm",
        worst * 1000.0
    );
    for (unum, z) in heights {
        assert!(
            (z - nominal).abs() <= 0.02,
            "{when}: player {unum} torso at {z:.3} m, nominal {nominal:.3} m"
        );
    }
}

fn assert_healthy(team: &libero_agent::Team) {
    for (unum, s) in &team.stats {
        let percepts = AgentStats::get(&s.percepts);
        assert_eq!(
            AgentStats::get(&s.connections),
            1,
            "player {unum} reconnected"
        );
        assert_eq!(
            AgentStats::get(&s.missed_cycles),
            0,
            "player {unum} missed cycles"
        );
        assert_eq!(
            AgentStats::get(&s.unreadable),
            0,
            "player {unum} got unreadable percepts"
        );
        assert!(percepts > 0);
        // Replies are counted after sending; the agent may be inside a cycle right now.
        let replies = AgentStats::get(&s.replies);
        assert!(
            percepts - replies <= 1,
            "player {unum}: {percepts} percepts, {replies} replies"
        );
    }
}

#[test]
fn seven_agents_stand_thirty_seconds_and_survive_a_second_team_joining() {
    let server = fast_server();
    let nominal = nominal_stand_height();
    let (home, home_stop) = standing_team(server.agent_port, "Home", 7);
    let (_, first) = &home.stats[0];
    wait_sim_seconds(first, 30.0);
    assert_all_standing(&home, nominal, "after 30 s");
    assert_healthy(&home);

    // Every join recompiles the server's model and wipes all motor gains; agents that send
    // all joints every cycle keep standing.
    let (away, away_stop) = standing_team(server.agent_port, "Away", 7);
    wait_sim_seconds(first, 3.0);
    assert_all_standing(&home, nominal, "after the second team joined");
    assert_all_standing(&away, nominal, "second team after joining");
    // Both teams beamed into their own halves (the right team's beam is mirrored on the wire).
    for (team, sign) in [(&home, -1.0), (&away, 1.0)] {
        for (unum, s) in &team.stats {
            let [x, _, _] = s.truth_position().unwrap();
            assert!(
                x * sign > 0.5,
                "player {unum} of the {} team stands at x = {x:.2}",
                if sign < 0.0 { "left" } else { "right" }
            );
        }
    }
    assert_healthy(&home);
    assert_healthy(&away);
    home_stop.store(true, std::sync::atomic::Ordering::Relaxed);
    away_stop.store(true, std::sync::atomic::Ordering::Relaxed);
    home.join();
    away.join();
}

#[test]
fn agents_reconnect_within_two_seconds_of_a_restarted_server() {
    let mut server = fast_server();
    let (team, stop) = standing_team(server.agent_port, "Home", 2);
    wait_sim_seconds(&team.stats[0].1, 1.0);
    server.kill();
    std::thread::sleep(Duration::from_millis(500));
    server.restart().expect("server restarts on the same ports");
    let before: Vec<u64> = team
        .stats
        .iter()
        .map(|(_, s)| AgentStats::get(&s.percepts))
        .collect();
    let took = wait_until(Duration::from_secs(10), || {
        team.stats.iter().zip(&before).all(|((_, s), &b)| {
            AgentStats::get(&s.connections) >= 2 && AgentStats::get(&s.percepts) > b
        })
    })
    .expect("agents did not resume after the restart");
    eprintln!("agents resumed {took:?} after the server was back");
    assert!(
        took <= Duration::from_secs(2),
        "resumed only after {took:?}"
    );
    // Back in business: beamed and standing again.
    wait_sim_seconds(&team.stats[0].1, 3.0);
    assert_all_standing(&team, nominal_stand_height(), "after reconnecting");
    stop.store(true, std::sync::atomic::Ordering::Relaxed);
    team.join();
    // The server's temporary run folder goes with it (a machine running the suite used to
    // collect hundreds of them).
    let run_dir = server.work_dir.clone();
    assert!(run_dir.join("server.log").exists());
    drop(server);
    assert!(!run_dir.exists(), "{} left behind", run_dir.display());
}
