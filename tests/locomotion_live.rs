//! Locomotion on the real rcssservermj (fast `--sync --no-realtime` mode), shortened for CI.
//!
//! The full measurements are `libero bench walk|getup|kick`. The bars sit below what the current walk
//! parameters reach (`libero bench walk`, seeds 1–3: forward 0.66 m/s over 20 m, sideways
//! 0.24 m/s, turning 51°/s; this test's 10 s walk: forward 0.62 m/s with the acceleration),
//! so a regression fails but run-to-run scatter does not. The gait before it (0.55 m/s limit)
//! fails the forward bar.

use libero_model::RobotModel;
use libero_skills::SkillParams;
use libero_trial::{bench, Trial};
use std::sync::MutexGuard;

/// This test's turn on the machine (the guard, dropped last), and a trial on its own server.
fn setup() -> (MutexGuard<'static, ()>, Trial, SkillParams) {
    let turn = libero_tests::live_turn();
    let trial = Trial::start().expect("server starts");
    let model = RobotModel::builtin("T1").unwrap();
    let params = SkillParams::builtin(&model).unwrap();
    (turn, trial, params)
}

/// Three get-ups from `side`, placed by `seed`: how many stood within the bench's 5 s.
fn get_ups(
    trial: &mut Trial,
    params: &SkillParams,
    side: libero_skills::getup::Lying,
    seed: u64,
) -> usize {
    use libero_trial::getup_bench::{self, GET_UP_LIMIT_S};
    getup_bench::varied_placements(side, 3, seed)
        .into_iter()
        .filter(|&placement| {
            let run = getup_bench::get_up(trial, params, placement, GET_UP_LIMIT_S).unwrap();
            eprintln!("{placement:?}: stood at {:?}", run.stood_at);
            run.succeeded()
        })
        .count()
}

#[test]
fn walks_forward_for_ten_seconds_without_falling() {
    let (_turn, mut trial, params) = setup();
    let f = bench::forward(&mut trial, &params, 10.0, 10.0).unwrap();
    eprintln!(
        "forward {:.3} m/s over {:.1} s, fell at {:?}",
        f.speed, f.seconds, f.fell_at
    );
    assert_eq!(f.fell_at, None);
    assert!(f.speed >= 0.56, "forward {:.3} m/s", f.speed);
}

#[test]
fn walks_sideways_and_turns_on_the_spot_without_falling() {
    let (_turn, mut trial, params) = setup();
    let s = bench::sideways(&mut trial, &params, 10.0).unwrap();
    eprintln!("sideways {:.3} m/s, fell at {:?}", s.speed, s.fell_at);
    assert_eq!(s.fell_at, None);
    assert!(s.speed >= 0.21, "sideways {:.3} m/s", s.speed);
    let t = bench::turning(&mut trial, &params, 10.0).unwrap();
    eprintln!("turn {:.1} deg/s, fell at {:?}", t.speed, t.fell_at);
    assert_eq!(t.fell_at, None);
    assert!(t.speed >= 45.0, "turn {:.1} deg/s", t.speed);
}

/// Three get-ups from lying face down, each placed with another heading, roll and position and
/// started by the agent's own fall detector; then a walk from the pose a get-up ends in. All
/// three must stand within the bench's 5 s. The first placement (heading −87°, roll 3°) is the
/// one whose squat stalled on the toes in about 1 run of 3 with the old 0.09 s snap (session 3's
/// CI misses); with the 0.12 s snap it stood in 26 of 26 probe runs, and `libero bench getup`
/// stood 200 of 200 front get-ups (10 runs, seeds 1 and 3–11; worst 2.8 s).
#[test]
fn gets_up_from_the_front_then_walks() {
    use libero_skills::getup::Lying;
    use libero_trial::getup_bench::{self, GET_UP_LIMIT_S};
    let (_turn, mut trial, params) = setup();
    let stood = get_ups(&mut trial, &params, Lying::Front, 5);
    assert_eq!(
        stood, 3,
        "only {stood} of 3 front get-ups within {GET_UP_LIMIT_S} s"
    );
    let placement = getup_bench::varied_placements(Lying::Front, 1, 9)[0];
    let walk = getup_bench::walk_after_get_up(
        &mut trial,
        &params,
        placement,
        GET_UP_LIMIT_S + 0.5,
        0.3,
        3.0,
    )
    .unwrap();
    eprintln!("walk after get-up: {walk:?}");
    assert!(
        walk.stood_at.is_some_and(|t| t < GET_UP_LIMIT_S),
        "{walk:?}"
    );
    assert!(!walk.fell, "{walk:?}");
    assert!(walk.walked_m > 0.3, "{walk:?}");
}

/// Three get-ups from lying on the back (the motion rolls onto the front, waits for the IMU to
/// read face down and still, then runs on into the front motion), each placed differently; all
/// three within the bench's 5 s. `libero bench getup` stood 240 of 240 (12 runs, seeds 1–11,
/// with the 0.12 s snap), mean 4.0–4.2 s, worst 4.4 s.
#[test]
fn gets_up_from_the_back() {
    use libero_skills::getup::Lying;
    use libero_trial::getup_bench::GET_UP_LIMIT_S;
    let (_turn, mut trial, params) = setup();
    let stood = get_ups(&mut trial, &params, Lying::Back, 6);
    assert_eq!(
        stood, 3,
        "only {stood} of 3 back get-ups within {GET_UP_LIMIT_S} s"
    );
}

/// Three long kicks from different sides of the ball (the robot starts behind it, beside it
/// facing away, and in front of it), each asked for 8 m in another direction. A kick is good
/// when it is made without a fall, travels at least 7 m and keeps its direction within 12°;
/// two good kicks of three are asked for, and a mean of 9 m over them. One bad kick of three is
/// allowed because the full measurement has a tail of about one in fifty (`libero bench kick
/// --seed 2..6`, session 32, 100 long kicks each with this and the previous capture step:
/// shortest 8.9 / 8.0 m, |error| up to 12.1 / 13.4°, 1 / 3 bad by these bars) — and CI once met
/// a 6.9 m kick. A kick that is broken (short, crooked or falling) fails most of the three.
#[test]
fn long_kicks_from_three_sides_travel_and_keep_their_direction() {
    use libero_trial::kick_bench::{kick_once, KickSetup, KICK_LIMIT_S};
    let (_turn, mut trial, params) = setup();
    let setups = [
        // Behind the ball, off to one side.
        KickSetup {
            robot: [-6.0, 0.8, 0.0],
            ball: [-5.0, 0.0],
            direction_deg: 0.0,
            distance_m: 8.0,
        },
        // Beside the ball, facing away from it.
        KickSetup {
            robot: [0.0, -3.0, -90.0],
            ball: [0.0, -1.5],
            direction_deg: 90.0,
            distance_m: 8.0,
        },
        // In front of the ball: it has to walk round.
        KickSetup {
            robot: [2.0, 2.0, 180.0],
            ball: [3.0, 1.0],
            direction_deg: -135.0,
            distance_m: 8.0,
        },
    ];
    // Measured (session 3, after the contact-geometry and curve-aim work; 12 kicks of
    // `CI_SIDES=1 kick_probe`): no falls, 9.6–14.4 m, |direction| ≤ 6.1°. Kicks along a field
    // axis (0°, 90°) are the least precise: there the ball's curve amplifies launch errors.
    let mut good = 0;
    let mut travelled = 0.0;
    let mut verdicts = Vec::new();
    for s in setups {
        let o = kick_once(&mut trial, &params, s, KICK_LIMIT_S).unwrap();
        eprintln!("{s:?}: {o:?}");
        let verdict = if !o.kicked {
            "not kicked".to_string()
        } else if o.fell {
            "fell".to_string()
        } else if o.distance_m < 7.0 {
            format!("only {:.2} m", o.distance_m)
        } else if o.direction_error_deg.abs() > 12.0 {
            format!("direction off by {:.1}°", o.direction_error_deg)
        } else {
            good += 1;
            travelled += o.distance_m;
            format!(
                "good: {:.2} m, {:+.1}°",
                o.distance_m, o.direction_error_deg
            )
        };
        verdicts.push(verdict);
    }
    assert!(good >= 2, "{good} of 3 kicks good: {verdicts:?}");
    let mean = travelled / f64::from(good);
    assert!(mean >= 9.0, "kicks made travelled {mean:.2} m on average");
}

/// The dribble's kick step (`walk.kick_step`): a robot behind a ball dribbles it along +x with
/// kick steps allowed, three times. A dribble is good when a kick step is made within 10 s
/// without a fall and the ball rolls at least 3 m within 45° of the dribble's direction (it
/// goes forwards); two of three are asked for. Measured (`walk_kick_probe 20`, seeds 1 and
/// 2, NOTES.md session 33): 36 of 40 made a kick step, rolls 4.3-7.4 m but one miss, |direction|
/// 10° mean and 42° at most, 0 falls. A dribble without the kick step walks the ball on at
/// ~0.3 m/s: under a metre in the 2.5 s measured.
#[test]
fn a_dribbles_kick_step_sends_the_ball_metres_ahead_without_a_fall() {
    use libero_trial::kick_step_bench::{kick_step_once, setups, KICK_STEP_LIMIT_S};
    let (_turn, mut trial, params) = setup();
    assert!(params.walk.kick_step.is_some() && params.dribble.kick.is_some());
    let mut good = 0;
    let mut verdicts = Vec::new();
    for s in setups(3, 1) {
        let o = kick_step_once(&mut trial, &params, s, KICK_STEP_LIMIT_S).unwrap();
        eprintln!("{s:?}: {o:?}");
        let verdict = if o.fell {
            "fell".to_string()
        } else if o.first_after_s.is_none() {
            "no kick step".to_string()
        } else if o.roll_m < 3.0 {
            format!("only {:.2} m", o.roll_m)
        } else if o.direction_error_deg.abs() > 45.0 {
            format!("direction off by {:.1}°", o.direction_error_deg)
        } else {
            good += 1;
            format!("good: {:.2} m, {:+.1}°", o.roll_m, o.direction_error_deg)
        };
        verdicts.push(verdict);
    }
    assert!(good >= 2, "{good} of 3 dribbles good: {verdicts:?}");
}

/// A dive to the left from standing on the goal line (ground truth + FK of the measured angles
/// give the body's span along the line): it must cover the line 1.0 m beside the start point
/// within 1.0 s of the request, and the get-up the fall detector starts must stand the robot
/// again within 8 s. `dive_probe left` measured 0.60 s to 1.0 m, 0.76 s to the whole stretch
/// 0.3–1.3 m, and standing again at 3.64–3.70 s in 20 of 20 (NOTES.md "Save motions"); the bars
/// leave room for the slower back get-up (~5 s) should a landing end on the back.
#[test]
fn dives_left_across_the_goal_line_then_gets_up() {
    use libero_skills::DiveSide;
    use libero_trial::save_bench::{self, KEEPER_START};
    let (_turn, mut trial, params) = setup();
    let run = save_bench::save(&mut trial, &params, DiveSide::Left, KEEPER_START, 9.6).unwrap();
    eprintln!(
        "left dive: 1.0 m at {:?} s, 0.3-1.3 m at {:?} s, max reach {:.2} m, tilt 30 deg at {:?} s, stood at {:?} s",
        run.covers_at(1.0),
        run.covers_span_at(0.3, 1.3),
        run.max_reach(),
        run.tilt_30_s,
        run.stood_at
    );
    assert!(
        run.covers_at(1.0).is_some_and(|t| t <= 1.0),
        "the dive did not cover 1.0 m within 1.0 s (max reach {:.2} m)",
        run.max_reach()
    );
    assert!(
        run.stood_at.is_some_and(|t| t <= 8.0),
        "not standing again within 8 s: {:?}",
        run.stood_at
    );
}

/// The block: arms out and legs spread cover ±0.5 m beside the start within 0.3 s (measured:
/// 0.12 s, ±0.61 m) and the robot stays on its feet.
#[test]
fn blocks_half_a_metre_either_side_without_falling() {
    use libero_skills::DiveSide;
    use libero_trial::save_bench::{self, KEEPER_START};
    let (_turn, mut trial, params) = setup();
    let run = save_bench::save(&mut trial, &params, DiveSide::Centre, KEEPER_START, 3.0).unwrap();
    eprintln!(
        "block: ±0.5 m at {:?} s, reach {:.2} m, fell {}",
        run.covers_at(0.5),
        run.max_reach(),
        run.fell
    );
    assert!(
        run.covers_at(0.5).is_some_and(|t| t <= 0.3),
        "{:?}",
        run.covers_at(0.5)
    );
    assert!(!run.fell, "the block fell");
}
