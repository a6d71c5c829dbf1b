//! Several agents in one process: one thread each, joining one at a time.

use crate::player::Player;
use crate::run::{run_agent, AgentConfig, JoinGate};
use crate::stats::AgentStats;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

/// A running team.
pub struct Team {
    pub stats: Vec<(u32, Arc<AgentStats>)>,
    threads: Vec<JoinHandle<()>>,
    shutdown: Arc<AtomicBool>,
}

impl Team {
    /// Start one agent per player, each after the previous one received its first percept
    /// (joins recompile the server's model; simultaneous joins stall servers). The agents
    /// share a join gate, so after a stall that drops them all they rejoin one at a time too.
    pub fn start(config: &AgentConfig, players: Vec<Player>, shutdown: Arc<AtomicBool>) -> Team {
        let mut config = config.clone();
        if config.join_gate.is_none() {
            config.join_gate = Some(Arc::new(JoinGate::default()));
        }
        let config = &config;
        let mut team = Team {
            stats: Vec::new(),
            threads: Vec::new(),
            shutdown,
        };
        for mut player in players {
            let unum = player.world.game.unum;
            let stats = Arc::clone(player.stats());
            team.stats.push((unum, Arc::clone(&stats)));
            let config = config.clone();
            let stop = Arc::clone(&team.shutdown);
            let handle = std::thread::Builder::new()
                .name(format!("agent-{unum}"))
                .spawn(move || {
                    if let Err(e) = run_agent(&config, &mut player, &stop) {
                        log::error!("agent {unum}: {e}");
                    }
                })
                .expect("spawning an agent thread");
            team.threads.push(handle);
            let deadline = Instant::now() + Duration::from_secs(30);
            while AgentStats::get(&stats.percepts) == 0
                && Instant::now() < deadline
                && !team.shutdown.load(Ordering::Relaxed)
            {
                std::thread::sleep(Duration::from_millis(5));
            }
        }
        team
    }

    /// Ask every agent to stop and wait for them.
    pub fn stop(mut self) {
        self.shutdown.store(true, Ordering::Relaxed);
        for t in self.threads.drain(..) {
            let _ = t.join();
        }
    }

    /// Wait for the agents to end (after the shutdown flag is set elsewhere).
    pub fn join(mut self) {
        for t in self.threads.drain(..) {
            let _ = t.join();
        }
    }

    /// Whether each agent's thread has ended (uniform number, ended), without waiting: in a
    /// running match a thread ends only on a panic or an error it could not recover from.
    pub fn finished(&self) -> Vec<(u32, bool)> {
        self.stats
            .iter()
            .zip(&self.threads)
            .map(|((unum, _), t)| (*unum, t.is_finished()))
            .collect()
    }

    /// Ask every agent to stop, wait for them, and name the ones whose thread panicked.
    pub fn stop_reporting_panics(mut self) -> Vec<u32> {
        self.shutdown.store(true, Ordering::Relaxed);
        let unums: Vec<u32> = self.stats.iter().map(|(unum, _)| *unum).collect();
        unums
            .into_iter()
            .zip(self.threads.drain(..))
            .filter_map(|(unum, t)| t.join().is_err().then_some(unum))
            .collect()
    }
}

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
