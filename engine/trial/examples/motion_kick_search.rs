//! Experiment helper: CMA-ES over a key-frame kick's numbers (a named motion of the parameter
//! file) and where the ball lies before it, on the real server.
//! `motion_kick_search <params.ron> <motion> <spec|-> <generations>`; `ROBOT` (default
//! nao_type0). With 0 generations (spec `-`), a probe: the file's motion played as it stands
//! from each placement, the ball at `AX`, `AY`. Spec lines: `d <frame> <lo> <hi>` (a duration), `J <frame> <joint> <lo> <hi>`,
//! `ax <lo> <hi>`, `ay <lo> <hi>` (the ball's place in the robot frame before the kick, from
//! the torso where it truly stands: the frame `libero bench kick` logs the ball in at the
//! kick's start; until session 21 it was from the placement, ~3.5 cm behind the torso).
//! `WALK_S` > 0: the robot walks forward that long and stops before the ball is placed.
//! Each candidate kicks from `PLACEMENTS` (1) spots, the ball `JITTER` [m] round its place in
//! each (0: on it); the cost rewards the ball's mean travel and punishes a mean direction more
//! than 30° off the heading, the directions' spread (`SPREAD_WEIGHT` m per deg, 0.05) and falls.
//! The best so far is printed
//! after every generation as RON key frames.
//! `SKILL_KICKS` > 0: each candidate is judged by that many kicks of the kick skill itself
//! (`kick_bench::kick_once`: the approach's walk-in, then the key frames from the stance it
//! ends in), from the bench's seeded setups (the same ones for every candidate of a
//! generation); `ax` / `ay` then move the approach's kicking place (`ball_ahead_m`,
//! `ball_beside_m`). `TRIALS` servers judge candidates side by side (the runs are
//! latency-bound).
use libero_skills::getup::Keyframe;
use libero_skills::{BodyIntent, Intent, SkillParams};
use libero_trial::cmaes::CmaEs;
use libero_trial::kick_bench::{kick_once, setups, KickDirections, KICK_LIMIT_S};
use libero_trial::{Episode, Trial};
use std::sync::{Arc, Mutex};

/// The ball when the kick began and now, and whether it fell / the lowest torso height.
type Progress = (Option<[f64; 3]>, Option<[f64; 3]>, bool);

enum Knob {
    Duration(usize),
    Joint(usize, String),
    BallX,
    BallY,
}

struct Dim {
    knob: Knob,
    lo: f64,
    hi: f64,
}

/// One kick: the ball's travel [m] and direction [deg, robot frame], and whether it fell.
fn kick(
    trial: &mut Trial,
    params: &SkillParams,
    motion: &str,
    y: f64,
    ball: [f64; 2],
) -> (f64, f64, bool) {
    let id = params.motion_id(motion).expect("no such motion");
    let model = trial.model().clone();
    let ball_z = libero_model::FieldGeometry::builtin(model.server.default_field())
        .unwrap()
        .ball_radius;
    let fallen_below = model.standing_torso_height * 0.5;
    let start = [-5.0, y, 0.0];
    let monitor = trial.monitor();
    let out: Arc<Mutex<Progress>> = Arc::new(Mutex::new((None, None, false)));
    let shared = Arc::clone(&out);
    // WALK_S > 0: walk forward that long first and stand (the kick skill starts its motions
    // after a walk); the ball is placed relative to where the robot truly stands.
    let walk_s = std::env::var("WALK_S")
        .ok()
        .and_then(|s| s.parse::<f64>().ok())
        .unwrap_or(0.0);
    let (place_at, motion_at) = if walk_s > 0.0 {
        (walk_s + 0.8, walk_s + 1.0)
    } else {
        (0.3, 1.0)
    };
    let mut placed = false;
    let script = move |w: &libero_world::World, t: f64| -> Option<Intent> {
        let mut m = monitor.lock().ok()?;
        if !placed && t > place_at {
            // Relative to the torso where it truly stands (it settles ~3.5 cm ahead of a
            // placement), in the frame the kick bench reports the ball at the kick's start.
            let ([x, y, _], yaw_deg) = w.truth_pose()?;
            let at = libero_world::Pose::new(libero_world::Global::new(x, y), yaw_deg)
                .global(libero_world::Robot::new(ball[0], ball[1]))
                .to_array();
            let _ = m.send(&format!(
                "(ball (pos {} {} {ball_z})(vel 0 0 0))",
                at[0], at[1]
            ));
            placed = true;
        }
        let b = m.snapshot().ball;
        drop(m);
        let mut o = shared.lock().ok()?;
        if w.truth.torso_position.is_some_and(|p| p[2] < fallen_below) {
            o.2 = true;
        }
        if t < walk_s {
            return Some(Intent {
                body: BodyIntent::Walk {
                    forward_m_s: 0.15,
                    sideways_m_s: 0.0,
                    turn_deg_s: 0.0,
                },
                ..Default::default()
            });
        }
        if t < motion_at {
            return Some(Intent::default());
        }
        if o.0.is_none() {
            o.0 = b;
            if std::env::var("SHOW_START").is_ok() {
                let torso = w.truth.torso_position;
                eprintln!(
                    "motion starts: torso {torso:?} pitch {:.1} roll {:.1} joints {:?}",
                    w.me.pitch_deg,
                    w.me.roll_deg,
                    w.body
                        .joint_angles
                        .iter()
                        .map(|a| a.round())
                        .collect::<Vec<_>>()
                );
            }
        }
        o.1 = b;
        (t < motion_at + 3.5).then(|| Intent {
            body: if t < motion_at + 1.8 {
                BodyIntent::Motion { id }
            } else {
                BodyIntent::Stand
            },
            ..Default::default()
        })
    };
    if trial
        .run(
            params,
            Episode {
                start,
                lying: None,
                settle_s: 0.5,
                script,
            },
        )
        .is_err()
    {
        return (0.0, 0.0, true);
    }
    let o = out.lock().unwrap();
    match (o.0, o.1) {
        (Some(s), Some(e)) => (
            (e[0] - s[0]).hypot(e[1] - s[1]),
            (e[1] - s[1]).atan2(e[0] - s[0]).to_degrees(),
            o.2,
        ),
        _ => (0.0, 0.0, o.2),
    }
}

/// `count` kicks of the kick skill from the bench's setups of `seed`: (distance, direction
/// error, fell); a kick never made counts 0 m.
fn skill_kicks(
    trial: &mut Trial,
    params: &SkillParams,
    count: usize,
    seed: u64,
) -> Vec<(f64, f64, bool)> {
    setups(count, seed, 8.0, KickDirections::AllRound)
        .into_iter()
        .map(
            |setup| match kick_once(trial, params, setup, KICK_LIMIT_S) {
                Ok(o) if o.kicked => (o.distance_m, o.direction_error_deg, o.fell),
                Ok(o) => (0.0, 0.0, o.fell),
                Err(e) => {
                    eprintln!("kick lost: {e}");
                    (0.0, 0.0, true)
                }
            },
        )
        .collect()
}

/// The cost of one candidate's kicks (distance, direction, fell): the mean distance to gain;
/// a mean direction more than 30° to the side (within that, `keyframe_aim_deg` makes it up),
/// the spread of the directions round their mean (no aim makes that up) and falls to lose.
fn kick_cost(kicks: &[(f64, f64, bool)]) -> f64 {
    let n = kicks.len().max(1) as f64;
    let mean_d = kicks.iter().map(|k| k.0).sum::<f64>() / n;
    let mean_dir = kicks.iter().map(|k| k.1).sum::<f64>() / n;
    let spread = kicks.iter().map(|k| (k.1 - mean_dir).abs()).sum::<f64>() / n;
    let falls = kicks.iter().filter(|k| k.2).count() as f64;
    -mean_d
        + 0.05 * (mean_dir.abs() - 30.0).max(0.0)
        + env_weight("SPREAD_WEIGHT", 0.05) * spread
        + 4.0 * falls / n
}

fn env_weight(key: &str, default: f64) -> f64 {
    std::env::var(key)
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(default)
}

fn main() {
    let a: Vec<String> = std::env::args().collect();
    let robot = std::env::var("ROBOT").unwrap_or_else(|_| "nao_type0".into());
    let motion = a[2].clone();
    // `-`: no knobs (with 0 generations, a probe of the file's motion as it stands).
    let spec = if a[3] == "-" {
        String::new()
    } else {
        std::fs::read_to_string(&a[3]).unwrap()
    };
    let generations: usize = a[4].parse().unwrap();
    let placements: usize = std::env::var("PLACEMENTS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(1);
    let skill_kicks_per_candidate = env_weight("SKILL_KICKS", 0.0) as usize;
    let model = Arc::new(libero_model::RobotModel::builtin(&robot).unwrap());
    let mut trials: Vec<Trial> = (0..(env_weight("TRIALS", 1.0) as usize).max(1))
        .map(|_| Trial::start_on(Arc::clone(&model)).unwrap())
        .collect();
    let base = SkillParams::load(std::path::Path::new(&a[1]), &model).unwrap();
    let mut dims = Vec::new();
    for line in spec
        .lines()
        .map(str::trim)
        .filter(|l| !l.is_empty() && !l.starts_with('#'))
    {
        let w: Vec<&str> = line.split_whitespace().collect();
        let n = |i: usize| w[i].parse::<f64>().unwrap();
        dims.push(match w[0] {
            "d" => Dim {
                knob: Knob::Duration(n(1) as usize),
                lo: n(2),
                hi: n(3),
            },
            "J" => Dim {
                knob: Knob::Joint(n(1) as usize, w[2].to_string()),
                lo: n(3),
                hi: n(4),
            },
            "ax" => Dim {
                knob: Knob::BallX,
                lo: n(1),
                hi: n(2),
            },
            "ay" => Dim {
                knob: Knob::BallY,
                lo: n(1),
                hi: n(2),
            },
            other => panic!("unknown spec line {other}"),
        });
    }
    let env = env_weight;
    let (ax0, ay0) = if skill_kicks_per_candidate > 0 {
        (
            base.kick.approach.ball_ahead_m,
            base.kick.approach.ball_beside_m,
        )
    } else {
        (env("AX", 0.12), env("AY", -0.055))
    };
    let jitter = env("JITTER", 0.0);
    // The frames searched: the long kick's in skill mode, else the named motion's.
    let frames_of = |p: &SkillParams| -> Vec<Keyframe> {
        if skill_kicks_per_candidate > 0 {
            p.kick
                .long
                .keyframes
                .clone()
                .expect("the long kick has no key frames")
        } else {
            p.motions[&motion].to_vec()
        }
    };
    let frames0 = frames_of(&base);
    // Start from the file's numbers (normalised to 0..1 in each range).
    let start: Vec<f64> = dims
        .iter()
        .map(|d| {
            let v = match &d.knob {
                Knob::Duration(f) => frames0[*f].duration_s,
                Knob::Joint(f, j) => frames0[*f]
                    .pose
                    .get(j)
                    .copied()
                    .unwrap_or((d.lo + d.hi) / 2.0),
                Knob::BallX => ax0,
                Knob::BallY => ay0,
            };
            ((v - d.lo) / (d.hi - d.lo)).clamp(0.0, 1.0)
        })
        .collect();
    let apply = |x: &[f64]| -> (SkillParams, [f64; 2]) {
        let mut frames = frames0.clone();
        let mut ball = [ax0, ay0];
        for (d, v) in dims.iter().zip(x) {
            let v = d.lo + v.clamp(0.0, 1.0) * (d.hi - d.lo);
            match &d.knob {
                Knob::Duration(f) => frames[*f].duration_s = v,
                Knob::Joint(f, j) => {
                    frames[*f].pose.insert(j.clone(), v);
                }
                Knob::BallX => ball[0] = v,
                Knob::BallY => ball[1] = v,
            }
        }
        let mut p = base.clone();
        if skill_kicks_per_candidate > 0 {
            // The skill plays the long kick's frames after its own approach.
            p.kick.long.keyframes = Some(frames);
            p.kick.approach.ball_ahead_m = ball[0];
            p.kick.approach.ball_beside_m = ball[1];
        } else {
            p.motions.insert(motion.clone(), frames);
        }
        (p, ball)
    };
    let trial = &mut trials[0];
    if generations == 0 {
        // A probe: the file's motion from each placement, nothing searched.
        let mut total = 0.0;
        for k in 0..placements {
            let turn = std::f64::consts::TAU * k as f64 / placements as f64;
            let at = [ax0 + jitter * turn.cos(), ay0 + jitter * turn.sin()];
            let (d, dir, fell) = kick(trial, &base, &motion, -3.0 + 2.0 * k as f64, at);
            println!(
                "kick {k}: ball at ({:.3}, {:.3}) moved {d:.2} m at {dir:+.1} deg{}",
                at[0],
                at[1],
                if fell { ", FELL" } else { "" }
            );
            total += d;
        }
        println!("mean {:.2} m", total / placements.max(1) as f64);
        return;
    }
    let mut es = CmaEs::new(
        start.clone(),
        env("SIGMA", 0.15),
        None,
        env("SEED", 7.0) as u64,
    );
    let mut best = (f64::INFINITY, start);
    for g in 0..generations {
        let cands = es.ask();
        // Each server judges every `trials.len()`-th candidate; costs come back in order.
        let lanes = trials.len();
        let judged: Vec<Vec<(usize, f64, String)>> = std::thread::scope(|scope| {
            let handles: Vec<_> = trials
                .iter_mut()
                .enumerate()
                .map(|(lane, trial)| {
                    let (cands, apply, motion) = (&cands, &apply, &motion);
                    scope.spawn(move || {
                        let mut out = Vec::new();
                        for (i, c) in cands.iter().enumerate().skip(lane).step_by(lanes) {
                            let (p, ball) = apply(c);
                            let kicks = if skill_kicks_per_candidate > 0 {
                                skill_kicks(trial, &p, skill_kicks_per_candidate, 1000 + g as u64)
                            } else {
                                (0..placements)
                                    .map(|k| {
                                        // With JITTER, each placement moves the ball that far
                                        // round the candidate's place (a kick that only works
                                        // at one spot is no use after a walking approach).
                                        let turn =
                                            std::f64::consts::TAU * k as f64 / placements as f64;
                                        let at = [
                                            ball[0] + jitter * turn.cos(),
                                            ball[1] + jitter * turn.sin(),
                                        ];
                                        kick(trial, &p, motion, -3.0 + 2.0 * k as f64, at)
                                    })
                                    .collect()
                            };
                            let line: String = kicks
                                .iter()
                                .map(|(d, dir, fell)| {
                                    format!(
                                        " {d:.2}m {dir:+.0}° {}",
                                        if *fell { "FELL" } else { "" }
                                    )
                                })
                                .collect();
                            out.push((i, kick_cost(&kicks), line));
                        }
                        out
                    })
                })
                .collect();
            handles.into_iter().map(|h| h.join().unwrap()).collect()
        });
        let mut costs = vec![f64::INFINITY; cands.len()];
        for (i, cost, line) in judged.into_iter().flatten() {
            eprintln!("g{g} cost {cost:.3}:{line}");
            costs[i] = cost;
            if cost < best.0 {
                best = (cost, cands[i].clone());
            }
        }
        es.tell(&cands, &costs);
        let (p, ball) = apply(&best.1);
        println!(
            "generation {g}: best cost {:.3}, ball at ({:.3}, {:.3})",
            best.0, ball[0], ball[1]
        );
        println!("{}", ron::ser::to_string(&frames_of(&p)).unwrap());
        // The search's mean: a steadier pick than the luckiest single candidate.
        let (p, ball) = apply(es.mean.as_slice());
        println!("mean {g}: ball at ({:.3}, {:.3})", ball[0], ball[1]);
        println!("{}", ron::ser::to_string(&frames_of(&p)).unwrap());
    }
}
