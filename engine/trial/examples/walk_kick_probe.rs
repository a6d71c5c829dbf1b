//! Experiment helper: dribbles with the walk's kick step, each outcome and the summary.
//! `cargo run --release -p libero-trial --example walk_kick_probe -- <runs> [params.ron]`
//! (`SEED=n` varies the setups; `libero bench kick` prints the same summary).
use libero_skills::SkillParams;
use libero_trial::kick_step_bench::{dribbles, setups};
use libero_trial::Trial;

fn main() {
    env_logger::init();
    let a: Vec<String> = std::env::args().collect();
    let runs: usize = a.get(1).and_then(|s| s.parse().ok()).unwrap_or(6);
    let mut trial = Trial::start().unwrap();
    let model = trial.model().clone();
    let params = match a.get(2) {
        Some(p) => SkillParams::load(std::path::Path::new(p), &model).unwrap(),
        None => SkillParams::builtin(&model).unwrap(),
    };
    let seed: u64 = std::env::var("SEED")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(1);
    let (outcomes, summary) = dribbles(&mut trial, &params, runs, seed).unwrap();
    for (setup, o) in setups(runs, seed).iter().zip(&outcomes) {
        println!(
            "ball {:?}: {} kick steps, first after {:?} s, ball in robot {:?}, roll {:.2} m, direction {:+.1}°, fell {}",
            setup.ball,
            o.kick_steps,
            o.first_after_s.map(|t| (t * 100.0).round() / 100.0),
            o.ball_in_robot.map(|b| [(b[0] * 100.0).round() / 100.0, (b[1] * 100.0).round() / 100.0]),
            o.roll_m,
            o.direction_error_deg,
            o.fell
        );
    }
    println!("{summary:?}");
}
