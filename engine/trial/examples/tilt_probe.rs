//! Experiment helper: walk a changing course and compare the agent's roll/pitch estimate and
//! its ball-relative estimate with ground truth.
//! `cargo run --release -p libero-trial --example tilt_probe`
use libero_skills::{BodyIntent, Intent, SkillParams};
use libero_trial::{Episode, Trial};
use nalgebra::UnitQuaternion;
use std::sync::{Arc, Mutex};

fn main() {
    let mut trial = Trial::start().unwrap();
    let params = SkillParams::builtin(trial.model()).unwrap();
    let errors = Arc::new(Mutex::new(Vec::<[f64; 2]>::new()));
    let e = Arc::clone(&errors);
    let script = move |world: &libero_world::World, t: f64| {
        if t > 20.0 {
            return None;
        }
        if let Some([w, x, y, z]) = world.truth.torso_orientation {
            let (roll, pitch, _) =
                UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(w, x, y, z))
                    .euler_angles();
            if t > 1.0 {
                e.lock().unwrap().push([
                    world.me.roll_deg - roll.to_degrees(),
                    world.me.pitch_deg - pitch.to_degrees(),
                ]);
            }
        }
        let (f, s, r) = match (t / 5.0) as u32 {
            0 => (0.45, 0.0, 0.0),
            1 => (0.0, 0.18, 0.0),
            2 => (0.3, -0.1, 20.0),
            _ => (0.0, 0.0, 50.0),
        };
        Some(Intent {
            body: BodyIntent::Walk {
                forward_m_s: f,
                sideways_m_s: s,
                turn_deg_s: r,
            },
            ..Default::default()
        })
    };
    trial
        .run(
            &params,
            Episode {
                start: [-10.0, 0.0, 0.0],
                lying: None,
                settle_s: 1.0,
                script,
            },
        )
        .unwrap();
    let errors = errors.lock().unwrap();
    let per_phase = errors.len() / 4;
    for phase in 0..4 {
        let part = &errors[phase * per_phase..(phase + 1) * per_phase];
        let max = |axis: usize| part.iter().map(|e| e[axis].abs()).fold(0.0, f64::max);
        let mean = |axis: usize| part.iter().map(|e| e[axis]).sum::<f64>() / part.len() as f64;
        println!(
            "phase {phase}: roll mean {:+.2} max {:.2}, pitch mean {:+.2} max {:.2}",
            mean(0),
            max(0),
            mean(1),
            max(1)
        );
    }
    for (axis, name) in [(0, "roll"), (1, "pitch")] {
        let mut v: Vec<f64> = errors.iter().map(|e| e[axis].abs()).collect();
        v.sort_by(f64::total_cmp);
        let q = |f: f64| v[((v.len() - 1) as f64 * f) as usize];
        println!(
            "{name} error over {} cycles: median {:.2} deg, p95 {:.2} deg, max {:.2} deg",
            v.len(),
            q(0.5),
            q(0.95),
            q(1.0)
        );
    }
}
