use super::*;

fn field() -> Field {
    Field::by_name("fifa7vs7").unwrap()
}

fn spread(sd_deg: f64) -> KickSpread {
    KickSpread {
        direction_sd_deg: sd_deg,
        distance_m: 11.0,
        distance_sd_m: 1.0,
        diagonal_extra_m: 0.0,
    }
}

#[test]
fn phi_matches_the_normal_table() {
    assert!((phi(0.0) - 0.5).abs() < 1e-12);
    assert!((phi(1.0) - 0.841_344_7).abs() < 1e-6);
    assert!((phi(-1.96) - 0.024_997_9).abs() < 1e-6);
}

#[test]
fn empty_goal_straight_on_is_worked_by_hand() {
    let p = ShotParams::default();
    // 8 m straight out, aiming at the centre: lateral sd at the line 8 tan(2 deg) = 0.279 m;
    // inside the posts (+-1.83 m) is P(|z| < 6.55) ~ 1; distance: P(11 +- 1 m > 8 m) = phi(3).
    let ball = Own::new(19.5, 0.0);
    let target = Own::new(27.5, 0.0);
    let pr = p.probability(ball, target, &field(), &spread(2.0), &Defenders::default());
    assert!((pr - phi(3.0)).abs() < 1e-6, "{pr}");
    // Aimed at 1.53 m (0.3 inside the post): P(e < 0.30 m) for sd 8 tan 2 deg / cos(aim).
    let target = Own::new(27.5, 1.53);
    let d = ball.distance(target);
    let sd = d * 2f64.to_radians().tan() / ((27.5 - 19.5) / d);
    let expected = phi(3.0 - (d - 8.0)) * (phi((1.83 - 1.53) / sd) - phi((-1.83 - 1.53) / sd));
    let pr = p.probability(ball, target, &field(), &spread(2.0), &Defenders::default());
    assert!((pr - expected).abs() < 1e-6, "{pr} vs {expected}");
}

#[test]
fn keeper_in_the_middle_sends_the_best_shot_to_a_corner() {
    let p = ShotParams::default();
    let ball = Own::new(19.5, 0.0);
    let keeper = Defenders {
        keeper: Some(Own::new(27.0, 0.0)),
        field_players: Default::default(),
    };
    let best = p.best(ball, &field(), &spread(2.0), &keeper);
    assert!(best.target.y.abs() > 1.0, "{best:?}");
    // Straight at the keeper: its reach covers the ball's whole spread.
    let centre = p.probability(ball, Own::new(27.5, 0.0), &field(), &spread(2.0), &keeper);
    assert!(centre < 0.05, "{centre}");
    // A keeper standing at the left post leaves the right side open.
    let left_keeper = Defenders {
        keeper: Some(Own::new(27.0, 1.5)),
        field_players: Default::default(),
    };
    let best = p.best(ball, &field(), &spread(2.0), &left_keeper);
    assert!(best.target.y < 0.0 && best.probability > 0.9, "{best:?}");
    let at_keeper = p.probability(
        ball,
        Own::new(27.5, 1.53),
        &field(),
        &spread(2.0),
        &left_keeper,
    );
    assert!(at_keeper < 0.1, "{at_keeper}");
}

#[test]
fn a_defender_on_the_line_blocks_and_out_of_range_is_zero() {
    let p = ShotParams::default();
    let ball = Own::new(19.5, 0.0);
    let target = Own::new(27.5, 0.0);
    let wall = Defenders {
        keeper: None,
        field_players: [Own::new(23.0, 0.0)].into_iter().collect(),
    };
    let blocked = p.probability(ball, target, &field(), &spread(2.0), &wall);
    assert!(blocked < 0.05, "{blocked}");
    // Too far (16 m > max 14 m) or behind the ball.
    let far = p.probability(
        Own::new(11.5, 0.0),
        target,
        &field(),
        &spread(2.0),
        &Defenders::default(),
    );
    assert_eq!(far, 0.0);
    // A wider kick spread lowers the chance into a corner.
    let corner = Own::new(27.5, 1.53);
    let tight = p.probability(ball, corner, &field(), &spread(2.0), &Defenders::default());
    let wide = p.probability(ball, corner, &field(), &spread(8.0), &Defenders::default());
    assert!(wide < tight - 0.2, "{tight} {wide}");
}

#[test]
fn the_keeper_moves_only_after_its_reaction_time_worked_by_hand() {
    // Ball 8 m out, keeper on the line 0.5 m in front of the goal, 0.9 m to the side of the
    // shot line. The ball needs 7.5 m / 4 m/s = 1.875 s to the keeper's line.
    let ball = Own::new(19.5, 0.0);
    let target = Own::new(27.5, 0.0);
    let keeper = Defenders {
        keeper: Some(Own::new(27.0, 0.9)),
        field_players: Default::default(),
    };
    let sd = 7.5 * 2f64.to_radians().tan();
    let chance = |p: &ShotParams| {
        let reach = p.keeper_reach_m + p.keeper_speed_m_s * (1.875 - p.keeper_reaction_s).max(0.0);
        let stopped = phi((0.9 + reach) / sd) - phi((0.9 - reach) / sd);
        phi(3.0) * (1.0 - stopped)
    };
    for p in [
        ShotParams::default(),
        ShotParams {
            keeper_reaction_s: 0.0,
            keeper_speed_m_s: 0.6,
            ..ShotParams::default()
        },
    ] {
        let pr = p.probability(ball, target, &field(), &spread(2.0), &keeper);
        assert!((pr - chance(&p)).abs() < 1e-6, "{pr} vs {}", chance(&p));
    }
    // Reach 0.5 + 0.25 * 1.375 = 0.84 m < 0.9 m: mostly past; 0.5 + 0.6 * 1.875 = 1.63 m: saved.
    let default = ShotParams::default().probability(ball, target, &field(), &spread(2.0), &keeper);
    assert!(default > 0.5, "{default}");
    let quick = ShotParams {
        keeper_reaction_s: 0.0,
        keeper_speed_m_s: 0.6,
        ..ShotParams::default()
    };
    assert!(quick.probability(ball, target, &field(), &spread(2.0), &keeper) < 0.1);
}

#[test]
fn a_shot_off_the_field_axes_is_expected_to_roll_farther() {
    let p = ShotParams::default();
    // 11.5 m from the far post's target, 27 deg off the x axis: along an axis the 11 +- 1 m
    // kick reaches it about a third of the time; 2.9 m more on a diagonal (sin^2(54 deg) of it
    // here, +1.9 m) makes it likely.
    let ball = Own::new(17.3, -5.2);
    let target = Own::new(27.5, 0.0);
    let along_axis = p.probability(ball, target, &field(), &spread(2.0), &Defenders::default());
    let diagonal = KickSpread {
        diagonal_extra_m: 2.9,
        ..spread(2.0)
    };
    let with_curve = p.probability(ball, target, &field(), &diagonal, &Defenders::default());
    let rolls = diagonal.distance_along(target.x - ball.x, target.y - ball.y);
    assert!((rolls - 11.0 - 2.9 * (2.0 * 27.0_f64.to_radians()).sin().powi(2)).abs() < 0.05);
    assert!(along_axis < 0.4, "{along_axis}");
    assert!(with_curve > 0.85, "{with_curve}");
    // Straight along the axis the term adds nothing.
    let straight = Own::new(17.3, 0.0);
    assert_eq!(
        p.probability(straight, target, &field(), &diagonal, &Defenders::default()),
        p.probability(
            straight,
            target,
            &field(),
            &spread(2.0),
            &Defenders::default()
        )
    );
}
