//! `glview serve` without a browser: a real server process, WebSocket clients on loopback.
use super::common;
use super::serve_client::{decode_png, Got, Server};
use glview::image_out::Rgba;
use glview::image_out::RgbaFiles;
use serde_json::json;
use std::time::{Duration, Instant};

pub(crate) const SIZE: &str = "160x120";

/// The command line's picture with these options, at SIZE.
pub(crate) fn cli_png(name: &str, args: &[&str]) -> Rgba {
    let dir = common::out_dir("serve");
    let path = dir.join(format!("{name}.png"));
    let mut all = vec!["-o", path.to_str().unwrap(), "--size", SIZE];
    all.extend_from_slice(args);
    let out = common::run(&all, &[]);
    assert!(out.status.success(), "{:?}", out);
    Rgba::load_png(&path).unwrap()
}

pub(crate) fn assert_same(name: &str, got: &Rgba, want: &Rgba) {
    if got.data != want.data {
        let dir = common::out_dir("serve");
        got.save_png(&dir.join(format!("{name}-served.png")), &[])
            .unwrap();
        let d = common::write_diff(&dir, name, got, want);
        panic!("{name}: the served still differs from the command line's; see {d:?}");
    }
}

/// The first still and the still after two presses of Right are the command line's
/// pictures of the same options, pixel for pixel; the still's PNG text reproduces it.
#[test]
fn stills_equal_the_command_line() {
    let server = Server::start(&["--size", SIZE]);
    let mut c = server.viewer("");
    let hello = c.text("hello");
    assert_eq!(hello["size"], json!([160, 120]));
    let (h, png, _) = c.still(None);
    assert_eq!(h["format"], "png");
    assert_same("first", &decode_png(&png), &cli_png("first", &[]));
    c.send(json!({"type": "key", "key": "Right", "seq": 1}));
    c.send(json!({"type": "key", "key": "Right", "seq": 2}));
    let (h, png, _) = c.still(Some(2));
    assert_same(
        "right2",
        &decode_png(&png),
        &cli_png("right2", &["--yaw", "40"]),
    );
    assert!(h["command"].as_str().unwrap().contains("--yaw 40"), "{h}");
    // The state keys are options too: S is `--keys S`.
    c.send(json!({"type": "key", "key": "S", "seq": 3}));
    let (h, png, _) = c.still(Some(3));
    assert_eq!(h["shadows"], false);
    assert_same(
        "noshadow",
        &decode_png(&png),
        &cli_png("noshadow", &["--yaw", "40", "--keys", "S"]),
    );
}

/// 50 moves sent at once are drawn as at most 3 frames (the one in flight, the latest
/// view, its still), and no frame comes before the last one is acknowledged.
#[test]
fn inputs_coalesce_and_frames_wait_for_acks() {
    let server = Server::start(&["--size", SIZE]);
    let mut c = server.viewer("");
    c.still(None);
    for seq in 1..=50 {
        c.send(json!({"type": "drag", "dx": 2, "dy": 1, "seq": seq}));
    }
    let (h, _, frames) = c.still(Some(50));
    assert!(frames <= 3, "50 queued moves gave {frames} frames");
    assert_eq!(h["seq"], 50);
    // A frame not acknowledged holds the next one back, however much input comes.
    c.send(json!({"type": "key", "key": "Left", "seq": 51}));
    let (h, _) = c.frame(false);
    for seq in 52..60 {
        c.send(json!({"type": "key", "key": "Left", "seq": seq}));
    }
    let early = c.next_within(Duration::from_millis(700));
    assert!(
        !matches!(early, Some(Got::Frame(..))),
        "a second frame came before the ack"
    );
    c.send(json!({"type": "ack", "frame": h["frame"]}));
    let (h, _, _) = c.still(Some(59));
    assert_eq!(h["seq"], 59);
    // Idle: nothing more is drawn, and the server does no work (a frame of this view
    // takes several ticks of CPU time: idle for a second must cost under 3).
    assert!(c.next_within(Duration::from_millis(300)).is_none());
    let before = server.cpu_ticks();
    assert!(c.next_within(Duration::from_secs(1)).is_none());
    let idle = server.cpu_ticks() - before;
    assert!(
        idle < 3,
        "{idle} ticks of CPU in a second with nothing to draw"
    );
}

/// Previews while input arrives are smaller JPEGs; the still is the full-size PNG.
#[test]
fn previews_are_small_jpegs() {
    let server = Server::start(&["--size", SIZE, "--still-delay", "400"]);
    let mut c = server.viewer("");
    c.still(None);
    c.send(json!({"type": "drag", "dx": 5, "dy": 0, "seq": 1}));
    let (h, img) = c.frame(true);
    assert_eq!(h["still"], false, "{h}");
    assert_eq!(h["format"], "jpeg");
    assert_eq!(
        (h["width"].as_u64(), h["view"][0].as_u64()),
        (Some(80), Some(160))
    );
    assert_eq!(&img[..2], &[0xFF, 0xD8]);
    // libjpeg-turbo where installed (scripts/deps.sh installs it: required under CI).
    if common::in_ci() || glview::platform::turbojpeg::available() {
        assert_eq!(h["encoder"], "libjpeg-turbo", "{h}");
    }
    let preview = image::load_from_memory(&img).unwrap().to_rgba8();
    assert_eq!((preview.width(), preview.height()), (80, 60));
    let (h, _, _) = c.still(Some(1));
    assert_eq!(h["width"], 160);
}

/// Two viewers keep their own cameras.
#[test]
fn viewers_are_separate() {
    let server = Server::start(&["--size", SIZE]);
    let (mut a, mut b) = (server.viewer(""), server.viewer(""));
    let (_, first_a, _) = a.still(None);
    let (_, first_b, _) = b.still(None);
    assert_eq!(first_a, first_b);
    a.send(json!({"type": "key", "key": "Left", "seq": 1}));
    let (ha, moved, _) = a.still(Some(1));
    b.send(json!({"type": "still"}));
    let (hb, same, _) = b.still(None);
    assert_ne!(moved, first_a);
    assert_eq!(decode_png(&same).data, decode_png(&first_b).data);
    assert_ne!(ha["command"], hb["command"]);
}

/// The presenter's picture goes to every follower (one render), and a follower that moves
/// leaves the class, from the class's view.
#[test]
fn followers_see_the_presenter() {
    let server = Server::start(&["--size", SIZE]);
    let mut p = server.viewer(&format!("&present={}", server.presenter_key));
    assert_eq!(p.text("hello")["presenter"], true);
    let mut f: Vec<_> = (0..3).map(|_| server.viewer("")).collect();
    p.still(None);
    for c in &mut f {
        c.still(None);
        c.send(json!({"type": "follow", "on": true}));
    }
    p.send(json!({"type": "key", "key": "Right", "seq": 1}));
    p.send(json!({"type": "key", "key": "B", "seq": 2}));
    let (hp, still, _) = p.still(Some(2));
    for c in &mut f {
        // Each follower gets the presenter's frames (maybe the one from before the keys
        // first), ending on the same still.
        let mut last;
        loop {
            let (h, img) = c.frame(true);
            last = (h, img);
            if last.0["frame"] == hp["frame"] {
                break;
            }
        }
        assert_eq!(last.1, still);
        assert_eq!(last.0["presenter"], true);
    }
    // A follower's own key leaves: its view is the class's, turned once more.
    f[0].send(json!({"type": "key", "key": "Right", "seq": 3}));
    let (h, _, _) = f[0].still(Some(3));
    assert!(h["command"].as_str().unwrap().contains("--yaw 40"), "{h}");
    assert_eq!(h["presenter"], false);
    // The presenter goes; a follower that moves on its own is no follower of the next one.
    drop(p);
    f[1].text("presenter");
    f[1].send(json!({"type": "key", "key": "Down", "seq": 4}));
    let (h, _, _) = f[1].still(Some(4));
    assert!(h["command"].as_str().unwrap().contains("--pitch 20"), "{h}");
    let mut p2 = server.viewer(&format!("&present={}", server.presenter_key));
    p2.still(None);
    p2.send(json!({"type": "key", "key": "Left", "seq": 1}));
    p2.still(Some(1));
    assert!(
        !matches!(
            f[1].next_within(Duration::from_millis(600)),
            Some(Got::Frame(..))
        ),
        "a follower that left got the new presenter's frame"
    );
}

/// Folder mode: the list names the models; a viewer picks one by name; paths are no names.
#[test]
fn folder_models_by_name_only() {
    let dir = common::out_dir("serve-folder");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(dir.join("sub")).unwrap();
    let models = common::repo().join("models");
    std::fs::copy(models.join("glass_holder.obj"), dir.join("a.obj")).unwrap();
    std::fs::copy(
        models.join("glass_holder.mtl"),
        dir.join("glass_holder.mtl"),
    )
    .unwrap();
    std::fs::write(
        dir.join("sub/tri.obj"),
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
    )
    .unwrap();
    let secret = dir.with_extension("secret.obj");
    std::fs::write(&secret, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
    let _ = std::os::unix::fs::symlink(&secret, dir.join("link.obj"));
    let server = Server::start(&[dir.to_str().unwrap(), "--size", SIZE]);
    let mut c = server.viewer("");
    let hello = c.text("hello");
    assert_eq!(hello["models"], json!(["a.obj", "sub/tri.obj"]));
    c.still(None);
    let abs = secret.to_str().unwrap().to_string();
    for bad in [
        "../serve-folder.secret.obj",
        "link.obj",
        abs.as_str(),
        "%2e%2e/x.obj",
    ] {
        c.send(json!({"type": "model", "name": bad}));
        let e = c.text("error");
        assert!(
            e["message"].as_str().unwrap().contains("no model named"),
            "{e}"
        );
    }
    c.send(json!({"type": "model", "name": "sub/tri.obj", "seq": 1}));
    let (h, png, _) = c.still(Some(1));
    assert_eq!(h["model"], "sub/tri.obj");
    // The viewer sees names relative to the folder, never where the server keeps it.
    let folder = dir.canonicalize().unwrap();
    let folder = folder.to_str().unwrap();
    let command = h["command"].as_str().unwrap();
    assert!(
        command.contains(" sub/tri.obj") && !command.contains(folder),
        "{command}"
    );
    let png_text = String::from_utf8_lossy(&png);
    assert!(png_text.contains("sub/tri.obj") && !png_text.contains(folder));
}

/// Without the token: 401; a wrong one: 403; on every route, with no content.
#[test]
fn the_token_guards_everything() {
    let server = Server::start(&["--size", SIZE]);
    for path in ["/", "/app.js", "/style.css", "/models", "/ws"] {
        let (status, body) = server.get(path);
        assert_eq!(status, 401, "{path}: {body}");
        assert!(
            !body.contains("<html") && !body.contains("models"),
            "{path}"
        );
        let (status, _) = server.get(&format!("{path}?token=wrong"));
        assert_eq!(status, 403, "{path}");
    }
    let (status, body) = server.get(&format!("/?token={}", server.token));
    assert_eq!(status, 200);
    assert!(body.contains("Set-Cookie: glview_token="), "{body}");
    let cookie = format!(
        "GET /app.js HTTP/1.1\r\nHost: {}\r\nCookie: a=b; glview_token={}\r\n\r\n",
        server.addr, server.token
    );
    assert_eq!(server.raw(&cookie).0, 200);
    assert!(server.connect("/ws?token=nope", None).is_err());
    assert!(server.connect("/ws", None).is_err());
}

/// Traversal, other origins, huge and malformed input are refused; the server keeps
/// serving the viewer it has and the next one.
#[test]
fn hostile_requests_are_refused() {
    let mut server = Server::start(&["--size", SIZE]);
    let t = &server.token;
    for path in [
        format!("/../../etc/passwd?token={t}"),
        format!("/%2e%2e/%2e%2e/etc/passwd?token={t}"),
        format!("/..%2f..%2fetc%2fpasswd?token={t}"),
        format!("/%252e%252e/etc/passwd?token={t}"),
        format!("//etc/passwd?token={t}"),
        format!("/etc/passwd?token={t}"),
    ] {
        let (status, body) = server.get(&path);
        assert_eq!(status, 404, "{path}: {body}");
        assert!(!body.contains("root:"), "{path}");
    }
    // A head over the limit, and one that never ends, are answered or dropped.
    let big = format!(
        "GET /?token={t} HTTP/1.1\r\nHost: x\r\nX-Big: {}\r\n\r\n",
        "a".repeat(20_000)
    );
    assert_eq!(server.raw(&big).0, 431);
    let (status, _) = server.raw("BREW / HTCPCP/1.0\r\n\r\n");
    assert!(status == 400 || status == 405, "{status}");
    // Another site's page may not open a viewer.
    let ws = format!("/ws?token={t}");
    let e = server
        .connect(&ws, Some("http://evil.example"))
        .err()
        .unwrap();
    assert!(e.contains("403"), "{e}");
    let own = format!("http://{}", server.addr);
    assert!(server.connect(&ws, Some(&own)).is_ok());
    let mut c = server.viewer("");
    c.still(None);
    for bad in [
        "{not json",
        r#"{"type":"key","key":"Banana"}"#,
        r#"{"type":"drag","dx":"x","dy":0}"#,
        r#"{"type":"size","width":1,"height":99999}"#,
    ] {
        c.send_raw(bad);
        loop {
            match c.next() {
                Got::Text(v) if v["type"] == "error" => {
                    assert_eq!(v["closing"], false, "{bad}: {v}");
                    break;
                }
                Got::Frame(h, _) => c.send(json!({"type": "ack", "frame": h["frame"]})),
                Got::Text(_) => {}
                Got::Closed => panic!("{bad}: closed"),
            }
        }
    }
    c.send(json!({"type": "key", "key": "Up", "seq": 7}));
    assert_eq!(c.still(Some(7)).0["seq"], 7);
    // A huge message closes that socket only.
    c.send_raw(&format!(
        r#"{{"type":"key","key":"{}"}}"#,
        "x".repeat(100_000)
    ));
    let mut closed = false;
    for _ in 0..10 {
        match c.next_within(Duration::from_secs(5)) {
            Some(Got::Closed) | None => {
                closed = true;
                break;
            }
            _ => {}
        }
    }
    assert!(closed, "a 100 kB message did not close the socket");
    assert!(server.alive());
    let mut next = server.viewer("");
    next.still(None);
}

/// The next viewer past --max-viewers is told so; a silent socket is closed after
/// --idle-timeout and its place is free again.
#[test]
fn full_and_idle() {
    let server = Server::start(&["--size", SIZE, "--max-viewers", "1", "--idle-timeout", "1"]);
    let mut a = server.viewer("");
    a.still(None);
    let mut b = server.viewer("");
    let e = b.text("error");
    assert!(e["message"].as_str().unwrap().contains("full"), "{e}");
    assert_eq!(e["closing"], true);
    let t = Instant::now();
    let e = a.text("error");
    assert!(
        e["message"].as_str().unwrap().contains("without a message"),
        "{e}"
    );
    assert!(t.elapsed() < Duration::from_secs(5));
    std::thread::sleep(Duration::from_millis(300));
    let mut c = server.viewer("");
    c.still(None);
}

/// `--no-token` is refused on an address others can reach.
#[test]
fn no_token_only_on_loopback() {
    let out = common::run(&["serve", "--bind", "0.0.0.0:0", "--no-token"], &[]);
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("--no-token") && err.contains("loopback"),
        "{err}"
    );
    assert_eq!(err.trim().lines().count(), 1, "{err}");
}

/// A dropped socket frees what its viewer held: resident memory after 500 connect/close
/// cycles (each drawn once) stays within 20 MB of the memory after 10.
#[test]
fn closed_sockets_free_their_viewers() {
    let server = Server::start(&["--size", "64x48"]);
    let cycle = || {
        let mut c = server.viewer("");
        c.frame(false);
    };
    for _ in 0..10 {
        cycle();
    }
    std::thread::sleep(Duration::from_millis(200));
    let after_10 = server.rss_kb();
    for _ in 0..490 {
        cycle();
    }
    std::thread::sleep(Duration::from_millis(500));
    let after_500 = server.rss_kb();
    assert!(
        after_500 <= after_10 + 20 * 1024,
        "RSS {after_10} kB after 10 viewers, {after_500} kB after 500"
    );
    let mut c = server.viewer("");
    c.still(None);
}

/// Two viewers dragging at once are served in turn: neither starves.
#[test]
fn viewers_are_served_in_turn() {
    let server = Server::start(&["--size", SIZE]);
    let run = |mut c: super::serve_client::Client| {
        c.still(None);
        let start = Instant::now();
        let (mut frames, mut seq) = (0, 0);
        while start.elapsed() < Duration::from_millis(1500) {
            seq += 1;
            c.send(json!({"type": "drag", "dx": 1, "dy": 0, "seq": seq}));
            if let Some(Got::Frame(h, _)) = c.next_within(Duration::from_millis(20)) {
                c.send(json!({"type": "ack", "frame": h["frame"]}));
                frames += 1;
            }
        }
        frames
    };
    let (a, b) = (server.viewer(""), server.viewer(""));
    let ta = std::thread::spawn(move || run(a));
    let fb = run(b);
    let fa = ta.join().unwrap();
    assert!(fa >= 5 && fb >= 5, "frames {fa} and {fb}");
    assert!(
        fa <= 2 * fb + 2 && fb <= 2 * fa + 2,
        "frames {fa} and {fb}: not in turn"
    );
}

/// A viewer that leaves while its frame is drawn does not hold up the others: the messages
/// that came for the busy render thread are taken when its job ends, whoever's it was.
/// (They once waited for good: the class froze after any viewer closed mid-frame.)
#[test]
fn a_viewer_leaving_mid_frame_does_not_stall_the_others() {
    let server = Server::start(&["--size", "1024x768"]);
    let mut b = server.viewer("");
    b.still(None);
    for seq in 1..=5 {
        let mut leaver = server.viewer("");
        leaver.still(None);
        // Its PBR compare with bloom (the largest size) is being drawn while the drag comes.
        for key in ["P", "B", "C"] {
            leaver.send(json!({"type": "key", "key": key}));
        }
        std::thread::sleep(Duration::from_millis(60));
        b.send(json!({"type": "drag", "dx": 4, "dy": 0, "seq": seq}));
        drop(leaver);
        let start = Instant::now();
        let shown = loop {
            match b.next_within(Duration::from_millis(100)) {
                Some(Got::Frame(h, _)) => {
                    b.send(json!({"type": "ack", "frame": h["frame"]}));
                    if h["seq"] == seq {
                        break true;
                    }
                }
                Some(Got::Closed) => break false,
                _ if start.elapsed() > Duration::from_secs(10) => break false,
                _ => {}
            }
        };
        assert!(shown, "drag {seq}: no frame showing it within 10 s");
    }
}

/// A request head that never ends is dropped at the deadline (10 s); the server serves
/// others meanwhile.
#[test]
fn slow_request_heads_time_out() {
    use std::io::{Read, Write};
    let server = Server::start(&["--size", SIZE]);
    let mut slow = std::net::TcpStream::connect(&server.addr).unwrap();
    slow.write_all(b"GET / HTTP/1.1\r\nHost: x\r\n").unwrap();
    slow.set_read_timeout(Some(Duration::from_secs(20)))
        .unwrap();
    let t = Instant::now();
    let mut c = server.viewer("");
    c.still(None);
    let mut buf = [0u8; 64];
    let n = slow.read(&mut buf).unwrap_or(0);
    let waited = t.elapsed();
    assert_eq!(n, 0, "the slow request got an answer");
    assert!(
        waited >= Duration::from_secs(9) && waited < Duration::from_secs(15),
        "dropped after {waited:?}"
    );
}

/// An OSMesa context keeps its size: previews are the view's size (not a new context per
/// frame) and a size message is refused; the still is still the command line's picture.
#[test]
fn osmesa_views_keep_one_size() {
    let server = Server::start(&["--size", SIZE, "--backend", "osmesa"]);
    let mut c = server.viewer("");
    c.still(None);
    c.send(json!({"type": "drag", "dx": 5, "dy": 0, "seq": 1}));
    let (h, _) = c.frame(true);
    assert_eq!(
        (h["width"].as_u64(), h["view"][0].as_u64()),
        (Some(160), Some(160)),
        "{h}"
    );
    let (_, png, _) = c.still(Some(1));
    let cli_yaw = 30.0 - 5.0 * glview::keys::DRAG_DEG_PER_PIXEL;
    let want = cli_png(
        "osmesa-drag",
        &["--backend", "osmesa", "--yaw", &cli_yaw.to_string()],
    );
    assert_same("osmesa-drag", &decode_png(&png), &want);
    c.send(json!({"type": "size", "width": 200, "height": 100}));
    let e = c.text("error");
    assert!(
        e["message"].as_str().unwrap().contains("keeps one size"),
        "{e}"
    );
}

/// Stereo on the page: the picker's mode is drawn as the command line draws it, pixel for
/// pixel (T cycles on, Y swaps); a presenter's stereo reaches the followers (the class
/// shares the mode); a bad or quad-buffer mode is refused by name.
#[test]
fn the_stereo_picker_draws_the_command_lines_stereo_and_the_class_shares_it() {
    let server = Server::start(&["--size", SIZE]);
    let mut p = server.viewer(&format!("&present={}", server.presenter_key));
    let mut f = server.viewer("");
    p.still(None);
    f.still(None);
    f.send(json!({"type": "follow", "on": true}));
    p.send(json!({"type": "stereo", "mode": "rows", "seq": 1}));
    let (h, png, _) = p.still(Some(1));
    assert_eq!(h["stereo"], "rows");
    let rows = cli_png("stereo-rows", &["--stereo", "rows"]);
    assert_same("stereo-rows", &decode_png(&png), &rows);
    // The follower ends on the presenter's still.
    loop {
        let (hf, img) = f.frame(true);
        if hf["frame"] == h["frame"] {
            assert_eq!(decode_png(&img).data, rows.data);
            assert_eq!(hf["stereo"], "rows");
            break;
        }
    }
    p.send(json!({"type": "key", "key": "T", "seq": 2}));
    p.send(json!({"type": "key", "key": "Y", "seq": 3}));
    let (h, png, _) = p.still(Some(3));
    assert_eq!(h["stereo"], "columns");
    let want = cli_png("stereo-columns", &["--stereo", "columns", "--swap-eyes"]);
    assert_same("stereo-columns", &decode_png(&png), &want);
    for bad in ["sideways", "quad-buffer"] {
        p.send(json!({"type": "stereo", "mode": bad}));
        let e = p.text("error");
        assert!(e["message"].as_str().unwrap().contains("stereo"), "{e}");
    }
}
