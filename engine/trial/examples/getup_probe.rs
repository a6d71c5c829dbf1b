//! Experiment helper: place the robot lying and watch the get-up.
//! `cargo run -p libero-trial --example getup_probe -- front|back [params.ron]`
use libero_skills::getup::Lying;
use libero_skills::{Intent, SkillParams};
use libero_trial::{bench, Episode, Trial};

fn main() {
    let a: Vec<String> = std::env::args().collect();
    let lying = if a.get(1).map(String::as_str) == Some("back") {
        Lying::Back
    } else {
        Lying::Front
    };
    let mut trial = Trial::start().unwrap();
    let model = trial.model().clone();
    let params = match a.get(2) {
        Some(p) => SkillParams::load(std::path::Path::new(p), &model).unwrap(),
        None => SkillParams::builtin(&model).unwrap(),
    };
    let rec = trial
        .run(
            &params,
            Episode {
                start: [-20.0, 5.0, 0.0],
                lying: Some(lying),
                settle_s: 0.0,
                script: |_: &libero_world::World, t: f64| (t < 7.0).then(Intent::default),
            },
        )
        .unwrap();
    for s in rec.samples.iter().step_by(10) {
        println!(
            "t {:5.2} z {:5.3} pitch {:6.1} roll {:6.1} {:?}",
            s.t, s.position[2], s.pitch_deg, s.roll_deg, s.posture
        );
    }
    println!("stood up at {:?}", bench::stood_up_at(&rec));
}
