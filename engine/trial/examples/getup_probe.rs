//! Experiment helper: place the robot lying and watch the get-up.
//! `cargo run -p libero-trial --example getup_probe -- front|back [params.ron] [heading] [roll] [x] [y]`
//! With `SERIES=<n>` (and optionally `SEED`), runs `n` varied placements and prints one line each.
use libero_skills::getup::Lying;
use libero_skills::{Intent, SkillParams};
use libero_trial::getup_bench::{self, Placement};
use libero_trial::{Episode, LyingPlacement, Trial};

fn main() {
    let a: Vec<String> = std::env::args().collect();
    let num = |i: usize, d: f64| a.get(i).and_then(|s| s.parse().ok()).unwrap_or(d);
    let side = if a.get(1).map(String::as_str) == Some("back") {
        Lying::Back
    } else {
        Lying::Front
    };
    let mut trial = Trial::start().unwrap();
    let model = trial.model().clone();
    let params = match a.get(2).filter(|p| !p.is_empty() && *p != "-") {
        Some(p) => SkillParams::load(std::path::Path::new(p), &model).unwrap(),
        None => SkillParams::builtin(&model).unwrap(),
    };
    if let Some(n) = std::env::var("SERIES").ok().and_then(|s| s.parse().ok()) {
        let seed = std::env::var("SEED")
            .ok()
            .and_then(|s| s.parse().ok())
            .unwrap_or(1);
        let mut runs = Vec::new();
        for p in getup_bench::varied_placements(side, n, seed) {
            let run = getup_bench::get_up(&mut trial, &params, p, 5.0).unwrap();
            let last = run.recording.samples.last().unwrap();
            println!(
                "heading {:6.1} roll {:5.1} -> stood {:?} (end z {:.3} tilt {:.1})",
                p.start[2], p.lying.roll_deg, run.stood_at, last.position[2], last.tilt_deg
            );
            runs.push(run);
        }
        println!("{:?}", getup_bench::summarize(&runs));
        return;
    }
    let placement = Placement {
        lying: LyingPlacement {
            side,
            roll_deg: num(4, 0.0),
        },
        start: [num(5, -8.0), num(6, 0.0), num(3, 0.0)],
    };
    let every: usize = std::env::var("EVERY")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(5);
    // Measured joint angles, printed with the samples: which joints reach their targets.
    let joints: Vec<usize> = std::env::var("JOINTS")
        .unwrap_or_default()
        .split(',')
        .filter_map(|n| model.joint_id(n.trim()))
        .collect();
    let mut cycle = 0usize;
    let recording = trial
        .run(
            &params,
            Episode {
                start: placement.start,
                lying: Some(placement.lying),
                settle_s: 0.0,
                script: move |w: &libero_world::World, t: f64| {
                    if cycle.is_multiple_of(every) && !joints.is_empty() {
                        let q: Vec<String> = joints
                            .iter()
                            .map(|&j| format!("{:6.1}", w.body.joint_angles[j]))
                            .collect();
                        println!("  t {t:5.2} q {}", q.join(" "));
                    }
                    cycle += 1;
                    (t < 6.6).then(Intent::default)
                },
            },
        )
        .unwrap();
    for s in recording.samples.iter().step_by(every) {
        println!(
            "t {:5.2} z {:5.3} tilt {:5.1} pitch {:6.1} roll {:6.1} {:?}",
            s.t, s.position[2], s.tilt_deg, s.pitch_deg, s.roll_deg, s.posture
        );
    }
    println!(
        "stood up at {:?}",
        getup_bench::stood_up_at(&recording, getup_bench::STANDING_HOLD_S)
    );
}
