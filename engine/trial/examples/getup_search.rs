//! Experiment helper: CMA-ES over chosen get-up key-frame numbers.
//! `cargo run --release -p libero-trial --example getup_search -- <params.ron> <spec> <generations>`
//!
//! Spec lines: `side front|back`, `d <frame> <lo> <hi>` (a duration), `j <frame> <joint> <lo>
//! <hi>` (both sides; the right one mirrored where its sign flips), `J <frame> <full joint
//! name> <lo> <hi>` (one joint), `u <frame> <lo> <hi>` (the frame's `until` threshold, kind
//! kept), `b <ankle_per_deg|ankle_per_gyro|hip_per_deg|hip_per_gyro> <lo> <hi>` (balance
//! gain), `l <frame> <lo> <hi>` (the frame's `balance_pitch_deg`). Each candidate runs `PLACEMENTS` (default 2) varied
//! placements; the best key frames so far are printed after every generation. `ROBOT=nao_type0`
//! searches on SimSpark.
use libero_skills::getup::{Condition, Keyframe, Lying};
use libero_skills::SkillParams;
use libero_trial::cmaes::CmaEs;
use libero_trial::getup_bench::{self, GetUpRun};
use libero_trial::Trial;

enum Knob {
    Duration(usize),
    Joints(usize, Vec<(String, f64)>),
    Until(usize),
    Balance(String),
    Lean(usize),
}

struct Dim {
    knob: Knob,
    lo: f64,
    hi: f64,
}

const MIRRORED: [&str; 5] = [
    "shoulder_roll",
    "elbow_yaw",
    "elbow_roll",
    "hip_roll",
    "ankle_roll",
];

fn parse_spec(text: &str) -> (Lying, Vec<Dim>) {
    let mut side = Lying::Back;
    let mut dims = Vec::new();
    for line in text.lines().map(str::trim).filter(|l| !l.is_empty()) {
        let w: Vec<&str> = line.split_whitespace().collect();
        let num = |i: usize| w[i].parse::<f64>().expect("number");
        match w[0] {
            "side" => {
                side = if w[1] == "front" {
                    Lying::Front
                } else {
                    Lying::Back
                }
            }
            "d" => dims.push(Dim {
                knob: Knob::Duration(num(1) as usize),
                lo: num(2),
                hi: num(3),
            }),
            "j" => {
                let sign = if MIRRORED.contains(&w[2]) { -1.0 } else { 1.0 };
                dims.push(Dim {
                    knob: Knob::Joints(
                        num(1) as usize,
                        vec![
                            (format!("left_{}", w[2]), 1.0),
                            (format!("right_{}", w[2]), sign),
                        ],
                    ),
                    lo: num(3),
                    hi: num(4),
                })
            }
            "J" => dims.push(Dim {
                knob: Knob::Joints(num(1) as usize, vec![(w[2].to_string(), 1.0)]),
                lo: num(3),
                hi: num(4),
            }),
            "u" | "l" => dims.push(Dim {
                knob: if w[0] == "u" {
                    Knob::Until(num(1) as usize)
                } else {
                    Knob::Lean(num(1) as usize)
                },
                lo: num(2),
                hi: num(3),
            }),
            "b" => dims.push(Dim {
                knob: Knob::Balance(w[1].to_string()),
                lo: num(2),
                hi: num(3),
            }),
            other => panic!("unknown spec line `{other}`"),
        }
    }
    (side, dims)
}

fn motion(p: &mut SkillParams, side: Lying) -> &mut Vec<Keyframe> {
    match side {
        Lying::Front => &mut p.get_up.front,
        Lying::Back => &mut p.get_up.back,
    }
}

fn threshold(c: &mut Condition) -> &mut f64 {
    match c {
        Condition::TorsoPitchAbove(v)
        | Condition::TorsoPitchBelow(v)
        | Condition::UprightWithin(v)
        | Condition::FaceDown { within_deg: v, .. } => v,
    }
}

fn balance_gain<'a>(p: &'a mut SkillParams, name: &str) -> &'a mut f64 {
    let b = &mut p.get_up.balance;
    match name {
        "ankle_per_deg" => &mut b.ankle_per_deg,
        "ankle_per_gyro" => &mut b.ankle_per_gyro,
        "hip_per_deg" => &mut b.hip_per_deg,
        "hip_per_gyro" => &mut b.hip_per_gyro,
        other => panic!("unknown balance gain `{other}`"),
    }
}

fn current(p: &mut SkillParams, side: Lying, d: &Dim) -> f64 {
    if let Knob::Balance(name) = &d.knob {
        return *balance_gain(p, name);
    }
    let m = motion(p, side);
    match &d.knob {
        Knob::Balance(_) => unreachable!("handled above"),
        Knob::Until(k) => m[*k].until.as_mut().map_or(0.0, |c| *threshold(c)),
        Knob::Lean(k) => m[*k].balance_pitch_deg.unwrap_or(0.0),
        Knob::Duration(k) => m[*k].duration_s,
        Knob::Joints(k, joints) => m[*k].pose.get(&joints[0].0).copied().unwrap_or(0.0),
    }
}

fn apply(base: &SkillParams, side: Lying, dims: &[Dim], x: &[f64]) -> SkillParams {
    let mut p = base.clone();
    for (d, &u) in dims.iter().zip(x) {
        let v = d.lo + (d.hi - d.lo) * u.clamp(0.0, 1.0);
        if let Knob::Balance(name) = &d.knob {
            *balance_gain(&mut p, name) = v;
            continue;
        }
        let m = motion(&mut p, side);
        match &d.knob {
            Knob::Balance(_) => unreachable!("handled above"),
            Knob::Until(k) => {
                if let Some(c) = m[*k].until.as_mut() {
                    *threshold(c) = v;
                }
            }
            Knob::Lean(k) => m[*k].balance_pitch_deg = Some(v),
            Knob::Duration(k) => m[*k].duration_s = v,
            Knob::Joints(k, joints) => {
                for (name, sign) in joints {
                    m[*k].pose.insert(name.clone(), v * sign);
                }
            }
        }
    }
    p
}

fn score(run: &GetUpRun) -> f64 {
    let s = &run.recording.samples;
    let up = |x: &libero_trial::Sample| x.position[2] * x.tilt_deg.to_radians().cos().max(0.0);
    let end = s.last().map_or(0.0, |x| x.t);
    let tail: Vec<f64> = s.iter().filter(|x| x.t >= end - 1.0).map(up).collect();
    let tail_mean = tail.iter().sum::<f64>() / tail.len().max(1) as f64;
    let best = s.iter().map(up).fold(0.0, f64::max);
    let stood = run
        .stood_at
        .filter(|&t| t < getup_bench::GET_UP_LIMIT_S)
        .map_or(0.0, |t| 1.0 + 0.2 * (getup_bench::GET_UP_LIMIT_S - t));
    // With PRONE_WEIGHT (for a back motion that rolls onto the front first): credit for the
    // share of the episode the agent itself reports lying face down.
    let prone_weight: f64 = std::env::var("PRONE_WEIGHT")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(0.0);
    let prone = s
        .iter()
        .filter(|x| x.posture == libero_world::Posture::FallenFront)
        .count() as f64
        / s.len().max(1) as f64;
    tail_mean + 0.5 * best + stood + prone_weight * prone
}

fn print_motion(p: &mut SkillParams, side: Lying) {
    for f in motion(p, side).iter() {
        let pose: Vec<String> = f
            .pose
            .iter()
            .map(|(j, v)| format!("\"{j}\": {:.1}", v))
            .collect();
        let mut extra = String::new();
        if let Some(c) = f.until {
            extra += &format!(", until: Some({c:?}), timeout_s: {:.2}", f.timeout_s);
            if f.hold_s > 0.0 {
                extra += &format!(", hold_s: {:.2}", f.hold_s);
            }
            if let Some(next) = &f.on_timeout {
                extra += &format!(", on_timeout: Some({next:?})");
            }
        }
        if let Some(l) = f.balance_pitch_deg {
            extra += &format!(", balance_pitch_deg: Some({l:.1})");
        }
        println!(
            "            Keyframe(duration_s: {:.2}, pose: {{{}}}{extra}),",
            f.duration_s,
            pose.join(", ")
        );
    }
    println!("            balance: {:?}", p.get_up.balance);
}

fn main() {
    let a: Vec<String> = std::env::args().collect();
    // ROBOT=nao_type0 searches a NAO's get-up on SimSpark (default: the T1).
    let robot = std::env::var("ROBOT").unwrap_or_else(|_| "T1".into());
    let mut trial = Trial::start_on(std::sync::Arc::new(
        libero_model::RobotModel::builtin(&robot).unwrap(),
    ))
    .unwrap();
    let model = trial.model().clone();
    let mut base = SkillParams::load(std::path::Path::new(&a[1]), &model).unwrap();
    let (side, dims) = parse_spec(&std::fs::read_to_string(&a[2]).unwrap());
    let generations: usize = a[3].parse().unwrap();
    let n_places = std::env::var("PLACEMENTS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(2);
    let placements = getup_bench::varied_placements(side, n_places, 7);
    let start: Vec<f64> = dims
        .iter()
        .map(|d| ((current(&mut base, side, d) - d.lo) / (d.hi - d.lo)).clamp(0.0, 1.0))
        .collect();
    let sigma = std::env::var("SIGMA")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(0.2);
    let mut es = CmaEs::new(start.clone(), sigma, None, 11);
    let mut evaluate = |x: &[f64]| -> (f64, usize) {
        let p = apply(&base, side, &dims, x);
        if p.validate(&model).is_err() {
            return (10.0, 0);
        }
        let mut total = 0.0;
        let mut ok = 0;
        for &pl in &placements {
            let run = getup_bench::get_up(&mut trial, &p, pl, getup_bench::GET_UP_LIMIT_S).unwrap();
            ok += usize::from(run.succeeded());
            total += score(&run);
        }
        (-total / placements.len() as f64, ok)
    };
    let (c0, ok0) = evaluate(&start);
    println!("start cost {c0:.3} ({ok0} stood)");
    let mut best = (c0, start);
    for g in 0..generations {
        let cands = es.ask();
        let results: Vec<(f64, usize)> = cands.iter().map(|c| evaluate(c)).collect();
        let costs: Vec<f64> = results.iter().map(|r| r.0).collect();
        for (c, x) in costs.iter().zip(&cands) {
            if *c < best.0 {
                best = (*c, x.clone());
            }
        }
        es.tell(&cands, &costs);
        let oks: Vec<usize> = results.iter().map(|r| r.1).collect();
        println!(
            "gen {g} best {:.3} gen-best {:.3} stood {:?} sigma {:.3}",
            best.0,
            costs.iter().copied().fold(f64::INFINITY, f64::min),
            oks,
            es.sigma
        );
        let mut p = apply(&base, side, &dims, &best.1);
        print_motion(&mut p, side);
    }
}
