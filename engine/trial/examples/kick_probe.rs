//! Experiment helper: kicks from the kicking place (or from around the ball) and their outcome.
//! `cargo run --release -p libero-trial --example kick_probe -- <count> <distance_m> [params.ron]`
//! `CI_SIDES=1`: the live test's three approaches, repeated. `AROUND=1`: seeded setups from all round the ball (as `libero bench kick`); `SEED=n`;
//! `PLACE=1`: seeded setups at the kicking place within the approach's tolerances; with
//! either, `SHOTS=1`: directions within 25 deg of the +x axis, as shots go;
//! `BACK=d`: the robot d metres behind the kicking place; `ONLY=i,j`: only those setups. `ROBOT=nao_typeN`: a NAO on SimSpark.
use libero_skills::SkillParams;
use libero_trial::kick_bench::{
    kick_once, setups, setups_at_place, KickDirections, KickSetup, KickSummary,
};
use libero_trial::Trial;

fn main() {
    env_logger::init();
    let a: Vec<String> = std::env::args().collect();
    let count: usize = a.get(1).and_then(|s| s.parse().ok()).unwrap_or(3);
    let distance: f64 = a.get(2).and_then(|s| s.parse().ok()).unwrap_or(8.0);
    // ROBOT=nao_type0 kicks a NAO on SimSpark (default: the T1).
    let robot = std::env::var("ROBOT").unwrap_or_else(|_| "T1".into());
    let mut trial = Trial::start_on(std::sync::Arc::new(
        libero_model::RobotModel::builtin(&robot).unwrap(),
    ))
    .unwrap();
    let model = trial.model().clone();
    let params = match a.get(3) {
        Some(p) => SkillParams::load(std::path::Path::new(p), &model).unwrap(),
        None => SkillParams::builtin(&model).unwrap(),
    };
    let seed = std::env::var("SEED")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(1);
    // `SHOTS=1`: directions within 25 deg of the +x axis, as shots go.
    let directions = if std::env::var("SHOTS").is_ok() {
        KickDirections::Shots
    } else {
        KickDirections::AllRound
    };
    let list: Vec<KickSetup> = if std::env::var("AROUND").is_ok() {
        setups(count, seed, distance, directions)
    } else if std::env::var("PLACE").is_ok() {
        setups_at_place(count, seed, distance, &params.kick.approach, directions)
    } else if std::env::var("CI_SIDES").is_ok() {
        // The three approaches of the live test `long_kicks_from_three_sides_...`.
        let s = |robot: [f64; 3], ball: [f64; 2], direction_deg: f64| KickSetup {
            robot,
            ball,
            direction_deg,
            distance_m: distance,
        };
        [
            s([-6.0, 0.8, 0.0], [-5.0, 0.0], 0.0),
            s([0.0, -3.0, -90.0], [0.0, -1.5], 90.0),
            s([2.0, 2.0, 180.0], [3.0, 1.0], -135.0),
        ]
        .into_iter()
        .cycle()
        .take(count)
        .collect()
    } else {
        let ap = &params.kick.approach;
        let side = if std::env::var("RIGHT").is_ok() {
            -1.0
        } else {
            1.0
        };
        let heading: f64 = std::env::var("HEADING")
            .ok()
            .and_then(|s| s.parse().ok())
            .unwrap_or(0.0);
        let (c, s) = (heading.to_radians().cos(), heading.to_radians().sin());
        // `BACK=d`: the robot starts d metres behind its kicking place (an approach's last part).
        let back: f64 = std::env::var("BACK")
            .ok()
            .and_then(|s| s.parse().ok())
            .unwrap_or(0.0);
        (0..count)
            .map(|i| {
                let y = -2.0 + i as f64;
                let (ax, ay) = (ap.ball_ahead_m, side * ap.ball_beside_m);
                KickSetup {
                    robot: [-5.0 - back * c, y - back * s, heading],
                    ball: [-5.0 + ax * c - ay * s, y + ax * s + ay * c],
                    direction_deg: heading,
                    distance_m: distance,
                }
            })
            .collect()
    };
    // `ONLY=3,7`: just these setups of the list.
    let only: Option<Vec<usize>> = std::env::var("ONLY")
        .ok()
        .map(|v| v.split(',').filter_map(|i| i.trim().parse().ok()).collect());
    let list: Vec<KickSetup> = list
        .into_iter()
        .enumerate()
        .filter(|(i, _)| only.as_ref().is_none_or(|o| o.contains(i)))
        .map(|(_, s)| s)
        .collect();
    let mut outcomes = Vec::new();
    for s in list {
        let o = kick_once(&mut trial, &params, s, 40.0).unwrap();
        let c = o.contact.map_or(String::from("no contact"), |c| {
            format!(
                "{} foot yaw {:+.1}° swing {:+.1}° at {:.1} m/s, torso yaw {:+.1}°, ball in foot ({:+.3}, {:+.3}, {:+.3}) feet at start {:+.3?}",
                if c.left { "left" } else { "right" },
                c.foot_yaw_deg - s.direction_deg,
                c.swing_deg - s.direction_deg,
                c.toe_speed_m_s,
                c.torso_yaw_deg - s.direction_deg,
                c.ball_in_foot[0],
                c.ball_in_foot[1],
                c.ball_in_foot[2],
                c.start_feet
            )
        });
        println!(
            "towards {:+6.1}° {:5.2} m {:+6.1}° (launch {:+5.1}°, {:+5.2} m off at {:.1} m) kicked {} after {:4.1} s bumped {} fell {} | {c}",
            s.direction_deg,
            o.distance_m,
            o.direction_error_deg,
            o.launch_error_deg.unwrap_or(f64::NAN),
            o.miss_at_distance_m.unwrap_or(f64::NAN),
            s.distance_m,
            o.kicked,
            o.time_to_kick_s.unwrap_or(f64::NAN),
            o.bumped,
            o.fell
        );
        outcomes.push(o);
    }
    println!("{:?}", KickSummary::of(&outcomes));
}
