//! Experiment helper: walk with a fixed command for a while and print the trajectory.
//! `cargo run -p libero-trial --example walk_probe -- <forward> <sideways> <turn> <seconds> [params.ron]`
use libero_skills::{BodyIntent, Intent, SkillParams};
use libero_trial::{measure, Episode, Trial};

fn main() {
    let a: Vec<String> = std::env::args().collect();
    let num = |i: usize, d: f64| a.get(i).and_then(|s| s.parse().ok()).unwrap_or(d);
    let (f, s, w, secs) = (num(1, 0.3), num(2, 0.0), num(3, 0.0), num(4, 10.0));
    let hold: f64 = std::env::var("HOLD")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(0.0);
    // ROBOT=nao_type3 walks a NAO on SimSpark (default: the T1).
    let robot = std::env::var("ROBOT").unwrap_or_else(|_| "T1".into());
    let mut trial = Trial::start_on(std::sync::Arc::new(
        libero_model::RobotModel::builtin(&robot).unwrap(),
    ))
    .unwrap();
    let model = trial.model().clone();
    let params = match a.get(5) {
        Some(p) => SkillParams::load(std::path::Path::new(p), &model).unwrap(),
        None => SkillParams::builtin(&model).unwrap(),
    };
    if std::env::var("PRE").is_ok() {
        let f = libero_trial::bench::forward(&mut trial, &params, 10.0, 50.0).unwrap();
        println!("pre forward {f:?}");
        let f = libero_trial::bench::sideways(&mut trial, &params, 10.0).unwrap();
        println!("pre sideways {f:?}");
    }
    let rec = trial
        .run(
            &params,
            Episode {
                start: [
                    std::env::var("START_X")
                        .ok()
                        .and_then(|s| s.parse().ok())
                        .unwrap_or(-10.0),
                    0.0,
                    0.0,
                ],
                lying: None,
                settle_s: 1.0,
                // `HOLD=s`: stand this long after the command (how a short walk ends).
                script: move |_w: &libero_world::World, t: f64| {
                    let body = if t < secs {
                        BodyIntent::Walk {
                            forward_m_s: f,
                            sideways_m_s: s,
                            turn_deg_s: w,
                        }
                    } else {
                        BodyIntent::Stand
                    };
                    (t < secs + hold).then(|| Intent {
                        body,
                        ..Default::default()
                    })
                },
            },
        )
        .unwrap();
    for s in rec.samples.iter().step_by(
        std::env::var("EVERY")
            .ok()
            .and_then(|s| s.parse().ok())
            .unwrap_or(25),
    ) {
        println!(
            "t {:5.2} pos {:7.3} {:7.3} {:5.3} yaw {:6.1} pitch {:5.1} roll {:5.1} {:?}",
            s.t,
            s.position[0],
            s.position[1],
            s.position[2],
            s.yaw_deg,
            s.pitch_deg,
            s.roll_deg,
            s.posture
        );
    }
    println!("first fall {:?}", rec.first_fall_s());
    println!(
        "velocity after 2 s {:?}",
        measure::mean_velocity(&rec, 2.0, secs)
    );
}
