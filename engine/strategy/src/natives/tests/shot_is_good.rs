use super::{shipped_library, t1_kick_skills};
use crate::shot::ShotParams;
use crate::{strategy_of, AgentHost, Natives, PlayerMemory};
use libero_behavior::{Args, Host, NativeKind};
use libero_skills::Intent;
use libero_world::{Side, World};

/// One `ShotIsGood` with the shipped files but `threshold`; the memory carries over.
fn good(world: &World, threshold: f64, memory: &mut PlayerMemory) -> bool {
    let library = shipped_library();
    let mut strategy = strategy_of(&library).clone();
    strategy.shot = Some(ShotParams {
        threshold,
        hysteresis: 0.1,
        ..strategy.shot.unwrap()
    });
    let natives = Natives::new();
    let skills = t1_kick_skills();
    let mut intent = Intent::default();
    let host = AgentHost::new(world, &strategy, &natives, &skills, memory, &mut intent);
    let id = crate::vocabulary()
        .find(NativeKind::Condition, "ShotIsGood")
        .unwrap();
    host.condition(id, Args(&[]))
}

#[test]
fn once_good_a_shot_stays_good_until_it_falls_below_the_hysteresis_band() {
    let model = libero_model::RobotModel::builtin("T1").unwrap();
    let mut world = World::new(&model, "Libero", 7);
    world.game.side = Some(Side::Left);
    world.time = 10.0;
    world.me.localized = true;
    world.me.position = [18.0, 0.0];
    world.ball.position = [19.0, 0.0];
    world.ball.last_seen_time = Some(10.0);
    let mut memory = PlayerMemory::default();
    // Find this spot's chance by the threshold it just clears.
    let chance = (0..100)
        .map(|i| f64::from(i) / 100.0)
        .rfind(|t| good(&world, *t, &mut PlayerMemory::default()))
        .unwrap();
    assert!(chance > 0.1, "an empty goal 8.5 m away: {chance}");
    // Above the threshold, then the threshold rises past the chance, within the band.
    assert!(good(&world, chance, &mut memory));
    world.time += 0.02;
    assert!(
        good(&world, chance + 0.05, &mut memory),
        "kept within the band"
    );
    // Not chosen before: the same threshold is not met.
    assert!(!good(&world, chance + 0.05, &mut PlayerMemory::default()));
    // Beyond the band it lets go, and then the plain threshold counts again.
    world.time += 0.02;
    assert!(!good(&world, chance + 0.15, &mut memory));
    world.time += 0.02;
    assert!(!good(&world, chance + 0.05, &mut memory));
}
