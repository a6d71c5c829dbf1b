//! Experiment helper: a named key-frame motion played beside a ball.
//! `motion_kick_probe <params.ron> <motion> [count]`; AX, AY: the ball's place in the robot
//! frame [m]; ROBOT (default nao_type0). Prints the ball's travel and whether the robot fell.
use libero_skills::{BodyIntent, Intent, SkillParams};
use libero_trial::{Episode, Trial};
use std::sync::{Arc, Mutex};

/// The ball when the kick began and now, and the lowest torso height.
type Progress = (Option<[f64; 3]>, Option<[f64; 3]>, f64);

fn main() {
    let a: Vec<String> = std::env::args().collect();
    let robot = std::env::var("ROBOT").unwrap_or_else(|_| "nao_type0".into());
    let env = |k: &str, d: f64| {
        std::env::var(k)
            .ok()
            .and_then(|s| s.parse().ok())
            .unwrap_or(d)
    };
    let (ax, ay) = (env("AX", 0.15), env("AY", -0.05));
    let count: usize = a.get(3).and_then(|s| s.parse().ok()).unwrap_or(3);
    let mut trial =
        Trial::start_on(Arc::new(libero_model::RobotModel::builtin(&robot).unwrap())).unwrap();
    let model = trial.model().clone();
    let params = SkillParams::load(std::path::Path::new(&a[1]), &model).unwrap();
    let id = params.motion_id(&a[2]).expect("no such motion");
    let ball_z = libero_model::FieldGeometry::builtin(model.server.default_field())
        .unwrap()
        .ball_radius;
    let mut dists = vec![];
    for k in 0..count {
        let y = -3.0 + k as f64 * 1.5;
        let start = [-5.0, y, 0.0];
        let ball = [start[0] + ax, y + ay];
        let monitor = trial.monitor();
        let out: Arc<Mutex<Progress>> = Arc::new(Mutex::new((None, None, 9.0)));
        let shared = Arc::clone(&out);
        let place = format!("(ball (pos {} {} {ball_z})(vel 0 0 0))", ball[0], ball[1]);
        let mut placed = false;
        let script = move |w: &libero_world::World, t: f64| -> Option<Intent> {
            let mut m = monitor.lock().ok()?;
            if !placed && t > 0.3 {
                let _ = m.send(&place);
                placed = true;
            }
            let b = m.snapshot().ball;
            drop(m);
            let mut o = shared.lock().ok()?;
            if let Some(z) = w.truth.torso_position.map(|p| p[2]) {
                o.2 = o.2.min(z);
            }
            if t < 2.0 {
                return Some(Intent::default());
            }
            if o.0.is_none() {
                o.0 = b;
            }
            o.1 = b;
            (t < 7.0).then(|| Intent {
                body: if t < 4.0 {
                    BodyIntent::Motion { id }
                } else {
                    BodyIntent::Stand
                },
                ..Default::default()
            })
        };
        let _ = trial
            .run(
                &params,
                Episode {
                    start,
                    lying: None,
                    settle_s: 0.5,
                    script,
                },
            )
            .unwrap();
        let o = out.lock().unwrap();
        let d = match (o.0, o.1) {
            (Some(s), Some(e)) => (
                (e[0] - s[0]).hypot(e[1] - s[1]),
                (e[1] - s[1]).atan2(e[0] - s[0]).to_degrees(),
            ),
            _ => (f64::NAN, f64::NAN),
        };
        println!(
            "kick {k}: ball moved {:.2} m at {:+.1} deg, lowest torso {:.3} m",
            d.0, d.1, o.2
        );
        dists.push(d.0);
    }
    println!(
        "mean {:.2} m",
        dists.iter().sum::<f64>() / dists.len() as f64
    );
}
