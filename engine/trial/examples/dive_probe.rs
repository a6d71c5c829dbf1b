//! Experiment helper: the goalkeeper's save motions on a real server.
//! `cargo run --release -p libero-trial --example dive_probe -- left|right|block [params.ron]`
//! Stands the T1 at (−26, 0) facing +x, asks for the save after 1 s and prints the body's
//! lateral coverage of the goal line (ground truth + FK of the measured angles) against time,
//! when it first covers 0.5 / 1.0 / 1.5 m, the furthest reach, the time to 30° of tilt and when
//! the robot stood again. `SERIES=n`: n tries, one line each and a summary; `EVERY=k`: table
//! rows every k cycles (default 5); `UNTIL=s`: seconds to record after the request (default 9);
//! `WALK=vy [WALK_S=s]`: walk sideways at vy m/s for s seconds (default 2) before the request;
//! `HOLD=s`: keep asking for the save until s seconds after the request.
use libero_skills::{DiveSide, SkillParams};
use libero_trial::save_bench::{self, SaveRun};
use libero_trial::Trial;

fn main() {
    let a: Vec<String> = std::env::args().collect();
    let side = match a.get(1).map(String::as_str) {
        Some("right") => DiveSide::Right,
        Some("block") | Some("centre") => DiveSide::Centre,
        _ => DiveSide::Left,
    };
    let env = |k: &str| std::env::var(k).ok().and_then(|s| s.parse::<f64>().ok());
    let mut trial = Trial::start().unwrap();
    let model = trial.model().clone();
    let params = match a.get(2).filter(|p| !p.is_empty() && *p != "-") {
        Some(p) => SkillParams::load(std::path::Path::new(p), &model).unwrap(),
        None => SkillParams::builtin(&model).unwrap(),
    };
    let until = env("UNTIL").unwrap_or(9.0);
    // HOLD=s: keep asking for the save until s seconds after the request (stays down).
    let hold = env("HOLD").unwrap_or(0.0);
    let series = env("SERIES").map(|n| n as usize);
    let every = env("EVERY").unwrap_or(5.0) as usize;
    // WALK=vy: walk sideways at vy m/s (+ left) for WALK_S s (default 2) before the request.
    let lead_in = env("WALK").map(|vy| {
        (
            libero_skills::BodyIntent::Walk {
                forward_m_s: 0.0,
                sideways_m_s: vy,
                turn_deg_s: 0.0,
            },
            env("WALK_S").unwrap_or(2.0),
        )
    });
    let line = |r: &SaveRun| {
        let f = |v: Option<f64>| v.map_or("  -  ".to_string(), |v| format!("{v:5.2}"));
        format!(
            "cover 0.5 {} 1.0 {} 1.5 {} span 0.3-1.3 {} | max reach {:.2} m | tilt30 {} | fell {} stood {}",
            f(r.covers_at(0.5)),
            f(r.covers_at(1.0)),
            f(r.covers_at(1.5)),
            f(r.covers_span_at(0.3, 1.3)),
            r.max_reach(),
            f(r.tilt_30_s),
            r.fell,
            f(r.stood_at)
        )
    };
    let Some(n) = series else {
        let run = save_bench::save_after(
            &mut trial,
            &params,
            side,
            save_bench::KEEPER_START,
            lead_in,
            hold,
            until,
        )
        .unwrap();
        println!("   t     lo     hi  low lo low hi  torso z  tilt   roll  pitch  save");
        for c in run.coverage.iter().step_by(every.max(1)) {
            println!(
                "{:5.2} {:6.2} {:6.2} {:6.2} {:6.2}   {:5.3}  {:5.1} {:6.1} {:6.1}  {:?}",
                c.t,
                c.lo,
                c.hi,
                c.low_lo,
                c.low_hi,
                c.torso_z,
                c.tilt_deg,
                c.roll_deg,
                c.pitch_deg,
                c.save
            );
        }
        println!("{}", line(&run));
        return;
    };
    let mut runs = Vec::new();
    for i in 0..n {
        // Slightly different start headings and places, so the tries are not all alike.
        let k = i as f64;
        let start = [
            save_bench::KEEPER_START[0],
            save_bench::KEEPER_START[1] + 0.1 * ((k * 1.7).sin()),
            save_bench::KEEPER_START[2] + 5.0 * ((k * 2.3).sin()),
        ];
        let run =
            save_bench::save_after(&mut trial, &params, side, start, lead_in, hold, until).unwrap();
        println!("{i:2} {}", line(&run));
        runs.push(run);
    }
    let stood: Vec<f64> = runs.iter().filter_map(|r| r.stood_at).collect();
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len().max(1) as f64;
    let reach: Vec<f64> = runs.iter().map(SaveRun::max_reach).collect();
    let c10: Vec<f64> = runs.iter().filter_map(|r| r.covers_at(1.0)).collect();
    let span: Vec<f64> = runs
        .iter()
        .filter_map(|r| r.covers_span_at(0.3, 1.3))
        .collect();
    println!(
        "{side:?}: {n} tries, stood {} (mean {:.2} s, worst {:.2} s), fell {}, max reach mean {:.2} min {:.2}, cover 1.0 m in {} (mean {:.2} s, worst {:.2} s), span 0.3-1.3 in {} (mean {:.2}, worst {:.2})",
        stood.len(),
        mean(&stood),
        stood.iter().cloned().fold(0.0, f64::max),
        runs.iter().filter(|r| r.fell).count(),
        mean(&reach),
        reach.iter().cloned().fold(f64::INFINITY, f64::min),
        c10.len(),
        mean(&c10),
        c10.iter().cloned().fold(0.0, f64::max),
        span.len(),
        mean(&span),
        span.iter().cloned().fold(0.0, f64::max),
    );
    // Mean coverage against time.
    println!("  t   mean lo  mean hi  low lo  low hi");
    for step in 0..=20 {
        let t = step as f64 * 0.1;
        let at: Vec<_> = runs.iter().filter_map(|r| r.at(t)).collect();
        println!(
            "{t:4.1} {:7.2} {:7.2} {:7.2} {:7.2}",
            mean(&at.iter().map(|c| c.lo).collect::<Vec<_>>()),
            mean(&at.iter().map(|c| c.hi).collect::<Vec<_>>()),
            mean(&at.iter().map(|c| c.low_lo).collect::<Vec<_>>()),
            mean(&at.iter().map(|c| c.low_hi).collect::<Vec<_>>())
        );
    }
}
