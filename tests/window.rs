//! The interactive window as a person uses it: a real X server (Xvfb), keys pressed with
//! xdotool, screenshots compared with headless renders, idle CPU measured from /proc.
//!
//! Each test starts its own Xvfb; the tests run one at a time (a lock) so the CPU and latency
//! measurements are not disturbed by a neighbour rendering on the same cores.
mod common;
#[path = "support/xvfb.rs"]
mod xvfb;

use common::{assert_close, bin, check_frame, diff, out_dir, render};
use glview::image_out::Rgba;
use std::path::Path;
use std::sync::{Mutex, MutexGuard};
use std::time::{Duration, Instant};
use xvfb::{Viewer, Xvfb};

/// Debug builds on llvmpipe compile shaders and build a 2048² shadow map at start-up.
const START: Duration = Duration::from_secs(120);
const FRAME: Duration = Duration::from_secs(30);
const VIEW: &[&str] = &["--size", "320x240", "--yaw", "30", "--pitch", "15"];

static ONE_AT_A_TIME: Mutex<()> = Mutex::new(());

fn setup() -> Option<(MutexGuard<'static, ()>, Xvfb)> {
    let lock = ONE_AT_A_TIME.lock().unwrap_or_else(|p| p.into_inner());
    xvfb::tools_available().then(|| (lock, Xvfb::start()))
}

/// Starts glview in a window with `--stats`, waits for its first frame, and gives it the
/// keyboard focus (Xvfb has no window manager, so focus is set directly).
fn open(x: &Xvfb, dir: &Path, extra: &[&str]) -> (Viewer, String) {
    let mut args = VIEW.to_vec();
    args.extend_from_slice(&["--stats", "--screenshot-dir", dir.to_str().unwrap()]);
    args.extend_from_slice(extra);
    let mut v = Viewer::start(bin(), &x.display, &args, dir);
    v.wait_frame(START);
    let win = x.find_window("glview", FRAME);
    x.xdotool(&["windowfocus", "--sync", &win])
        .expect("xdotool windowfocus");
    (v, win)
}

/// Presses a key and returns the time until the frame it causes is reported.
fn key_to_frame(x: &Xvfb, v: &mut Viewer, key: &str) -> Duration {
    let t0 = Instant::now();
    x.xdotool(&["key", key])
        .unwrap_or_else(|| panic!("xdotool key {key}"));
    v.wait_frame(FRAME) - t0
}

fn screenshot(x: &Xvfb, v: &mut Viewer) -> Rgba {
    x.xdotool(&["key", "F12"]).expect("xdotool key F12");
    let (_, line) = v.wait_line(
        |l| l.starts_with("screenshot: "),
        FRAME,
        "the screenshot line",
    );
    let path = line.trim_start_matches("screenshot: ").to_string();
    Rgba::load_png(Path::new(&path)).unwrap_or_else(|e| panic!("read {path}: {e}"))
}

fn quit(v: &mut Viewer, x: &Xvfb, key: &str) {
    x.xdotool(&["key", key]).expect("xdotool key");
    let status = v
        .wait_exit(FRAME)
        .unwrap_or_else(|| panic!("glview still running 30 s after {key}"));
    let err = v.stderr();
    assert!(
        status.success(),
        "glview exited with {status} after {key}; stderr:\n{err}"
    );
    assert!(!err.contains("error"), "glview reported an error:\n{err}");
}

fn median(mut v: Vec<Duration>) -> Duration {
    v.sort();
    v[v.len() / 2]
}

/// Arrow keys in the window give the view `--keys` gives headless. Both paths are llvmpipe
/// with the same GL request (`--gl auto`: 3.3 core through GLX in the window, through the EGL
/// device headless) and run identical shaders on the same 320×240 grid, so they agree to
/// rounding: measured max 1/255 on 5 of 76,800 pixels. The tolerance, ≤ 2 per channel with
/// at most 0.1 % of pixels differing at all, leaves room for a different Mesa build while a
/// wrong view (one 5° step ≈ 40/255 at silhouettes) still fails. Alpha is not compared:
/// screenshots are opaque, headless PNGs keep the glass's alpha.
#[test]
fn arrow_keys_match_headless_render() {
    let Some((_lock, x)) = setup() else { return };
    let dir = out_dir("window_keys");
    for f in std::fs::read_dir(&dir).unwrap().flatten() {
        let _ = std::fs::remove_file(f.path());
    }
    let (mut v, _win) = open(&x, &dir, &[]);
    let mut latency = Vec::new();
    for key in ["Left", "Left", "Up"] {
        latency.push(key_to_frame(&x, &mut v, key));
    }
    let shot = screenshot(&x, &mut v);
    assert_eq!(
        (shot.width, shot.height),
        (320, 240),
        "screenshot is not the framebuffer size"
    );
    check_frame(&shot, "window screenshot");

    let mut headless = VIEW.to_vec();
    headless.extend_from_slice(&["--keys", "Left Left Up"]);
    let reference = render(&dir, "headless-keys", &headless, &[]);
    let before = render(&dir, "headless-start", VIEW, &[]);
    let mut shot_rgb = shot.clone();
    for (p, q) in shot_rgb
        .data
        .chunks_exact_mut(4)
        .zip(reference.data.chunks_exact(4))
    {
        p[3] = q[3];
    }
    assert_close(
        &dir,
        "window-vs-headless",
        &shot_rgb,
        &reference,
        0,
        320 * 240 / 1000,
        2,
    );
    let moved = diff(&shot, &before, 2);
    assert!(
        moved.max > 20,
        "the keys did not change the view (max diff {} from the start view)",
        moved.max
    );
    eprintln!(
        "key-to-frame latency (xdotool key → --stats line): {:?}, median {:?}",
        latency,
        median(latency.clone())
    );
    quit(&mut v, &x, "Escape");
}

/// No input for three seconds: no frames and (almost) no CPU.
#[test]
fn idle_window_draws_nothing_and_sleeps() {
    let Some((_lock, x)) = setup() else { return };
    let dir = out_dir("window_idle");
    let (mut v, _win) = open(&x, &dir, &[]);
    // Let start-up events (map, expose, focus) settle, then measure.
    v.drain_for(Duration::from_secs(1));
    let (cpu0, t0) = (v.cpu_time(), Instant::now());
    let frames = v
        .drain_for(Duration::from_secs(3))
        .iter()
        .filter(|l| l.starts_with('{'))
        .count();
    let (cpu, wall) = (v.cpu_time() - cpu0, t0.elapsed());
    let share = cpu.as_secs_f64() / wall.as_secs_f64();
    eprintln!(
        "idle: {frames} frames, CPU {cpu:?} in {wall:?} = {:.2} %",
        share * 100.0
    );
    assert_eq!(frames, 0, "frames drawn while idle");
    assert!(share < 0.05, "idle CPU {:.1} % of wall time", share * 100.0);
    // Still alive and responsive after idling.
    key_to_frame(&x, &mut v, "Right");
    quit(&mut v, &x, "Escape");
}

/// Resize, tiny sizes, minimise, unmap/map: no crash, no GL error; screenshots follow the
/// window's size; `G` shows in the title.
#[test]
fn resize_and_minimise_survive() {
    let Some((_lock, x)) = setup() else { return };
    let dir = out_dir("window_resize");
    let (mut v, win) = open(&x, &dir, &[]);
    x.xdotool(&["windowsize", "--sync", &win, "500", "300"])
        .expect("windowsize");
    v.wait_frame(FRAME);
    let shot = screenshot(&x, &mut v);
    assert_eq!(
        (shot.width, shot.height),
        (500, 300),
        "screenshot does not follow the resize"
    );
    check_frame(&shot, "resized screenshot");
    x.xdotool(&["windowsize", "--sync", &win, "1", "1"])
        .expect("windowsize 1x1");
    v.wait_frame(FRAME);
    // Without a window manager minimising may do nothing; unmapping hides the window for real.
    let _ = x.xdotool(&["windowminimize", "--sync", &win]);
    x.xdotool(&["windowunmap", "--sync", &win])
        .expect("windowunmap");
    x.xdotool(&["windowmap", "--sync", &win])
        .expect("windowmap");
    x.xdotool(&["windowsize", "--sync", &win, "320", "240"])
        .expect("windowsize back");
    x.xdotool(&["windowfocus", "--sync", &win])
        .expect("windowfocus");
    v.drain_for(Duration::from_millis(500));
    key_to_frame(&x, &mut v, "g");
    let title = x.xdotool(&["getwindowname", &win]).expect("getwindowname");
    assert!(
        title.starts_with("glview — glass_holder — legacy Gouraud — "),
        "title after G: {title:?}"
    );
    let shot = screenshot(&x, &mut v);
    assert_eq!((shot.width, shot.height), (320, 240));
    quit(&mut v, &x, "Escape");
}

/// `Esc` closes the window and glview exits 0; so does `Q`.
#[test]
fn escape_and_q_exit_zero() {
    let Some((_lock, x)) = setup() else { return };
    let dir = out_dir("window_quit");
    for key in ["Escape", "q"] {
        let (mut v, _win) = open(&x, &dir, &[]);
        quit(&mut v, &x, key);
    }
}
