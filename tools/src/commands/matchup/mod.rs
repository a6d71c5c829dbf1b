//! `libero match`: the main job — a match on a server the project installs itself, between two
//! team configurations (or one of ours and an external team), with a report of what happened.

mod observer;
mod side;

use super::setup::{ctrl_c_flag, load_robot, robot_for_unum, DataArgs, LogArgs};
use super::CliResult;
use clap::Args;
use libero_model::FieldGeometry;
use libero_server::{Rules, ServerKind, ServerOptions, ServerProcess};
use observer::{DownAndUp, Figures, Goals, Observer, Sample};
use serde::Serialize;
use side::{TeamEntry, TeamSetup};
use std::io::{IsTerminal, Write};
use std::path::PathBuf;
use std::process::ExitCode;
use std::sync::atomic::Ordering;
use std::time::{Duration, Instant};

/// Play time between the last join and the kick-off [s].
const SETTLE_BEFORE_KICK_OFF_S: f64 = 1.0;

#[derive(Args)]
pub struct MatchArgs {
    /// `rcssservermj` (T1 players, 7 a side with ssim rules) or `simspark` (NAO players of the
    /// types the team rules give each number, 11 a side on the 30 × 20 m field).
    #[arg(long, default_value = "rcssservermj")]
    pub server: ServerKind,
    /// Players per team [default: a full team].
    #[arg(long)]
    pub players: Option<u32>,
    /// Keep 20 ms cycles instead of the fast `--sync --no-realtime` mode.
    #[arg(long)]
    pub realtime: bool,
    #[arg(long, default_value = "ssim")]
    pub rules: Rules,
    /// Stop each half after this much play time [s] instead of at its end.
    #[arg(long)]
    pub duration: Option<f64>,
    /// Two halves, the teams changing sides (a second server run: rcssservermj plays one half).
    #[arg(long)]
    pub full: bool,
    /// The home team plays the first half on the right (and kicks off second).
    #[arg(long)]
    pub home_right: bool,
    /// The home team's folder: `behaviors/`, `formations/` and `<robot>.ron` skill parameters
    /// inside it, each optional [default: this repository's; `--behaviors` etc. override]
    #[arg(long, value_name = "DIR")]
    pub home: Option<PathBuf>,
    /// The away team's folder, like `--home` [default: the home team's files]
    #[arg(long, value_name = "DIR", conflicts_with = "away_cmd")]
    pub away: Option<PathBuf>,
    /// Run an external away team instead, as `CMD <host> <port>` (the RoboCup start-script
    /// convention, with `PLAYERS` and `TEAM` in its environment); its process group is
    /// stopped at the end of each half.
    #[arg(long, value_name = "CMD")]
    pub away_cmd: Option<String>,
    #[arg(long, default_value = "Libero", alias = "left")]
    pub home_name: String,
    #[arg(long, default_value = "LiberoB", alias = "right")]
    pub away_name: String,
    /// Write the summary's figures as JSON.
    #[arg(long, value_name = "FILE")]
    pub report: Option<PathBuf>,
    /// The home team's files (and, without `--away`, the away team's).
    #[command(flatten)]
    pub data: DataArgs,
    #[command(flatten)]
    pub log: LogArgs,
    #[command(flatten)]
    pub view: super::view::ViewArgs,
}

/// One half as the report shows it.
#[derive(Debug, Serialize)]
pub struct HalfReport {
    pub half: u32,
    pub left: String,
    pub right: String,
    pub score: [u32; 2],
    pub play_time_s: f64,
    pub play_on_s: f64,
    pub end_mode: String,
    pub wall_s: f64,
    /// `[left, right]`.
    pub figures: [Figures; 2],
}

/// The match: each team's figures added over the halves.
#[derive(Debug, Serialize)]
pub struct MatchReport {
    pub home: String,
    pub away: String,
    pub score: [u32; 2],
    /// Share of the play-on time each team had the ball (home, away).
    pub possession_share: [f64; 2],
    /// `[home, away]`.
    pub figures: [Figures; 2],
    pub halves: Vec<HalfReport>,
}

impl MatchArgs {
    /// A full team for the server and rules.
    fn players_per_team(&self) -> u32 {
        match self.server {
            ServerKind::RcssMj => self.rules.players_per_team(),
            ServerKind::SimSpark => 11,
        }
    }

    pub fn players(&self) -> u32 {
        self.players.unwrap_or(self.players_per_team())
    }

    /// The field the server plays on.
    fn field_name(&self) -> &'static str {
        match (self.server, self.rules) {
            (ServerKind::SimSpark, _) => "simspark",
            (ServerKind::RcssMj, Rules::Ssim) => "fifa7vs7",
            (ServerKind::RcssMj, Rules::Fifa) => "fifa",
        }
    }

    /// Play time of one half [s] (SimSpark's `RuleHalfTime` is 300 s).
    fn half_time_s(&self) -> f64 {
        match self.server {
            ServerKind::RcssMj => self.rules.half_time_s(),
            ServerKind::SimSpark => 300.0,
        }
    }
}

pub fn run(args: MatchArgs) -> CliResult {
    let full = args.players_per_team();
    if args.players() == 0 || args.players() > full {
        return Err(format!(
            "--players must be 1–{full} on this server and rules (--server, --rules)"
        )
        .into());
    }
    let home_data = match &args.home {
        Some(dir) => DataArgs::from_team_dir(dir, &args.data)?,
        None => args.data.clone(),
    };
    let home = TeamSetup::ours(&args.home_name, home_data.clone());
    let away = match (&args.away, &args.away_cmd) {
        (_, Some(cmd)) => TeamSetup::external(&args.away_name, cmd),
        (Some(dir), None) => {
            TeamSetup::ours(&args.away_name, DataArgs::from_team_dir(dir, &args.data)?)
        }
        (None, None) => TeamSetup::ours(&args.away_name, home_data.clone()),
    };
    if home.name == away.name {
        return Err("the two teams need different names (--home-name, --away-name)".into());
    }
    let field = FieldGeometry::builtin(args.field_name())?;
    let (half_length, _) = field.half_extent();
    let goals = Goals {
        half_length,
        goal_half_width: field.goal_width / 2.0,
    };
    let view = super::view::LiveView::start(&args.view, field.clone(), &home_data)?;
    let shutdown = ctrl_c_flag();
    let mut halves = Vec::new();
    let halves_to_play = if args.full { 2 } else { 1 };
    for half in 1..=halves_to_play {
        // The home team takes the left side in the first half (the right with `--home-right`),
        // the other in the second.
        let order = if (half == 1) != args.home_right {
            [&home, &away]
        } else {
            [&away, &home]
        };
        let report = play_half(&args, half, order, goals, &shutdown, view.as_ref())?;
        halves.push(report);
        if shutdown.load(Ordering::Relaxed) {
            break;
        }
    }
    let report = total(&home.name, &away.name, halves);
    print_summary(&report);
    if let Some(path) = &args.report {
        let json = serde_json::to_string_pretty(&report)?;
        std::fs::write(path, json + "\n")
            .map_err(|e| format!("cannot write the report {}: {e}", path.display()))?;
        println!("report written to {}", path.display());
    }
    Ok(ExitCode::SUCCESS)
}

fn play_half(
    args: &MatchArgs,
    half: u32,
    order: [&TeamSetup; 2],
    goals: Goals,
    shutdown: &std::sync::Arc<std::sync::atomic::AtomicBool>,
    view: Option<&super::view::LiveView>,
) -> Result<HalfReport, Box<dyn std::error::Error>> {
    if let Some(view) = view {
        view.set.clear();
    }
    println!(
        "half {half}: starting {} ({} mode)…",
        match args.server {
            ServerKind::RcssMj => "rcssservermj",
            ServerKind::SimSpark => "SimSpark rcssserver3d",
        },
        if args.realtime { "real-time" } else { "fast" }
    );
    let server = ServerProcess::start(ServerOptions {
        server: args.server,
        sync: !args.realtime,
        realtime: args.realtime,
        rules: args.rules,
        ..ServerOptions::default()
    })?;
    let mut server = server;
    let port = server.agent_port;
    let half_over = std::sync::Arc::new(std::sync::atomic::AtomicBool::new(false));
    let mut entries: Vec<TeamEntry> = Vec::new();
    for setup in order {
        // Connect one team after the other: the first team the server hears from plays left.
        let entry = setup.start(
            port,
            args.server,
            args.players(),
            &args.log,
            &half_over,
            view,
        )?;
        entry.wait_joined(Duration::from_secs(90), shutdown);
        entries.push(entry);
    }
    // Sides as the server gave them (an external team may have been slow to connect).
    let ours_left: Vec<Option<bool>> = entries.iter().map(TeamEntry::plays_left).collect();
    let left_index = match (ours_left[0], ours_left[1]) {
        (Some(false), _) | (_, Some(true)) => 1,
        _ => 0,
    };
    let names = [
        entries[left_index].name.clone(),
        entries[1 - left_index].name.clone(),
    ];
    let monitor = server.monitor();
    if let Some(view) = view {
        view.set
            .set_monitor(Some(super::view::monitor_feed(monitor, names.clone())));
    }
    // A second of play time for the beams to settle, on the server's clock: a wall-clock pause
    // left a loaded machine's robots less settled and the kick-off slower (3.96 s vs 2.28 s).
    let joined_at = monitor.snapshot().time;
    let deadline = Instant::now() + Duration::from_secs(30);
    while monitor.snapshot().time < joined_at + SETTLE_BEFORE_KICK_OFF_S
        && Instant::now() < deadline
    {
        std::thread::sleep(Duration::from_millis(5));
    }
    // The left team kicks off each half: the teams change sides, so each half's kick-off goes
    // to the other team (and `first_kick_off: "Left"` in team.ron holds for both).
    monitor.kick_off_left()?;
    println!(
        "half {half}: {} (left) v {} (right), kick-off",
        names[0], names[1]
    );
    let started = Instant::now();
    let end_time = args.duration.unwrap_or(f64::INFINITY);
    let half_length_s = args.duration.unwrap_or(args.half_time_s());
    let mut observer = Observer::new(goals, down_and_up(args.server, args.players())?);
    let mut progress = Progress::new(half_length_s);
    let mut last_frame = 0;
    let snapshot = loop {
        let s = monitor.snapshot();
        // SimSpark goes on to the second half by itself (BeforeKickOff, half 2): each half is
        // a server run of its own here, as on rcssservermj.
        let simspark_half_over = args.server == ServerKind::SimSpark && s.half > 1;
        if s.play_mode == "GameOver"
            || simspark_half_over
            || s.time >= end_time
            || shutdown.load(Ordering::Relaxed)
        {
            break s;
        }
        if s.frames != last_frame {
            last_frame = s.frames;
            if let Some(ball) = s.ball {
                observer.feed(Sample {
                    time: s.time,
                    mode: s.play_mode.clone(),
                    ball,
                    score: (s.score_left, s.score_right),
                    robots: match args.server {
                        ServerKind::RcssMj => entries.iter().flat_map(TeamEntry::robots).collect(),
                        // The monitor's scene graph, for the sides our agents play.
                        ServerKind::SimSpark => side::with_estimates(&s.robots, &entries),
                    },
                });
            }
            progress.show(&s, &names);
        }
        std::thread::sleep(Duration::from_millis(5));
    };
    progress.finish();
    let missed: Vec<u64> = entries.iter().map(TeamEntry::missed_cycles).collect();
    for entry in entries {
        entry.stop();
    }
    drop(server);
    let (mut figures, play_on_s) = observer.finish(snapshot.time);
    figures[0].missed_cycles = missed[left_index];
    figures[1].missed_cycles = missed[1 - left_index];
    // The score from the game state, not the observer's count of its changes.
    figures[0].goals = snapshot.score_left;
    figures[1].goals = snapshot.score_right;
    figures[0].set_fouls(&snapshot.fouls, true);
    figures[1].set_fouls(&snapshot.fouls, false);
    let [left, right] = names;
    Ok(HalfReport {
        half,
        left,
        right,
        score: [snapshot.score_left, snapshot.score_right],
        play_time_s: snapshot.time,
        play_on_s,
        end_mode: snapshot.play_mode,
        wall_s: started.elapsed().as_secs_f64(),
        figures,
    })
}

fn total(home: &str, away: &str, halves: Vec<HalfReport>) -> MatchReport {
    let mut figures: [Figures; 2] = Default::default();
    let mut play_on = 0.0;
    for half in &halves {
        play_on += half.play_on_s;
        for (side, name) in [&half.left, &half.right].into_iter().enumerate() {
            let team = usize::from(name != home);
            figures[team].add(&half.figures[side]);
        }
    }
    let share = |f: &Figures| {
        if play_on > 0.0 {
            f.possession_s / play_on
        } else {
            0.0
        }
    };
    MatchReport {
        home: home.to_string(),
        away: away.to_string(),
        score: [figures[0].goals, figures[1].goals],
        possession_share: [share(&figures[0]), share(&figures[1])],
        figures,
        halves,
    }
}

fn print_summary(report: &MatchReport) {
    println!();
    println!(
        "final: {} {} - {} {}",
        report.home, report.score[0], report.score[1], report.away
    );
    for half in &report.halves {
        println!(
            "  half {}: {} {} - {} {} | play time {:.1} s, ended {} | wall {:.1} s",
            half.half,
            half.left,
            half.score[0],
            half.score[1],
            half.right,
            half.play_time_s,
            half.end_mode,
            half.wall_s
        );
    }
    let width = report.home.len().max(report.away.len()).max(4);
    println!("  {:width$}  shots (on target)  possession  passes  falls (>8 s)  longest down  most down  relocated  loc. error  kick-offs taken [s]  missed cycles", "");
    for (team, (name, f)) in [&report.home, &report.away]
        .into_iter()
        .zip(&report.figures)
        .enumerate()
    {
        if !f.observed {
            println!(
                "  {name:width$}  {:>5} ({:>2})         (an external team: its robots are not observed)",
                f.shots, f.shots_on_target
            );
            continue;
        }
        let kick_offs: Vec<String> = f
            .kick_off_times_s
            .iter()
            .map(|t| format!("{t:.1}"))
            .collect();
        println!(
            "  {name:width$}  {:>5} ({:>2})         {:>5.0} %  {:>6}  {:>5} ({:>2})  {:>9.1} s  {:>7.1} %  {:>9}  {:>8}  {:>19}  {:>13}",
            f.shots,
            f.shots_on_target,
            report.possession_share[team] * 100.0,
            f.passes_completed,
            f.falls,
            f.falls_slow_to_stand,
            f.longest_down_s,
            f.most_down_share * 100.0,
            f.relocations,
            f.localization_error_m
                .map_or_else(|| "-".to_string(), |e| format!("{e:.2} m")),
            if kick_offs.is_empty() { "-".to_string() } else { kick_offs.join(" ") },
            f.missed_cycles
        );
        for (unum, at, down) in &f.slow_falls {
            // The referee's calls on that player while it lay (SimSpark: a robot lying 15 s is
            // removed to the touchline, which reads as a long lie here).
            let called: Vec<String> = f
                .recent_fouls
                .iter()
                .filter(|c| c.unum == *unum && c.time_s >= at - 1.0 && c.time_s <= at + down + 1.0)
                .map(|c| format!("{} at {:.1} s", c.kind, c.time_s))
                .collect();
            let called = if called.is_empty() {
                String::new()
            } else {
                format!(" ({})", called.join(", "))
            };
            println!("    {name} {unum} fell at {at:.1} s and lay {down:.1} s{called}");
        }
        if !f.fouls.is_empty() {
            let fouls: Vec<String> = f
                .fouls
                .iter()
                .map(|c| format!("{} {} x{}", c.unum, c.kind, c.count))
                .collect();
            println!("    {name} fouls: {}", fouls.join(", "));
        }
    }
}

/// Time, score and play mode as the half goes: a bar redrawn in place on a terminal, a line
/// every 10 s of wall time otherwise.
struct Progress {
    length_s: f64,
    terminal: bool,
    last: Instant,
}

impl Progress {
    fn new(length_s: f64) -> Self {
        Self {
            length_s,
            terminal: std::io::stdout().is_terminal(),
            last: Instant::now() - Duration::from_secs(60),
        }
    }

    fn show(&mut self, s: &libero_server::GameSnapshot, names: &[String; 2]) {
        let every = if self.terminal { 200 } else { 10_000 };
        if self.last.elapsed() < Duration::from_millis(every) {
            return;
        }
        self.last = Instant::now();
        let done = (s.time / self.length_s).clamp(0.0, 1.0);
        let filled = (done * 30.0).round() as usize;
        let line = format!(
            "[{}{}] {:6.1} s  {} {} - {} {}  {}",
            "#".repeat(filled),
            ".".repeat(30 - filled),
            s.time,
            names[0],
            s.score_left,
            s.score_right,
            names[1],
            s.play_mode
        );
        let mut out = std::io::stdout().lock();
        if self.terminal {
            let _ = write!(out, "\r{line:<90}");
            let _ = out.flush();
        } else {
            let _ = writeln!(out, "{line}");
        }
    }

    fn finish(&self) {
        if self.terminal {
            println!();
        }
    }
}

/// The torso heights the report counts falls by: from the lowest standing robot a team of
/// `players` fields on the server (SimSpark's NAO types differ by 5.5 cm).
fn down_and_up(server: ServerKind, players: u32) -> Result<DownAndUp, Box<dyn std::error::Error>> {
    let mut lowest = f64::INFINITY;
    for unum in 1..=players {
        let model = load_robot(&robot_for_unum(side::team_robot(server), unum, None), None)?;
        lowest = lowest.min(model.standing_torso_height);
    }
    Ok(DownAndUp::of_standing(lowest))
}
