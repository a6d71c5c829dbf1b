use super::*;

fn field() -> Field {
    Field::by_name("fifa7vs7").unwrap()
}

fn robot(x: f64, y: f64) -> Obstacle {
    Obstacle {
        at: Own::new(x, y),
        radius: 0.65,
    }
}

/// A collision is two torsos within 0.45 m; the planner keeps 0.65 m, less what a grid path
/// (0.2 m cells) cuts off at a corner.
const SAFE_M: f64 = 0.5;

/// Walks a point robot along the planner's waypoints; the closest it came to each obstacle.
fn walk(obstacles: &[Obstacle], from: Own, to: Own) -> (bool, f64) {
    let params = AvoidanceParams::default();
    let mut planner = Planner::default();
    let mut me = from;
    let mut closest = f64::INFINITY;
    for cycle in 0..5_000 {
        let w = planner.next_waypoint(&params, &field(), me, to, obstacles, cycle as f64 * 0.02);
        let step = w - me;
        let n = step.norm();
        if n < 1e-9 {
            break;
        }
        me = me + step.scaled(0.02_f64.min(n) / n);
        for o in obstacles {
            closest = closest.min(me.distance(o.at));
        }
        if me.distance(to) < 0.05 {
            return (true, closest);
        }
    }
    (false, closest)
}

#[test]
fn clear_way_goes_straight() {
    let params = AvoidanceParams::default();
    let mut planner = Planner::default();
    let to = Own::new(5.0, 0.0);
    let w = planner.next_waypoint(
        &params,
        &field(),
        Own::default(),
        to,
        &[robot(2.0, 2.0)],
        0.0,
    );
    assert_eq!(w, to);
}

#[test]
fn one_robot_in_the_corridor_is_passed_beside_it() {
    let (arrived, closest) = walk(&[robot(2.5, 0.05)], Own::default(), Own::new(5.0, 0.0));
    assert!(arrived);
    assert!(closest >= SAFE_M, "came within {closest:.2} m");
}

#[test]
fn a_wall_of_three_is_passed_round_its_end() {
    let wall = [robot(2.5, -0.5), robot(2.5, 0.0), robot(2.5, 0.5)];
    let (arrived, closest) = walk(&wall, Own::default(), Own::new(5.0, 0.0));
    assert!(arrived);
    assert!(closest >= SAFE_M, "came within {closest:.2} m");
}

#[test]
fn a_cup_that_blocks_every_detour_is_left_by_the_grid_path() {
    let mut cup: Vec<Obstacle> = [-1.0, -0.5, 0.0, 0.5, 1.0]
        .iter()
        .map(|y| robot(3.0, *y))
        .collect();
    cup.extend([robot(2.5, 1.3), robot(2.5, -1.3)]);
    let params = AvoidanceParams::default();
    let mut planner = Planner::default();
    let (from, to) = (Own::new(1.5, 0.0), Own::new(6.0, 0.0));
    let near = effective(&cup, from);
    assert!(
        planner.detour(&params, from, to, &near).is_none(),
        "no detour is clear"
    );
    assert!(plan_path(&params, &field(), from, to, &cup).is_some());
    let (arrived, closest) = walk(&cup, from, to);
    assert!(arrived);
    assert!(closest >= SAFE_M, "came within {closest:.2} m");
}

#[test]
fn no_path_through_a_closed_ring_falls_back_to_the_target() {
    let ring: Vec<Obstacle> = (0..16)
        .map(|i| {
            let a = f64::from(i) * std::f64::consts::TAU / 16.0;
            robot(5.0 + 1.2 * a.cos(), 1.2 * a.sin())
        })
        .collect();
    let params = AvoidanceParams::default();
    assert!(plan_path(&params, &field(), Own::default(), Own::new(5.0, 0.0), &ring).is_none());
}

#[test]
fn a_robot_inside_an_obstacle_can_walk_out() {
    let (arrived, _) = walk(&[robot(0.2, 0.0)], Own::default(), Own::new(-3.0, 0.0));
    assert!(arrived);
}
