//! One connection: its request answered, or upgraded to a viewer's WebSocket with a reader
//! (this thread) and a writer (a thread of its own, so a frame going out never waits for the
//! client to speak, and a slow client only stalls its own writer).
use super::http::{self, Request};
use super::protocol::{error_json, ClientMsg, Event, Outgoing, MAX_MESSAGE};
use std::io::{Read, Write};
use std::net::TcpStream;
use std::sync::atomic::{AtomicBool, AtomicU64, AtomicUsize, Ordering};
use std::sync::mpsc::{self, Sender};
use std::time::Duration;
use tungstenite::protocol::{frame::coding::CloseCode, CloseFrame, Role, WebSocketConfig};
use tungstenite::{Message, WebSocket};

const PAGE: &str = include_str!("page/index.html");
const APP_JS: &str = include_str!("page/app.js");
const STYLE: &str = include_str!("page/style.css");

/// A frame the client cannot take within this is a dead or stalled client.
const WRITE_TIMEOUT: Duration = Duration::from_secs(10);

/// What every connection thread shares.
pub struct Shared {
    pub token: Option<String>,
    pub presenter_key: String,
    /// `GET /models` without the presenter's state.
    pub models: Vec<String>,
    pub first_model: String,
    pub size: (u32, u32),
    pub max_viewers: usize,
    pub idle_timeout: Duration,
    pub events: Sender<Event>,
    pub viewers: AtomicUsize,
    pub next_id: AtomicU64,
    pub presenter_online: std::sync::Arc<AtomicBool>,
}

/// Both halves of a viewer's socket: client messages over [`MAX_MESSAGE`] are refused.
fn ws_config() -> WebSocketConfig {
    WebSocketConfig::default()
        .max_message_size(Some(MAX_MESSAGE))
        .max_frame_size(Some(MAX_MESSAGE))
}

/// Answers one connection.
pub fn handle(mut stream: TcpStream, shared: &Shared) {
    let _ = stream.set_nodelay(true);
    let req = match http::read_request(&mut stream) {
        Ok(r) => r,
        Err(http::Refused(Some((status, why)))) => return http::text(&mut stream, status, &why),
        Err(http::Refused(None)) => return,
    };
    if req.method != "GET" {
        return http::text(&mut stream, 405, "only GET is served");
    }
    if let Err((status, why)) = authorized(&req, shared) {
        log::info!("{}: {status} {why}", req.describe());
        return http::text(&mut stream, status, why);
    }
    let cookie = shared
        .token
        .as_ref()
        .map(|t| format!("glview_token={t}; Path=/; HttpOnly; SameSite=Strict"));
    let with_cookie: Vec<(&str, String)> = cookie.into_iter().map(|c| ("Set-Cookie", c)).collect();
    match req.path.as_str() {
        "/" => http::respond(
            &mut stream,
            200,
            "text/html; charset=utf-8",
            &with_cookie,
            PAGE.as_bytes(),
        ),
        "/app.js" => http::respond(
            &mut stream,
            200,
            "text/javascript; charset=utf-8",
            &[],
            APP_JS.as_bytes(),
        ),
        "/style.css" => http::respond(
            &mut stream,
            200,
            "text/css; charset=utf-8",
            &[],
            STYLE.as_bytes(),
        ),
        "/models" => {
            let body = serde_json::json!({
                "models": shared.models,
                "model": shared.first_model,
                "size": [shared.size.0, shared.size.1],
                "presenter_online": shared.presenter_online.load(Ordering::Relaxed),
            });
            http::respond(
                &mut stream,
                200,
                "application/json",
                &[],
                body.to_string().as_bytes(),
            )
        }
        "/ws" => upgrade(stream, &req, shared),
        _ => http::text(&mut stream, 404, "not found"),
    }
}

/// The token from the query or the page's cookie: none → 401, wrong → 403.
fn authorized(req: &Request, shared: &Shared) -> Result<(), (u16, &'static str)> {
    let Some(token) = &shared.token else {
        return Ok(());
    };
    match req.param("token").or_else(|| req.cookie("glview_token")) {
        None => Err((
            401,
            "a token is required: open the address `glview serve` printed",
        )),
        Some(t) if http::same_secret(t, token) => Ok(()),
        Some(_) => Err((403, "wrong token")),
    }
}

/// The WebSocket handshake (RFC 6455), then the viewer's life.
fn upgrade(mut stream: TcpStream, req: &Request, shared: &Shared) {
    let key = req.header("sec-websocket-key");
    let is_ws = req
        .header("upgrade")
        .is_some_and(|u| u.eq_ignore_ascii_case("websocket"));
    let (Some(key), true) = (key, is_ws) else {
        return http::text(&mut stream, 400, "a WebSocket upgrade is expected here");
    };
    if !http::origin_ok(req) {
        log::info!("{}: 403 wrong Origin", req.describe());
        return http::text(
            &mut stream,
            403,
            "this page's origin may not open a viewer here",
        );
    }
    let presenter = match req.param("present") {
        None => false,
        Some(k) if http::same_secret(k, &shared.presenter_key) => true,
        Some(_) => return http::text(&mut stream, 403, "wrong presenter key"),
    };
    let accept = tungstenite::handshake::derive_accept_key(key.as_bytes());
    let head = format!(
        "HTTP/1.1 101 Switching Protocols\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n\
         Sec-WebSocket-Accept: {accept}\r\n\r\n"
    );
    if stream.write_all(head.as_bytes()).is_err() {
        return;
    }
    let Ok(write_half) = stream.try_clone() else {
        return;
    };
    let _ = write_half.set_write_timeout(Some(WRITE_TIMEOUT));
    let mut writer = WebSocket::from_raw_socket(write_half, Role::Server, Some(ws_config()));
    // The viewer count is taken before the viewer exists, so two at once cannot both pass.
    let count = shared.viewers.fetch_add(1, Ordering::SeqCst) + 1;
    if count > shared.max_viewers {
        shared.viewers.fetch_sub(1, Ordering::SeqCst);
        let msg = format!(
            "the server is full ({} viewers): try again later",
            shared.max_viewers
        );
        let _ = writer.send(Message::text(error_json(&msg, true)));
        let _ = writer.close(Some(CloseFrame {
            code: CloseCode::Again,
            reason: "server full".into(),
        }));
        let _ = writer.flush();
        return;
    }
    let id = shared.next_id.fetch_add(1, Ordering::SeqCst);
    let (out, rx) = mpsc::channel();
    let writer_thread = std::thread::Builder::new()
        .name(format!("glview-ws-write-{id}"))
        .spawn(move || write_loop(writer, rx));
    if writer_thread.is_err()
        || shared
            .events
            .send(Event::Join {
                id,
                out: out.clone(),
                presenter,
            })
            .is_err()
    {
        shared.viewers.fetch_sub(1, Ordering::SeqCst);
        return;
    }
    read_loop(&stream, id, &out, shared);
    let _ = shared.events.send(Event::Leave { id });
    let _ = out.send(Outgoing::Close(1000, String::new()));
    drop(out);
    if let Ok(t) = writer_thread {
        let _ = t.join();
    }
    let _ = stream.shutdown(std::net::Shutdown::Both);
    shared.viewers.fetch_sub(1, Ordering::SeqCst);
}

/// The read side of the socket for tungstenite: reads from the stream; what tungstenite
/// would write in answer (pongs, the close echo) is dropped, since the writer thread owns
/// the write side (browsers send no pings, and the writer sends the close).
struct ReadHalf<'a>(&'a TcpStream);

impl Read for ReadHalf<'_> {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        (&mut &*self.0).read(buf)
    }
}

impl Write for ReadHalf<'_> {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        Ok(buf.len())
    }
    fn flush(&mut self) -> std::io::Result<()> {
        Ok(())
    }
}

/// Reads messages until the client closes, goes silent for the idle timeout, sends
/// something too large, or the connection fails; each good message goes to the GL thread,
/// each malformed one is answered with an error.
fn read_loop(stream: &TcpStream, id: u64, out: &Sender<Outgoing>, shared: &Shared) {
    let _ = stream.set_read_timeout(Some(shared.idle_timeout));
    let mut ws = WebSocket::from_raw_socket(ReadHalf(stream), Role::Server, Some(ws_config()));
    loop {
        let text = match ws.read() {
            Ok(Message::Text(t)) => t,
            Ok(Message::Binary(_)) => {
                let _ = out.send(Outgoing::Text(error_json(
                    "bad message: the client sends JSON text",
                    false,
                )));
                continue;
            }
            Ok(Message::Close(_)) => return,
            Ok(_) => continue,
            Err(tungstenite::Error::Capacity(e)) => {
                let why = format!("message refused: {e} (the limit is {MAX_MESSAGE} bytes)");
                let _ = out.send(Outgoing::Text(error_json(&why, true)));
                let _ = out.send(Outgoing::Close(1009, "message too big".into()));
                return;
            }
            Err(tungstenite::Error::Io(e))
                if matches!(
                    e.kind(),
                    std::io::ErrorKind::WouldBlock | std::io::ErrorKind::TimedOut
                ) =>
            {
                let why = format!(
                    "closed after {} s without a message",
                    shared.idle_timeout.as_secs()
                );
                let _ = out.send(Outgoing::Text(error_json(&why, true)));
                let _ = out.send(Outgoing::Close(1001, "idle".into()));
                return;
            }
            Err(_) => return,
        };
        match ClientMsg::parse(&text) {
            Ok(ClientMsg::Ping) => {}
            Ok(msg) => {
                if shared.events.send(Event::Input { id, msg }).is_err() {
                    return;
                }
            }
            Err(e) => {
                let _ = out.send(Outgoing::Text(error_json(&e, false)));
            }
        }
    }
}

/// Sends what the GL thread queues until it says close or the client cannot take it.
fn write_loop(mut ws: WebSocket<TcpStream>, rx: mpsc::Receiver<Outgoing>) {
    while let Ok(m) = rx.recv() {
        let sent = match m {
            Outgoing::Frame(bytes) => ws.send(Message::Binary(bytes)),
            Outgoing::Text(t) => ws.send(Message::text(t)),
            Outgoing::Close(code, reason) => {
                let _ = ws.close(Some(CloseFrame {
                    code: CloseCode::from(code),
                    reason: reason.into(),
                }));
                let _ = ws.flush();
                break;
            }
        };
        if sent.is_err() {
            // A stalled or dead client: the reader sees the shut socket and leaves.
            let _ = ws.get_ref().shutdown(std::net::Shutdown::Both);
            break;
        }
    }
}
