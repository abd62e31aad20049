//! A private X server (Xvfb) per test, a viewer process on it with its output read line by
//! line, and xdotool to press keys as a person would. Every process is killed by a Drop
//! guard and every wait has a deadline, so a failing test never hangs or leaks a server.
#![allow(dead_code)]
use std::io::{BufRead, BufReader, Read};
use std::path::Path;
use std::process::{Child, Command, ExitStatus, Stdio};
use std::sync::mpsc::{channel, Receiver, RecvTimeoutError};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

/// Whether `name` is an executable on PATH.
fn on_path(name: &str) -> bool {
    std::env::var_os("PATH")
        .is_some_and(|paths| std::env::split_paths(&paths).any(|d| d.join(name).is_file()))
}

/// Xvfb and xdotool present? In CI their absence fails the test; elsewhere it is a note.
pub fn tools_available() -> bool {
    let missing: Vec<_> = ["Xvfb", "xdotool"]
        .into_iter()
        .filter(|t| !on_path(t))
        .collect();
    if missing.is_empty() {
        return true;
    }
    let msg = format!(
        "{} not installed (apt-get install xvfb xdotool)",
        missing.join(" and ")
    );
    assert!(
        std::env::var("CI").map_or(true, |v| v != "true"),
        "CI=true but {msg}"
    );
    eprintln!("note: skipping the window test: {msg}");
    false
}

/// Kills and reaps a child on drop.
pub struct Guard(pub Child);

impl Drop for Guard {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

/// A running Xvfb on a display number it chose itself (`-displayfd`), so tests running at
/// once never race for a number.
pub struct Xvfb {
    _server: Guard,
    pub display: String,
}

impl Xvfb {
    pub fn start() -> Xvfb {
        let child = Command::new("Xvfb")
            .args([
                "-displayfd",
                "1",
                "-screen",
                "0",
                "1280x1024x24",
                "-nolisten",
                "tcp",
            ])
            .stdin(Stdio::null())
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .expect("start Xvfb");
        let mut server = Guard(child);
        let stdout = server.0.stdout.take().expect("Xvfb stdout");
        let (tx, rx) = channel();
        std::thread::spawn(move || {
            let mut line = String::new();
            let mut r = BufReader::new(stdout);
            let _ = r.read_line(&mut line);
            let _ = tx.send(line);
            // Keep the pipe open and drained for the server's lifetime.
            let _ = std::io::copy(&mut r, &mut std::io::sink());
        });
        let line = rx
            .recv_timeout(Duration::from_secs(30))
            .expect("Xvfb did not report its display in 30 s");
        let n: u32 = line
            .trim()
            .parse()
            .unwrap_or_else(|_| panic!("Xvfb said {line:?}, not a display number"));
        Xvfb {
            _server: server,
            display: format!(":{n}"),
        }
    }

    /// Runs xdotool on this display; returns stdout, or None when it fails or times out.
    pub fn xdotool(&self, args: &[&str]) -> Option<String> {
        let child = Command::new("xdotool")
            .args(args)
            .env("DISPLAY", &self.display)
            .stdin(Stdio::null())
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .ok()?;
        let mut g = Guard(child);
        let status = wait_deadline(&mut g.0, Duration::from_secs(20))?;
        let mut out = String::new();
        g.0.stdout.take()?.read_to_string(&mut out).ok()?;
        status.success().then_some(out)
    }

    /// The id of the first window whose title contains `name`, polled until `timeout`.
    pub fn find_window(&self, name: &str, timeout: Duration) -> String {
        let end = Instant::now() + timeout;
        loop {
            if let Some(out) = self.xdotool(&["search", "--name", name]) {
                if let Some(id) = out.split_whitespace().next() {
                    return id.to_string();
                }
            }
            assert!(
                Instant::now() < end,
                "no window named {name:?} after {timeout:?}"
            );
            std::thread::sleep(Duration::from_millis(100));
        }
    }
}

fn wait_deadline(child: &mut Child, timeout: Duration) -> Option<ExitStatus> {
    let end = Instant::now() + timeout;
    loop {
        if let Ok(Some(s)) = child.try_wait() {
            return Some(s);
        }
        if Instant::now() >= end {
            return None;
        }
        std::thread::sleep(Duration::from_millis(20));
    }
}

/// A glview process on an Xvfb display: stdout lines arrive with the time they were read;
/// stderr is collected for failure messages.
pub struct Viewer {
    child: Guard,
    lines: Receiver<(Instant, String)>,
    stderr: Arc<Mutex<String>>,
    /// Every stdout line so far, for failure messages.
    pub seen: Vec<String>,
}

impl Viewer {
    pub fn start(bin: &str, display: &str, args: &[&str], cwd: &Path) -> Viewer {
        Self::start_env(bin, display, args, cwd, &[])
    }

    /// [`Viewer::start`] with extra environment variables (e.g. Mesa's version overrides).
    pub fn start_env(
        bin: &str,
        display: &str,
        args: &[&str],
        cwd: &Path,
        env: &[(&str, &str)],
    ) -> Viewer {
        let mut child = Command::new(bin)
            .args(args)
            .current_dir(cwd)
            .envs(env.iter().copied())
            .env("DISPLAY", display)
            .env_remove("WAYLAND_DISPLAY")
            .stdin(Stdio::null())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .expect("start glview");
        let out = child.stdout.take().expect("stdout");
        let err = child.stderr.take().expect("stderr");
        let (tx, lines) = channel();
        std::thread::spawn(move || {
            for line in BufReader::new(out).lines().map_while(Result::ok) {
                if tx.send((Instant::now(), line)).is_err() {
                    break;
                }
            }
        });
        let stderr = Arc::new(Mutex::new(String::new()));
        let sink = stderr.clone();
        std::thread::spawn(move || {
            for line in BufReader::new(err).lines().map_while(Result::ok) {
                let mut s = sink.lock().unwrap_or_else(|p| p.into_inner());
                s.push_str(&line);
                s.push('\n');
            }
        });
        Viewer {
            child: Guard(child),
            lines,
            stderr,
            seen: Vec::new(),
        }
    }

    pub fn pid(&self) -> u32 {
        self.child.0.id()
    }

    pub fn stderr(&self) -> String {
        self.stderr
            .lock()
            .unwrap_or_else(|p| p.into_inner())
            .clone()
    }

    /// The next stdout line matching `want`, with the time it was read; panics after
    /// `timeout` with everything the viewer printed.
    pub fn wait_line(
        &mut self,
        want: impl Fn(&str) -> bool,
        timeout: Duration,
        what: &str,
    ) -> (Instant, String) {
        let end = Instant::now() + timeout;
        loop {
            let left = end.saturating_duration_since(Instant::now());
            match self.lines.recv_timeout(left) {
                Ok((t, line)) => {
                    self.seen.push(line.clone());
                    if want(&line) {
                        return (t, line);
                    }
                }
                Err(e) => {
                    let why = if e == RecvTimeoutError::Timeout {
                        "timed out"
                    } else {
                        "viewer exited"
                    };
                    panic!(
                        "waiting for {what}: {why} after {timeout:?}\nstdout:\n{}\nstderr:\n{}",
                        self.seen.join("\n"),
                        self.stderr()
                    );
                }
            }
        }
    }

    /// The next `--stats` line (one per drawn frame).
    pub fn wait_frame(&mut self, timeout: Duration) -> Instant {
        self.wait_line(|l| l.starts_with('{'), timeout, "a frame").0
    }

    /// Stdout lines that arrive within `d` (nothing is waited for beyond it).
    pub fn drain_for(&mut self, d: Duration) -> Vec<String> {
        let end = Instant::now() + d;
        let mut got = Vec::new();
        while let Ok((_, line)) = self
            .lines
            .recv_timeout(end.saturating_duration_since(Instant::now()))
        {
            self.seen.push(line.clone());
            got.push(line);
        }
        got
    }

    /// User + system CPU time of the process so far (/proc/PID/stat fields 14 and 15).
    pub fn cpu_time(&self) -> Duration {
        let stat = std::fs::read_to_string(format!("/proc/{}/stat", self.pid()))
            .expect("read /proc/PID/stat");
        // The command name (field 2) may hold spaces; count fields after its closing paren.
        let rest = &stat[stat.rfind(')').expect("stat format") + 2..];
        let f: Vec<u64> = rest
            .split_whitespace()
            .map(|x| x.parse().unwrap_or(0))
            .collect();
        Duration::from_secs_f64((f[11] + f[12]) as f64 / clock_ticks() as f64)
    }

    /// CPU time of the live threads in nanoseconds (/proc/PID/task/*/schedstat), finer than
    /// the 10 ms ticks of `cpu_time`; None where the kernel has no schedstat.
    pub fn cpu_time_ns(&self) -> Option<u64> {
        let tasks = std::fs::read_dir(format!("/proc/{}/task", self.pid())).ok()?;
        let mut sum = 0;
        for t in tasks.flatten() {
            let s = std::fs::read_to_string(t.path().join("schedstat")).ok()?;
            sum += s.split_whitespace().next()?.parse::<u64>().ok()?;
        }
        Some(sum)
    }

    pub fn wait_exit(&mut self, timeout: Duration) -> Option<ExitStatus> {
        wait_deadline(&mut self.child.0, timeout)
    }
}

fn clock_ticks() -> u64 {
    Command::new("getconf")
        .arg("CLK_TCK")
        .output()
        .ok()
        .and_then(|o| String::from_utf8_lossy(&o.stdout).trim().parse().ok())
        .unwrap_or(100)
}
