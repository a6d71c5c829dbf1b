//! Experiment helper: walk the bench's random course and print the samples around a time.
//! `course_probe <params.ron> <seed> <from_s> <to_s> [seconds]`
use libero_skills::SkillParams;
use libero_trial::{course::Course, Episode, Trial};

fn main() {
    let a: Vec<String> = std::env::args().collect();
    let num = |i: usize, d: f64| a.get(i).and_then(|s| s.parse().ok()).unwrap_or(d);
    let (seed, from, to, secs) = (
        num(2, 1.0) as u64,
        num(3, 0.0),
        num(4, 300.0),
        num(5, 300.0),
    );
    let mut trial = Trial::start().unwrap();
    let model = trial.model().clone();
    let params = SkillParams::load(std::path::Path::new(&a[1]), &model).unwrap();
    let w = &params.walk;
    let course = Course::random(
        secs,
        [w.max_forward_m_s, w.max_sideways_m_s, w.max_turn_deg_s],
        seed,
    );
    let rec = trial
        .run(
            &params,
            Episode {
                start: [-5.0, 0.0, 0.0],
                lying: None,
                settle_s: 1.0,
                script: course.script(),
            },
        )
        .unwrap();
    for s in rec
        .samples
        .iter()
        .filter(|s| s.t >= from && s.t <= to)
        .step_by(5)
    {
        let l = course.at(s.t);
        println!(
            "t {:6.2} cmd {:5.2} {:5.2} {:5.0} pos {:7.3} {:7.3} z {:5.3} yaw {:6.1} pitch {:5.1} roll {:5.1} {:?}",
            s.t, l.map_or(0.0, |l| l.forward_m_s), l.map_or(0.0, |l| l.sideways_m_s), l.map_or(0.0, |l| l.turn_deg_s),
            s.position[0], s.position[1], s.position[2], s.yaw_deg, s.pitch_deg, s.roll_deg, s.posture
        );
    }
    println!("first fall {:?}", rec.first_fall_s());
}
