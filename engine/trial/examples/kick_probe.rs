//! Experiment helper: kicks from the kicking place (or from around the ball) and their outcome.
//! `cargo run --release -p libero-trial --example kick_probe -- <count> <distance_m> [params.ron]`
//! `CI_SIDES=1`: the live test's three approaches, repeated. `AROUND=1`: seeded setups from all round the ball (as `libero bench kick`); `SEED=n`.
use libero_skills::SkillParams;
use libero_trial::kick_bench::{kick_once, setups, KickSetup, KickSummary};
use libero_trial::Trial;

fn main() {
    env_logger::init();
    let a: Vec<String> = std::env::args().collect();
    let count: usize = a.get(1).and_then(|s| s.parse().ok()).unwrap_or(3);
    let distance: f64 = a.get(2).and_then(|s| s.parse().ok()).unwrap_or(8.0);
    let mut trial = Trial::start().unwrap();
    let model = trial.model().clone();
    let params = match a.get(3) {
        Some(p) => SkillParams::load(std::path::Path::new(p), &model).unwrap(),
        None => SkillParams::builtin(&model).unwrap(),
    };
    let seed = std::env::var("SEED")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(1);
    let list: Vec<KickSetup> = if std::env::var("AROUND").is_ok() {
        setups(count, seed, distance)
    } else if std::env::var("CI_SIDES").is_ok() {
        // The three approaches of the live test `long_kicks_from_three_sides_...`.
        let s = |robot: [f64; 3], ball: [f64; 2], direction_deg: f64| KickSetup {
            robot,
            ball,
            direction_deg,
            distance_m: distance,
        };
        [
            s([-6.0, 0.8, 0.0], [-5.0, 0.0], 0.0),
            s([0.0, -3.0, -90.0], [0.0, -1.5], 90.0),
            s([2.0, 2.0, 180.0], [3.0, 1.0], -135.0),
        ]
        .into_iter()
        .cycle()
        .take(count)
        .collect()
    } else {
        let ap = &params.kick.approach;
        let side = if std::env::var("RIGHT").is_ok() {
            -1.0
        } else {
            1.0
        };
        let heading: f64 = std::env::var("HEADING")
            .ok()
            .and_then(|s| s.parse().ok())
            .unwrap_or(0.0);
        let (c, s) = (heading.to_radians().cos(), heading.to_radians().sin());
        (0..count)
            .map(|i| {
                let y = -2.0 + i as f64;
                let (ax, ay) = (ap.ball_ahead_m, side * ap.ball_beside_m);
                KickSetup {
                    robot: [-5.0, y, heading],
                    ball: [-5.0 + ax * c - ay * s, y + ax * s + ay * c],
                    direction_deg: heading,
                    distance_m: distance,
                }
            })
            .collect()
    };
    let mut outcomes = Vec::new();
    for s in list {
        let o = kick_once(&mut trial, &params, s, 40.0).unwrap();
        println!("{s:?}\n  -> {o:?}");
        outcomes.push(o);
    }
    println!("{:?}", KickSummary::of(&outcomes));
}
