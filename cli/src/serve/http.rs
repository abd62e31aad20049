//! The HTTP side's pieces over hyper's request type: the request as the routes read it
//! (path and query percent-decoded once), the answers (the page's files are built into the
//! binary: no request reads a file), and the checks of secrets, `Host` and `Origin`.
use http_body_util::Full;
use hyper::body::Bytes;
use hyper::{Response, StatusCode};
use percent_encoding::percent_decode_str;
use std::time::Duration;

/// A request head larger than this is refused (431, by hyper).
pub const MAX_HEAD: usize = 8 * 1024;
pub const MAX_HEADERS: usize = 32;
/// The whole head must arrive within this (hyper closes the connection past it).
pub const HEAD_DEADLINE: Duration = Duration::from_secs(10);

pub type Answer = Response<Full<Bytes>>;

pub struct Request {
    pub method: String,
    /// Percent-decoded once.
    pub path: String,
    /// Names and values percent-decoded once.
    pub query: Vec<(String, String)>,
    /// Names in lower case.
    pub headers: Vec<(String, String)>,
}

impl Request {
    /// The parts the routes read of hyper's request; None when the path or query does not
    /// decode to UTF-8 (a 400).
    pub fn of<B>(req: &hyper::Request<B>) -> Option<Request> {
        let decode = |s: &str| {
            percent_decode_str(s)
                .decode_utf8()
                .ok()
                .map(|c| c.into_owned())
        };
        let query = req
            .uri()
            .query()
            .unwrap_or("")
            .split('&')
            .filter(|p| !p.is_empty())
            .map(|p| {
                let (n, v) = p.split_once('=').unwrap_or((p, ""));
                Some((decode(n)?, decode(v)?))
            })
            .collect::<Option<_>>()?;
        let headers = req
            .headers()
            .iter()
            .map(|(n, v)| {
                (
                    n.as_str().to_ascii_lowercase(),
                    String::from_utf8_lossy(v.as_bytes()).into_owned(),
                )
            })
            .collect();
        Some(Request {
            method: req.method().as_str().to_string(),
            path: decode(req.uri().path())?,
            query,
            headers,
        })
    }

    pub fn header(&self, name: &str) -> Option<&str> {
        self.headers
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, v)| v.as_str())
    }

    pub fn param(&self, name: &str) -> Option<&str> {
        self.query
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, v)| v.as_str())
    }

    /// A cookie's value.
    pub fn cookie(&self, name: &str) -> Option<&str> {
        self.headers
            .iter()
            .filter(|(n, _)| n == "cookie")
            .flat_map(|(_, v)| v.split(';'))
            .filter_map(|c| c.trim().split_once('='))
            .find(|(n, _)| *n == name)
            .map(|(_, v)| v)
    }

    /// One line for the log: method and path (clipped), never the query (it holds the token).
    pub fn describe(&self) -> String {
        format!("{} {}", clip(&self.method), clip(&self.path))
    }
}

/// A client's string as it may appear in a log line or an answer: at most 64 characters
/// (an error never echoes a long client string back).
pub fn clip(s: &str) -> String {
    const MAX: usize = 64;
    match s.char_indices().nth(MAX) {
        Some((i, _)) => format!("{}…", &s[..i]),
        None => s.to_string(),
    }
}

/// A whole response (the connection may carry the next request: its head has the same
/// deadline, so an idle kept-alive connection is closed after it).
pub fn respond(status: u16, content_type: &str, extra: &[(&str, String)], body: Bytes) -> Answer {
    let mut r = Response::builder()
        .status(StatusCode::from_u16(status).unwrap_or(StatusCode::INTERNAL_SERVER_ERROR))
        .header("Content-Type", content_type)
        .header("Cache-Control", "no-store")
        .header("X-Content-Type-Options", "nosniff");
    for (n, v) in extra {
        r = r.header(*n, v.as_str());
    }
    r.body(Full::new(body)).unwrap_or_else(|_| {
        // Only a header value with a newline fails here, and the values are the server's.
        let mut plain = Response::new(Full::new(Bytes::from_static(b"internal error\n")));
        *plain.status_mut() = StatusCode::INTERNAL_SERVER_ERROR;
        plain
    })
}

/// A plain-text answer (errors).
pub fn text(status: u16, message: &str) -> Answer {
    respond(
        status,
        "text/plain; charset=utf-8",
        &[],
        Bytes::from(format!("{message}\n")),
    )
}

/// Compares secrets in time independent of where they differ.
pub fn same_secret(a: &str, b: &str) -> bool {
    a.len() == b.len() && a.bytes().zip(b.bytes()).fold(0u8, |d, (x, y)| d | (x ^ y)) == 0
}

/// The browser's `Origin`, when sent, must be this server as the browser reached it (a page
/// of another site must not drive a viewer with the user's cookie).
pub fn origin_ok(req: &Request) -> bool {
    match (req.header("origin"), req.header("host")) {
        (None, _) => true,
        (Some(o), Some(h)) => o == format!("http://{h}") || o == format!("https://{h}"),
        (Some(_), None) => false,
    }
}

/// A random token: 128 bits, hex.
pub fn random_token() -> String {
    let mut b = [0u8; 16];
    getrandom::fill(&mut b).expect("the system's random source");
    b.iter().map(|x| format!("{x:02x}")).collect()
}
