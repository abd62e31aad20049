//! `glview serve`'s render threads and the class's limits (issue 40): a still drawn on
//! either thread is the command line's picture; one address cannot take every viewer's
//! place; on an unspecified bind address only this machine's names are answered; a
//! link's camera is absolute.
use super::common;
use super::serve::{assert_same, cli_png, SIZE};
use super::serve_client::{decode_png, Got, Server};
use serde_json::json;
use std::time::{Duration, Instant};

/// Two viewers on two models with `--render-threads 2` are drawn on the two threads, and
/// each still equals `glview MODEL -o` pixel for pixel; a viewer who picks a model moves
/// to the thread that has it.
#[test]
fn stills_equal_the_command_line_on_every_render_thread() {
    let dir = common::out_dir("serve-pool");
    let models = common::repo().join("models");
    for f in [
        "box_on_floor.obj",
        "box_on_floor.mtl",
        "sphere.obj",
        "sphere.mtl",
    ] {
        std::fs::copy(models.join(f), dir.join(f)).unwrap();
    }
    let dir_arg = dir.to_str().unwrap();
    let server = Server::start(&[dir_arg, "--size", SIZE, "--render-threads", "2"]);
    let mut a = server.viewer("");
    let (ha, png_a, _) = a.still(None);
    assert_eq!(ha["model"], "box_on_floor.obj");
    let mut b = server.viewer("");
    b.still(None);
    b.send(json!({"type": "model", "name": "sphere.obj", "seq": 1}));
    let (hb, png_b, _) = b.still(Some(1));
    assert_eq!(hb["model"], "sphere.obj");
    assert_ne!(ha["thread"], hb["thread"], "{ha} {hb}");
    let box_path = dir.join("box_on_floor.obj");
    let want_a = cli_png("pool-box", &[box_path.to_str().unwrap()]);
    assert_same("pool-box", &decode_png(&png_a), &want_a);
    let sphere_path = dir.join("sphere.obj");
    let want_b = cli_png("pool-sphere", &[sphere_path.to_str().unwrap()]);
    assert_same("pool-sphere", &decode_png(&png_b), &want_b);
    // A third viewer (on the first thread: the second has its share) who picks the sphere
    // moves to the thread that has it, and draws the same picture there.
    let mut c = server.viewer("");
    let (hc, _, _) = c.still(None);
    assert_eq!(hc["thread"], ha["thread"], "{hc}");
    c.send(json!({"type": "model", "name": "sphere.obj", "seq": 1}));
    let (hc, png_c, _) = c.still(Some(1));
    assert_eq!(hc["thread"], hb["thread"], "{hc}");
    assert_same("pool-sphere-moved", &decode_png(&png_c), &want_b);
    // The first viewer's next still, after a turn, still comes from its thread and equals
    // the command line's.
    a.send(json!({"type": "key", "key": "Right", "seq": 2}));
    let (ha2, png, _) = a.still(Some(2));
    assert_eq!(ha2["thread"], ha["thread"]);
    let right = cli_png(
        "pool-box-right",
        &[box_path.to_str().unwrap(), "--keys", "Right"],
    );
    assert_same("pool-box-right", &decode_png(&png), &right);
}

/// `--max-viewers-per-address 2`: a third viewer from the address is refused with a line
/// naming the option; once one leaves, another comes in.
#[test]
fn one_address_cannot_take_every_viewer() {
    let server = Server::start(&["--size", "64x48", "--max-viewers-per-address", "2"]);
    let mut a = server.viewer("");
    a.still(None);
    let mut b = server.viewer("");
    b.still(None);
    let mut c = server.viewer("");
    let e = c.text("error");
    let msg = e["message"].as_str().unwrap();
    assert!(msg.contains("--max-viewers-per-address"), "{e}");
    assert_eq!(e["closing"], true);
    drop(b);
    // The server sees the close a moment later: the place is given back then.
    let start = Instant::now();
    loop {
        let mut d = server.viewer("");
        if matches!(d.next(), Got::Text(v) if v["type"] == "hello") {
            break;
        }
        assert!(
            start.elapsed() < Duration::from_secs(5),
            "a closed viewer's place is not given back"
        );
        std::thread::sleep(Duration::from_millis(100));
    }
}

/// Bound to 0.0.0.0 without `--public-url`: IP literals, `localhost` and this machine's
/// name are answered; any other name (DNS rebinding) gets 421.
#[test]
fn an_unspecified_address_answers_only_this_machines_names() {
    let server = Server::start(&["--size", "64x48", "--bind", "0.0.0.0:0"]);
    let port = server.addr.rsplit(':').next().unwrap().to_string();
    let at = |host: &str| {
        server.raw(&format!(
            "GET /models?token={} HTTP/1.1\r\nHost: {host}\r\nConnection: close\r\n\r\n",
            server.token
        ))
    };
    let name = std::fs::read_to_string("/proc/sys/kernel/hostname").unwrap();
    for ok in [
        format!("127.0.0.1:{port}"),
        format!("192.0.2.7:{port}"),
        format!("[::1]:{port}"),
        format!("localhost:{port}"),
        format!("{}:{port}", name.trim().to_uppercase()),
        name.trim().to_string(),
    ] {
        assert_eq!(at(&ok).0, 200, "{ok}");
    }
    for bad in [
        format!("evil.example:{port}"),
        format!("127.0.0.1.evil.example:{port}"),
        format!("{}.evil.example", name.trim()),
        String::new(),
    ] {
        let (status, body) = at(&bad);
        assert_eq!(status, 421, "{bad}: {body}");
        assert!(!body.contains("models\""), "{body}");
    }
}

/// A link's camera is absolute: `{"type":"camera"}` draws `glview -o --yaw --pitch
/// --distance`'s picture, and the camera a frame's header carries (what "Copy link"
/// writes), sent by another viewer, draws the first viewer's still again.
#[test]
fn a_links_camera_is_absolute() {
    let server = Server::start(&["--size", SIZE]);
    let mut a = server.viewer("");
    a.still(None);
    a.send(json!({"type": "camera", "yaw": 70, "pitch": -10, "distance": 5, "seq": 1}));
    let (h, png, _) = a.still(Some(1));
    assert_eq!(h["camera"]["yaw"], 70.0);
    let want = cli_png(
        "link-camera",
        &["--yaw", "70", "--pitch", "-10", "--distance", "5"],
    );
    assert_same("link-camera", &decode_png(&png), &want);
    // A dragged and zoomed view, carried over by its header's camera.
    a.send(json!({"type": "drag", "dx": 37, "dy": -11, "seq": 2}));
    a.send(json!({"type": "wheel", "notches": 2, "seq": 3}));
    let (h, png, _) = a.still(Some(3));
    let mut cam = h["camera"].clone();
    cam["type"] = json!("camera");
    cam["seq"] = json!(1);
    let mut b = server.viewer("");
    b.still(None);
    b.send(cam);
    let (hb, png_b, _) = b.still(Some(1));
    assert_eq!(hb["camera"], h["camera"]);
    assert_same("link-carried", &decode_png(&png_b), &decode_png(&png));
    // Out of range is the client's error, not a view.
    b.send(json!({"type": "camera", "yaw": 0, "pitch": 0, "fov": 200}));
    let e = b.text("error");
    assert!(e["message"].as_str().unwrap().contains("fov"), "{e}");
}
