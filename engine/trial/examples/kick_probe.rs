//! Experiment helper: kicks from the kicking place (or from around the ball) and their outcome.
//! `cargo run --release -p libero-trial --example kick_probe -- <count> <distance_m> [params.ron]`
//! `AROUND=1`: seeded setups from all round the ball (as `libero bench kick`); `SEED=n`.
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
