//! Experiment helper: place the robot lying and watch the get-up.
//! `cargo run -p libero-trial --example getup_probe -- front|back [params.ron] [heading] [roll] [x] [y]`
//! With `SERIES=<n>` (and optionally `SEED`), runs `n` varied placements and prints one line each;
//! with `SERIES=<n> PICK=<k>` only the k-th of those placements, traced like a single one;
//! `LIMIT` the seconds each may take (5); `REPEAT=<r>` plays each placement of a series r
//! times (SimSpark is chaotic: one pose that fails now and then is measured by playing it
//! again and again).
use libero_skills::getup::Lying;
use libero_skills::{Intent, SkillParams};
use libero_trial::getup_bench::{self, Placement};
use libero_trial::{Episode, LyingPlacement, Trial};

/// A number from the environment, if set and readable.
fn env_number<T: std::str::FromStr>(name: &str) -> Option<T> {
    std::env::var(name).ok().and_then(|s| s.parse().ok())
}

/// The fouls the referee has called on our side so far, by kind.
fn fouls_called(trial: &Trial) -> Vec<(&'static str, u32)> {
    let monitor = trial.monitor();
    let Ok(monitor) = monitor.lock() else {
        return Vec::new();
    };
    let mut out: Vec<(&'static str, u32)> = Vec::new();
    for (_, kind, n) in monitor.snapshot().fouls.counts(true) {
        match out.iter_mut().find(|o| o.0 == kind) {
            Some(o) => o.1 += n,
            None => out.push((kind, n)),
        }
    }
    out
}

fn main() {
    let a: Vec<String> = std::env::args().collect();
    let num = |i: usize, d: f64| a.get(i).and_then(|s| s.parse().ok()).unwrap_or(d);
    let side = if a.get(1).map(String::as_str) == Some("back") {
        Lying::Back
    } else {
        Lying::Front
    };
    // ROBOT=nao_type0 watches a NAO on SimSpark (default: the T1).
    let robot = std::env::var("ROBOT").unwrap_or_else(|_| "T1".into());
    let mut trial = Trial::start_on(std::sync::Arc::new(
        libero_model::RobotModel::builtin(&robot).unwrap(),
    ))
    .unwrap();
    let model = trial.model().clone();
    let params = match a.get(2).filter(|p| !p.is_empty() && *p != "-") {
        Some(p) => SkillParams::load(std::path::Path::new(p), &model).unwrap(),
        None => SkillParams::builtin(&model).unwrap(),
    };
    let series: Option<usize> = env_number("SERIES");
    let seed = env_number("SEED").unwrap_or(1);
    let pick: Option<usize> = env_number("PICK");
    if let (Some(n), None) = (series, pick) {
        let mut runs = Vec::new();
        let repeat: usize = env_number("REPEAT").unwrap_or(1);
        let limit_s: f64 = env_number("LIMIT").unwrap_or(5.0);
        let placements = getup_bench::varied_placements(side, n, seed);
        for p in placements
            .iter()
            .flat_map(|&p| std::iter::repeat_n(p, repeat))
        {
            let fouls_before = fouls_called(&trial);
            let run = getup_bench::get_up(&mut trial, &params, p, limit_s).unwrap();
            let last = run.recording.samples.last().unwrap();
            // The referee's calls during the get-up (SimSpark freezes a limb for 1 s on a
            // self-collision).
            let called: Vec<String> = fouls_called(&trial)
                .into_iter()
                .map(|(kind, n)| {
                    let before = fouls_before.iter().find(|b| b.0 == kind).map_or(0, |b| b.1);
                    (kind, n - before)
                })
                .filter(|(_, n)| *n > 0)
                .map(|(kind, n)| format!(" {kind} x{n}"))
                .collect();
            println!(
                "heading {:6.1} roll {:5.1} -> stood {:?} (end z {:.3} tilt {:.1}){}",
                p.start[2],
                p.lying.roll_deg,
                run.stood_at,
                last.position[2],
                last.tilt_deg,
                called.concat()
            );
            // TRACE_FAIL=1: the ground truth of a failed get-up, every 5th cycle; TRACE_ALL=1: of
            // every get-up (what a success does that a failure does not).
            let trace_all = std::env::var("TRACE_ALL").is_ok();
            if trace_all || (!run.succeeded() && std::env::var("TRACE_FAIL").is_ok()) {
                for s in run.recording.samples.iter().step_by(5) {
                    println!(
                        "  t {:5.2} z {:5.3} tilt {:5.1} pitch {:6.1} roll {:6.1} {:?}",
                        s.t, s.position[2], s.tilt_deg, s.pitch_deg, s.roll_deg, s.posture
                    );
                }
            }
            runs.push(run);
        }
        println!("{:?}", getup_bench::summarize(&runs));
        return;
    }
    let placement = match (series, pick) {
        (Some(n), Some(k)) => getup_bench::varied_placements(side, n, seed)[k],
        _ => Placement {
            lying: LyingPlacement {
                side,
                roll_deg: num(4, 0.0),
            },
            start: [num(5, -8.0), num(6, 0.0), num(3, 0.0)],
        },
    };
    println!("placement {placement:?}");
    let every: usize = env_number("EVERY").unwrap_or(5);
    // Measured joint angles, printed with the samples: which joints reach their targets.
    let joints: Vec<usize> = std::env::var("JOINTS")
        .unwrap_or_default()
        .split(',')
        .filter_map(|n| model.joint_id(n.trim()))
        .collect();
    // The agent's own attitude (what `until` conditions read), with JOINTS or IMU=1.
    let imu = !joints.is_empty() || std::env::var("IMU").is_ok();
    let mut cycle = 0usize;
    let recording = trial
        .run(
            &params,
            Episode {
                start: placement.start,
                lying: Some(placement.lying),
                settle_s: 0.0,
                script: move |w: &libero_world::World, t: f64| {
                    if cycle.is_multiple_of(every) && imu {
                        let q: Vec<String> = joints
                            .iter()
                            .map(|&j| format!("{:6.1}", w.body.joint_angles[j]))
                            .collect();
                        let s = libero_skills::getup::Sensed::from_body(&w.body);
                        println!(
                            "  t {t:5.2} imu pitch {:6.1} filtered {:6.1} roll {:6.1} from face down {:5.1} rate {:5.0} q {}",
                            s.attitude.pitch_deg,
                            w.me.pitch_deg,
                            s.attitude.roll_deg,
                            s.from_face_down_deg,
                            s.rate_deg_s,
                            q.join(" ")
                        );
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
