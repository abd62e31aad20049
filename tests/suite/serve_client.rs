//! A `glview serve` process and WebSocket clients of it, for the server's tests (the
//! protocol is docs/serve.md's).
use super::common;
use serde_json::Value;
use std::io::{BufRead, BufReader, Read, Write};
use std::net::TcpStream;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};
use tungstenite::client::IntoClientRequest;
use tungstenite::{Message, WebSocket};

pub struct Server {
    child: Child,
    /// host:port
    pub addr: String,
    pub token: String,
    pub presenter_key: String,
}

impl Server {
    /// `glview serve ARGS --bind 127.0.0.1:0` (unless ARGS bind elsewhere), started and its
    /// addresses read.
    pub fn start(args: &[&str]) -> Server {
        Self::start_with_env(args, &[])
    }

    /// As [`Server::start`], with extra environment variables.
    pub fn start_with_env(args: &[&str], env: &[(&str, &str)]) -> Server {
        common::at_repo();
        // The load test measures another build when told to (its before/after table).
        let bin = std::env::var("GLVIEW_SERVE_BIN").unwrap_or_else(|_| common::bin().into());
        let mut child = Command::new(bin)
            .arg("serve")
            .args(if args.contains(&"--bind") {
                &[][..]
            } else {
                &["--bind", "127.0.0.1:0"][..]
            })
            .args(args)
            // Local mode only where a test gives a browser build (`--web-dir`): the one
            // scripts/build_web.sh may be writing meanwhile is no test's.
            .env("GLVIEW_WEB_DIR", "/nonexistent/glview-web")
            .envs(env.iter().copied())
            .stdout(Stdio::piped())
            .stderr(Stdio::inherit())
            .spawn()
            .expect("glview serve starts");
        let mut lines = BufReader::new(child.stdout.take().expect("piped"));
        let (mut open, mut presenter, mut listening) = (None, None, None);
        while presenter.is_none() {
            let mut line = String::new();
            if lines.read_line(&mut line).unwrap_or(0) == 0 {
                let status = child.wait();
                panic!("glview serve ended before printing its address: {status:?}");
            }
            if let Some(a) = line.trim().strip_prefix("glview serve: listening on ") {
                listening = Some(a.to_string());
            }
            if let Some(u) = line.trim().strip_prefix("glview serve: open ") {
                open = Some(u.to_string());
            }
            if let Some(u) = line.trim().strip_prefix("glview serve: presenter ") {
                presenter = Some(u.to_string());
            }
        }
        // The rest of its output is not read: drain it so the server never blocks on it.
        std::thread::spawn(move || std::io::copy(&mut lines, &mut std::io::sink()));
        let open = open.expect("the open line comes first");
        // The address to connect to (the open line names --public-url's when given).
        let addr = listening.unwrap_or_else(|| {
            open.trim_start_matches("http://")
                .split('/')
                .next()
                .unwrap()
                .to_string()
        });
        let token = open.split("token=").nth(1).unwrap_or("").to_string();
        let presenter_key = presenter
            .unwrap()
            .split("present=")
            .nth(1)
            .unwrap()
            .to_string();
        Server {
            child,
            addr,
            token,
            presenter_key,
        }
    }

    /// A viewer: `/ws` with the token and `query` (`&present=...`).
    pub fn viewer(&self, query: &str) -> Client {
        self.connect(&format!("/ws?token={}{query}", self.token), None)
            .expect("the viewer connects")
    }

    /// The WebSocket handshake on `path`, with an Origin header when given.
    pub fn connect(&self, path: &str, origin: Option<&str>) -> Result<Client, String> {
        let mut req = format!("ws://{}{path}", self.addr)
            .into_client_request()
            .unwrap();
        if let Some(o) = origin {
            req.headers_mut().insert("Origin", o.parse().unwrap());
        }
        let stream = TcpStream::connect(&self.addr).map_err(|e| e.to_string())?;
        stream
            .set_read_timeout(Some(Duration::from_secs(30)))
            .unwrap();
        let (ws, _) = tungstenite::client(req, stream).map_err(|e| e.to_string())?;
        Ok(Client { ws })
    }

    /// A raw HTTP request (what a browser's URL bar would not send as is): status and body.
    pub fn raw(&self, request: &str) -> (u16, String) {
        let mut s = TcpStream::connect(&self.addr).unwrap();
        s.set_read_timeout(Some(Duration::from_secs(20))).unwrap();
        s.write_all(request.as_bytes()).unwrap();
        let mut out = Vec::new();
        let _ = s.read_to_end(&mut out);
        let text = String::from_utf8_lossy(&out).into_owned();
        let status = text
            .split(' ')
            .nth(1)
            .and_then(|c| c.parse().ok())
            .unwrap_or(0);
        (status, text)
    }

    /// `GET path` with the Host header.
    pub fn get(&self, path: &str) -> (u16, String) {
        self.raw(&format!(
            "GET {path} HTTP/1.1\r\nHost: {}\r\nConnection: close\r\n\r\n",
            self.addr
        ))
    }

    /// The server's resident memory in kB.
    pub fn rss_kb(&self) -> u64 {
        let status = std::fs::read_to_string(format!("/proc/{}/status", self.child.id())).unwrap();
        status
            .lines()
            .find_map(|l| l.strip_prefix("VmRSS:"))
            .and_then(|v| v.trim().trim_end_matches("kB").trim().parse().ok())
            .unwrap()
    }

    /// CPU time the server has used, in clock ticks (user + system).
    pub fn cpu_ticks(&self) -> u64 {
        let stat = std::fs::read_to_string(format!("/proc/{}/stat", self.child.id())).unwrap();
        // Fields after the command's closing parenthesis; utime and stime are 14th and 15th.
        let rest = stat.rsplit_once(')').unwrap().1;
        let f: Vec<&str> = rest.split_whitespace().collect();
        f[11].parse::<u64>().unwrap() + f[12].parse::<u64>().unwrap()
    }

    pub fn alive(&mut self) -> bool {
        self.child.try_wait().unwrap().is_none()
    }
}

impl Drop for Server {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

pub struct Client {
    pub ws: WebSocket<TcpStream>,
}

/// What the server sent.
pub enum Got {
    Text(Value),
    Frame(Value, Vec<u8>),
    Closed,
}

impl Client {
    pub fn send(&mut self, v: Value) {
        self.ws.send(Message::text(v.to_string())).unwrap();
    }

    /// Sends `text` as it is; a server that closes the socket meanwhile (a message over
    /// its limit) is no failure here: the caller reads what came back.
    pub fn send_raw(&mut self, text: &str) {
        let _ = self.ws.send(Message::text(text.to_string()));
    }

    /// The next message, or None when nothing came within `wait`.
    pub fn next_within(&mut self, wait: Duration) -> Option<Got> {
        self.ws.get_ref().set_read_timeout(Some(wait)).unwrap();
        let got = match self.ws.read() {
            Ok(Message::Text(t)) => Some(Got::Text(serde_json::from_str(&t).unwrap())),
            Ok(Message::Binary(b)) => {
                let n = u32::from_le_bytes(b[..4].try_into().unwrap()) as usize;
                let header: Value = serde_json::from_slice(&b[4..4 + n]).unwrap();
                Some(Got::Frame(header, b[4 + n..].to_vec()))
            }
            Ok(Message::Close(_)) => Some(Got::Closed),
            Ok(_) => self.next_within(wait),
            Err(tungstenite::Error::Io(e))
                if matches!(
                    e.kind(),
                    std::io::ErrorKind::WouldBlock | std::io::ErrorKind::TimedOut
                ) =>
            {
                None
            }
            Err(_) => Some(Got::Closed),
        };
        self.ws
            .get_ref()
            .set_read_timeout(Some(Duration::from_secs(30)))
            .unwrap();
        got
    }

    /// The next message (30 s at most).
    pub fn next(&mut self) -> Got {
        self.next_within(Duration::from_secs(30))
            .expect("the server answers within 30 s")
    }

    /// The next frame, skipping text messages (acknowledged when `ack`).
    pub fn frame(&mut self, ack: bool) -> (Value, Vec<u8>) {
        loop {
            match self.next() {
                Got::Frame(h, img) => {
                    if ack {
                        self.send(serde_json::json!({"type": "ack", "frame": h["frame"]}));
                    }
                    return (h, img);
                }
                Got::Text(_) => continue,
                Got::Closed => panic!("the server closed the socket"),
            }
        }
    }

    /// Frames, each acknowledged, until a still showing input `seq` (or any still when
    /// None); returns it and how many frames came.
    pub fn still(&mut self, seq: Option<u64>) -> (Value, Vec<u8>, usize) {
        let start = Instant::now();
        let mut n = 0;
        loop {
            let (h, img) = self.frame(true);
            n += 1;
            let seen = seq.is_none_or(|s| h["seq"].as_u64() >= Some(s));
            if h["still"] == true && seen {
                return (h, img, n);
            }
            assert!(start.elapsed() < Duration::from_secs(60), "no still");
        }
    }

    /// The next text message of this type (frames on the way are acknowledged).
    pub fn text(&mut self, kind: &str) -> Value {
        loop {
            match self.next() {
                Got::Text(v) if v["type"] == kind => return v,
                Got::Closed => panic!("closed while waiting for {kind}"),
                Got::Frame(h, _) => {
                    self.send(serde_json::json!({"type": "ack", "frame": h["frame"]}))
                }
                Got::Text(_) => {}
            }
        }
    }
}

/// PNG bytes decoded to RGBA.
pub fn decode_png(bytes: &[u8]) -> glview::image_out::Rgba {
    let img = image::load_from_memory_with_format(bytes, image::ImageFormat::Png)
        .expect("a PNG")
        .to_rgba8();
    glview::image_out::Rgba {
        width: img.width(),
        height: img.height(),
        data: img.into_raw(),
    }
}
