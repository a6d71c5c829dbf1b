//! The field view: one web page, served by the program itself, that draws what the agents
//! believe and decide — live from running agents ([`ViewSlot`]s) or replayed from evaluation
//! logs — and edits formation files when allowed.
//!
//! Cost to the agents: each copies its view into its slot at most every 40 ms (a lock and a
//! copy); everything else (JSON, sockets, browsers) runs on the view's own threads. A browser
//! that does not keep up is dropped, never waited for.

pub mod edit;
mod http;
pub mod replay;
mod stream;

pub use edit::{EditTarget, FormationDoc};
pub use replay::Replay;

use libero_agent::ViewSlot;
use libero_behavior::LiveLibrary;
use libero_model::FieldGeometry;
use serde::Serialize;
use std::net::SocketAddr;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};

/// The game as the server's monitor sees it (ground truth; for the view only).
#[derive(Debug, Clone, Default, Serialize)]
pub struct MonitorView {
    pub time: f64,
    pub half: u32,
    pub score: [u32; 2],
    pub play_mode: String,
    pub ball: Option<[f64; 3]>,
    /// Team names, left and right, when known.
    pub teams: [String; 2],
}

/// Something that reads the monitor when asked (the match runner's connection).
pub type MonitorFeed = Arc<dyn Fn() -> Option<MonitorView> + Send + Sync>;

/// Running agents as the view sees them: their slots, the monitor when there is one, and the
/// libraries they run (for the reload panel). A match runner replaces them at each half.
#[derive(Default)]
pub struct LiveSet {
    agents: Mutex<Vec<Arc<ViewSlot>>>,
    monitor: Mutex<Option<MonitorFeed>>,
    libraries: Mutex<Vec<(String, Arc<LiveLibrary>)>>,
}

impl LiveSet {
    /// A new slot for an agent, shown from now on.
    pub fn add_agent(&self) -> Arc<ViewSlot> {
        let slot = ViewSlot::new(ViewSlot::DEFAULT_PERIOD);
        if let Ok(mut agents) = self.agents.lock() {
            agents.push(Arc::clone(&slot));
        }
        slot
    }

    /// Show a team's library reloads.
    pub fn add_library(&self, team: &str, library: Arc<LiveLibrary>) {
        if let Ok(mut libraries) = self.libraries.lock() {
            libraries.push((team.to_string(), library));
        }
    }

    pub fn set_monitor(&self, feed: Option<MonitorFeed>) {
        if let Ok(mut monitor) = self.monitor.lock() {
            *monitor = feed;
        }
    }

    /// Forget the agents and libraries (a new half brings new ones).
    pub fn clear(&self) {
        if let Ok(mut agents) = self.agents.lock() {
            agents.clear();
        }
        if let Ok(mut libraries) = self.libraries.lock() {
            libraries.clear();
        }
        self.set_monitor(None);
    }

    /// The slots shown now.
    pub fn agents(&self) -> Vec<Arc<ViewSlot>> {
        self.agents.lock().map(|a| a.clone()).unwrap_or_default()
    }

    /// The slot showing this agent.
    pub(crate) fn slot_of(&self, team: &str, unum: u32) -> Option<Arc<ViewSlot>> {
        self.agents
            .lock()
            .ok()?
            .iter()
            .find(|s| s.is(team, unum))
            .cloned()
    }

    pub(crate) fn libraries(&self) -> Vec<(String, Arc<LiveLibrary>)> {
        self.libraries.lock().map(|l| l.clone()).unwrap_or_default()
    }

    pub(crate) fn monitor(&self) -> Option<MonitorView> {
        let feed = self.monitor.lock().ok()?.clone()?;
        feed()
    }
}

/// What the view shows.
pub enum Source {
    Live(Arc<LiveSet>),
    /// Evaluation logs.
    Replay(Replay),
}

/// How to serve the view.
pub struct ViewOptions {
    /// Where to listen (port 0: a free one).
    pub address: SocketAddr,
    pub field: FieldGeometry,
    /// Formation editing, when allowed (`--edit`).
    pub edit: Option<EditTarget>,
}

/// A running view server; stopped when dropped.
pub struct ViewServer {
    pub address: SocketAddr,
    /// The per-run secret that edits must carry.
    pub token: String,
    stop: Arc<AtomicBool>,
    threads: Vec<std::thread::JoinHandle<()>>,
}

impl ViewServer {
    /// Listen and serve. A non-loopback address is allowed but warned about loudly.
    pub fn start(options: ViewOptions, source: Source) -> Result<ViewServer, String> {
        if !options.address.ip().is_loopback() {
            log::warn!(
                "THE FIELD VIEW LISTENS ON {} — NOT LOOPBACK: anyone who can reach this address can watch{}",
                options.address,
                if options.edit.is_some() { " (edits still need the token)" } else { "" }
            );
        }
        let server = tiny_http::Server::http(options.address)
            .map_err(|e| format!("field view: cannot listen on {}: {e}", options.address))?;
        let address = server
            .server_addr()
            .to_ip()
            .ok_or("field view: not an IP address")?;
        let token = new_token()?;
        let stop = Arc::new(AtomicBool::new(false));
        let clients = stream::Clients::default();
        let shared = Arc::new(http::Shared {
            address,
            token: token.clone(),
            field: options.field,
            edit: options.edit,
            source,
            clients: clients.clone(),
            reloads: stream::Reloads::default(),
        });
        let mut threads = Vec::new();
        if matches!(shared.source, Source::Live(_)) {
            let (shared, stop) = (Arc::clone(&shared), Arc::clone(&stop));
            threads.push(
                std::thread::Builder::new()
                    .name("view-stream".into())
                    .spawn(move || stream::broadcast(&shared, &stop))
                    .map_err(|e| e.to_string())?,
            );
        }
        let server = Arc::new(server);
        {
            let (shared, stop, server) =
                (Arc::clone(&shared), Arc::clone(&stop), Arc::clone(&server));
            threads.push(
                std::thread::Builder::new()
                    .name("view-http".into())
                    .spawn(move || http::serve(&server, &shared, &stop))
                    .map_err(|e| e.to_string())?,
            );
        }
        Ok(ViewServer {
            address,
            token,
            stop,
            threads,
        })
    }

    /// The page's address, with the token when edits are on (what to open in a browser).
    pub fn url(&self, with_token: bool) -> String {
        if with_token {
            format!("http://{}/?token={}", self.address, self.token)
        } else {
            format!("http://{}/", self.address)
        }
    }
}

impl Drop for ViewServer {
    fn drop(&mut self) {
        self.stop.store(true, Ordering::Relaxed);
        // The HTTP loop wakes every 100 ms to look at the flag.
        for t in self.threads.drain(..) {
            let _ = t.join();
        }
    }
}

/// 128 random bits as hex.
fn new_token() -> Result<String, String> {
    let mut bytes = [0u8; 16];
    getrandom::fill(&mut bytes).map_err(|e| format!("no randomness for the edit token: {e}"))?;
    Ok(bytes.iter().map(|b| format!("{b:02x}")).collect())
}

/// A viewer without a browser: reads the live stream on a thread of its own and counts what
/// arrives (for benchmarks and tests of the stream's cost).
pub struct StreamCounter {
    pub frames: Arc<std::sync::atomic::AtomicU64>,
    pub bytes: Arc<std::sync::atomic::AtomicU64>,
    stop: Arc<AtomicBool>,
    thread: Option<std::thread::JoinHandle<()>>,
}

impl StreamCounter {
    pub fn connect(address: SocketAddr) -> Result<StreamCounter, String> {
        let stream = std::net::TcpStream::connect(address).map_err(|e| e.to_string())?;
        stream
            .set_read_timeout(Some(std::time::Duration::from_millis(200)))
            .map_err(|e| e.to_string())?;
        let (mut socket, _) =
            tungstenite::client::client(format!("ws://{address}/api/stream"), stream)
                .map_err(|e| format!("the view's stream: {e}"))?;
        let frames = Arc::new(std::sync::atomic::AtomicU64::new(0));
        let bytes = Arc::new(std::sync::atomic::AtomicU64::new(0));
        let stop = Arc::new(AtomicBool::new(false));
        let (f, b, s) = (Arc::clone(&frames), Arc::clone(&bytes), Arc::clone(&stop));
        let thread = std::thread::Builder::new()
            .name("view-counter".into())
            .spawn(move || {
                while !s.load(Ordering::Relaxed) {
                    match socket.read() {
                        Ok(tungstenite::Message::Text(text)) => {
                            f.fetch_add(1, Ordering::Relaxed);
                            b.fetch_add(text.len() as u64, Ordering::Relaxed);
                        }
                        Ok(_) => {}
                        Err(tungstenite::Error::Io(e))
                            if matches!(
                                e.kind(),
                                std::io::ErrorKind::WouldBlock | std::io::ErrorKind::TimedOut
                            ) => {}
                        Err(_) => return,
                    }
                }
            })
            .map_err(|e| e.to_string())?;
        Ok(StreamCounter {
            frames,
            bytes,
            stop,
            thread: Some(thread),
        })
    }
}

impl StreamCounter {
    /// Select an agent as a page does (`/api/select`), for its whole decision to be copied.
    pub fn select(address: SocketAddr, team: &str, unum: u32) -> std::io::Result<()> {
        use std::io::{Read, Write};
        let mut stream = std::net::TcpStream::connect(address)?;
        write!(
            stream,
            "GET /api/select?team={team}&unum={unum} HTTP/1.1\r\nHost: {address}\r\nConnection: close\r\n\r\n"
        )?;
        let mut response = Vec::new();
        stream.read_to_end(&mut response)?;
        Ok(())
    }
}

impl Drop for StreamCounter {
    fn drop(&mut self) {
        self.stop.store(true, Ordering::Relaxed);
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}
