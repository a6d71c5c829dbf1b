use super::*;

/// The error a parameter text is refused with.
fn refused(name: &str, text: &str, model: &RobotModel) -> String {
    SkillParams::from_ron(name, text, model)
        .unwrap_err()
        .to_string()
}

#[test]
fn builtin_t1_parameters_load() {
    let t1 = RobotModel::builtin("T1").unwrap();
    let p = SkillParams::builtin(&t1).unwrap();
    let pose = p.stand_pose(&t1).unwrap();
    assert_eq!(pose[t1.joint_id("left_knee").unwrap()], 24.0);
}

#[test]
fn walk_gains_must_name_joints_on_both_legs_of_the_model() {
    let t1 = RobotModel::builtin("T1").unwrap();
    let shipped = include_str!("../../params/t1.ron");
    let text = shipped.replacen("\"hip_yaw\": Gains", "\"hip_yaw_pitch\": Gains", 1);
    assert_ne!(text, shipped);
    let e = refused("t1.ron", &text, &t1);
    assert!(
        e.contains("`hip_yaw_pitch` is not a leg joint of T1"),
        "{e}"
    );
}

#[test]
fn unknown_joints_and_out_of_range_angles_are_rejected() {
    let t1 = RobotModel::builtin("T1").unwrap();
    let shipped = include_str!("../../params/t1.ron");
    let text = shipped.replacen("\"left_knee\": 24.0", "\"left_kne\": 1.0", 1);
    let e = refused("x.ron", &text, &t1);
    assert!(e.contains("`left_kne` is not a joint"), "{e}");
    let text = shipped.replacen("\"left_knee\": 24.0", "\"left_knee\": -5.0", 1);
    let e = refused("x.ron", &text, &t1);
    assert!(e.contains("outside its limits"), "{e}");
    let at = shipped.find("step_period_s: ").unwrap() + "step_period_s: ".len();
    let end = at + shipped[at..].find(',').unwrap();
    let text = format!("{}5.0{}", &shipped[..at], &shipped[end..]);
    let e = refused("x.ron", &text, &t1);
    assert!(e.starts_with("x.ron:"), "{e}");
    assert!(e.contains("walk.step_period_s = 5 is outside"), "{e}");
}

/// A misspelt optional field is an error, not silently the default (an old binary read a file
/// with `kick_by_type` in it without a word).
#[test]
fn unknown_fields_are_named_with_their_place() {
    let t1 = RobotModel::builtin("T1").unwrap();
    let shipped = include_str!("../../params/t1.ron");
    let text = shipped.replacen("step_period_s: ", "step_perod_s: 0.3, step_period_s: ", 1);
    let e = refused("x.ron", &text, &t1);
    let line = 1 + shipped[..shipped.find("step_period_s: ").unwrap()]
        .matches('\n')
        .count();
    assert!(e.starts_with(&format!("x.ron:{line}:")), "{e}");
    assert!(e.contains("step_perod_s"), "{e}");
    let nao = RobotModel::builtin("nao_type3").unwrap();
    let shipped = include_str!("../../params/nao.ron");
    let text = shipped.replacen("kick_by_type:", "kick_by_typ:", 1);
    let e = refused("nao.ron", &text, &nao);
    assert!(e.contains("kick_by_typ"), "{e}");
}

#[test]
fn out_of_range_walk_numbers_name_their_field() {
    let t1 = RobotModel::builtin("T1").unwrap();
    let mut p = SkillParams::builtin(&t1).unwrap();
    p.walk.step_period_s = 5.0;
    let e = p.validate(&t1).unwrap_err().to_string();
    assert!(e.contains("walk.step_period_s = 5 is outside"), "{e}");
}

#[test]
fn out_of_range_kick_numbers_name_their_field() {
    let t1 = RobotModel::builtin("T1").unwrap();
    let mut p = SkillParams::builtin(&t1).unwrap();
    p.kick.long.swing_s = 0.0;
    let e = p.validate(&t1).unwrap_err().to_string();
    assert!(e.contains("kick.long.swing_s = 0 is outside"), "{e}");
    let mut p = SkillParams::builtin(&t1).unwrap();
    p.kick.approach.clearance_m = 0.5;
    p.kick.approach.circle_radius_m = 0.6;
    let e = p.validate(&t1).unwrap_err().to_string();
    assert!(e.contains("kick.approach.clearance_m"), "{e}");
    let shipped = include_str!("../../params/t1.ron");
    let text = shipped.replacen(
        "\"hip_pitch\": Gains(kp: 1200.0",
        "\"hip_pich\": Gains(kp: 1200.0",
        1,
    );
    assert_ne!(text, shipped);
    let e = refused("t1.ron", &text, &t1);
    assert!(
        e.contains("swing_gains: `hip_pich` is not a leg joint"),
        "{e}"
    );
}

#[test]
fn parameters_survive_a_round_trip_through_ron() {
    let t1 = RobotModel::builtin("T1").unwrap();
    let p = SkillParams::builtin(&t1).unwrap();
    let again = SkillParams::from_ron("again.ron", &p.to_ron(), &t1).unwrap();
    assert_eq!(p, again);
}

#[test]
fn a_type_with_its_own_kick_plays_it_and_the_others_play_the_common_one() {
    let text = include_str!("../../params/nao.ron");
    let model = |t: u8| RobotModel::builtin(&format!("NAO_type{t}")).unwrap();
    let family = SkillParams::from_ron_for_family("nao.ron", text, &model(0)).unwrap();
    assert!(!family.kick_by_type.is_empty());
    for t in 0..5 {
        let played = family.for_type(&model(t)).kick;
        let Some(own) = family.kick_by_type.get(&t) else {
            assert_eq!(played, family.kick, "type {t}");
            continue;
        };
        if let Some(long) = &own.long {
            assert_eq!(&played.long, long, "type {t}");
            assert_ne!(
                long, &family.kick.long,
                "type {t}'s long kick is the common one"
            );
        }
        let short = own.short.as_ref().unwrap_or(&family.kick.short);
        assert_eq!(&played.short, short, "type {t}");
        let ahead = own
            .ball_ahead_m
            .unwrap_or(family.kick.approach.ball_ahead_m);
        assert_eq!(played.approach.ball_ahead_m, ahead, "type {t}");
        assert_eq!(
            played.measured,
            own.measured.unwrap_or(family.kick.measured),
            "type {t}"
        );
    }
    // A type's kick that breaks a rule is refused by name.
    let at = text
        .find("ball_ahead_m: Some(")
        .expect("a type's own kicking place");
    let end = at + text[at..].find(')').unwrap();
    let broken = format!("{}ball_ahead_m: Some(5.0{}", &text[..at], &text[end..]);
    let e = SkillParams::from_ron_for_family("nao.ron", &broken, &model(0))
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("kick_by_type 3") && e.contains("ball_ahead_m"),
        "{e}"
    );
}

#[test]
fn a_type_with_its_own_get_up_plays_it_and_the_others_play_the_common_one() {
    let text = include_str!("../../params/nao.ron");
    let shipped = |t: u8| {
        let nao = RobotModel::builtin(&format!("NAO_type{t}")).unwrap();
        SkillParams::from_ron("nao.ron", text, &nao).unwrap()
    };
    let common = shipped(0);
    assert!(!common.get_up_by_type.contains_key(&0));
    for &t in common.get_up_by_type.keys() {
        let theirs = shipped(t).get_up;
        let [front, back] = motions_of_type(&common.get_up_by_type, t).unwrap();
        assert!(front.is_some() || back.is_some(), "type {t}");
        for (mine, common_one, played) in [
            (front, &common.get_up.front, &theirs.front),
            (back, &common.get_up.back, &theirs.back),
        ] {
            assert_eq!(played, mine.unwrap_or(common_one), "type {t}");
            if let Some(mine) = mine {
                assert_ne!(mine, common_one, "type {t}'s motion is the common one");
            }
        }
    }
    // A side named after another type plays that type's own motion.
    assert_eq!(shipped(1).get_up.front, shipped(3).get_up.front);
    assert_eq!(shipped(3).get_up.back, shipped(4).get_up.back);
    for t in (0..5).filter(|t| !common.get_up_by_type.contains_key(t)) {
        assert_eq!(shipped(t).get_up, common.get_up, "type {t}");
    }
    // A broken type's get-up is refused by name, whatever the robot's own type.
    let broken = text.replacen(
        "get_up_by_type: {",
        "get_up_by_type: { 9: (back: Some([])),",
        1,
    );
    let nao = RobotModel::builtin("NAO_type0").unwrap();
    let e = refused("nao.ron", &broken, &nao);
    assert!(e.contains("get_up_by_type 9"), "{e}");
    // A side named after a type without a motion of its own there is refused by name.
    for (entry, says) in [
        (
            "9: (front_of_type: Some(2)),",
            "get_up_by_type 9.front_of_type: type 2",
        ),
        (
            "9: (back_of_type: Some(3)),",
            "get_up_by_type 9.back_of_type: type 3",
        ),
        (
            "9: (front: Some([]), front_of_type: Some(3)),",
            "both `front` and `front_of_type`",
        ),
    ] {
        let broken = text.replacen(
            "get_up_by_type: {",
            &format!("get_up_by_type: {{ {entry}"),
            1,
        );
        let e = refused("nao.ron", &broken, &nao);
        assert!(e.contains(says), "{entry}: {e}");
    }
}

#[test]
fn every_nao_type_has_parameters() {
    for t in 0..5 {
        let nao = RobotModel::builtin(&format!("NAO_type{t}")).unwrap();
        let params = SkillParams::builtin(&nao).unwrap_or_else(|e| panic!("type {t}: {e}"));
        let pose = params.stand_pose(&nao).unwrap();
        assert_eq!(pose[nao.joint_id("left_knee").unwrap()], -40.0);
        crate::Skills::new(&nao, params).unwrap_or_else(|e| panic!("type {t}: {e}"));
    }
}
