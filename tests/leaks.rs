//! No leaks: every GL object the GPU layer creates is deleted when its owner is dropped, and
//! loading and dropping a model again and again keeps memory flat. (The 1,000-round soak is
//! `glview bench --soak`; the test runs a smaller count.)
#[path = "suite/common.rs"]
mod common;
use glview::headless::Headless;
use glview::metrics::{rss_kib, trend_per_round};
use glview::platform::{Backend, GlRequest};
use glview::render::Renderer;

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
    let rounds: usize = std::env::var("GLVIEW_LEAK_ROUNDS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(100);
    for round in 0..rounds {
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
        if round % 20 == 19 {
            eprintln!("round {}: RSS {} KiB", round + 1, rss_kib());
        }
    }
    // Resident memory jumps between levels 16 MiB apart from round to round (allocator
    // arenas and llvmpipe's buffers), so a single before/after pair proves nothing. Fit a
    // line through every round after warm-up instead: its slope must stay below 1 MiB a
    // round. Leaking one scene's buffers (the built-in scene's are ≈2.5 MiB) would double it;
    // the noise gives a standard error near 0.1 MiB a round over 100 rounds.
    let slope = trend_per_round(&rss[10..]);
    eprintln!(
        "RSS from {} to {} KiB over {} rounds; trend {slope:.1} KiB per round",
        rss[10],
        rss[rss.len() - 1],
        rss.len()
    );
    assert!(slope < 1024.0, "memory grows by {slope:.0} KiB per round");
}
