//! Timing a child process: wall time from spawn to exit, and its peak resident memory from
//! GNU time (`/usr/bin/time -f %M`), or, without it, by polling `VmHWM` in /proc (which can
//! miss a peak in the last few milliseconds before exit).
use glview::{Error, Result};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

const GNU_TIME: &str = "/usr/bin/time";

#[derive(Clone, Copy, Debug, Default, serde::Serialize)]
pub struct Measured {
    pub seconds: f64,
    /// Peak resident set size in MiB.
    pub peak_mib: f64,
}

/// How the peak memory is measured on this machine.
pub fn memory_method() -> &'static str {
    if Path::new(GNU_TIME).is_file() {
        "GNU time %M"
    } else {
        "VmHWM polled every 2 ms"
    }
}

/// Runs `program args` with `env`, discarding its output, and fails if it exits non-zero.
pub fn measure(program: &Path, args: &[String], env: &[(&str, String)]) -> Result<Measured> {
    let rss_file = std::env::temp_dir().join(format!("glview-bench-rss-{}", std::process::id()));
    let use_time = Path::new(GNU_TIME).is_file();
    let mut cmd = if use_time {
        let mut c = Command::new(GNU_TIME);
        c.arg("-f").arg("%M").arg("-o").arg(&rss_file).arg(program);
        c
    } else {
        Command::new(program)
    };
    cmd.args(args)
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped());
    for (k, v) in env {
        cmd.env(k, v);
    }
    let start = Instant::now();
    let mut child = cmd
        .spawn()
        .map_err(|e| Error::io(PathBuf::from(program), e))?;
    let mut polled_kib = 0u64;
    let status = loop {
        if let Some(s) = child.try_wait().map_err(|e| Error::io(program, e))? {
            break s;
        }
        if !use_time {
            polled_kib = polled_kib.max(vm_hwm_kib(child.id()).unwrap_or(0));
        }
        std::thread::sleep(Duration::from_millis(2));
    };
    let seconds = start.elapsed().as_secs_f64();
    let mut stderr = String::new();
    if let Some(mut e) = child.stderr.take() {
        use std::io::Read;
        let _ = e.read_to_string(&mut stderr);
    }
    if !status.success() {
        return Err(Error::Unsupported(format!(
            "{} {} failed ({status}): {}",
            program.display(),
            args.join(" "),
            stderr.lines().rev().take(3).collect::<Vec<_>>().join(" | ")
        )));
    }
    let kib = if use_time {
        let text = std::fs::read_to_string(&rss_file).map_err(|e| Error::io(&rss_file, e))?;
        let _ = std::fs::remove_file(&rss_file);
        // GNU time appends its line after any "Command exited with ..." note.
        text.lines()
            .filter_map(|l| l.trim().parse::<u64>().ok())
            .next_back()
            .unwrap_or(0)
    } else {
        polled_kib
    };
    Ok(Measured {
        seconds,
        peak_mib: kib as f64 / 1024.0,
    })
}

fn vm_hwm_kib(pid: u32) -> Option<u64> {
    let status = std::fs::read_to_string(format!("/proc/{pid}/status")).ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    line.split_whitespace().nth(1)?.parse().ok()
}
