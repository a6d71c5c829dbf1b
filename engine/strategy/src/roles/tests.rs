use super::*;

fn candidates(points: &[(u8, f64, f64)]) -> Vec<Candidate> {
    points
        .iter()
        .map(|&(unum, x, y)| Candidate {
            unum,
            at: Own::new(x, y),
        })
        .collect()
}

fn slots(points: &[(u8, f64, f64)]) -> Vec<Slot> {
    points
        .iter()
        .map(|&(default_unum, x, y)| Slot {
            default_unum,
            at: Own::new(x, y),
        })
        .collect()
}

#[test]
fn players_take_the_positions_nearest_them_overall() {
    // Player 2 stands where 3's slot is and vice versa: they swap rather than cross the field.
    let c = candidates(&[(2, 0.0, 10.0), (3, 0.0, -10.0), (4, 5.0, 0.0)]);
    let s = slots(&[(2, 0.0, -9.0), (3, 0.0, 9.0), (4, 6.0, 0.0)]);
    assert_eq!(assign(&c, &s).as_deref(), Some(&[1, 0, 2][..]));
    // The sum of squares is least, not each player greedily: player 4 is nearest the slot at
    // (1, 0) but leaving it to player 2 saves more overall.
    let c = candidates(&[(2, 0.0, 0.0), (4, 2.0, 0.0)]);
    let s = slots(&[(2, 1.0, 0.0), (4, 10.0, 0.0)]);
    assert_eq!(assign(&c, &s).as_deref(), Some(&[0, 1][..]));
}

#[test]
fn unequal_counts_give_no_assignment() {
    let c = candidates(&[(2, 0.0, 0.0)]);
    let s = slots(&[(2, 1.0, 0.0), (3, 2.0, 0.0)]);
    assert_eq!(assign(&c, &s), None);
    let mut roles = RoleAssignment::default();
    assert_eq!(roles.update(&c, &s, 1.0), &[(2, 2)]);
}

#[test]
fn a_near_tie_does_not_flip_the_roles_back_and_forth() {
    let s = slots(&[(2, -1.0, 0.0), (3, 1.0, 0.0)]);
    let mut roles = RoleAssignment::default();
    // Both at the middle, player 2 slightly left: 2 takes the left slot.
    let first = roles
        .update(&candidates(&[(2, -0.05, 0.0), (3, 0.05, 0.0)]), &s, 1.0)
        .to_vec();
    assert_eq!(first, vec![(2, 2), (3, 3)]);
    // They wobble past each other by a few centimetres: nothing changes.
    for wobble in [0.05, -0.05, 0.1, -0.1] {
        let held = roles
            .update(&candidates(&[(2, wobble, 0.0), (3, -wobble, 0.0)]), &s, 1.0)
            .to_vec();
        assert_eq!(held, first, "wobble {wobble}");
    }
    // Clearly swapped sides: the roles follow.
    let swapped = roles
        .update(&candidates(&[(2, 1.0, 0.0), (3, -1.0, 0.0)]), &s, 1.0)
        .to_vec();
    assert_eq!(swapped, vec![(2, 3), (3, 2)]);
    assert_eq!(roles.slot_of(2), Some(3));
}

proptest::proptest! {
    /// The stack-only Hungarian method finds an optimum as good as a general-purpose solver's
    /// (the assignments may differ on ties; the total cost may not).
    #[test]
    fn the_assignment_is_optimal(
        points in proptest::collection::vec((-30.0f64..30.0, -20.0f64..20.0, -30.0f64..30.0, -20.0f64..20.0), 1..=MAX_PLAYERS)
    ) {
        let c: Vec<Candidate> = points
            .iter()
            .enumerate()
            .map(|(i, p)| Candidate { unum: i as u8 + 2, at: Own::new(p.0, p.1) })
            .collect();
        let s: Vec<Slot> = points
            .iter()
            .enumerate()
            .map(|(i, p)| Slot { default_unum: i as u8 + 2, at: Own::new(p.2, p.3) })
            .collect();
        let ours = assign(&c, &s).unwrap();
        let mut sorted = ours.clone();
        sorted.sort_unstable();
        proptest::prop_assert!(sorted.iter().copied().eq(0..c.len()), "a permutation: {:?}", ours);
        let weights = pathfinding::prelude::Matrix::from_fn(c.len(), s.len(), |(i, j)| cost(c[i].at, s[j].at));
        let (best, _) = pathfinding::prelude::kuhn_munkres_min(&weights);
        proptest::prop_assert_eq!(total_cost(&c, &s, &ours), best);
    }
}
