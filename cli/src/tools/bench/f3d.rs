//! The peer: f3d (Debian's package) rendering the same files to PNG. f3d needs an X display,
//! so the bench starts one Xvfb server for the whole run — `xvfb-run` per file would add the
//! server's start-up (about a second) to every f3d time.
use glview::{Error, Result};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

/// The f3d executable on PATH, if any.
pub fn find() -> Option<PathBuf> {
    which("f3d")
}

pub(crate) fn which(name: &str) -> Option<PathBuf> {
    let path = std::env::var_os("PATH")?;
    std::env::split_paths(&path)
        .map(|d| d.join(name))
        .find(|p| p.is_file())
}

/// `f3d --version`'s first line naming the version, e.g. "f3d 1.3.1".
pub fn version(f3d: &Path) -> String {
    Command::new(f3d)
        .arg("--version")
        .stdin(Stdio::null())
        .output()
        .ok()
        .and_then(|o| {
            let text = String::from_utf8_lossy(&o.stdout).into_owned();
            text.lines()
                .find(|l| l.to_lowercase().starts_with("f3d"))
                .map(|l| l.trim().to_string())
        })
        .unwrap_or_else(|| "f3d (version unknown)".into())
}

/// The options for one headless render of `model` into `png`: the built-in defaults only
/// (`--dry-run` ignores any user configuration file).
pub fn args(model: &Path, png: &Path, size: (u32, u32)) -> Vec<String> {
    vec![
        model.display().to_string(),
        "--dry-run".into(),
        "--output".into(),
        png.display().to_string(),
        "--resolution".into(),
        format!("{},{}", size.0, size.1),
    ]
}

/// A virtual X server, stopped when dropped.
pub struct Xvfb {
    child: Child,
    pub display: String,
}

impl Xvfb {
    /// Starts Xvfb on the first free display from :90 and waits for its socket.
    pub fn start(size: (u32, u32)) -> Result<Xvfb> {
        let xvfb = which("Xvfb").ok_or_else(|| {
            Error::Unsupported("Xvfb is not installed (apt-get install xvfb)".into())
        })?;
        let n = (90..200)
            .find(|n| {
                !Path::new(&format!("/tmp/.X11-unix/X{n}")).exists()
                    && !Path::new(&format!("/tmp/.X{n}-lock")).exists()
            })
            .ok_or_else(|| Error::Unsupported("no free X display number".into()))?;
        let display = format!(":{n}");
        let child = Command::new(&xvfb)
            .args([
                display.as_str(),
                "-screen",
                "0",
                &format!("{}x{}x24", size.0.max(1280), size.1.max(1024)),
                "-nolisten",
                "tcp",
            ])
            .stdin(Stdio::null())
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .map_err(|e| Error::io(&xvfb, e))?;
        let mut server = Xvfb { child, display };
        let socket = PathBuf::from(format!("/tmp/.X11-unix/X{n}"));
        let start = Instant::now();
        while !socket.exists() {
            if let Ok(Some(status)) = server.child.try_wait() {
                return Err(Error::Unsupported(format!(
                    "Xvfb exited at start ({status})"
                )));
            }
            if start.elapsed() > Duration::from_secs(15) {
                return Err(Error::Unsupported("Xvfb did not start within 15 s".into()));
            }
            std::thread::sleep(Duration::from_millis(20));
        }
        Ok(server)
    }
}

impl Drop for Xvfb {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}
