//! No leaks: every GL object the GPU layer creates is deleted when its owner is dropped, and
//! loading and dropping a model again and again keeps memory flat. (The 1,000-round soak is
//! `glview bench --soak`; the test runs a smaller count.)
mod common;
use glview::headless::Headless;
use glview::platform::{Backend, GlRequest};
use glview::render::Renderer;

fn rss_kib() -> u64 {
    let s = std::fs::read_to_string("/proc/self/statm").unwrap();
    let pages: u64 = s.split_whitespace().nth(1).unwrap().parse().unwrap();
    pages * 4
}

#[test]
fn gl_objects_return_to_zero_and_memory_stays_flat() {
    let (settings, scene) = common::settings_for(&["--size", "64x48"]);
    let textured = common::settings_for(&[
        common::models().join("textured_quad.obj").to_str().unwrap(),
        "--size",
        "64x48",
    ]);
    let hl = Headless::new(Backend::Egl, GlRequest::Core, 64, 48).expect("EGL context");
    let base = hl.gpu.live_objects();
    let mut rss = Vec::new();
    for round in 0..60 {
        for (s, sc) in [(&settings, &scene), (&textured.0, &textured.1)] {
            let mut r = Renderer::new(&hl.gpu, sc.clone()).unwrap();
            r.render(s, &hl.target()).unwrap();
            assert!(hl.gpu.live_objects() > base, "nothing was counted");
            drop(r);
            assert_eq!(
                hl.gpu.live_objects(),
                base,
                "round {round}: GL objects leaked"
            );
        }
        rss.push(rss_kib());
    }
    // After warm-up (driver caches, shader compiler), resident memory must not keep growing:
    // allow 8 MiB between round 20 and round 60 (one leaked scene would be ~5 MiB each round).
    let growth = rss[59] as i64 - rss[19] as i64;
    eprintln!(
        "RSS round 20: {} KiB, round 60: {} KiB, growth {growth} KiB",
        rss[19], rss[59]
    );
    assert!(
        growth < 8 * 1024,
        "memory grew by {growth} KiB over 40 rounds"
    );
}
