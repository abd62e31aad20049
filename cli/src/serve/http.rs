//! The HTTP side: one request per connection (the page makes four), read with limits and a
//! deadline, routed by exact path, answered with the page's files (built into the binary:
//! no request reads a file), the model list, or the upgrade to a WebSocket.
use percent_encoding::percent_decode_str;
use std::io::{Read, Write};
use std::net::TcpStream;
use std::time::{Duration, Instant};

/// A request head larger than this is refused (431).
pub const MAX_HEAD: usize = 8 * 1024;
const MAX_HEADERS: usize = 32;
/// The whole head must arrive within this (a slow sender holds no thread for long).
pub const HEAD_DEADLINE: Duration = Duration::from_secs(10);

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

    /// One line for the log: method and path, never the query (it holds the token).
    pub fn describe(&self) -> String {
        format!("{} {}", self.method, self.path)
    }
}

/// Why a request was not read: the status to answer with (None: the peer went away or was
/// too slow; nothing is answered).
pub struct Refused(pub Option<(u16, String)>);

fn decode(s: &str) -> Result<String, Refused> {
    percent_decode_str(s)
        .decode_utf8()
        .map(|c| c.into_owned())
        .map_err(|_| Refused(Some((400, "the path is not UTF-8".into()))))
}

/// Reads one request head from `stream`: at most [`MAX_HEAD`] bytes, [`MAX_HEADERS`] headers,
/// within [`HEAD_DEADLINE`].
pub fn read_request(stream: &mut TcpStream) -> Result<Request, Refused> {
    let start = Instant::now();
    let mut buf = Vec::with_capacity(1024);
    let mut chunk = [0u8; 1024];
    loop {
        let left = HEAD_DEADLINE.saturating_sub(start.elapsed());
        if left.is_zero() || stream.set_read_timeout(Some(left)).is_err() {
            return Err(Refused(None));
        }
        let n = match stream.read(&mut chunk) {
            Ok(0) | Err(_) => return Err(Refused(None)),
            Ok(n) => n,
        };
        buf.extend_from_slice(&chunk[..n]);
        let mut headers = [httparse::EMPTY_HEADER; MAX_HEADERS];
        let mut req = httparse::Request::new(&mut headers);
        match req.parse(&buf) {
            Ok(httparse::Status::Complete(_)) => return request_of(&req),
            Ok(httparse::Status::Partial) if buf.len() <= MAX_HEAD => continue,
            Ok(httparse::Status::Partial) => {}
            Err(httparse::Error::TooManyHeaders) => {
                return Err(Refused(Some((431, "too many headers".into()))))
            }
            Err(e) => return Err(Refused(Some((400, format!("bad request: {e}"))))),
        }
        return Err(Refused(Some((
            431,
            format!("the request head is over {MAX_HEAD} bytes"),
        ))));
    }
}

fn request_of(req: &httparse::Request) -> Result<Request, Refused> {
    let target = req.path.unwrap_or("/");
    let (path, query) = target.split_once('?').unwrap_or((target, ""));
    let query = query
        .split('&')
        .filter(|p| !p.is_empty())
        .map(|p| {
            let (n, v) = p.split_once('=').unwrap_or((p, ""));
            Ok((decode(n)?, decode(v)?))
        })
        .collect::<Result<_, Refused>>()?;
    let headers = req
        .headers
        .iter()
        .map(|h| {
            (
                h.name.to_ascii_lowercase(),
                String::from_utf8_lossy(h.value).into_owned(),
            )
        })
        .collect();
    Ok(Request {
        method: req.method.unwrap_or("").to_string(),
        path: decode(path)?,
        query,
        headers,
    })
}

/// Writes a whole response and closes (one request per connection).
pub fn respond(
    stream: &mut TcpStream,
    status: u16,
    content_type: &str,
    extra: &[(&str, String)],
    body: &[u8],
) {
    let reason = match status {
        200 => "OK",
        400 => "Bad Request",
        401 => "Unauthorized",
        403 => "Forbidden",
        404 => "Not Found",
        405 => "Method Not Allowed",
        431 => "Request Header Fields Too Large",
        503 => "Service Unavailable",
        _ => "Error",
    };
    let mut head = format!(
        "HTTP/1.1 {status} {reason}\r\nContent-Type: {content_type}\r\nContent-Length: {}\r\n\
         Cache-Control: no-store\r\nX-Content-Type-Options: nosniff\r\nConnection: close\r\n",
        body.len()
    );
    for (n, v) in extra {
        head += &format!("{n}: {v}\r\n");
    }
    head += "\r\n";
    let _ = stream.set_write_timeout(Some(Duration::from_secs(10)));
    let _ = stream.write_all(head.as_bytes());
    let _ = stream.write_all(body);
    let _ = stream.flush();
}

/// A plain-text answer (errors).
pub fn text(stream: &mut TcpStream, status: u16, message: &str) {
    respond(
        stream,
        status,
        "text/plain; charset=utf-8",
        &[],
        format!("{message}\n").as_bytes(),
    );
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
