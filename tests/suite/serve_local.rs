//! `glview serve`'s local mode (issue 52) without a browser: pages that draw the view
//! themselves get its state and no picture. A class of 30 local followers and a local
//! presenter: every follower reaches the presenter's state within a frame of the presenter's
//! own, ends on exactly its state, and the server draws no picture meanwhile; a streaming
//! follower still gets pictures; the build and the scenes are served behind the token. The
//! browser's half (the page drawing) is python/tests_web/test_serve_local.py.
use super::common;
use super::serve_client::{Got, Server};
use serde_json::{json, Value};
use std::path::PathBuf;
use std::sync::Mutex;
use std::time::{Duration, Instant};

const SIZE: &str = "160x120";
const FOLLOWERS: usize = 30;
/// Presenter inputs in the class test, one every 33 ms (a 30 Hz drag).
const INPUTS: u64 = 30;

/// A stand-in browser build: the server only serves it (the real one is the browser tests').
fn fake_web_dir() -> PathBuf {
    let dir = common::out_dir("serve_local").join("web");
    std::fs::create_dir_all(dir.join("no-modules")).unwrap();
    std::fs::write(dir.join("glview_web_bg.wasm"), b"\0asm\x01\0\0\0").unwrap();
    std::fs::write(dir.join("no-modules/glview_web.js"), "var wasm_bindgen;\n").unwrap();
    dir
}

fn local_server(extra: &[&str]) -> Server {
    sized_server(SIZE, extra)
}

fn sized_server(size: &str, extra: &[&str]) -> Server {
    let web = fake_web_dir();
    let mut args = vec!["--size", size, "--web-dir", web.to_str().unwrap()];
    args.extend_from_slice(extra);
    Server::start(&args)
}

/// The next frame (acknowledged), skipping text.
fn frame(c: &mut super::serve_client::Client) -> Value {
    c.frame(true).0
}

/// A viewer in local mode: hello, its first picture, then state frames only.
fn local_viewer(server: &Server, query: &str) -> super::serve_client::Client {
    let mut c = server.viewer(query);
    let hello = c.text("hello");
    assert_eq!(
        (hello["protocol"].as_u64(), hello["local"].as_bool()),
        (Some(2), Some(true))
    );
    c.still(None);
    c.send(json!({"type": "local", "on": true}));
    // Its state now, without a picture.
    loop {
        let (h, img) = c.frame(true);
        if h["format"] == "none" {
            assert!(img.is_empty());
            assert!(h["state"]["options"].is_object(), "{h}");
            return c;
        }
    }
}

/// What a class did while the presenter dragged.
struct Class {
    /// Each input's lag, sorted: from the presenter's frame showing it to a follower's.
    lags: Vec<f64>,
    /// Pictures the server drew meanwhile.
    drawn: u64,
    /// The server's CPU, in cores.
    cpu: f64,
    /// The presenter's frames, and every follower's last one.
    presenter_frames: usize,
    last: Value,
    followers_last: Vec<Value>,
}

impl Class {
    fn lag(&self, q: f64) -> f64 {
        self.lags[((self.lags.len() - 1) as f64 * q) as usize]
    }
}

/// A presenter and [`FOLLOWERS`] followers, all local or all streaming, with views of
/// `size`; the presenter drags [`INPUTS`] times at 30 Hz, every frame acknowledged at once
/// as a page does.
fn class(local: bool, size: &str) -> Class {
    let server = sized_server(
        size,
        &["--max-viewers-per-address", "64", "--max-viewers", "64"],
    );
    let join = |query: &str| {
        if local {
            local_viewer(&server, query)
        } else {
            let mut c = server.viewer(query);
            c.still(None);
            c
        }
    };
    let mut p = join(&format!("&present={}", server.presenter_key));
    let mut followers: Vec<_> = (0..FOLLOWERS).map(|_| join("")).collect();
    for f in &mut followers {
        f.send(json!({"type": "follow", "on": true}));
    }
    // The presenter's frame before the class moves: the count of pictures drawn.
    p.send(json!({"type": "key", "key": "S", "seq": 1}));
    let before = loop {
        let h = frame(&mut p);
        if h["seq"] == 1 && (local || h["still"] == true) {
            break h;
        }
    };
    let drawn_before = before["drawn"].as_u64().unwrap();
    let cpu_before = server.cpu_ticks();
    let start = Instant::now();
    // Followers record when each of the presenter's inputs first reached them.
    let arrivals: Vec<Mutex<Vec<(u64, Instant, Value)>>> =
        (0..FOLLOWERS).map(|_| Mutex::new(Vec::new())).collect();
    let mut own = Vec::new();
    std::thread::scope(|s| {
        for (f, log) in followers.iter_mut().zip(&arrivals) {
            s.spawn(move || loop {
                match f.next_within(Duration::from_secs(20)) {
                    Some(Got::Frame(h, img)) => {
                        assert!(
                            !local || img.is_empty(),
                            "a local follower was sent a picture"
                        );
                        f.send(json!({"type": "ack", "frame": h["frame"]}));
                        let seq = h["seq"].as_u64().unwrap_or(0);
                        log.lock().unwrap().push((seq, Instant::now(), h));
                        if seq == INPUTS + 1 {
                            return;
                        }
                    }
                    Some(Got::Text(_)) => {}
                    other => panic!("a follower lost the class: {}", other.is_some()),
                }
            });
        }
        let mut next = Instant::now();
        let mut seq = 1;
        while own
            .last()
            .is_none_or(|(s, _, _): &(u64, Instant, Value)| *s < INPUTS + 1)
        {
            if seq <= INPUTS && Instant::now() >= next {
                seq += 1;
                p.send(json!({"type": "drag", "dx": 3, "dy": 1, "seq": seq}));
                next += Duration::from_millis(33);
            }
            if let Some(Got::Frame(h, img)) = p.next_within(Duration::from_millis(5)) {
                assert!(
                    !local || img.is_empty(),
                    "a local presenter was sent a picture"
                );
                p.send(json!({"type": "ack", "frame": h["frame"]}));
                own.push((h["seq"].as_u64().unwrap(), Instant::now(), h));
            }
            assert!(
                start.elapsed() < Duration::from_secs(60),
                "the presenter's frames stopped"
            );
        }
    });
    let secs = start.elapsed().as_secs_f64();
    let cpu = (server.cpu_ticks() - cpu_before) as f64 / 100.0 / secs;
    let mut lags = Vec::new();
    let mut followers_last = Vec::new();
    for log in &arrivals {
        let log = log.lock().unwrap();
        followers_last.push(log.last().unwrap().2.clone());
        for (seq, at, _) in own.iter() {
            let reached = log.iter().find(|(s, _, _)| s >= seq).expect("reached");
            lags.push(reached.1.saturating_duration_since(*at).as_secs_f64() * 1e3);
        }
    }
    lags.sort_by(f64::total_cmp);
    let last = own.last().unwrap().2.clone();
    let c = Class {
        lags,
        drawn: last["drawn"].as_u64().unwrap() - drawn_before,
        cpu,
        presenter_frames: own.len(),
        last,
        followers_last,
    };
    println!(
        "{} class at {size}: {FOLLOWERS} followers, {} presenter frames in {secs:.2} s; follower lag \
         median {:.2} ms, p95 {:.2} ms, max {:.2} ms; pictures drawn {}; server CPU {:.1} % of a core",
        if local { "local" } else { "streaming" },
        c.presenter_frames,
        c.lag(0.5),
        c.lag(0.95),
        c.lag(1.0),
        c.drawn,
        c.cpu * 100.0
    );
    c
}

#[test]
fn a_local_class_follows_the_presenter_and_costs_no_pictures() {
    let c = class(true, SIZE);
    for h in &c.followers_last {
        assert_eq!(
            h["state"], c.last["state"],
            "a follower ended on another view"
        );
        assert_eq!(h["presenter"], true);
    }
    assert_eq!(c.drawn, 0, "the server drew for a class that draws itself");
    // One frame at 60 Hz: the followers' states leave in the same turn as the presenter's.
    assert!(
        c.lag(0.5) < 1000.0 / 60.0,
        "median lag {:.1} ms",
        c.lag(0.5)
    );
    assert!(
        c.last["state"]["options"]["camera"]["yaw"]
            .as_f64()
            .unwrap()
            != 0.0
    );
}

/// The benchmark (docs/benchmarks.md): the same class streaming and local, side by side,
/// at serve's default size. `cargo test -p glview-cli --test suite serve_local::bench --
/// --ignored --nocapture`.
#[test]
#[ignore]
fn bench_a_class_streaming_and_local() {
    let (stream, local) = (class(false, "1024x768"), class(true, "1024x768"));
    println!(
        "server CPU for the class: streaming {:.1} %, local {:.1} % of a core ({:.0}× less); \
         pictures {} vs {}",
        stream.cpu * 100.0,
        local.cpu * 100.0,
        stream.cpu / local.cpu.max(1e-9),
        stream.drawn,
        local.drawn
    );
}

/// A streaming follower of a local presenter gets pictures (drawn for it alone); the
/// presenter itself still gets states.
#[test]
fn a_streaming_follower_of_a_local_presenter_gets_pictures() {
    let server = local_server(&[]);
    let mut p = local_viewer(&server, &format!("&present={}", server.presenter_key));
    let mut f = server.viewer("");
    f.still(None);
    f.send(json!({"type": "follow", "on": true}));
    p.send(json!({"type": "key", "key": "Right", "seq": 7}));
    // The presenter acknowledges its states, as its page does: its next frame waits for it.
    loop {
        let (h, img) = p.frame(true);
        assert!(img.is_empty(), "the local presenter was sent a picture");
        if h["seq"] == 7 {
            break;
        }
    }
    // A picture of the presenter's view follows (the presenter's still would wait for
    // the presenter's next acknowledgement, which this test does not send).
    let h = loop {
        let (h, img) = f.frame(true);
        if !img.is_empty() && h["seq"] == 7 {
            break h;
        }
    };
    assert_eq!(h["presenter"], true);
    // The built-in scene's yaw is 30; Right turns it by 5.
    assert!(h["command"].as_str().unwrap().contains("--yaw 35"), "{h}");
}

/// A page on the stream is sent pictures without the view's state (~3 KB a frame); a
/// streaming presenter's frames carry it from the moment a follower draws itself (one
/// frame serves the presenter and its class), and that follower gets the presenter's view
/// as state.
#[test]
fn the_state_goes_only_to_pages_that_draw() {
    let server = local_server(&[]);
    let mut p = server.viewer(&format!("&present={}", server.presenter_key));
    let (h, img, _) = p.still(None);
    assert!(!img.is_empty() && h["state"].is_null(), "{h}");
    let mut f = local_viewer(&server, "");
    f.send(json!({"type": "follow", "on": true}));
    // Following: the presenter's last frame comes (its picture had no state to take).
    while f.frame(true).0["presenter"] != true {}
    p.send(json!({"type": "key", "key": "Right", "seq": 3}));
    // The presenter's own frames carry it now (the same frame goes to the class); it
    // acknowledges them, as its page does: its next frame waits for that.
    let h = loop {
        let (h, _) = p.frame(true);
        if h["seq"] == 3 {
            break h;
        }
    };
    assert!(h["state"].is_object(), "{h}");
    // The follower takes the presenter's frames: a state, turned by the key.
    let h = loop {
        let (h, img) = f.frame(true);
        if h["presenter"] == true && h["seq"] == 3 {
            assert!(img.is_empty() || h["state"].is_object(), "{h}");
            if h["state"].is_object() {
                break h;
            }
        }
    };
    assert_eq!(h["state"]["options"]["camera"]["yaw"], 35.0, "{h}");
}

/// The build and the scenes are served behind the token, named by the model list only; a
/// server without a build says so in the hello and on the socket.
#[test]
fn the_build_and_the_scenes_are_behind_the_token() {
    let server = local_server(&[]);
    let t = &server.token;
    let (status, body) = server.get(&format!("/scene?token={t}"));
    assert_eq!(status, 200, "{body}");
    let json: Value = serde_json::from_str(body.split("\r\n\r\n").nth(1).unwrap()).unwrap();
    assert!(
        json["words"].is_array() && json["maps"].is_string(),
        "{json}"
    );
    assert!(
        json["files"].as_array().unwrap().is_empty(),
        "the built-in scene has no files"
    );
    let (status, body) = server.get(&format!("/scene?token={t}&model=../../etc/passwd"));
    assert_eq!(status, 404, "{body}");
    assert_eq!(body.split("\r\n\r\n").nth(1).unwrap().lines().count(), 1);
    let (status, body) = server.get(&format!("/web/glview_web_bg.wasm?token={t}"));
    assert_eq!(status, 200);
    assert!(body.contains("Content-Encoding: gzip"), "{body}");
    for path in ["/scene", "/web/glview_web_bg.wasm", "/web/glview_web.js"] {
        assert_eq!(server.get(path).0, 401, "{path} without the token");
    }
    assert_eq!(server.get(&format!("/web/other.wasm?token={t}")).0, 404);

    let plain = Server::start(&["--size", SIZE, "--stream-only"]);
    assert_eq!(plain.get(&format!("/scene?token={}", plain.token)).0, 404);
    let mut c = plain.viewer("");
    assert_eq!(c.text("hello")["local"], false);
    c.send(json!({"type": "local", "on": true}));
    let e = c.text("error");
    assert!(
        e["message"].as_str().unwrap().contains("no browser build"),
        "{e}"
    );
}

/// A folder's model's scene is its files under the page's names, and a broken one is a
/// one-line error naming the model, not a server's path.
#[test]
fn a_models_scene_carries_its_files() {
    let dir = common::out_dir("serve_local").join("models");
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(
        dir.join("tri.obj"),
        "mtllib tri.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
    )
    .unwrap();
    std::fs::write(dir.join("tri.mtl"), "newmtl a\nKd 1 0 0\n").unwrap();
    std::fs::write(dir.join("bad.glb"), "not a glb at all").unwrap();
    let web = fake_web_dir();
    let server = Server::start(&[
        dir.to_str().unwrap(),
        "--size",
        SIZE,
        "--web-dir",
        web.to_str().unwrap(),
    ]);
    let t = &server.token;
    let (status, body) = server.get(&format!("/scene?token={t}&model=tri.obj"));
    assert_eq!(status, 200, "{body}");
    let json: Value = serde_json::from_str(body.split("\r\n\r\n").nth(1).unwrap()).unwrap();
    let paths: Vec<&str> = json["files"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| f["path"].as_str().unwrap())
        .collect();
    assert_eq!(paths, ["/lesson/tri.mtl", "/lesson/tri.obj"]);
    let words: Vec<&str> = json["words"]
        .as_array()
        .unwrap()
        .iter()
        .map(|w| w.as_str().unwrap())
        .collect();
    assert!(words.contains(&"/lesson/tri.obj"), "{words:?}");
    assert!(
        !body.contains(dir.to_str().unwrap()),
        "the server's path reached the page"
    );
    let (status, body) = server.get(&format!("/scene?token={t}&model=bad.glb"));
    let text = body.split("\r\n\r\n").nth(1).unwrap();
    assert_eq!(status, 422, "{body}");
    assert_eq!(text.lines().count(), 1, "{text}");
    assert!(text.starts_with("bad.glb: "), "{text}");
    assert!(!text.contains(dir.to_str().unwrap()), "{text}");
}
