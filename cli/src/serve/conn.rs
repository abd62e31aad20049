//! Connections: accepted on tokio's runtime (a task each, so an idle or half-open one costs a
//! little memory, not a thread or a slot a viewer needs), at most so many per address, read
//! by hyper's HTTP/1 server (head size, header count and the head's deadline are its), routed
//! by exact path, and the viewer's socket upgraded to a WebSocket ([`super::socket`]).
use super::http::{self, Answer, Request};
use super::protocol::Event;
use hyper::body::{Bytes, Incoming};
use hyper::server::conn::http1;
use hyper::service::service_fn;
use hyper_util::rt::{TokioIo, TokioTimer};
use std::collections::HashMap;
use std::net::IpAddr;
use std::sync::atomic::{AtomicBool, AtomicU64, AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};
use std::time::Duration;

const PAGE: &str = include_str!("page/index.html");
const APP_JS: &str = include_str!("page/app.js");
/// Local mode: the page drawing the view itself (only fetched where the server has the
/// browser build); its renderer's start is the live lesson page's.
const LOCAL_JS: &str = include_str!("page/local.js");
const STYLE: &str = include_str!("page/style.css");

/// What every connection shares.
pub struct Shared {
    pub token: Option<String>,
    pub presenter_key: String,
    /// `GET /models` without the presenter's state.
    pub models: Vec<String>,
    pub first_model: String,
    pub size: (u32, u32),
    pub max_viewers: usize,
    pub idle_timeout: Duration,
    /// The `Host` values this server answers to.
    pub hosts: super::hosts::Hosts,
    pub max_per_address: usize,
    /// Viewers at once from one address.
    pub max_viewers_per_address: usize,
    /// The page's `Content-Security-Policy: frame-ancestors` sources.
    pub frame_ancestors: String,
    /// The cookie's `SameSite` (and `Secure`) attributes.
    pub cookie_site: &'static str,
    pub events: std::sync::mpsc::Sender<Event>,
    pub viewers: AtomicUsize,
    pub next_id: AtomicU64,
    pub presenter_online: Arc<AtomicBool>,
    /// The browser build and the scenes of local mode (None: every page gets the stream).
    pub web: Option<Arc<super::web::Web>>,
    per_address: Mutex<HashMap<IpAddr, usize>>,
    viewers_per_address: Mutex<HashMap<IpAddr, usize>>,
}

/// The counts `glview serve` limits.
pub struct Limits {
    pub max_viewers: usize,
    pub max_per_address: usize,
    pub max_viewers_per_address: usize,
    pub idle_timeout: Duration,
}

impl Shared {
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        token: Option<String>,
        presenter_key: String,
        models: (Vec<String>, String),
        size: (u32, u32),
        limits: Limits,
        hosts: super::hosts::Hosts,
        events: std::sync::mpsc::Sender<Event>,
        presenter_online: Arc<AtomicBool>,
    ) -> Shared {
        Shared {
            token,
            presenter_key,
            models: models.0,
            first_model: models.1,
            size,
            max_viewers: limits.max_viewers,
            max_per_address: limits.max_per_address,
            max_viewers_per_address: limits.max_viewers_per_address,
            idle_timeout: limits.idle_timeout,
            hosts,
            frame_ancestors: "'self'".into(),
            cookie_site: "SameSite=Strict",
            events,
            viewers: AtomicUsize::new(0),
            next_id: AtomicU64::new(1),
            presenter_online,
            web: None,
            per_address: Mutex::new(HashMap::new()),
            viewers_per_address: Mutex::new(HashMap::new()),
        }
    }
}

/// One connection's (or viewer's) place in its address's count, given back when dropped
/// (the upgraded socket holds its connection's for its life).
pub struct Slot {
    shared: Arc<Shared>,
    ip: IpAddr,
    viewer: bool,
}

impl Slot {
    fn take(shared: &Arc<Shared>, ip: IpAddr) -> Option<Slot> {
        Slot::counted(shared, ip, false)
    }

    /// A viewer's place in its address's count of viewers (None: it has its
    /// `--max-viewers-per-address`).
    pub fn viewer(&self) -> Option<Slot> {
        Slot::counted(&self.shared, self.ip, true)
    }

    fn counted(shared: &Arc<Shared>, ip: IpAddr, viewer: bool) -> Option<Slot> {
        let (map, max) = if viewer {
            (&shared.viewers_per_address, shared.max_viewers_per_address)
        } else {
            (&shared.per_address, shared.max_per_address)
        };
        let mut m = map.lock().unwrap_or_else(|e| e.into_inner());
        let n = m.entry(ip).or_insert(0);
        if *n >= max {
            return None;
        }
        *n += 1;
        Some(Slot {
            shared: shared.clone(),
            ip,
            viewer,
        })
    }
}

impl Drop for Slot {
    fn drop(&mut self) {
        let map = if self.viewer {
            &self.shared.viewers_per_address
        } else {
            &self.shared.per_address
        };
        let mut m = map.lock().unwrap_or_else(|e| e.into_inner());
        if let Some(n) = m.get_mut(&self.ip) {
            *n -= 1;
            if *n == 0 {
                m.remove(&self.ip);
            }
        }
    }
}

/// Accepts connections until the process ends.
pub async fn accept(listener: tokio::net::TcpListener, shared: Arc<Shared>) {
    loop {
        let (stream, peer) = match listener.accept().await {
            Ok(s) => s,
            Err(e) => {
                // Out of descriptors (or the like): wait for some to close, do not spin.
                log::warn!("accept: {e}");
                tokio::time::sleep(Duration::from_millis(50)).await;
                continue;
            }
        };
        let Some(slot) = Slot::take(&shared, peer.ip()) else {
            // Over the address's count: closed at once, nothing read.
            continue;
        };
        let _ = stream.set_nodelay(true);
        let shared = shared.clone();
        tokio::spawn(async move {
            let slot = Arc::new(slot);
            let service = service_fn(move |req| {
                let (shared, slot) = (shared.clone(), slot.clone());
                async move { Ok::<_, std::convert::Infallible>(handle(req, &shared, slot).await) }
            });
            let conn = http1::Builder::new()
                .timer(TokioTimer::new())
                .header_read_timeout(http::HEAD_DEADLINE)
                .max_header_size(http::MAX_HEAD)
                .max_headers(http::MAX_HEADERS)
                .title_case_headers(true)
                .serve_connection(TokioIo::new(stream), service)
                .with_upgrades();
            let _ = conn.await;
        });
    }
}

/// Answers one request.
async fn handle(req: hyper::Request<Incoming>, shared: &Arc<Shared>, slot: Arc<Slot>) -> Answer {
    let Some(r) = Request::of(&req) else {
        return http::text(400, "the path is not UTF-8");
    };
    if r.method != "GET" {
        return http::text(405, "only GET is served");
    }
    let host = r.header("host").unwrap_or("");
    if !shared.hosts.allows(host) {
        log::info!("{}: 421 Host {}", r.describe(), http::clip(host));
        return http::text(421, shared.hosts.refusal());
    }
    if let Err((status, why)) = authorized(&r, shared) {
        log::info!("{}: {status} {why}", r.describe());
        return http::text(status, why);
    }
    let cookie = shared
        .token
        .as_ref()
        .map(|t| format!("glview_token={t}; Path=/; HttpOnly; {}", shared.cookie_site));
    let mut page_headers: Vec<(&str, String)> =
        cookie.into_iter().map(|c| ("Set-Cookie", c)).collect();
    // Who may frame the page: this server, and the sites --embed-origin names.
    page_headers.push((
        "Content-Security-Policy",
        format!("frame-ancestors {}", shared.frame_ancestors),
    ));
    let file = |ty: &str, body: &'static str| http::respond(200, ty, &[], Bytes::from(body));
    match r.path.as_str() {
        "/" => http::respond(
            200,
            "text/html; charset=utf-8",
            &page_headers,
            page(&r, shared),
        ),
        "/app.js" => file("text/javascript; charset=utf-8", APP_JS),
        "/local.js" => file("text/javascript; charset=utf-8", LOCAL_JS),
        "/start.js" => file(
            "text/javascript; charset=utf-8",
            glview::export::START_SCRIPT,
        ),
        "/style.css" => file("text/css; charset=utf-8", STYLE),
        "/models" => {
            let body = serde_json::json!({
                "models": shared.models,
                "model": shared.first_model,
                "size": [shared.size.0, shared.size.1],
                "presenter_online": shared.presenter_online.load(Ordering::Relaxed),
            });
            http::respond(200, "application/json", &[], Bytes::from(body.to_string()))
        }
        "/ws" => upgrade(req, &r, shared, slot),
        // Local mode's: the browser build and a model's scene (404 without the build).
        "/scene" => match &shared.web {
            Some(web) => web.scene(r.param("model")).await,
            None => http::text(404, "this server streams only: it has no browser build"),
        },
        p if p.starts_with("/web/") => shared
            .web
            .as_ref()
            .and_then(|w| w.file(p))
            .unwrap_or_else(|| http::text(404, "not found")),
        _ => http::text(404, "not found"),
    }
}

/// The page. Opened with the token in its address, its script and style carry it too: in
/// a frame of another site the cookie (SameSite=Strict) is not sent for them.
fn page(r: &Request, shared: &Shared) -> Bytes {
    match (&shared.token, r.param("token")) {
        (Some(t), Some(_)) => Bytes::from(
            ["app.js", "local.js", "start.js", "style.css"]
                .iter()
                .fold(PAGE.to_string(), |page, f| {
                    page.replace(&format!("\"{f}\""), &format!("\"{f}?token={t}\""))
                }),
        ),
        _ => Bytes::from(PAGE),
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

/// The WebSocket handshake (RFC 6455): the 101 answer now, the viewer's life on a task of
/// its own once hyper hands the connection over.
fn upgrade(
    mut req: hyper::Request<Incoming>,
    r: &Request,
    shared: &Arc<Shared>,
    slot: Arc<Slot>,
) -> Answer {
    let key = r.header("sec-websocket-key");
    let is_ws = r
        .header("upgrade")
        .is_some_and(|u| u.eq_ignore_ascii_case("websocket"));
    let (Some(key), true) = (key, is_ws) else {
        return http::text(400, "a WebSocket upgrade is expected here");
    };
    if !http::origin_ok(r) {
        log::info!("{}: 403 wrong Origin", r.describe());
        return http::text(403, "this page's origin may not open a viewer here");
    }
    let presenter = match r.param("present") {
        None => false,
        Some(k) if http::same_secret(k, &shared.presenter_key) => true,
        Some(_) => return http::text(403, "wrong presenter key"),
    };
    let accept = tungstenite::handshake::derive_accept_key(key.as_bytes());
    let on_upgrade = hyper::upgrade::on(&mut req);
    let shared = shared.clone();
    tokio::spawn(async move {
        if let Ok(upgraded) = on_upgrade.await {
            let place = slot.viewer();
            super::socket::viewer(TokioIo::new(upgraded), shared, presenter, place).await;
        }
        drop(slot);
    });
    hyper::Response::builder()
        .status(101)
        .header("Upgrade", "websocket")
        .header("Connection", "Upgrade")
        .header("Sec-WebSocket-Accept", accept)
        .body(http_body_util::Full::new(Bytes::new()))
        .unwrap_or_else(|_| http::text(500, "internal error"))
}
