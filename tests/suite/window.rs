//! The interactive window as a person uses it: a real X server (Xvfb), keys pressed with
//! xdotool, screenshots compared with headless renders, idle CPU measured from /proc.
//!
//! Each test starts its own Xvfb; the tests run one at a time (a lock) so the CPU and latency
//! measurements are not disturbed by a neighbour rendering on the same cores.
use crate::common;
use crate::xvfb;
use glview::image_out::RgbaFiles;

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

/// The test's output folder, emptied (screenshot names count up from what is there).
fn fresh_dir(name: &str) -> std::path::PathBuf {
    let dir = out_dir(name);
    for f in std::fs::read_dir(&dir).into_iter().flatten().flatten() {
        let _ = std::fs::remove_file(f.path());
    }
    dir
}

/// Starts glview in a window with `--stats`, waits for its first frame, and gives it the
/// keyboard focus (Xvfb has no window manager, so focus is set directly).
fn open(x: &Xvfb, dir: &Path, extra: &[&str]) -> (Viewer, String) {
    open_env(x, dir, extra, &[])
}

fn open_env(x: &Xvfb, dir: &Path, extra: &[&str], env: &[(&str, &str)]) -> (Viewer, String) {
    let mut args = VIEW.to_vec();
    args.extend_from_slice(&["--stats", "--screenshot-dir", dir.to_str().unwrap()]);
    args.extend_from_slice(extra);
    let mut v = Viewer::start_env(bin(), &x.display, &args, dir, env);
    v.wait_frame(START);
    let win = x.find_window("glview", FRAME);
    x.xdotool(&["windowfocus", "--sync", &win])
        .expect("xdotool windowfocus");
    // Start-up may draw twice (our first redraw, then the server's expose); skip the second.
    v.drain_for(Duration::from_millis(300));
    (v, win)
}

/// Presses a key; returns the time from starting `xdotool key` until the frame it causes is
/// reported (an upper bound: it includes starting xdotool), and that frame's own render time.
fn key_to_frame(x: &Xvfb, v: &mut Viewer, key: &str) -> (Duration, f64) {
    let t0 = Instant::now();
    x.xdotool(&["key", key])
        .unwrap_or_else(|| panic!("xdotool key {key}"));
    let (t, line) = v.wait_line(|l| l.starts_with('{'), FRAME, "a frame");
    let ms = serde_json::from_str::<serde_json::Value>(&line)
        .ok()
        .and_then(|j| j["ms"].as_f64())
        .unwrap_or(f64::NAN);
    (t - t0, ms)
}

fn screenshot(x: &Xvfb, v: &mut Viewer) -> Rgba {
    screenshot_file(x, v).0
}

fn screenshot_file(x: &Xvfb, v: &mut Viewer) -> (Rgba, std::path::PathBuf) {
    x.xdotool(&["key", "F12"]).expect("xdotool key F12");
    let (_, line) = v.wait_line(
        |l| l.starts_with("screenshot: "),
        FRAME,
        "the screenshot line",
    );
    let path = line.trim_start_matches("screenshot: ").to_string();
    let img = Rgba::load_png(Path::new(&path)).unwrap_or_else(|e| panic!("read {path}: {e}"));
    (img, path.into())
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

/// `img` with the alpha of `of`: screenshots are opaque, headless PNGs keep the glass's
/// alpha, and only colour is compared.
fn with_alpha_of(img: &Rgba, of: &Rgba) -> Rgba {
    let mut out = img.clone();
    for (p, q) in out.data.chunks_exact_mut(4).zip(of.data.chunks_exact(4)) {
        p[3] = q[3];
    }
    out
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
    let dir = fresh_dir("window_keys");
    let (mut v, _win) = open(&x, &dir, &[]);
    let (mut latency, mut render_ms) = (Vec::new(), Vec::new());
    for key in ["Left", "Left", "Up"] {
        let (l, ms) = key_to_frame(&x, &mut v, key);
        latency.push(l);
        render_ms.push(ms);
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
    let shot_rgb = with_alpha_of(&shot, &reference);
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
        "key-to-frame latency (xdotool key → --stats line): {:?}, median {:?}; \
         render time of those frames (ms): {render_ms:?}",
        latency,
        median(latency.clone())
    );
    quit(&mut v, &x, "Escape");
}

/// K and V in the window: a glTF file with two cameras and two variants; K looks through
/// its first camera, V draws its first variant (a reload of the scene), and the window then
/// shows what `--camera 0 --variant 0` renders headless, to the arrow-key test's tolerance
/// (the same llvmpipe, shaders and grid; a wrong camera or variant differs by far more).
#[test]
fn k_and_v_look_through_the_files_camera_and_variant() {
    let Some((_lock, x)) = setup() else { return };
    let dir = fresh_dir("window_views");
    let model = crate::gltf_views::views_file(&dir);
    let model = model.to_str().unwrap();
    let (mut v, _win) = open(&x, &dir, &[model]);
    key_to_frame(&x, &mut v, "k");
    key_to_frame(&x, &mut v, "v");
    // The variant reloads the scene: let any frames of the reload pass before the screenshot.
    v.drain_for(Duration::from_millis(500));
    let shot = screenshot(&x, &mut v);
    let mut headless = VIEW.to_vec();
    headless.extend_from_slice(&[model, "--camera", "0", "--variant", "0"]);
    let reference = render(&dir, "headless-camera-variant", &headless, &[]);
    let mut plain = VIEW.to_vec();
    plain.push(model);
    let before = render(&dir, "headless-orbit", &plain, &[]);
    let shot_rgb = with_alpha_of(&shot, &reference);
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
        "K and V did not change the view (max diff {} from the orbit view)",
        moved.max
    );
    quit(&mut v, &x, "Escape");
}

/// A glTF animation in the window: three presses of `.` show what `--time 3/15` renders
/// headless (to the K/V test's tolerance); Space plays (frames come with no input) and
/// Space again pauses: then not one frame is drawn, and the still is `glview -o` of the
/// moment its PNG text holds (the label is drawn after the screenshot's read-back).
#[test]
fn play_keys_step_play_and_pause() {
    let Some((_lock, x)) = setup() else { return };
    let dir = fresh_dir("window_play");
    let model = crate::play::animated_file(&dir);
    let model = model.to_str().unwrap();
    let (mut v, _win) = open(&x, &dir, &[model]);
    for _ in 0..3 {
        key_to_frame(&x, &mut v, "period");
    }
    let shot = screenshot(&x, &mut v);
    let t = format!("{}", 3.0f32 / 15.0);
    fn at<'a>(model: &'a str, t: &'a str) -> Vec<&'a str> {
        let mut a = VIEW.to_vec();
        a.extend_from_slice(&[model, "--time", t]);
        a
    }
    let reference = render(&dir, "headless-steps", &at(model, &t), &[]);
    let tolerance = 320 * 240 / 1000;
    let shot_rgb = with_alpha_of(&shot, &reference);
    assert_close(&dir, "steps", &shot_rgb, &reference, 0, tolerance, 2);
    let mut plain = VIEW.to_vec();
    plain.push(model);
    let before = render(&dir, "headless-static", &plain, &[]);
    let moved = diff(&shot, &before, 2);
    assert!(
        moved.max > 20,
        "3 steps did not move the box ({})",
        moved.max
    );
    let count = |lines: Vec<String>| lines.iter().filter(|l| l.starts_with('{')).count();
    x.xdotool(&["key", "space"]).expect("xdotool key space");
    let playing = count(v.drain_for(Duration::from_millis(700)));
    x.xdotool(&["key", "space"]).expect("xdotool key space");
    v.drain_for(Duration::from_millis(300));
    let paused = count(v.drain_for(Duration::from_secs(1)));
    eprintln!("window: {playing} frames in 0.7 s playing, {paused} in 1 s paused");
    assert!(playing >= 5, "{playing} frames in 0.7 s of playing");
    assert_eq!(paused, 0, "frames drawn while paused");
    let (shot, path) = screenshot_file(&x, &mut v);
    let o = glview::repro::options_of_png(&path).expect("the screenshot's options");
    let t = o.motion.time.expect("a moment");
    assert!(t > 0.25, "the clock did not move the time: {t}");
    let t = t.to_string();
    let reference = render(&dir, "headless-paused", &at(model, &t), &[]);
    let shot_rgb = with_alpha_of(&shot, &reference);
    assert_close(&dir, "paused", &shot_rgb, &reference, 0, tolerance, 2);
    quit(&mut v, &x, "Escape");
}

/// No input for three seconds: no frames and (almost) no CPU.
#[test]
fn idle_window_draws_nothing_and_sleeps() {
    let Some((_lock, x)) = setup() else { return };
    let dir = fresh_dir("window_idle");
    let (mut v, _win) = open(&x, &dir, &[]);
    // Let start-up events (map, expose, focus) settle, then measure.
    v.drain_for(Duration::from_secs(1));
    let (cpu0, ns0, t0) = (v.cpu_time(), v.cpu_time_ns(), Instant::now());
    let frames = v
        .drain_for(Duration::from_secs(3))
        .iter()
        .filter(|l| l.starts_with('{'))
        .count();
    let (cpu, wall) = (v.cpu_time() - cpu0, t0.elapsed());
    let share = cpu.as_secs_f64() / wall.as_secs_f64();
    let fine = ns0
        .zip(v.cpu_time_ns())
        .map(|(a, b)| Duration::from_nanos(b.saturating_sub(a)));
    eprintln!(
        "idle: {frames} frames, CPU {cpu:?} (utime+stime, 10 ms ticks; schedstat {fine:?}) in \
         {wall:?} = {:.2} %",
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
    let dir = fresh_dir("window_resize");
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
    let dir = fresh_dir("window_quit");
    for key in ["Escape", "q"] {
        let (mut v, _win) = open(&x, &dir, &[]);
        quit(&mut v, &x, key);
    }
}

/// A 25-pixel left-drag to the right (0.4°/pixel = −10° yaw) and one wheel notch up give the
/// view of `--keys "Left Left Plus"` (same tolerance as the arrow keys).
///
/// winit 0.30.13 reports a wheel turn made of X button 4 press *and* release events (xdotool,
/// VNC, evdev wheel emulation) as two notches (fixed upstream in winit PR #4386, not released
/// for 0.30); a real wheel arrives as XInput2 motion and counts once. So one emulated click
/// may zoom by one or two steps, and both are accepted.
#[test]
fn mouse_drag_and_wheel_match_keys() {
    let Some((_lock, x)) = setup() else { return };
    let dir = fresh_dir("window_mouse");
    let (mut v, win) = open(&x, &dir, &[]);
    x.xdotool(&["mousemove", "--window", &win, "100", "100"])
        .expect("mousemove");
    x.xdotool(&["mousedown", "1"]).expect("mousedown");
    x.xdotool(&["mousemove", "--window", &win, "125", "100"])
        .expect("mousemove");
    x.xdotool(&["mouseup", "1"]).expect("mouseup");
    v.wait_frame(FRAME);
    let dragged = screenshot(&x, &mut v);
    x.xdotool(&["click", "4"]).expect("wheel up");
    v.wait_frame(FRAME);
    let zoomed = screenshot(&x, &mut v);
    quit(&mut v, &x, "Escape");

    let opaque = |mut img: Rgba| {
        img.data.chunks_exact_mut(4).for_each(|p| p[3] = 255);
        img
    };
    let reference = |name: &str, keys: &str| {
        let mut args = VIEW.to_vec();
        args.extend_from_slice(&["--keys", keys]);
        opaque(render(&dir, name, &args, &[]))
    };
    let drag_ref = reference("headless-drag", "Left Left");
    assert_close(
        &dir,
        "drag-vs-headless",
        &dragged,
        &drag_ref,
        0,
        320 * 240 / 1000,
        2,
    );
    let one = reference("headless-wheel1", "Left Left Plus");
    let two = reference("headless-wheel2", "Left Left Plus Plus");
    let (d1, d2) = (diff(&zoomed, &one, 0), diff(&zoomed, &two, 0));
    let notches = if d1.max <= d2.max { 1 } else { 2 };
    eprintln!(
        "one wheel click zoomed {notches} step(s) (max diff {} / {})",
        d1.max, d2.max
    );
    let best = if notches == 1 { &one } else { &two };
    assert_close(
        &dir,
        "wheel-vs-headless",
        &zoomed,
        best,
        0,
        320 * 240 / 1000,
        2,
    );
}

/// `C` shows Phong and PBR side by side on one camera (each pane the headless render of its
/// size at the pane's distance, to rounding); `P` cycles to the PBR tier; `H` draws the overlay over the top-left
/// corner and hides it again.
#[test]
fn compare_mode_pbr_key_and_overlay() {
    let Some((_lock, x)) = setup() else { return };
    let dir = fresh_dir("window_compare");
    // A fixed distance (so the replay below is exact); each half scales it by the ratio of
    // its fit to the window's (`compare::split::pane_camera`), which the headless panes are
    // given as their distance.
    let (mut v, _win) = open(&x, &dir, &["--distance", "3"]);
    let mut window = VIEW.to_vec();
    window.extend_from_slice(&["--distance", "3"]);
    let (settings, scene) = common::settings_for(&window);
    let camera = glview::compare::split::pane_camera(
        &settings.camera,
        &scene.bounds,
        320.0 / 240.0,
        160.0 / 240.0,
    );
    assert!(camera.distance > 3.0, "a portrait half steps back");
    let distance = camera.distance.to_string();
    key_to_frame(&x, &mut v, "c");
    let shot = screenshot(&x, &mut v);
    let half = |img: &Rgba, right: bool| {
        let mut data = Vec::new();
        for y in 0..img.height {
            let s = ((y * img.width + if right { 160 } else { 0 }) * 4) as usize;
            data.extend_from_slice(&img.data[s..s + 160 * 4]);
        }
        Rgba {
            width: 160,
            height: img.height,
            data,
        }
    };
    let pane_args = |shading: &'static str| {
        vec![
            "--size",
            "160x240",
            "--yaw",
            "30",
            "--pitch",
            "15",
            "--distance",
            distance.as_str(),
            "--shading",
            shading,
        ]
    };
    for (right, shading) in [(false, "phong"), (true, "pbr")] {
        let headless = render(&dir, shading, &pane_args(shading), &[]);
        let pane = with_alpha_of(&half(&shot, right), &headless);
        assert_close(
            &dir,
            &format!("pane-{shading}"),
            &pane,
            &headless,
            2,
            160 * 240 / 500,
            8,
        );
    }
    key_to_frame(&x, &mut v, "c");
    key_to_frame(&x, &mut v, "p");
    key_to_frame(&x, &mut v, "p");
    let (pbr, pbr_file) = screenshot_file(&x, &mut v);
    // The screenshot's PNG text holds what the keys that changed state stand for (P P is
    // `--shading pbr`; `c` only split the window) with the camera and size: headless gives
    // the same picture to the window-vs-headless tolerance of
    // `arrow_keys_match_headless_render`.
    let text = glview::image_out::png_text(&pbr_file).unwrap();
    let command = &text.iter().find(|(k, _)| k == "glview.command").unwrap().1;
    assert!(
        command.contains("--shading pbr") && !command.contains("--keys"),
        "{command}"
    );
    let words = shlex::split(command).unwrap();
    let words: Vec<&str> = words[1..].iter().map(String::as_str).collect();
    let replayed = with_alpha_of(&render(&dir, "pbr-replayed", &words, &[]), &pbr);
    assert_close(
        &dir,
        "pbr-replayed",
        &pbr,
        &replayed,
        0,
        320 * 240 / 1000,
        2,
    );
    let headless_pbr = render(
        &dir,
        "pbr-full",
        &[
            "--size",
            "320x240",
            "--yaw",
            "30",
            "--pitch",
            "15",
            "--distance",
            "3",
            "--shading",
            "pbr",
        ],
        &[],
    );
    assert!(
        diff(&pbr, &headless_pbr, 8).over < 320 * 240 / 500,
        "P P did not reach the PBR tier"
    );
    key_to_frame(&x, &mut v, "h");
    let with_overlay = screenshot(&x, &mut v);
    let corner = |img: &Rgba| {
        (0..40)
            .flat_map(|y| (0..120).map(move |x| (x, y)))
            .filter(|&(x, y)| img.pixel(x, y) != pbr.pixel(x, y))
            .count()
    };
    assert!(corner(&with_overlay) > 300, "the overlay is not drawn");
    key_to_frame(&x, &mut v, "h");
    let without = screenshot(&x, &mut v);
    assert_eq!(corner(&without), 0, "the overlay did not go away");
    quit(&mut v, &x, "Escape");
}

/// `--aa msaa|ssaa|fxaa` in the window: MSAA through a multisampled framebuffer resolved into
/// the back buffer, SSAA drawn 2× larger and box-filtered on the GPU, FXAA as the post pass;
/// each screenshot equals the headless render of the same options (≤ 2/255, at most 0.1 % of
/// pixels off by more than 1: the GPU box filter rounds ties as the CPU one does, to within one
/// step) and differs from the aliased frame.
#[test]
fn anti_aliasing_matches_headless_render() {
    let Some((_lock, x)) = setup() else { return };
    let dir = fresh_dir("window_aa");
    let plain = render(&dir, "headless-none", VIEW, &[]);
    for (name, aa) in [
        ("msaa", &["--aa", "msaa", "--aa-samples", "4"][..]),
        ("ssaa", &["--aa", "ssaa", "--aa-samples", "2"][..]),
        ("fxaa", &["--aa", "fxaa"][..]),
    ] {
        let (mut v, _win) = open(&x, &dir, aa);
        let mut shot = screenshot(&x, &mut v);
        quit(&mut v, &x, "Escape");
        let mut args = VIEW.to_vec();
        args.extend_from_slice(aa);
        let reference = render(&dir, &format!("headless-{name}"), &args, &[]);
        for (p, q) in shot
            .data
            .chunks_exact_mut(4)
            .zip(reference.data.chunks_exact(4))
        {
            p[3] = q[3];
        }
        let d = diff(&shot, &reference, 1);
        eprintln!(
            "window {name}: max {} mean {:.4}, {} pixels > 1 from headless",
            d.max, d.mean, d.over
        );
        assert_close(
            &dir,
            &format!("window-{name}-vs-headless"),
            &shot,
            &reference,
            1,
            320 * 240 / 1000,
            2,
        );
        let changed = diff(&shot, &plain, 8).over;
        assert!(
            changed > 50,
            "{name}: the window frame is not anti-aliased ({changed} pixels changed)"
        );
    }
}

/// Bloom and FXAA in a GL 2.1 window without framebuffer objects (Mesa's overrides): the
/// copy-to-texture path draws in the back buffer and copies from it; the screenshot equals
/// the headless OSMesa render of the same options (measured: identical).
#[test]
fn post_without_framebuffer_objects_matches_headless() {
    let Some((_lock, x)) = setup() else { return };
    let dir = fresh_dir("window_post_copy");
    let opts = [
        "--shading",
        "pbr",
        "--bloom",
        "1",
        "--bloom-threshold",
        "0.6",
        "--aa",
        "fxaa",
        "--gl",
        "2.1",
    ];
    let (mut v, _win) = open_env(&x, &dir, &opts, common::GL21_NO_FBO);
    let mut shot = screenshot(&x, &mut v);
    let copy_path = v.seen.iter().any(|l| l.contains("post(copy, bloom"));
    quit(&mut v, &x, "Escape");
    assert!(
        copy_path,
        "the window did not take the copy path: {:?}",
        v.seen
    );
    let mut args = VIEW.to_vec();
    args.extend_from_slice(&opts);
    args.extend_from_slice(&["--backend", "osmesa"]);
    let reference = render(&dir, "headless-copy", &args, common::GL21_NO_FBO);
    for (p, q) in shot
        .data
        .chunks_exact_mut(4)
        .zip(reference.data.chunks_exact(4))
    {
        p[3] = q[3];
    }
    let d = diff(&shot, &reference, 1);
    eprintln!(
        "window copy path against headless: max {} mean {:.4}",
        d.max, d.mean
    );
    assert_close(
        &dir,
        "window-copy-vs-headless",
        &shot,
        &reference,
        1,
        320 * 240 / 1000,
        2,
    );
}

/// `C` splits the window into Phong | PBR, each half framed for its own aspect: each half of
/// the screenshot is the headless `--compare` pane of that size, which is fitted to the pane
/// (`compare::split_view_panes_frame_the_model` checks that the model lies inside it).
#[test]
fn split_view_frames_each_half() {
    let Some((_lock, x)) = setup() else { return };
    let dir = fresh_dir("window_split");
    let duck = common::shared().join("gltf-samples/Duck/Duck.glb");
    let duck = duck.to_str().unwrap();
    let (mut v, _win) = open(&x, &dir, &[duck]);
    key_to_frame(&x, &mut v, "c");
    let shot = screenshot(&x, &mut v);
    quit(&mut v, &x, "q");
    let out = dir.join("compare.png");
    let mut args = vec![duck, "--compare", "phong,pbr", "--size", "160x240"];
    args.extend_from_slice(&VIEW[2..]);
    args.extend_from_slice(&["-o", out.to_str().unwrap()]);
    let o = common::run(&args, &[]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let panes = Rgba::load_png(&out).unwrap();
    let strip = panes.height - 240;
    let crop = |img: &Rgba, x0: u32, y0: u32| {
        let mut data = Vec::new();
        for y in y0..y0 + 240 {
            let s = ((y * img.width + x0) * 4) as usize;
            data.extend_from_slice(&img.data[s..s + 160 * 4]);
        }
        Rgba {
            width: 160,
            height: 240,
            data,
        }
    };
    for i in 0..2 {
        let (half, pane) = (crop(&shot, i * 160, 0), crop(&panes, i * 160, strip));
        let name = format!("half-{i}");
        // The window's distance is the fit to the whole window scaled by the ratio of the
        // two fits, the headless pane's the fit itself: one float rounding apart, which moves
        // a few silhouette pixels (measured: 11 pixels of 38,400, up to 6/255, in the PBR half).
        assert_close(&dir, &name, &half, &pane, 0, 160 * 240 / 1000, 8);
    }
}

/// Stereo in the window: rows follow the screen (moved down one row, each row shows the
/// other eye: the headless picture with the eyes swapped), `T` cycles the modes, `Y` swaps
/// the eyes, `}` widens the separation; each screenshot equals its headless picture.
#[test]
fn stereo_rows_follow_the_screen_and_keys_cycle_the_modes() {
    let Some((_lock, x)) = setup() else { return };
    let dir = fresh_dir("window_stereo");
    let (mut v, win) = open(&x, &dir, &["--stereo", "rows"]);
    let check = |v: &mut Viewer, name: &str, headless: &[&str]| {
        let shot = screenshot(&x, v);
        let mut args = VIEW.to_vec();
        args.extend_from_slice(headless);
        let reference = render(&dir, name, &args, &[]);
        let shot = with_alpha_of(&shot, &reference);
        assert_close(&dir, name, &shot, &reference, 0, 320 * 240 / 1000, 2);
        reference
    };
    let move_to = |v: &mut Viewer, y: &str| {
        x.xdotool(&["windowmove", "--sync", &win, "10", y])
            .expect("xdotool windowmove");
        v.wait_frame(FRAME);
        v.drain_for(Duration::from_millis(300));
    };
    move_to(&mut v, "20");
    let even = check(&mut v, "rows-even", &["--stereo", "rows"]);
    move_to(&mut v, "21");
    let odd = check(&mut v, "rows-odd", &["--stereo", "rows", "--swap-eyes"]);
    assert!(
        diff(&even, &odd, 8).over > 1000,
        "the row parity changes the picture"
    );
    move_to(&mut v, "20");
    key_to_frame(&x, &mut v, "t");
    check(&mut v, "columns", &["--stereo", "columns"]);
    key_to_frame(&x, &mut v, "y");
    check(
        &mut v,
        "columns-swapped",
        &["--stereo", "columns", "--swap-eyes"],
    );
    key_to_frame(&x, &mut v, "braceright");
    // The default separation (the fitted distance / 30) times 1.25, as glview computes it.
    let (s, _) = common::settings_for(&[VIEW, &["--stereo", "columns"][..]].concat());
    let wider = format!("{}", s.stereo.separation * 1.25);
    check(
        &mut v,
        "columns-wider",
        &[
            "--stereo",
            "columns",
            "--swap-eyes",
            "--eye-separation",
            &wider,
        ],
    );
    quit(&mut v, &x, "Escape");
}

/// `--stereo quad-buffer` where the driver has no stereo configs (Mesa's GLX and EGL on
/// Xvfb): one line naming what it offered, exit status non-zero, no window left.
#[test]
fn quad_buffer_without_stereo_configs_is_a_one_line_error() {
    let Some((_lock, x)) = setup() else { return };
    let o = std::process::Command::new(bin())
        .args(VIEW)
        .args(["--stereo", "quad-buffer"])
        .env("DISPLAY", &x.display)
        .output()
        .expect("run glview");
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success(), "a quad-buffered window opened:\n{err}");
    assert!(
        err.contains("none with stereo (GL_STEREO) buffers"),
        "{err}"
    );
    assert_eq!(err.trim().lines().count(), 1, "{err}");
}
