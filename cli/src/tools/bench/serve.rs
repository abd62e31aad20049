//! `glview bench --serve`: `glview serve` under simulated viewers on loopback. Each viewer
//! drags at 60 input events a second (as a mouse does) and acknowledges every frame; the
//! figures are frames a second per viewer and in all, the latency from an input to the
//! first frame that shows it, bytes a frame, and where a frame's time goes (the server's
//! own timings in each frame's header). Teacher mode: one presenter drags, 30 followers.
//! Render-thread scaling: 30 viewers on 1 and 2 `--render-threads`, the server's CPU time
//! a frame, and the rate those costs give a 16-core server ([`scaling`]).
use glview::{Error, Result};
use serde_json::{json, Value};
use std::io::{BufRead, BufReader};
use std::net::TcpStream;
use std::path::Path;
use std::process::{Child, Command, Stdio};
use std::sync::{Arc, Barrier};
use std::time::{Duration, Instant};
use tungstenite::client::IntoClientRequest;
use tungstenite::{Message, WebSocket};

/// One input every 1/60 s while dragging.
const INPUT_EVERY: Duration = Duration::from_micros(16_667);

struct Server {
    child: Child,
    addr: String,
    presenter_key: String,
}

impl Drop for Server {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

fn start(model: &Path, size: &str, tier: &str, extra: &[&str], jpeg: &str) -> Result<Server> {
    let exe = std::env::current_exe().map_err(|e| Error::Usage(e.to_string()))?;
    let mut child = Command::new(exe)
        .args([
            "serve",
            "--bind",
            "127.0.0.1:0",
            "--no-token",
            "--max-viewers",
            "64",
            // Every simulated viewer is on 127.0.0.1.
            "--max-viewers-per-address",
            "64",
        ])
        .arg(model)
        .args(["--size", size, "--shading", tier])
        .args(extra)
        .env("GLVIEW_JPEG", jpeg)
        .stdout(Stdio::piped())
        .spawn()
        .map_err(|e| Error::Usage(format!("glview serve: {e}")))?;
    let mut lines = BufReader::new(child.stdout.take().expect("piped"));
    let (mut addr, mut key) = (None, None);
    while key.is_none() {
        let mut line = String::new();
        if lines.read_line(&mut line).unwrap_or(0) == 0 {
            return Err(Error::Usage("glview serve ended at start".into()));
        }
        if let Some(u) = line.trim().strip_prefix("glview serve: open http://") {
            addr = u.split('/').next().map(str::to_string);
        }
        if let Some((_, k)) = line.trim().split_once("present=") {
            key = Some(k.to_string());
        }
    }
    std::thread::spawn(move || std::io::copy(&mut lines, &mut std::io::sink()));
    Ok(Server {
        child,
        addr: addr.unwrap_or_default(),
        presenter_key: key.unwrap_or_default(),
    })
}

fn encoder_name(jpeg: &str) -> &'static str {
    match jpeg {
        "image" => "the image crate",
        _ if glview::platform::turbojpeg::available() => "libjpeg-turbo",
        _ => "the image crate (no libturbojpeg)",
    }
}

/// What one simulated viewer saw.
#[derive(Default)]
struct Seen {
    frames: usize,
    bytes: usize,
    /// Input → first frame showing it, ms.
    latency: Vec<f64>,
    /// The server's render, read-back and encode ms of each frame.
    server: Vec<[f64; 3]>,
}

fn connect(addr: &str, query: &str) -> WebSocket<TcpStream> {
    let req = format!("ws://{addr}/ws?x=1{query}")
        .into_client_request()
        .expect("a URL");
    let stream = TcpStream::connect(addr).expect("the server listens");
    let _ = stream.set_nodelay(true);
    let (ws, _) = tungstenite::client(req, stream).expect("the handshake");
    ws
}

/// The next frame's header and size (text messages skipped); None on timeout.
fn next_frame(ws: &mut WebSocket<TcpStream>, wait: Duration) -> Option<(Value, usize)> {
    let _ = ws.get_ref().set_read_timeout(Some(wait));
    loop {
        match ws.read() {
            Ok(Message::Binary(b)) => {
                let n = u32::from_le_bytes(b[..4].try_into().ok()?) as usize;
                let h: Value = serde_json::from_slice(&b[4..4 + n]).ok()?;
                return Some((h, b.len()));
            }
            Ok(_) => continue,
            Err(_) => return None,
        }
    }
}

/// One viewer: joins, waits for everyone, then drags for `run` (or, a follower, only
/// acknowledges what comes).
fn viewer(
    addr: &str,
    query: &str,
    drags: bool,
    follow: bool,
    start: &Barrier,
    run: Duration,
) -> Seen {
    let mut ws = connect(addr, query);
    let ack = |ws: &mut WebSocket<TcpStream>, h: &Value| {
        let _ = ws.send(Message::text(
            json!({"type": "ack", "frame": h["frame"]}).to_string(),
        ));
    };
    if let Some((h, _)) = next_frame(&mut ws, Duration::from_secs(60)) {
        ack(&mut ws, &h);
    }
    if follow {
        let _ = ws.send(Message::text(
            json!({"type": "follow", "on": true}).to_string(),
        ));
    }
    start.wait();
    let t0 = Instant::now();
    let mut seen = Seen::default();
    let mut sent: Vec<Instant> = Vec::new();
    let mut shown = 0usize;
    let mut next_input = t0;
    while t0.elapsed() < run {
        if drags && Instant::now() >= next_input {
            sent.push(Instant::now());
            let m = json!({"type": "drag", "dx": 3, "dy": 0, "seq": sent.len()});
            let _ = ws.send(Message::text(m.to_string()));
            next_input += INPUT_EVERY;
        }
        let wait = next_input
            .saturating_duration_since(Instant::now())
            .max(Duration::from_millis(1));
        let Some((h, size)) = next_frame(&mut ws, if drags { wait } else { run }) else {
            continue;
        };
        let now = Instant::now();
        ack(&mut ws, &h);
        seen.frames += 1;
        seen.bytes += size;
        let ms = |k: &str| h["ms"][k].as_f64().unwrap_or(0.0);
        seen.server.push([ms("render"), ms("read"), ms("encode")]);
        let seq = h["seq"].as_u64().unwrap_or(0) as usize;
        while drags && shown < seq.min(sent.len()) {
            seen.latency.push((now - sent[shown]).as_secs_f64() * 1e3);
            shown += 1;
        }
    }
    seen
}

struct Row {
    what: String,
    viewers: usize,
    total_fps: f64,
    min_fps: f64,
    mean_fps: f64,
    p50: f64,
    p95: f64,
    kb_per_frame: f64,
    server_ms: [f64; 3],
}

fn percentile(v: &mut [f64], p: f64) -> f64 {
    if v.is_empty() {
        return f64::NAN;
    }
    v.sort_by(f64::total_cmp);
    v[((v.len() - 1) as f64 * p).round() as usize]
}

/// `n` viewers dragging (or, `teacher`, one presenter dragging and `n` followers).
fn scenario(server: &Server, what: &str, n: usize, teacher: bool, run: Duration) -> Row {
    let total = if teacher { n + 1 } else { n };
    let start = Arc::new(Barrier::new(total));
    let handles: Vec<_> = (0..total)
        .map(|i| {
            let (addr, start) = (server.addr.clone(), start.clone());
            let presenter = teacher && i == 0;
            let query = if presenter {
                format!("&present={}", server.presenter_key)
            } else {
                String::new()
            };
            let (drags, follow) = (!teacher || presenter, teacher && !presenter);
            std::thread::spawn(move || viewer(&addr, &query, drags, follow, &start, run))
        })
        .collect();
    let mut seen: Vec<Seen> = handles.into_iter().filter_map(|h| h.join().ok()).collect();
    // Teacher mode: the latency is the presenter's; the rates are the followers'.
    let mut lat: Vec<f64> = seen.iter().flat_map(|s| s.latency.clone()).collect();
    if teacher {
        seen.remove(0);
    }
    let secs = run.as_secs_f64();
    let fps: Vec<f64> = seen.iter().map(|s| s.frames as f64 / secs).collect();
    let frames: usize = seen.iter().map(|s| s.frames).sum();
    let bytes: usize = seen.iter().map(|s| s.bytes).sum();
    let server_ms = [0, 1, 2].map(|k| {
        let mut v: Vec<f64> = seen
            .iter()
            .flat_map(|s| s.server.iter().map(|m| m[k]))
            .collect();
        percentile(&mut v, 0.5)
    });
    Row {
        what: what.to_string(),
        viewers: n,
        total_fps: frames as f64 / secs,
        min_fps: fps.iter().copied().fold(f64::INFINITY, f64::min),
        mean_fps: fps.iter().sum::<f64>() / fps.len().max(1) as f64,
        p50: percentile(&mut lat, 0.5),
        p95: percentile(&mut lat, 0.95),
        kb_per_frame: bytes as f64 / frames.max(1) as f64 / 1024.0,
        server_ms,
    }
}

/// Runs the scenarios and prints the table (Markdown) and JSON.
pub fn run_serve(models_dir: &Path, seconds: f64, size: &str) -> Result<()> {
    let bunny = models_dir.join("stanford-bunny/stanford-bunny.obj");
    if !bunny.is_file() {
        return Err(Error::Usage(format!("{}: missing", bunny.display())));
    }
    let run = Duration::from_secs_f64(seconds.max(1.0));
    let mut rows = Vec::new();
    for tier in ["phong", "pbr"] {
        let server = start(&bunny, size, tier, &[], "auto")?;
        for n in [1, 5, 30] {
            rows.push(scenario(&server, tier, n, false, run));
            eprintln!("bench serve: {tier}, {n} viewer(s) done");
        }
        if tier == "phong" {
            rows.push(scenario(
                &server,
                "phong, teacher → followers",
                30,
                true,
                run,
            ));
        }
        drop(server);
        // Previews at the view's full size: the figure to set beside jupyter_rfb's (28
        // frames/s of 800x600 JPEG).
        for jpeg in ["auto", "image"] {
            let full = start(&bunny, size, tier, &["--drag-scale", "1"], jpeg)?;
            let what = format!("{tier}, full-size previews, JPEG by {}", encoder_name(jpeg));
            rows.push(scenario(&full, &what, 1, false, run));
        }
    }
    println!(
        "glview serve, stanford bunny, {size}, viewers dragging at 60 inputs/s for {seconds} s each (loopback):\n"
    );
    println!("| tier | viewers | frames/s in all | per viewer (min / mean) | input→frame p50 / p95 ms | KB/frame | server ms: render / read / encode (median) |");
    println!("|---|---|---|---|---|---|---|");
    for r in &rows {
        println!(
            "| {} | {} | {:.1} | {:.1} / {:.1} | {:.1} / {:.1} | {:.1} | {:.1} / {:.1} / {:.1} |",
            r.what,
            r.viewers,
            r.total_fps,
            r.min_fps,
            r.mean_fps,
            r.p50,
            r.p95,
            r.kb_per_frame,
            r.server_ms[0],
            r.server_ms[1],
            r.server_ms[2]
        );
    }
    let single = rows[0].mean_fps;
    if let Some(t) = rows.iter().find(|r| r.what.contains("teacher")) {
        println!(
            "\nteacher mode: each of 30 followers at {:.1} frames/s = {:.0} % of one viewer's {single:.1}",
            t.min_fps,
            100.0 * t.min_fps / single
        );
    }
    let json: Vec<Value> = rows
        .iter()
        .map(|r| {
            json!({"tier": r.what, "viewers": r.viewers, "fps_total": r.total_fps,
                "fps_min": r.min_fps, "fps_mean": r.mean_fps, "latency_p50_ms": r.p50,
                "latency_p95_ms": r.p95, "kb_per_frame": r.kb_per_frame,
                "server_ms_render_read_encode": r.server_ms})
        })
        .collect();
    println!("{}", Value::Array(json));
    scaling(&bunny, size, run)
}

/// The server's CPU time so far (user + system), from /proc.
fn cpu_ms(pid: u32) -> f64 {
    let stat = std::fs::read_to_string(format!("/proc/{pid}/stat")).unwrap_or_default();
    // Fields after the command's closing parenthesis, from the state (field 3): utime and
    // stime are fields 14 and 15.
    let rest = stat.rsplit_once(')').map_or("", |(_, r)| r);
    let f: Vec<&str> = rest.split_whitespace().collect();
    let field = |i: usize| f.get(i).and_then(|v| v.parse::<f64>().ok()).unwrap_or(0.0);
    #[cfg(unix)]
    // SAFETY: sysconf reads a constant.
    let hz = unsafe { libc::sysconf(libc::_SC_CLK_TCK) }.max(1) as f64;
    // No /proc there: the figure is 0 (the serve benchmark is a Linux server's).
    #[cfg(not(unix))]
    let hz = 100.0;
    (field(11) + field(12)) * 1e3 / hz
}

/// Render-thread scaling: 30 Phong viewers dragging with 1 and 2 render threads (their
/// clients on the same cores: a server with the clients elsewhere has these cores to
/// itself), then the rate a 16-core server would give from the measured costs.
fn scaling(model: &Path, size: &str, run: Duration) -> Result<()> {
    let cores = std::thread::available_parallelism().map_or(2, |n| n.get());
    let mut rows = Vec::new();
    for threads in [1, 2] {
        let n = threads.to_string();
        let server = start(model, size, "phong", &["--render-threads", &n], "auto")?;
        let pid = server.child.id();
        let cpu = cpu_ms(pid);
        let row = scenario(
            &server,
            &format!("{threads} render thread(s)"),
            30,
            false,
            run,
        );
        let frames = row.total_fps * run.as_secs_f64();
        let cpu_per_frame = (cpu_ms(pid) - cpu) / frames.max(1.0);
        eprintln!("bench serve: {threads} render thread(s) done");
        rows.push((threads, row, cpu_per_frame));
    }
    println!(
        "\nrender threads, 30 viewers dragging, phong, {size}, on this machine's {cores} cores \
         (the 30 simulated clients run on the same cores as the server):\n"
    );
    println!("| render threads | frames/s in all | per viewer (min / mean) | server ms a frame: render / read / encode (median) | server CPU ms a frame |");
    println!("|---|---|---|---|---|");
    for (t, r, cpu) in &rows {
        println!(
            "| {t} | {:.1} | {:.1} / {:.1} | {:.1} / {:.1} / {:.1} | {cpu:.1} |",
            r.total_fps, r.min_fps, r.mean_fps, r.server_ms[0], r.server_ms[1], r.server_ms[2]
        );
    }
    // The model: a frame holds one render thread for render + read, an encoder for
    // encode, and costs the server `cpu` ms of CPU in all; the rate is the least of what
    // the render threads, the encoders and the cores allow.
    let (_, one, cpu) = &rows[0];
    let (threads16, encoders16, cores16) = (4.0, 4.0, 16.0);
    let by_threads = threads16 * 1e3 / (one.server_ms[0] + one.server_ms[1]).max(0.1);
    let by_encode = encoders16 * 1e3 / one.server_ms[2].max(0.01);
    let by_cores = cores16 * 1e3 / cpu.max(0.1);
    let total = by_threads.min(by_encode).min(by_cores);
    println!(
        "\n16-core lab server (extrapolated from the 1-thread row: frames/s = min(threads × \
         1000 / (render + read ms), encoders × 1000 / encode ms, cores × 1000 / server CPU ms \
         a frame); its default 4 render threads and 4 encoders, the clients elsewhere): \
         render threads {by_threads:.0}, encoders {by_encode:.0}, cores {by_cores:.0} → \
         ≈ {total:.0} frames/s in all, {:.1} a viewer for 30 viewers",
        total / 30.0
    );
    Ok(())
}
