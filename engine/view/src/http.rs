//! The view's HTTP side: the page, its JSON endpoints, the WebSocket stream, and the editor's
//! two writes, which need `--edit`, the run's token and a request from the page's own origin.

use crate::edit::{EditError, EditTarget, FormationDoc};
use crate::stream::{live_frame, Clients, Frame, Reloads, CLIENT_QUEUE};
use crate::{MonitorView, Source};
use libero_model::FieldGeometry;
use serde::{Deserialize, Serialize};
use std::io::Read;
use std::net::SocketAddr;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::Duration;
use tiny_http::{Header, Method, Request, Response, StatusCode};

const PAGE: &str = include_str!("page/index.html");
/// The largest request body read (an edit is a few dozen bytes).
const MAX_BODY_BYTES: u64 = 4096;

pub struct Shared {
    pub address: SocketAddr,
    pub token: String,
    pub field: FieldGeometry,
    pub edit: Option<EditTarget>,
    pub source: Source,
    pub clients: Clients,
    pub reloads: Reloads,
}

pub fn serve(server: &tiny_http::Server, shared: &Arc<Shared>, stop: &AtomicBool) {
    while !stop.load(Ordering::Relaxed) {
        match server.recv_timeout(Duration::from_millis(100)) {
            Ok(Some(request)) => handle(request, shared),
            Ok(None) => {}
            Err(e) => {
                log::error!("field view: {e}");
                return;
            }
        }
    }
}

fn header(name: &str, value: &str) -> Header {
    Header::from_bytes(name.as_bytes(), value.as_bytes()).expect("a valid header")
}

fn json<T: Serialize>(status: u16, value: &T) -> Response<std::io::Cursor<Vec<u8>>> {
    let body = serde_json::to_vec(value).unwrap_or_else(|_| b"null".to_vec());
    Response::from_data(body)
        .with_status_code(StatusCode(status))
        .with_header(header("Content-Type", "application/json"))
        .with_header(header("Cache-Control", "no-store"))
}

#[derive(Serialize)]
struct Refusal {
    error: String,
}

fn refuse(status: u16, message: impl Into<String>) -> Response<std::io::Cursor<Vec<u8>>> {
    json(
        status,
        &Refusal {
            error: message.into(),
        },
    )
}

fn get_header<'a>(request: &'a Request, name: &'static str) -> Option<&'a str> {
    request
        .headers()
        .iter()
        .find(|h| h.field.equiv(name))
        .map(|h| h.value.as_str())
}

fn query<'a>(url: &'a str, key: &str) -> Option<&'a str> {
    let (_, q) = url.split_once('?')?;
    q.split('&')
        .filter_map(|kv| kv.split_once('='))
        .find(|(k, _)| *k == key)
        .map(|(_, v)| v)
}

#[derive(Serialize)]
struct Info<'a> {
    mode: &'static str,
    edit: bool,
    field: &'a FieldGeometry,
    /// Replay: steps on the timeline.
    steps: usize,
}

/// The same-origin rule for anything but plain page loads: a `Host` naming this server (a
/// rebinding page names another) and, when the browser sends one, an `Origin` that is ours.
fn same_origin(request: &Request, shared: &Shared) -> bool {
    let host_ok = get_header(request, "Host").is_none_or(|h| is_us(shared.address, h));
    let origin_ok = get_header(request, "Origin").is_none_or(|o| {
        o.strip_prefix("http://")
            .is_some_and(|h| is_us(shared.address, h))
    });
    host_ok && origin_ok
}

/// Whether `host` (a `Host` header's `name:port`) names this server: its own address or
/// `localhost` on loopback; any name with its port when it listens beyond loopback (asked for
/// by the user, and said loudly at start).
fn is_us(address: SocketAddr, host: &str) -> bool {
    let port = format!(":{}", address.port());
    if host == address.to_string() || host == format!("localhost{port}") {
        return true;
    }
    !address.ip().is_loopback() && host.ends_with(&port)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_this_servers_names_are_its_origin() {
        let loopback: SocketAddr = "127.0.0.1:4000".parse().unwrap();
        assert!(is_us(loopback, "127.0.0.1:4000"));
        assert!(is_us(loopback, "localhost:4000"));
        assert!(!is_us(loopback, "evil.example:4000"), "a rebinding name");
        assert!(!is_us(loopback, "127.0.0.1:4001"));
        let open: SocketAddr = "0.0.0.0:4000".parse().unwrap();
        assert!(is_us(open, "192.168.1.5:4000"));
        assert!(!is_us(open, "192.168.1.5:80"));
    }

    #[test]
    fn query_values_are_found_and_decoded() {
        assert_eq!(query("/api/tree?team=A%2FB&unum=2", "team"), Some("A%2FB"));
        assert_eq!(percent_decode("A%2FB+C%zz"), "A/B C%zz");
        assert_eq!(query("/api/tree", "team"), None);
    }
}

fn handle(request: Request, shared: &Arc<Shared>) {
    let url = request.url().to_string();
    let path = url.split('?').next().unwrap_or("").to_string();
    if !same_origin(&request, shared) {
        let _ = request.respond(refuse(403, "cross-origin request refused"));
        return;
    }
    let response = match (request.method(), path.as_str()) {
        (Method::Get, "/") | (Method::Get, "/index.html") => {
            let _ = request.respond(
                Response::from_string(PAGE)
                    .with_header(header("Content-Type", "text/html; charset=utf-8"))
                    .with_header(header("Cache-Control", "no-store"))
                    .with_header(header(
                        "Content-Security-Policy",
                        "default-src 'self'; script-src 'unsafe-inline'; style-src 'unsafe-inline'; connect-src 'self' ws: ; img-src 'self' data:",
                    )),
            );
            return;
        }
        (Method::Get, "/api/info") => json(
            200,
            &Info {
                mode: match shared.source {
                    Source::Live(_) => "live",
                    Source::Replay(_) => "replay",
                },
                edit: shared.edit.is_some(),
                field: &shared.field,
                steps: match &shared.source {
                    Source::Replay(r) => r.len(),
                    Source::Live(_) => 0,
                },
            },
        ),
        (Method::Get, "/api/frame") => frame(shared, query(&url, "step")),
        (Method::Get, "/api/tree") => tree(shared, &url),
        (Method::Get, "/api/select") => select(shared, &url),
        (Method::Get, "/api/formations") => match &shared.edit {
            Some(target) => json(200, &target.formations()),
            None => json(200, &Vec::<FormationDoc>::new()),
        },
        (Method::Get, "/api/stream") => {
            stream(request, shared);
            return;
        }
        (Method::Post, "/api/formation/move") | (Method::Post, "/api/formation/add") => {
            let add = path.ends_with("/add");
            edit(request, shared, add);
            return;
        }
        _ => refuse(404, format!("no such page: {path}")),
    };
    let _ = request.respond(response);
}

fn frame(shared: &Shared, step: Option<&str>) -> Response<std::io::Cursor<Vec<u8>>> {
    match &shared.source {
        Source::Replay(replay) => {
            let Some(step) = step.and_then(|s| s.parse::<usize>().ok()) else {
                return refuse(400, "a replay frame needs ?step=N");
            };
            let Some(time) = replay.time(step) else {
                return refuse(404, format!("the replay has {} steps", replay.len()));
            };
            let agents = replay.agents_at(step);
            let monitor = agents.first().map(|a| MonitorView {
                time,
                score: a.score,
                play_mode: a.play_mode.clone(),
                ..MonitorView::default()
            });
            json(
                200,
                &Frame {
                    seq: step as u64,
                    time,
                    step: Some(step),
                    monitor,
                    agents: &agents,
                    reloads: Vec::new(),
                    files: Vec::new(),
                },
            )
        }
        Source::Live(set) => match live_frame(shared, set, 0, &mut Vec::new()) {
            Ok(body) => Response::from_data(body.into_bytes())
                .with_header(header("Content-Type", "application/json"))
                .with_header(header("Cache-Control", "no-store")),
            Err(e) => refuse(500, format!("frame not encoded: {e}")),
        },
    }
}

/// The agent a request names: `?team=…&unum=…`.
fn agent_in(url: &str) -> (String, u32) {
    let team = percent_decode(query(url, "team").unwrap_or(""));
    let unum = query(url, "unum").and_then(|u| u.parse().ok()).unwrap_or(0);
    (team, unum)
}

fn tree(shared: &Shared, url: &str) -> Response<std::io::Cursor<Vec<u8>>> {
    let (team, unum) = agent_in(url);
    let generation: u64 = query(url, "generation")
        .and_then(|g| g.parse().ok())
        .unwrap_or(0);
    let shape = match &shared.source {
        Source::Replay(replay) => replay.shape(&team, unum, generation).cloned(),
        Source::Live(set) => set
            .slot_of(&team, unum)
            .and_then(|slot| slot.shape(generation)),
    };
    match shape {
        Some(shape) => json(200, &shape),
        None => refuse(
            404,
            format!("no tree of generation {generation} for {team} {unum}"),
        ),
    }
}

/// How long a selection holds without being renewed (the page renews it every 2 s).
const SELECTION_HOLDS: Duration = Duration::from_secs(5);

/// A browser has an agent selected: that agent copies its whole decision for a while.
fn select(shared: &Shared, url: &str) -> Response<std::io::Cursor<Vec<u8>>> {
    let (team, unum) = agent_in(url);
    let Source::Live(set) = &shared.source else {
        // A replay shows what the logs hold.
        return json(200, &true);
    };
    match set.slot_of(&team, unum) {
        Some(slot) => {
            slot.want_detail_for(SELECTION_HOLDS);
            json(200, &true)
        }
        None => refuse(404, format!("no agent {team} {unum} in the view")),
    }
}

fn percent_decode(s: &str) -> String {
    let bytes = s.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        let hex = bytes
            .get(i + 1..i + 3)
            .and_then(|h| std::str::from_utf8(h).ok())
            .and_then(|h| u8::from_str_radix(h, 16).ok());
        match (bytes[i], hex) {
            (b'%', Some(b)) => {
                out.push(b);
                i += 3;
            }
            (b'+', _) => {
                out.push(b' ');
                i += 1;
            }
            (b, _) => {
                out.push(b);
                i += 1;
            }
        }
    }
    String::from_utf8_lossy(&out).into_owned()
}

fn stream(request: Request, shared: &Arc<Shared>) {
    if !matches!(shared.source, Source::Live(_)) {
        let _ = request.respond(refuse(
            400,
            "a replay has no live stream; ask /api/frame?step=N",
        ));
        return;
    }
    let Some(key) = get_header(&request, "Sec-WebSocket-Key").map(str::to_string) else {
        let _ = request.respond(refuse(400, "the stream is a WebSocket"));
        return;
    };
    let accept = tungstenite::handshake::derive_accept_key(key.as_bytes());
    let response = Response::empty(StatusCode(101))
        .with_header(header("Upgrade", "websocket"))
        .with_header(header("Connection", "Upgrade"))
        .with_header(header("Sec-WebSocket-Accept", &accept));
    let socket = request.upgrade("websocket", response);
    let (sender, receiver) = std::sync::mpsc::sync_channel::<Arc<str>>(CLIENT_QUEUE);
    shared.clients.add(sender);
    let spawned = std::thread::Builder::new()
        .name("view-client".into())
        .spawn(move || {
            let mut ws = tungstenite::WebSocket::from_raw_socket(
                socket,
                tungstenite::protocol::Role::Server,
                None,
            );
            // Ends when the broadcaster drops this browser or the browser goes away.
            while let Ok(frame) = receiver.recv() {
                if ws
                    .send(tungstenite::Message::text(frame.to_string()))
                    .is_err()
                {
                    break;
                }
            }
            let _ = ws.close(None);
        });
    if let Err(e) = spawned {
        log::error!("field view: no thread for a browser: {e}");
    }
}

#[derive(Deserialize)]
struct MoveRequest {
    file: String,
    sample: usize,
    unum: u8,
    x: f64,
    y: f64,
}

#[derive(Deserialize)]
struct AddRequest {
    file: String,
    x: f64,
    y: f64,
}

fn edit(mut request: Request, shared: &Shared, add: bool) {
    let Some(target) = &shared.edit else {
        let _ = request.respond(refuse(
            403,
            "the view is read-only: start the program with --edit to edit formations",
        ));
        return;
    };
    if get_header(&request, "X-Libero-Token") != Some(shared.token.as_str()) {
        let _ = request.respond(refuse(
            403,
            "edits need this run's token (the URL printed at start)",
        ));
        return;
    }
    let mut body = String::new();
    if request
        .as_reader()
        .take(MAX_BODY_BYTES)
        .read_to_string(&mut body)
        .is_err()
    {
        let _ = request.respond(refuse(400, "the request body is not text"));
        return;
    }
    let half = [
        shared.field.length / 2.0 + shared.field.border,
        shared.field.width / 2.0 + shared.field.border,
    ];
    let on_field =
        |x: f64, y: f64| x.is_finite() && y.is_finite() && x.abs() <= half[0] && y.abs() <= half[1];
    let result = if add {
        match serde_json::from_str::<AddRequest>(&body) {
            Ok(r) if on_field(r.x, r.y) => {
                target.apply(&r.file, |doc, text| doc.add_sample(text, [r.x, r.y]))
            }
            Ok(_) => Err(EditError::Refused("the ball is off the field".into())),
            Err(e) => Err(EditError::Refused(format!("not an edit: {e}"))),
        }
    } else {
        match serde_json::from_str::<MoveRequest>(&body) {
            Ok(r) if on_field(r.x, r.y) => target.apply(&r.file, |doc, text| {
                doc.move_player(text, r.sample, r.unum, [r.x, r.y])
            }),
            Ok(_) => Err(EditError::Refused("the position is off the field".into())),
            Err(e) => Err(EditError::Refused(format!("not an edit: {e}"))),
        }
    };
    let response = match result {
        Ok(doc) => {
            log::info!("field view: edited formations/{}", doc.file);
            json(200, &doc)
        }
        Err(EditError::NotFound(m)) => refuse(404, m),
        Err(EditError::Invalid(report)) => refuse(
            422,
            format!("the edit does not validate; nothing was written:\n{report}"),
        ),
        Err(e) => refuse(400, e.to_string()),
    };
    let _ = request.respond(response);
}
