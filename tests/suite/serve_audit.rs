//! `glview serve`'s audit (issue 40): the `Host` header, `--token`'s length, views larger
//! than `--size`, a presenter coming back.
use super::common;
use super::serve_client::Server;
use serde_json::json;

/// Only the bind address's names (and `--public-url`'s) are answered: a page of another
/// site reached through DNS rebinding gets nothing, with or without a token.
#[test]
fn the_host_header_is_checked() {
    for args in [&["--no-token"][..], &[]] {
        let server = Server::start(&[&["--size", "64x48"], args].concat());
        let t = format!("/models?token={}", server.token);
        let at = |host: &str| {
            server.raw(&format!(
                "GET {t} HTTP/1.1\r\nHost: {host}\r\nConnection: close\r\n\r\n"
            ))
        };
        let port = server.addr.rsplit(':').next().unwrap();
        assert_eq!(at(&server.addr).0, 200);
        assert_eq!(at(&format!("localhost:{port}")).0, 200);
        let (status, body) = at(&format!("evil.example:{port}"));
        assert_eq!(status, 421, "{body}");
        assert!(!body.contains("models\""), "{body}");
    }
    let server = Server::start(&["--size", "64x48", "--public-url", "https://Course.Example/"]);
    let req = |host: &str| {
        format!(
            "GET /models?token={} HTTP/1.1\r\nHost: {host}\r\nConnection: close\r\n\r\n",
            server.token
        )
    };
    assert_eq!(server.raw(&req("course.example")).0, 200);
    assert_eq!(server.raw(&req("other.example")).0, 421);
}

/// A short `--token` is refused in one line.
#[test]
fn short_tokens_are_refused() {
    let out = common::run(
        &["serve", "--bind", "127.0.0.1:0", "--token", "abc123"],
        &[],
    );
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("--token") && err.contains("16"), "{err}");
    assert_eq!(err.trim().lines().count(), 1, "{err}");
}

/// `--size` is the largest view: a larger one is refused, naming the limit, and the view
/// keeps its size.
#[test]
fn views_larger_than_size_are_refused() {
    let server = Server::start(&["--size", "64x48"]);
    let mut c = server.viewer("");
    c.still(None);
    c.send(json!({"type": "size", "width": 4096, "height": 4096}));
    let e = c.text("error");
    let m = e["message"].as_str().unwrap();
    assert!(m.contains("64x48") && m.contains("--size"), "{e}");
    c.send(json!({"type": "size", "width": 32, "height": 48}));
    c.send(json!({"type": "still"}));
    let (h, _, _) = c.still(None);
    assert_eq!(h["view"], json!([32, 48]), "{h}");
}

/// A presenter who reconnects (its old socket not closed yet) takes the role over at once.
#[test]
fn a_presenter_reclaims_its_role() {
    let server = Server::start(&["--size", "64x48"]);
    let key = format!("&present={}", server.presenter_key);
    let mut old = server.viewer(&key);
    assert_eq!(old.text("hello")["presenter"], true);
    let mut new = server.viewer(&key);
    assert_eq!(new.text("hello")["presenter"], true);
    let e = old.text("error");
    assert!(
        e["message"].as_str().unwrap().contains("another page"),
        "{e}"
    );
    // The new socket's frames are the presenter's.
    let (h, _) = new.frame(true);
    assert_eq!(h["presenter"], true, "{h}");
}
