//! Playing glTF animations in `glview serve` (issue 39) on a generated file: a moment set
//! from the page (time message, `.` steps) is drawn as `glview -o --time` draws it; a play
//! message makes frames with increasing times at most `--fps` a second; paused, nothing is
//! drawn; a follower gets the presenter's time; bad values get a one-line error. The
//! window's play keys are tested in window.rs with the same file.
use crate::common;
use crate::gltf_materials::b64;
use crate::serve::{assert_same, cli_png, SIZE};
use crate::serve_client::{decode_png, Client, Got, Server};
use serde_json::{json, Value};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// The box of gltf_views's file, with two animations of its node: "Slide" (LINEAR
/// translation along +X by 1 over 2 s) and "Turn" (a 45° turn about +Y over 1 s).
pub(crate) fn animated_file(dir: &Path) -> PathBuf {
    let views = crate::gltf_views::views_file(dir);
    let mut doc: Value = serde_json::from_str(&std::fs::read_to_string(views).unwrap()).unwrap();
    let at = doc["nodes"][0]["translation"].clone();
    let c: Vec<f32> = (0..3).map(|i| at[i].as_f64().unwrap() as f32).collect();
    let s = std::f32::consts::FRAC_PI_8.sin();
    let floats: Vec<f32> = [
        vec![0.0, 1.0, 2.0],
        vec![
            c[0],
            c[1],
            c[2],
            c[0] + 0.5,
            c[1],
            c[2],
            c[0] + 1.0,
            c[1],
            c[2],
        ],
        vec![0.0, 1.0],
        vec![
            0.0,
            0.0,
            0.0,
            1.0,
            0.0,
            s,
            0.0,
            std::f32::consts::FRAC_PI_8.cos(),
        ],
    ]
    .concat();
    let bin: Vec<u8> = floats.iter().flat_map(|f| f.to_le_bytes()).collect();
    let buffer = doc["buffers"].as_array().unwrap().len();
    let views = doc["bufferViews"].as_array().unwrap().len();
    let acc = doc["accessors"].as_array().unwrap().len();
    doc["buffers"]
        .as_array_mut()
        .unwrap()
        .push(json!({"byteLength": bin.len(),
        "uri": format!("data:application/octet-stream;base64,{}", b64(&bin))}));
    doc["bufferViews"]
        .as_array_mut()
        .unwrap()
        .push(json!({"buffer": buffer, "byteLength": bin.len()}));
    let accessor = |offset: usize, count: usize, kind: &str, range: Option<(f32, f32)>| {
        let mut a = json!({"bufferView": views, "byteOffset": offset * 4, "componentType": 5126,
            "count": count, "type": kind});
        if let Some((lo, hi)) = range {
            a["min"] = json!([lo]);
            a["max"] = json!([hi]);
        }
        a
    };
    doc["accessors"].as_array_mut().unwrap().extend([
        accessor(0, 3, "SCALAR", Some((0.0, 2.0))),
        accessor(3, 3, "VEC3", None),
        accessor(12, 2, "SCALAR", Some((0.0, 1.0))),
        accessor(14, 2, "VEC4", None),
    ]);
    let channel = |sampler_input: usize, path: &str| {
        json!({"channels": [{"sampler": 0, "target": {"node": 0, "path": path}}],
            "samplers": [{"input": acc + sampler_input, "output": acc + sampler_input + 1,
                "interpolation": "LINEAR"}]})
    };
    let mut slide = channel(0, "translation");
    slide["name"] = "Slide".into();
    let mut turn = channel(2, "rotation");
    turn["name"] = "Turn".into();
    doc["animations"] = json!([slide, turn]);
    let p = dir.join("animated.gltf");
    std::fs::write(&p, serde_json::to_string(&doc).unwrap()).unwrap();
    p
}

/// A server of the animated file, written in the test's own folder (a file rewritten under
/// another test's server is another scene to it, loaded again).
fn start(test: &str, extra: &[&str]) -> (Server, String) {
    let model = animated_file(&common::out_dir(&format!("serve-play-{test}")));
    let model = model.to_str().unwrap().to_string();
    let mut args = vec!["--size", SIZE, &model];
    args.extend_from_slice(extra);
    (Server::start(&args), model)
}

/// The header's time (None: the static pose).
fn time(h: &Value) -> Option<f64> {
    h["motion"]["time"].as_f64()
}

/// Acknowledged frames for `wait` (stopping early at `until` frames).
fn frames_for(c: &mut Client, wait: Duration, until: usize) -> Vec<Value> {
    let start = Instant::now();
    let mut got = Vec::new();
    while start.elapsed() < wait && got.len() < until {
        if let Some(Got::Frame(h, _)) = c.next_within(wait.saturating_sub(start.elapsed())) {
            c.send(json!({"type": "ack", "frame": h["frame"]}));
            got.push(h);
        }
    }
    got
}

/// A moment set from the page is the command line's still of it, pixel for pixel: the time
/// message, three `.` steps (`--time` 10/15 exactly) and another animation by index. Bad
/// values get a one-line error and the view goes on.
#[test]
fn served_moments_are_the_command_lines() {
    let (server, model) = start("moments", &[]);
    let mut c = server.viewer("");
    let (h, _, _) = c.still(None);
    assert_eq!(time(&h), None, "the static pose first: {h}");
    assert_eq!(h["motion"]["animations"][1]["name"], "Turn", "{h}");
    c.send(json!({"type": "time", "seconds": 0.5, "seq": 1}));
    let (h, png, _) = c.still(Some(1));
    assert!(h["command"].as_str().unwrap().contains("--time 0.5"), "{h}");
    assert_same(
        "t05",
        &decode_png(&png),
        &cli_png("t05", &[&model, "--time", "0.5"]),
    );
    for seq in 2..=4 {
        c.send(json!({"type": "key", "key": ".", "seq": seq}));
    }
    let (h, png, _) = c.still(Some(4));
    let t = format!("{}", 10.0f32 / 15.0);
    assert_eq!(time(&h), Some(f64::from(10.0f32 / 15.0)), "{h}");
    assert_same(
        "steps",
        &decode_png(&png),
        &cli_png("steps", &[&model, "--time", &t]),
    );
    c.send(json!({"type": "time", "seconds": 0.25, "animation": 1, "seq": 5}));
    let (_, png, _) = c.still(Some(5));
    let want = cli_png("turn", &[&model, "--animation", "1", "--time", "0.25"]);
    assert_same("turn", &decode_png(&png), &want);
    for bad in [
        r#"{"type":"time","seconds":NaN}"#,
        r#"{"type":"time","seconds":-1}"#,
        r#"{"type":"time","seconds":1,"animation":7,"seq":6}"#,
    ] {
        c.send_raw(bad);
        let e = c.text("error");
        let m = e["message"].as_str().unwrap();
        assert!(!m.contains('\n') && e["closing"] == false, "{bad}: {e}");
    }
    c.send(json!({"type": "time", "seconds": 0.5, "seq": 7}));
    let (h, _, _) = c.still(Some(7));
    assert_eq!(
        (time(&h), h["motion"]["animation"].as_u64()),
        (Some(0.5), Some(1))
    );
}

/// Play: frames with increasing times, at most `--fps` a second (each time at least one
/// frame interval after the last); pause: one still, which is the command line's picture of
/// its moment, then nothing drawn at all.
#[test]
fn play_advances_at_fps_and_pause_draws_nothing() {
    let (server, model) = start("fps", &["--fps", "10"]);
    let mut c = server.viewer("");
    c.still(None);
    c.send(json!({"type": "play", "on": true, "seq": 1}));
    let window = Duration::from_millis(1200);
    let frames = frames_for(&mut c, window, usize::MAX);
    let times: Vec<f64> = frames
        .iter()
        .filter(|h| h["seq"].as_u64() >= Some(1))
        .filter_map(time)
        .collect();
    eprintln!(
        "playing at --fps 10 for {window:?}: {} frames, times {times:?}",
        times.len()
    );
    assert!(times.len() >= 3, "{times:?}");
    assert!(times.len() <= 14, "more than --fps frames: {times:?}");
    for w in times.windows(2) {
        assert!(w[1] - w[0] >= 0.099, "frames closer than 1/fps: {times:?}");
    }
    c.send(json!({"type": "play", "on": false, "seq": 2}));
    let (h, png, _) = c.still(Some(2));
    assert_eq!(h["motion"]["playing"], false);
    let t = format!("{}", time(&h).unwrap() as f32);
    assert_same(
        "paused",
        &decode_png(&png),
        &cli_png("paused", &[&model, "--time", &t]),
    );
    let before = server.cpu_ticks();
    let idle = frames_for(&mut c, Duration::from_secs(1), usize::MAX);
    assert_eq!(idle.len(), 0, "frames drawn while paused: {idle:?}");
    let ticks = server.cpu_ticks() - before;
    assert!(ticks < 3, "{ticks} ticks of CPU in a second paused");
}

/// A follower gets the presenter's playing frames (the presenter's times, the presenter's
/// bytes); leaving the class it plays on from the class's time.
#[test]
fn a_follower_gets_the_presenters_time() {
    let (server, _) = start("follow", &[]);
    let mut p = server.viewer(&format!("&present={}", server.presenter_key));
    let mut f = server.viewer("");
    p.still(None);
    f.still(None);
    f.send(json!({"type": "follow", "on": true}));
    p.send(json!({"type": "play", "on": true, "seq": 1}));
    // Both pages read and acknowledge as they go (a follower is sent the newest frame
    // once it acknowledged the last).
    let (mut played, mut followed) = (Vec::new(), Vec::new());
    let start = Instant::now();
    while start.elapsed() < Duration::from_millis(800) {
        played.extend(frames_for(&mut p, Duration::from_millis(20), 1));
        followed.extend(frames_for(&mut f, Duration::from_millis(20), 1));
    }
    p.send(json!({"type": "play", "on": false, "seq": 2}));
    let (hp, _, _) = p.still(Some(2));
    let mut seen = Vec::new();
    let mut followed = followed.into_iter();
    loop {
        let h = followed.next().unwrap_or_else(|| f.frame(true).0);
        assert_eq!(h["presenter"], true, "{h}");
        // Frames from before the play (the one sent on following) are not among these.
        if let Some(same) = played
            .iter()
            .chain([&hp])
            .find(|p| p["frame"] == h["frame"])
        {
            assert_eq!(time(same), time(&h));
            seen.extend(time(&h));
        }
        if h["frame"] == hp["frame"] {
            break;
        }
    }
    seen.dedup();
    assert!(seen.len() >= 2, "the follower saw no time move: {seen:?}");
    f.send(json!({"type": "play", "on": true, "seq": 1}));
    let own = frames_for(&mut f, Duration::from_millis(400), 3);
    let t = own
        .iter()
        .filter_map(time)
        .next_back()
        .expect("its own frames");
    assert!(
        own.iter().all(|h| h["presenter"] == false) && t >= time(&hp).unwrap(),
        "{own:?}"
    );
}

/// `--keys` replays the play keys headless, where there is no clock: Space is the moment
/// shown (time 0 from the static pose), `.` steps are `--time k/fps`, `A` is the next
/// animation at 0; pixel for pixel. On a file without animations Space is a one-line error.
#[test]
fn play_keys_replayed_headless_are_moments() {
    let dir = common::out_dir("play-keys");
    let model = animated_file(&dir);
    let model = model.to_str().unwrap();
    let shot = |name: &str, extra: &[&str]| {
        let mut a = vec![model, "--size", "64x48"];
        a.extend_from_slice(extra);
        common::render(&dir, name, &a, &[])
    };
    let still = shot("static", &[]);
    for (name, keys, moment) in [
        ("space", "Space", &["--time", "0"][..]),
        ("steps", ". . .", &["--time", "0.2"][..]),
        (
            "space-steps",
            ". . . Space , Space",
            &["--time", "0.13333334"][..],
        ),
        // The file's two animations drive different nodes: both play by default (the last
        // entry, "all"), and `A` goes on to the first.
        ("next", "A", &["--animation", "0", "--time", "0"][..]),
        ("next-next", "A A", &["--animation", "1", "--time", "0"][..]),
        ("all", "A A A", &["--animation", "all", "--time", "0"][..]),
    ] {
        let replayed = shot(&format!("keys-{name}"), &["--keys", keys]);
        let want = shot(&format!("time-{name}"), moment);
        assert!(
            replayed.data == want.data,
            "--keys {keys:?} is not {moment:?}"
        );
        if name == "steps" {
            let d = common::diff(&replayed, &still, 2);
            assert!(d.max > 20, "three steps did not move the box ({})", d.max);
        }
    }
    let out = dir.join("static-model.png");
    let o = common::run(
        &[
            "--size",
            "64x48",
            "--keys",
            "Space",
            "-o",
            out.to_str().unwrap(),
        ],
        &[],
    );
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        !o.status.success() && err.trim().lines().count() == 1,
        "{err}"
    );
    assert!(err.contains("no animations"), "{err}");
}
