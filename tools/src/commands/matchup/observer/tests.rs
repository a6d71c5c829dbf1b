use super::*;

/// The T1's: down below 0.30 m, up above 0.50 m.
const T1_POSTURE: DownAndUp = DownAndUp {
    down_below_m: 0.30,
    up_above_m: 0.50,
};

const GOALS: Goals = Goals {
    half_length: 27.5,
    goal_half_width: 1.83,
};

fn robot(left: bool, unum: u32, x: f64, y: f64, z: f64) -> RobotSample {
    RobotSample {
        left,
        unum,
        torso: [x, y, z],
        estimate: Some([x + 0.1, y]),
    }
}

fn sample(time: f64, mode: &str, ball: [f64; 2], robots: Vec<RobotSample>) -> Sample {
    Sample {
        time,
        mode: mode.into(),
        ball: [ball[0], ball[1], 0.11],
        score: (0, 0),
        robots,
    }
}

/// The ball rolling from `from` along `velocity` for 1 s, a kicker of `left` at the start.
fn kick(left: bool, from: [f64; 2], velocity: [f64; 2]) -> [Figures; 2] {
    let mut observer = Observer::new(GOALS, T1_POSTURE);
    let kicker = || vec![robot(left, 7, from[0] - 0.3, from[1], 0.6)];
    observer.feed(sample(10.0, "PlayOn", from, kicker()));
    observer.feed(sample(10.02, "PlayOn", from, kicker()));
    for i in 1..=50 {
        let t = i as f64 * 0.02;
        let at = [from[0] + velocity[0] * t, from[1] + velocity[1] * t];
        observer.feed(sample(10.02 + t, "PlayOn", at, kicker()));
    }
    observer.finish(20.0).0
}

#[test]
fn a_kick_at_the_goal_mouth_is_a_shot_on_target() {
    let [left, right] = kick(true, [15.0, 0.0], [5.0, 0.2]);
    assert_eq!((left.shots, left.shots_on_target), (1, 1));
    assert_eq!(right.shots, 0);
}

#[test]
fn a_kick_just_wide_is_a_shot_off_target_and_one_far_wide_is_none() {
    let wide = kick(true, [15.0, 0.0], [5.0, 1.2]);
    assert_eq!((wide[0].shots, wide[0].shots_on_target), (1, 0));
    let far_wide = kick(true, [15.0, 0.0], [5.0, 4.0]);
    assert_eq!(far_wide[0].shots, 0);
}

#[test]
fn a_kick_backwards_or_from_far_out_is_no_shot() {
    assert_eq!(kick(true, [15.0, 0.0], [-5.0, 0.0])[0].shots, 0);
    assert_eq!(kick(true, [-5.0, 0.0], [5.0, 0.0])[0].shots, 0);
}

#[test]
fn the_right_team_shoots_at_the_goal_at_minus_x() {
    let [left, right] = kick(false, [-15.0, 0.0], [-5.0, 0.0]);
    assert_eq!((right.shots, right.shots_on_target), (1, 1));
    assert_eq!(left.shots, 0);
}

/// Player `unum` of the left team in play, its torso at each `(height, until)` in turn from
/// time 0, one sample every 20 ms.
fn torso_heights(observer: &mut Observer, unum: u32, heights: &[(f64, f64)]) {
    let mut t = 0.0;
    for &(z, until) in heights {
        while t < until {
            observer.feed(sample(
                t,
                "PlayOn",
                [5.0, 5.0],
                vec![robot(true, unum, 0.0, 0.0, z)],
            ));
            t += 0.02;
        }
    }
}

#[test]
fn falls_count_with_how_long_the_robot_lay() {
    let mut observer = Observer::new(GOALS, T1_POSTURE);
    // Down 3 s, then 10 s.
    let heights = [
        (0.6, 1.0),
        (0.2, 4.0),
        (0.6, 10.0),
        (0.2, 20.0),
        (0.6, 30.0),
    ];
    torso_heights(&mut observer, 2, &heights);
    let [left, _] = observer.finish(30.0).0;
    assert_eq!(left.falls, 2);
    assert_eq!(left.falls_slow_to_stand, 1);
    assert_eq!(left.slow_falls.len(), 1);
    assert_eq!(left.slow_falls[0].0, 2);
    assert!((left.slow_falls[0].1 - 10.0).abs() < 0.03, "{left:?}");
    assert!((left.longest_down_s - 10.0).abs() < 0.1, "{left:?}");
    assert!(
        (left.most_down_share - 13.0 / 30.0).abs() < 0.01,
        "{left:?}"
    );
}

#[test]
fn a_jump_in_play_is_a_relocation_and_a_beam_is_not() {
    let mut observer = Observer::new(GOALS, T1_POSTURE);
    let at = |x: f64| vec![robot(true, 4, x, 0.0, 0.6)];
    observer.feed(sample(1.0, "PlayOn", [9.0, 9.0], at(0.0)));
    observer.feed(sample(1.02, "PlayOn", [9.0, 9.0], at(0.0)));
    observer.feed(sample(1.04, "PlayOn", [9.0, 9.0], at(-4.0)));
    observer.feed(sample(2.0, "Goal_Left", [9.0, 9.0], at(-4.0)));
    observer.feed(sample(2.02, "Goal_Left", [9.0, 9.0], at(-10.0)));
    observer.feed(sample(5.0, "KickOff_Right", [0.0, 0.0], at(-10.0)));
    let [left, _] = observer.finish(5.0).0;
    assert_eq!(left.relocations, 1);
}

#[test]
fn a_pass_is_a_teammate_holding_the_ball_next_after_it_travelled() {
    let mut observer = Observer::new(GOALS, T1_POSTURE);
    let team = vec![robot(true, 2, 0.0, 0.0, 0.6), robot(true, 3, 4.0, 0.0, 0.6)];
    let mut t = 0.0;
    for x in [0.2, 0.2, 1.0, 2.0, 3.0, 3.8, 3.8] {
        observer.feed(sample(t, "PlayOn", [x, 0.0], team.clone()));
        t += 0.1;
    }
    // Then an opponent takes it: no pass.
    let mut with_opponent = team.clone();
    with_opponent.push(robot(false, 5, 8.0, 0.0, 0.6));
    for x in [5.0, 6.0, 7.0, 7.8] {
        observer.feed(sample(t, "PlayOn", [x, 0.0], with_opponent.clone()));
        t += 0.1;
    }
    let [left, right] = observer.finish(t).0;
    assert_eq!(left.passes_completed, 1);
    assert_eq!(right.passes_completed, 0);
}

#[test]
fn kick_off_time_runs_from_the_mode_to_the_first_touch() {
    let mut observer = Observer::new(GOALS, T1_POSTURE);
    observer.feed(sample(0.0, "BeforeKickOff", [0.0, 0.0], vec![]));
    observer.feed(sample(0.0, "KickOff_Left", [0.0, 0.0], vec![]));
    observer.feed(sample(1.0, "KickOff_Left", [0.0, 0.0], vec![]));
    observer.feed(sample(2.1, "PlayOn", [0.0, 0.0], vec![]));
    observer.feed(sample(50.0, "KickOff_Right", [0.0, 0.0], vec![]));
    observer.feed(sample(65.0, "PlayOn", [0.0, 0.0], vec![]));
    let [left, right] = observer.finish(65.0).0;
    assert_eq!(left.kick_off_times_s, vec![2.1]);
    assert_eq!(right.kick_off_times_s, vec![15.0]);
}

#[test]
fn possession_goes_to_the_side_nearer_the_ball_and_localization_is_averaged() {
    let mut observer = Observer::new(GOALS, T1_POSTURE);
    let robots = vec![
        robot(true, 2, 0.0, 0.0, 0.6),
        robot(false, 2, 1.5, 0.0, 0.6),
    ];
    for i in 0..=100 {
        observer.feed(sample(
            i as f64 * 0.02,
            "PlayOn",
            [0.3, 0.0],
            robots.clone(),
        ));
    }
    let [left, right] = observer.finish(2.0).0;
    assert!((left.possession_s - 2.0).abs() < 0.03, "{left:?}");
    assert_eq!(right.possession_s, 0.0);
    assert!((left.localization_error_m.unwrap() - 0.1).abs() < 1e-9);
}

#[test]
fn a_nao_that_got_up_and_walks_crouched_is_up_again() {
    // NAO type 0 stands 0.385 m tall and walks crouched at ~0.35 m: with the T1's 0.5 m it
    // stayed down for the rest of the half after its first fall.
    let nao = DownAndUp::of_standing(0.385);
    let t1 = DownAndUp::of_standing(0.6735);
    assert!((t1.down_below_m - 0.30).abs() < 0.01 && (t1.up_above_m - 0.50).abs() < 0.01);
    let mut observer = Observer::new(GOALS, nao);
    // Down 3 s, then walking crouched.
    torso_heights(&mut observer, 5, &[(0.35, 1.0), (0.06, 4.0), (0.35, 30.0)]);
    let [left, _] = observer.finish(30.0).0;
    assert_eq!(left.falls, 1);
    assert_eq!(left.falls_slow_to_stand, 0, "{left:?}");
    assert!((left.longest_down_s - 3.0).abs() < 0.1, "{left:?}");
}

#[test]
fn the_referees_fouls_are_the_sides_own_and_add_up_over_halves() {
    let mut tally = libero_server::FoulTally::default();
    tally.record(10.0, [0.0, 4.0, 1.0, 6.0]);
    tally.record(11.0, [1.0, 6.0, 2.0, 9.0]);
    let mut first = Figures::default();
    first.set_fouls(&tally, true);
    assert_eq!(
        first.fouls,
        vec![FoulCount {
            unum: 6,
            kind: "incapable".into(),
            count: 1
        }]
    );
    let mut second = Figures::default();
    tally.record(50.0, [2.0, 4.0, 1.0, 6.0]);
    tally.record(51.0, [3.0, 7.0, 1.0, 2.0]);
    second.set_fouls(&tally, true);
    first.add(&second);
    assert_eq!(
        first.fouls,
        vec![
            FoulCount {
                unum: 2,
                kind: "self-collision".into(),
                count: 1
            },
            FoulCount {
                unum: 6,
                kind: "incapable".into(),
                count: 3
            },
        ]
    );
    assert_eq!(first.recent_fouls.len(), 4);
}
