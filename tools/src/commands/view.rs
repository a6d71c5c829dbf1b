//! The field view from the command line: `--view [ADDR]` / `--edit` on the commands that run
//! agents, and `libero view LOG…` to replay evaluation logs.

use super::setup::DataArgs;
use super::CliResult;
use clap::Args;
use libero_agent::{LibrarySource, Player};
use libero_model::FieldGeometry;
use libero_view::{EditTarget, LiveSet, Replay, Source, ViewOptions, ViewServer};
use std::net::SocketAddr;
use std::path::PathBuf;
use std::process::ExitCode;
use std::sync::atomic::Ordering;
use std::sync::Arc;

/// The field a team's files are for (`team.ron`), as a view draws it.
pub fn field_of(source: &LibrarySource) -> FieldGeometry {
    libero_strategy::strategy_of(&source.current())
        .field()
        .geometry()
        .clone()
}

/// Where the page is served when `--view` names no address.
const DEFAULT_VIEW_ADDRESS: &str = "127.0.0.1:0";

#[derive(clap::Args, Clone, Debug, Default)]
pub struct ViewArgs {
    /// Serve the live field view in the browser at ADDR [default: 127.0.0.1 on a free port;
    /// the URL is printed at start]
    #[arg(long, value_name = "ADDR", num_args = 0..=1, default_missing_value = DEFAULT_VIEW_ADDRESS)]
    pub view: Option<SocketAddr>,
    /// Let the view's formation editor write the team's formation files (edits need the
    /// run's token, which the printed URL carries).
    #[arg(long, requires = "view")]
    pub edit: bool,
}

/// A running live view and the set its agents show themselves in.
pub struct LiveView {
    pub set: Arc<LiveSet>,
    /// Serves while the view lives.
    _server: ViewServer,
}

impl LiveView {
    /// Start the view when `--view` was given. `data` names the team whose formations the
    /// editor may write.
    pub fn start(
        args: &ViewArgs,
        field: FieldGeometry,
        data: &DataArgs,
    ) -> Result<Option<LiveView>, Box<dyn std::error::Error>> {
        let Some(address) = args.view else {
            return Ok(None);
        };
        let edit = args.edit.then(|| {
            let [behaviors, formations] = data.folders();
            EditTarget {
                library_dirs: vec![behaviors, formations.clone()],
                formations,
            }
        });
        let set = Arc::new(LiveSet::default());
        let server = ViewServer::start(
            ViewOptions {
                address,
                field,
                edit,
            },
            Source::Live(Arc::clone(&set)),
        )?;
        println!("field view: {}", server.url(args.edit));
        if args.edit {
            println!("field view: formation edits on (the token in the URL allows them)");
        }
        Ok(Some(LiveView {
            set,
            _server: server,
        }))
    }

    /// Show `player` in the view.
    pub fn show(&self, player: &mut Player) {
        player.show_in(self.set.add_agent());
    }

    /// Show a team's reloads.
    pub fn watch_library(&self, team: &str, source: &LibrarySource) {
        if let LibrarySource::Live(library) = source {
            self.set.add_library(team, Arc::clone(library));
        }
    }
}

/// A scenario series shown in the view: every robot of both sides, and the monitor.
impl libero_scenario::Watcher for LiveView {
    fn player(&self, _team: &str, player: &mut Player) {
        self.show(player);
    }

    fn monitor(&self, monitor: &libero_server::Monitor) {
        self.set.set_monitor(Some(monitor_feed(
            monitor,
            [
                libero_scenario::OUR_TEAM.to_string(),
                libero_scenario::THEIR_TEAM.to_string(),
            ],
        )));
    }
}

/// The view's reading of a server's monitor, with the team names left and right.
pub fn monitor_feed(
    monitor: &libero_server::Monitor,
    teams: [String; 2],
) -> libero_view::MonitorFeed {
    let read = monitor.reader();
    Arc::new(move || {
        let s = read();
        Some(libero_view::MonitorView {
            time: s.time,
            half: s.half,
            score: [s.score_left, s.score_right],
            play_mode: s.play_mode,
            ball: s.ball,
            teams: teams.clone(),
        })
    })
}

#[derive(Args)]
pub struct ViewCommandArgs {
    /// Evaluation logs to replay together (one per agent of a match: `--log FILE --trace`
    /// writes them).
    #[arg(required = true, value_name = "LOG")]
    pub logs: Vec<PathBuf>,
    /// Where to serve the page [default: 127.0.0.1 on a free port]
    #[arg(long, value_name = "ADDR", default_value = DEFAULT_VIEW_ADDRESS)]
    pub view: SocketAddr,
    /// The field the logs were played on.
    #[arg(long, default_value = "fifa7vs7")]
    pub field: String,
}

/// `libero view LOG…`: serve a replay until Ctrl-C.
pub fn run(args: ViewCommandArgs) -> CliResult {
    let replay = Replay::open(&args.logs)?;
    let field = FieldGeometry::builtin(&args.field)?;
    let steps = replay.len();
    let server = ViewServer::start(
        ViewOptions {
            address: args.view,
            field,
            edit: None,
        },
        Source::Replay(replay),
    )?;
    println!(
        "field view: {} ({} logs, {steps} steps); Ctrl-C stops it",
        server.url(false),
        args.logs.len()
    );
    let stop = super::setup::ctrl_c_flag();
    while !stop.load(Ordering::Relaxed) {
        std::thread::sleep(std::time::Duration::from_millis(100));
    }
    drop(server);
    Ok(ExitCode::SUCCESS)
}
