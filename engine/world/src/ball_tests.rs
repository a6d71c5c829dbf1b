use super::*;
use crate::params::WorldParams;

/// Observations of a launch every 0.04 s following the motion model exactly, starting from rest.
/// Timed ball observations.
type Track = Vec<(f64, Vector3<f64>)>;

fn launch(speed: f64, heading: f64) -> (BallEstimate, Track, Vector2<f64>) {
    let params = WorldParams::builtin().ball;
    let ball = BallEstimate::new(&params);
    let model = BallMotion::new(&params, 1.0, heading);
    let start = Vector2::new(-3.0, 2.0);
    let dir = Vector2::new(heading.cos(), heading.sin());
    let roll = Some(speed * model.rolling_speed_ratio);
    let launch_time = 1.013;
    let mut obs = Vec::new();
    for k in 0..300 {
        let t = 0.04 * k as f64;
        let d = model
            .advance(speed, roll, (t - launch_time).max(0.0))
            .distance;
        let p = start + dir * d;
        obs.push((t, Vector3::new(p.x, p.y, 0.11)));
    }
    let stop = start + dir * model.stop_distance(speed, roll);
    (ball, obs, stop)
}

#[test]
fn stop_point_from_the_first_third_of_a_second() {
    for &(speed, heading) in &[(1.0, 0.3), (3.5, -2.0), (8.0, 1.2)] {
        let (mut ball, obs, stop) = launch(speed, heading);
        let mut predicted = None;
        for (t, p) in &obs {
            ball.update(*t, Some(*p));
            if *t >= 1.013 + 0.3 && predicted.is_none() {
                predicted = Some(Vector2::from(ball.predicted_stop));
            }
        }
        let roll = (stop - Vector2::new(-3.0, 2.0)).norm();
        let err = (predicted.unwrap() - stop).norm();
        assert!(err < 0.03 * roll, "speed {speed}: error {err} of {roll}");
        assert!(
            ball.velocity == [0.0, 0.0],
            "at rest at the end: {:?}",
            ball.velocity
        );
        assert!((Vector2::from(ball.position) - stop).norm() < 0.02);
    }
}

#[test]
fn predictions_line_crossing_and_interception() {
    let (mut ball, obs, stop) = launch(4.0, 0.0);
    for (t, p) in obs.iter().take(40) {
        ball.update(*t, Some(*p));
    }
    let now = Vector2::from(ball.position);
    // Along +x from (−3, 2): crosses x = 0 if it gets that far.
    let crossing = ball.line_crossing([0.0, -5.0], [0.0, 1.0]);
    let (t, at) = crossing.expect("crosses x = 0");
    assert!((at[0]).abs() < 1e-9 && (at[1] - 2.0).abs() < 1e-6);
    assert!((ball.predict_position(t)[0]).abs() < 1e-6);
    assert!(ball
        .line_crossing([stop.x + 1.0, 0.0], [0.0, 1.0])
        .is_none());
    // A player standing on the path meets it there; a slow far one meets it at rest.
    let (t_meet, p_meet) = ball.interception([0.0, 2.0], 0.0, 0.1).unwrap();
    assert!((p_meet[0] + 0.1).abs() < 1e-3 && t_meet > 0.0, "{p_meet:?}");
    let (_, far) = ball.interception([stop.x, 8.0], 0.5, 0.0).unwrap();
    assert!(
        (Vector2::from(far) - stop).norm() < 0.05,
        "{far:?} vs {stop}"
    );
    assert!(now.x < stop.x);
}

#[test]
fn drag_factor_learns_from_a_slower_rollout() {
    let params = WorldParams::builtin().ball;
    let mut ball = BallEstimate::new(&params);
    // A rolling ball (no launch seen) that stops 30 % earlier than the model says.
    let heavy = BallMotion::new(&params, 1.5, 0.0);
    let mut before = None;
    for k in 0..200 {
        let t = 0.04 * k as f64;
        let d = heavy.advance(3.0, None, t).distance;
        ball.update(t, Some(Vector3::new(d, 0.0, 0.11)));
        before.get_or_insert(ball.drag_factor);
    }
    assert!(ball.drag_factor > 1.05, "{}", ball.drag_factor);
}
