//! SimSpark's heterogeneous NAO types in a team: the server's rules for a team's mix, and the
//! mix a team plays when its team file names none.

/// SimSpark heterogeneous robot types for a team of `n` (uniform numbers 1…n), meeting the
/// server's rules: at most 7 of a type, any two types together at most 9, so a full team has
/// at least 3 types.
pub fn simspark_team_types(n: usize) -> Vec<u8> {
    // Goalkeeper and most field players on type 0; the rest spread over the other types.
    const ORDER: [u8; 11] = [0, 0, 0, 0, 0, 1, 2, 0, 3, 4, 0];
    ORDER.iter().copied().cycle().take(n).collect()
}

/// Whether a team's robot types satisfy SimSpark's rules (`MaxRobotTypeCount` 7,
/// `MaxSumTwoRobotTypes` 9, `MinRobotTypesCount` 3 for a full team of 11).
pub fn check_simspark_types(types: &[u8]) -> Result<(), String> {
    let mut count = [0usize; 5];
    for &t in types {
        *count
            .get_mut(t as usize)
            .ok_or(format!("robot type {t} does not exist (0–4)"))? += 1;
    }
    if let Some(t) = count.iter().position(|&c| c > 7) {
        return Err(format!("{} robots of type {t}: at most 7", count[t]));
    }
    for a in 0..5 {
        for b in a + 1..5 {
            if count[a] + count[b] > 9 {
                return Err(format!(
                    "types {a} and {b} together: {}, at most 9",
                    count[a] + count[b]
                ));
            }
        }
    }
    if types.len() > 11 {
        return Err("more than 11 players".into());
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn simspark_compositions_follow_the_rules_for_every_team_size() {
        for n in 1..=11 {
            let types = simspark_team_types(n);
            assert_eq!(types.len(), n);
            check_simspark_types(&types).unwrap_or_else(|e| panic!("{n}: {e}"));
        }
        let full = simspark_team_types(11);
        let distinct = (0..5u8).filter(|t| full.contains(t)).count();
        assert!(distinct >= 3);
    }

    #[test]
    fn rule_violations_are_reported() {
        assert!(check_simspark_types(&[0; 8])
            .unwrap_err()
            .contains("at most 7"));
        assert!(check_simspark_types(&[0, 0, 0, 0, 0, 0, 0, 1, 1, 1])
            .unwrap_err()
            .contains("at most 9"));
        assert!(check_simspark_types(&[5]).is_err());
    }
}
