//! Locomotion on the real rcssservermj (fast `--sync --no-realtime` mode), shortened for CI.
//!
//! The full measurements are `libero bench walk`. The bars sit below what the current walk
//! parameters reach (forward 0.56 m/s, sideways 0.21–0.22 m/s, turning 52°/s in 5 consecutive
//! `libero bench walk` runs, 3 of them `--short`), so a regression fails but run-to-run scatter
//! does not.

use libero_model::RobotModel;
use libero_skills::SkillParams;
use libero_trial::{bench, Trial};

fn setup() -> (Trial, SkillParams) {
    let _ = env_logger::builder().is_test(true).try_init();
    let trial = Trial::start().expect("server starts");
    let model = RobotModel::builtin("T1").unwrap();
    let params = SkillParams::builtin(&model).unwrap();
    (trial, params)
}

#[test]
fn walks_forward_for_ten_seconds_without_falling() {
    let (mut trial, params) = setup();
    let f = bench::forward(&mut trial, &params, 10.0, 10.0).unwrap();
    eprintln!(
        "forward {:.3} m/s over {:.1} s, fell at {:?}",
        f.speed, f.seconds, f.fell_at
    );
    assert_eq!(f.fell_at, None);
    assert!(f.speed >= 0.5, "forward {:.3} m/s", f.speed);
}

#[test]
fn walks_sideways_and_turns_on_the_spot_without_falling() {
    let (mut trial, params) = setup();
    let s = bench::sideways(&mut trial, &params, 10.0).unwrap();
    eprintln!("sideways {:.3} m/s, fell at {:?}", s.speed, s.fell_at);
    assert_eq!(s.fell_at, None);
    assert!(s.speed >= 0.19, "sideways {:.3} m/s", s.speed);
    let t = bench::turning(&mut trial, &params, 10.0).unwrap();
    eprintln!("turn {:.1} deg/s, fell at {:?}", t.speed, t.fell_at);
    assert_eq!(t.fell_at, None);
    assert!(t.speed >= 45.0, "turn {:.1} deg/s", t.speed);
}
