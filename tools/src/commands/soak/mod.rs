//! `libero soak`: the hardening match of issue #13 — a long stretch of play with an edit to
//! the team's files every few seconds (good and broken, alternately), judged on memory, the
//! agents' connections, missed cycles and panics.
//!
//! One fast-mode server; our team (tree players, hot reload on, from a private copy of the
//! shipped `behaviors/` and `formations/`, see [`edits`]) plays left and kicks off; the away
//! side is the standing team. rcssservermj 0.2.1 ends play for good at the end of a half (its
//! referee sets `GameOver` on every step past the half's end; the monitor's `playMode` command
//! does nothing), so the soak plays under the FIFA rule book (one 2700 s half) on the 7-a-side
//! field: the same field and referee as a match, only the half is longer.

mod edits;
mod report;

use super::behavior::Format;
use super::setup::{build_player, ctrl_c_flag, load_robot, proc_status_mb};
use super::CliResult;
use clap::Args;
use edits::Editor;
use libero_agent::{build, AgentConfig, AgentStats, LibrarySource, SkillSource, Team};
use libero_server::{Rules, ServerOptions, ServerProcess};
use report::{AgentFigures, SoakReport};
use std::process::ExitCode;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

/// The rule book and field the soak plays under (see the module's comment).
const RULES: Rules = Rules::Fifa;
const FIELD: &str = "fifa7vs7";
/// Play time kept clear of the half's end [s], so the referee never ends the soak.
const HALF_END_MARGIN_S: f64 = 60.0;
/// Wall time without any progress of play time after which the soak gives up [s].
const STALL_LIMIT: Duration = Duration::from_secs(60);

const HOME: &str = "Libero";
const AWAY: &str = "Standing";

#[derive(Args)]
pub struct SoakArgs {
    /// Play time [min] (at most 44: one 45-minute half).
    #[arg(long, default_value_t = 30.0)]
    pub minutes: f64,
    /// Play time between edits [s]; the edits alternate good and broken.
    #[arg(long, default_value_t = 10.0)]
    pub edit_every: f64,
    /// Players of our team (1–7).
    #[arg(long, default_value_t = 7)]
    pub players: u32,
    /// Players of the standing team on the other side (0–7) [default: as many as ours].
    #[arg(long)]
    pub away_players: Option<u32>,
    /// Play time at which the baseline RSS is read [s]; the end's RSS is compared with it.
    #[arg(long, default_value_t = 60.0)]
    pub rss_baseline_at: f64,
    /// `json` prints one document with every figure.
    #[arg(long, value_enum, default_value = "text")]
    pub format: Format,
}

/// What to soak, checked.
#[derive(Debug, Clone, PartialEq)]
pub struct SoakOptions {
    pub play_s: f64,
    pub edit_every_s: f64,
    pub players: u32,
    pub away_players: u32,
    pub rss_baseline_at_s: f64,
}

impl SoakArgs {
    pub fn options(&self) -> Result<SoakOptions, String> {
        let longest_s = RULES.half_time_s() - HALF_END_MARGIN_S;
        let play_s = self.minutes * 60.0;
        if !(play_s > 0.0 && play_s <= longest_s) {
            return Err(format!(
                "--minutes must be above 0 and at most {:.0} (the server plays one {:.0}-minute half)",
                longest_s / 60.0,
                RULES.half_time_s() / 60.0
            ));
        }
        if !(self.edit_every >= 1.0 && self.edit_every.is_finite()) {
            return Err(
                "--edit-every must be at least 1 s of play (an edit and its restore take two reloads)"
                    .into(),
            );
        }
        let away_players = self.away_players.unwrap_or(self.players);
        if !(1..=7).contains(&self.players) || away_players > 7 {
            return Err("--players must be 1–7 and --away-players 0–7 (7 a side)".into());
        }
        if !(self.rss_baseline_at >= 0.0 && self.rss_baseline_at < play_s) {
            return Err(format!(
                "--rss-baseline-at must lie within the play time (0 to {play_s:.0} s)"
            ));
        }
        Ok(SoakOptions {
            play_s,
            edit_every_s: self.edit_every,
            players: self.players,
            away_players,
            rss_baseline_at_s: self.rss_baseline_at,
        })
    }
}

pub fn run(args: SoakArgs) -> CliResult {
    let options = args.options()?;
    let report = soak(&options)?;
    match args.format {
        Format::Text => println!("{}", report.text()),
        Format::Json => println!("{}", serde_json::to_string_pretty(&report)?),
    }
    Ok(if report.passed {
        ExitCode::SUCCESS
    } else {
        ExitCode::FAILURE
    })
}

/// Resident memory of this process now [MB].
fn rss_mb() -> f64 {
    proc_status_mb("VmRSS").unwrap_or(f64::NAN)
}

/// Run the soak: start the server and both teams, play `options.play_s` with the edits, and
/// report. Errors only when it cannot start; everything after kick-off goes into the report.
pub fn soak(options: &SoakOptions) -> Result<SoakReport, Box<dyn std::error::Error>> {
    let started = Instant::now();
    let interrupted = ctrl_c_flag();
    let data = tempfile::Builder::new().prefix("libero-soak-").tempdir()?;
    let shipped = build::default_data_dirs();
    let (mut editor, dirs) = Editor::copy_data(data.path(), &shipped[0], &shipped[1])?;
    let source = build::load_library(&dirs, true)?;
    let LibrarySource::Live(live) = &source else {
        return Err("the soak needs the watched library".into());
    };
    let model = load_robot("T1", None)?;
    let skills = watched_skill_params(data.path(), &model)?;
    let mut server = ServerProcess::start(ServerOptions {
        rules: RULES,
        field: Some(FIELD),
        ..ServerOptions::default()
    })?;
    let ours = (1..=options.players)
        .map(|unum| build_player(&model, HOME, unum, &source, &skills))
        .collect::<Result<Vec<_>, _>>()?;
    let theirs = (1..=options.away_players)
        .map(|unum| build::standing_player(&model, AWAY, unum))
        .collect::<Result<Vec<_>, _>>()?;
    eprintln!(
        "soak: {} of ours v {} standing, {:.0} s of play, an edit every {} s; joining…",
        options.players, options.away_players, options.play_s, options.edit_every_s
    );
    let config = AgentConfig::new("127.0.0.1", server.agent_port);
    let stop_agents = Arc::new(AtomicBool::new(false));
    // Ours first: the first team to join plays left, and the left team kicks off.
    let home = Team::start(&config, ours, Arc::clone(&stop_agents));
    let away = (!theirs.is_empty()).then(|| Team::start(&config, theirs, Arc::clone(&stop_agents)));
    let our_stats: Vec<Arc<AgentStats>> = home.stats.iter().map(|(_, s)| Arc::clone(s)).collect();
    std::thread::sleep(Duration::from_millis(500));
    server.monitor().kick_off_left()?;
    let kick_off = server
        .monitor()
        .wait_for(Duration::from_secs(10), |s| s.play_mode != "BeforeKickOff")
        .ok_or("the kick-off was not taken by the server within 10 s")?
        .time;
    eprintln!("soak: kick-off at {kick_off:.1} s of play");

    let end = kick_off + options.play_s;
    let mut next_edit = kick_off + options.edit_every_s;
    let mut next_minute = kick_off + 60.0;
    let mut rss_baseline = None;
    let mut rss_by_minute = Vec::new();
    let mut progress = (kick_off, Instant::now());
    let mut reported_ended: Vec<u32> = Vec::new();
    let ended = loop {
        let s = server.monitor().snapshot();
        // Before the end check, so the last minute's sample is taken too.
        if s.time >= next_minute {
            rss_by_minute.push(rss_mb());
            eprintln!(
                "soak: minute {} of {:.0}, {:.0} s of wall time, {} edits, RSS {:.1} MB",
                rss_by_minute.len(),
                options.play_s / 60.0,
                started.elapsed().as_secs_f64(),
                editor.counts.good_written + editor.counts.broken_written,
                rss_mb()
            );
            next_minute += 60.0;
        }
        if s.time >= end {
            break "full".to_string();
        }
        if s.play_mode == "GameOver" {
            break format!("the referee ended play at {:.1} s", s.time);
        }
        if interrupted.load(Ordering::Relaxed) {
            break "interrupted".to_string();
        }
        if s.time > progress.0 {
            progress = (s.time, Instant::now());
        } else if progress.1.elapsed() > STALL_LIMIT {
            break format!(
                "play time stalled at {:.1} s for {} s",
                s.time,
                STALL_LIMIT.as_secs()
            );
        }
        if !server.is_running() {
            break format!("the server stopped at {:.1} s", s.time);
        }
        if rss_baseline.is_none() && s.time >= kick_off + options.rss_baseline_at_s {
            rss_baseline = Some(rss_mb());
        }
        for (unum, ended) in home.finished() {
            if ended && !reported_ended.contains(&unum) {
                log::error!(
                    "soak: agent {unum}'s thread ended at {:.1} s of play",
                    s.time
                );
                reported_ended.push(unum);
            }
        }
        if s.time >= next_edit {
            editor.edit_and_restore(live, &our_stats);
            next_edit += options.edit_every_s;
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    let play_time_s = server.monitor().snapshot().time - kick_off;
    let rss_end_mb = rss_mb();
    let rss_peak_mb = proc_status_mb("VmHWM").unwrap_or(f64::NAN);
    let mut agents = figures(HOME, &home);
    if let Some(away) = &away {
        agents.extend(figures(AWAY, away));
    }
    mark_answering(&mut agents, &home, away.as_ref());
    let mut panicked: Vec<(&str, u32)> = home
        .stop_reporting_panics()
        .into_iter()
        .map(|unum| (HOME, unum))
        .collect();
    if let Some(away) = away {
        panicked.extend(
            away.stop_reporting_panics()
                .into_iter()
                .map(|unum| (AWAY, unum)),
        );
    }
    for agent in &mut agents {
        agent.panicked = panicked.contains(&(agent.team.as_str(), agent.unum));
    }
    drop(server);
    // The watchers stop before their folders go.
    drop(source);
    drop(skills);
    drop(data);
    let mut report = SoakReport {
        planned_play_s: options.play_s,
        play_time_s,
        wall_time_s: started.elapsed().as_secs_f64(),
        ended,
        edit_every_s: options.edit_every_s,
        edits: editor.counts.clone(),
        rss_baseline_at_s: options.rss_baseline_at_s,
        rss_baseline_mb: rss_baseline,
        rss_end_mb,
        rss_growth_mb: rss_baseline.map(|b| rss_end_mb - b),
        rss_peak_mb,
        rss_by_minute_mb: rss_by_minute,
        missed_cycles: agents.iter().map(|a| a.missed_cycles).sum(),
        unreadable: agents.iter().map(|a| a.unreadable).sum(),
        agents,
        failures: Vec::new(),
        passed: false,
    };
    report.judge();
    Ok(report)
}

/// A copy of the shipped skill parameters, watched like a match's (never edited: the soak's
/// edits are to the trees and strategy files); the built-in ones outside a checkout.
fn watched_skill_params(
    root: &std::path::Path,
    model: &libero_model::RobotModel,
) -> Result<SkillSource, Box<dyn std::error::Error>> {
    let shipped = build::default_skill_params_file(model);
    if !shipped.is_file() {
        return Ok(SkillSource::Builtin);
    }
    // A folder of its own, so the edits' temporary files never wake its watcher.
    let dir = root.join("params");
    std::fs::create_dir_all(&dir)?;
    let copy = dir.join(shipped.file_name().unwrap_or_default());
    std::fs::copy(&shipped, &copy)?;
    Ok(SkillSource::from_file(&copy, model, true)?)
}

/// Each agent's counters (`answering_at_end` and `panicked` are filled in later).
fn figures(team: &str, running: &Team) -> Vec<AgentFigures> {
    running
        .stats
        .iter()
        .map(|(unum, s)| AgentFigures {
            team: team.to_string(),
            unum: *unum,
            connections: AgentStats::get(&s.connections),
            missed_cycles: AgentStats::get(&s.missed_cycles),
            unreadable: AgentStats::get(&s.unreadable),
            percepts: AgentStats::get(&s.percepts),
            answering_at_end: false,
            panicked: false,
        })
        .collect()
}

/// Whether each agent still answers: its reply count moves on within 2 s of wall time (a
/// fast-mode server steps every few milliseconds).
fn mark_answering(agents: &mut [AgentFigures], home: &Team, away: Option<&Team>) {
    let stats: Vec<&Arc<AgentStats>> = home
        .stats
        .iter()
        .chain(away.into_iter().flat_map(|t| t.stats.iter()))
        .map(|(_, s)| s)
        .collect();
    let before: Vec<u64> = stats.iter().map(|s| AgentStats::get(&s.replies)).collect();
    let deadline = Instant::now() + Duration::from_secs(2);
    loop {
        let moved: Vec<bool> = stats
            .iter()
            .zip(&before)
            .map(|(s, &b)| AgentStats::get(&s.replies) > b)
            .collect();
        if moved.iter().all(|&m| m) || Instant::now() > deadline {
            for (agent, m) in agents.iter_mut().zip(moved) {
                agent.answering_at_end = m;
            }
            return;
        }
        std::thread::sleep(Duration::from_millis(10));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn args(minutes: f64, edit_every: f64, players: u32, away: Option<u32>) -> SoakArgs {
        SoakArgs {
            minutes,
            edit_every,
            players,
            away_players: away,
            rss_baseline_at: 60.0,
            format: Format::Text,
        }
    }

    #[test]
    fn options_are_checked_with_clear_errors() {
        let ok = args(30.0, 10.0, 7, None).options().unwrap();
        assert_eq!((ok.play_s, ok.players, ok.away_players), (1800.0, 7, 7));
        assert_eq!(
            args(2.0, 5.0, 3, Some(0)).options().unwrap().away_players,
            0
        );
        for (bad, expected) in [
            (args(50.0, 10.0, 7, None), "--minutes"),
            (args(0.0, 10.0, 7, None), "--minutes"),
            (args(f64::NAN, 10.0, 7, None), "--minutes"),
            (args(30.0, 0.5, 7, None), "--edit-every"),
            (args(30.0, f64::INFINITY, 7, None), "--edit-every"),
            (args(30.0, 10.0, 0, None), "--players"),
            (args(30.0, 10.0, 8, None), "--players"),
            (args(30.0, 10.0, 7, Some(9)), "--away-players"),
            (args(0.5, 10.0, 7, None), "--rss-baseline-at"),
        ] {
            let err = bad.options().unwrap_err();
            assert!(err.contains(expected), "{expected}: {err}");
        }
    }
}
