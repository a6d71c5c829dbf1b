use super::*;

fn field() -> Field {
    Field::by_name("fifa7vs7").unwrap()
}

#[test]
fn ball_line_point_lies_towards_the_ball_and_moves_out_with_its_distance() {
    let p = GoalkeeperParams {
        min_distance_m: 0.5,
        distance_per_ball_m: 0.1,
        max_distance_m: 2.0,
        ..GoalkeeperParams::default()
    };
    // Ball straight out 10 m: 0.5 + 0.1 x 10 = 1.5 m in front of the goal centre.
    let q = p.defense_point(Own::new(-17.5, 0.0), &field());
    assert!((q.x - -26.0).abs() < 1e-9 && q.y.abs() < 1e-9, "{q:?}");
    // 30 m away: capped at 2 m.
    let q = p.defense_point(Own::new(2.5, 0.0), &field());
    assert!((q.x - -25.5).abs() < 1e-9, "{q:?}");
    // At 45 degrees, 5 m away: 1 m out along the diagonal.
    let b = Own::new(-27.5 + 5.0 / 2f64.sqrt(), 5.0 / 2f64.sqrt());
    let q = p.defense_point(b, &field());
    let s = 1.0 / 2f64.sqrt();
    assert!(
        (q.x - (-27.5 + s)).abs() < 1e-9 && (q.y - s).abs() < 1e-9,
        "{q:?}"
    );
}

#[test]
fn post_bisector_starts_from_the_point_dividing_the_mouth_by_the_post_distances() {
    let p = GoalkeeperParams {
        line: DefenseLine::PostBisector,
        min_distance_m: 0.0,
        distance_per_ball_m: 0.0,
        max_distance_m: 0.0,
        min_line_offset_m: 0.0,
        ..GoalkeeperParams::default()
    };
    // Ball level with the left post, 3 m out: distances 3 (left) and hypot(3, 3.66) (right).
    let ball = Own::new(-24.5, 1.83);
    let (dl, dr) = (3.0, 3.0f64.hypot(3.66));
    let q = p.defense_point(ball, &field());
    let expected_y = 1.83 - 3.66 * dl / (dl + dr);
    assert!(
        (q.y - expected_y).abs() < 1e-9 && (q.x + 27.5).abs() < 1e-9,
        "{q:?}"
    );
    // Straight in front the bisector is the centre line.
    let q = p.defense_point(Own::new(-20.0, 0.0), &field());
    assert!(q.y.abs() < 1e-9);
}

#[test]
fn defense_point_stays_inside_the_goal_area() {
    let p = GoalkeeperParams {
        min_distance_m: 5.0,
        max_distance_m: 10.0,
        area_margin_m: 0.5,
        ..GoalkeeperParams::default()
    };
    // Goal area: 4 m deep, 3.65 m half width.
    for ball in [
        Own::new(0.0, 0.0),
        Own::new(-27.0, 17.0),
        Own::new(-30.0, -2.0),
    ] {
        let q = p.defense_point(ball, &field());
        assert!(
            q.x <= -27.5 + 3.5 + 1e-9 && q.x >= -27.5 + 0.3 - 1e-9,
            "{ball:?} -> {q:?}"
        );
        assert!(q.y.abs() <= 3.15 + 1e-9, "{ball:?} -> {q:?}");
    }
}

#[test]
fn save_walks_when_there_is_time_blocks_at_the_body_and_dives_beside_it() {
    let p = GoalkeeperParams {
        walk_speed_m_s: 0.4,
        save_within_s: 1.2,
        block_reach_m: 0.35,
        dive_reach_m: 1.4,
        ..GoalkeeperParams::default()
    };
    // The keeper faces the field from (-26.5, 0): its left is own +y.
    let shot = |y: f64, t: f64| Shot {
        passes_at: Own::new(-26.5, y),
        offset_left_m: y,
        in_s: t,
    };
    assert_eq!(p.save(&shot(0.2, 0.8)), Save::Block);
    assert_eq!(p.save(&shot(1.0, 0.8)), Save::Dive { left: true });
    assert_eq!(p.save(&shot(-1.0, 0.8)), Save::Dive { left: false });
    // 3 s away: walk there (0.4 m/s covers 1 m in 2.5 s).
    assert_eq!(p.save(&shot(1.0, 3.0)), Save::Walk(Own::new(-26.5, 1.0)));
    // Beyond the dive's reach: only walking can help.
    assert_eq!(p.save(&shot(2.0, 0.8)), Save::Walk(Own::new(-26.5, 2.0)));
}

#[test]
fn clearing_needs_the_ball_near_and_us_first_by_the_margin() {
    let p = GoalkeeperParams {
        clear_within_m: 5.0,
        clear_margin_s: 1.0,
        ..GoalkeeperParams::default()
    };
    let near = Own::new(-24.0, 1.0);
    assert!(p.should_clear(near, &field(), Some(2.0), Some(3.5)));
    assert!(!p.should_clear(near, &field(), Some(2.0), Some(2.5)));
    assert!(p.should_clear(near, &field(), Some(2.0), None));
    assert!(!p.should_clear(Own::new(-20.0, 0.0), &field(), Some(1.0), None));
    assert!(!p.should_clear(near, &field(), None, None));
}
