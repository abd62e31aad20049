//! No leaks: every GL object the GPU layer creates is deleted when its owner is dropped, and
//! loading and dropping a model again and again keeps memory flat. (The 1,000-round soak is
//! `glview bench --soak`; the test runs a smaller count.) The library API's contexts too:
//! one-shot pictures and renderers opened and closed again and again keep memory flat.
//!
//! The tests measure the process's resident memory, so they take turns (`serial`).
#[path = "suite/common.rs"]
mod common;
use glview::api::{self, Outputs};
use glview::headless::Headless;
use glview::metrics::{rss_kib, trend_per_round};
use glview::platform::{Backend, GlRequest};
use glview::render::Renderer;
use std::sync::{Mutex, MutexGuard};

/// Resident memory is the process's: one test measures at a time.
fn serial() -> MutexGuard<'static, ()> {
    static SERIAL: Mutex<()> = Mutex::new(());
    SERIAL.lock().unwrap_or_else(|p| p.into_inner())
}

#[test]
fn gl_objects_return_to_zero_and_memory_stays_flat() {
    let _serial = serial();
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

/// What the API tests may grow by after warm-up. A leaked context was ~2 MB bare and ~30 MB
/// once it had drawn; resident memory also jumps between levels 16 MiB apart (above).
const BUDGET_KIB: u64 = 50 << 10;

/// Resident memory after the allocator has returned what is free to the system: each
/// temporary renderer runs on a thread of its own, whose malloc arena keeps freed pages
/// resident until trimmed (tens of MB on a busy machine), which is not a leak; a leak stays.
fn live_rss_kib() -> u64 {
    // SAFETY: malloc_trim only releases free memory of glibc's arenas.
    unsafe {
        libc::malloc_trim(0);
    }
    rss_kib()
}

fn api_options(words: &[&str]) -> glview::Options {
    glview::Options::from_words(words.iter().copied()).expect("valid options")
}

/// Runs `warm_up` rounds, then `rounds` more, failing at the first round that leaves the
/// process more than [`BUDGET_KIB`] above where the warm-up left it (a leak fails early,
/// before it can take the machine's memory).
fn stays_flat(what: &str, warm_up: usize, rounds: usize, mut round: impl FnMut(usize)) {
    for i in 0..warm_up {
        round(i);
    }
    let base = live_rss_kib();
    let mut top = base;
    for i in 0..rounds {
        round(warm_up + i);
        let now = live_rss_kib();
        top = top.max(now);
        assert!(
            now <= base + BUDGET_KIB,
            "{what}: RSS grew from {base} to {now} KiB in {} rounds after warm-up \
             ({:.0} KiB a round)",
            i + 1,
            (now - base) as f64 / (i + 1) as f64
        );
    }
    eprintln!("{what}: RSS {base} KiB after warm-up, at most {top} KiB over {rounds} rounds");
}

/// One-shot `api::render` calls share one kept renderer: 1,000 of them keep memory flat
/// (each made and dropped a context before, and each context stayed: ~30 MB a call).
#[test]
fn one_shot_renders_keep_memory_flat() {
    let _serial = serial();
    let o = api_options(&["--size", "32x24", "--backend", "egl"]);
    let first = api::render(&o, Outputs::default()).expect("EGL context");
    stays_flat("one-shot api::render", 20, 1000, |_| {
        let f = api::render(&o, Outputs::default()).unwrap();
        assert!(
            f.color.data == first.color.data,
            "the kept renderer drew another picture"
        );
    });
}

/// 200 renderers opened and closed keep memory flat; every tenth draws a picture first (a
/// context that has drawn holds its compiled programs and llvmpipe's buffers).
#[test]
fn renderers_opened_and_closed_keep_memory_flat() {
    let _serial = serial();
    let o = api_options(&["--size", "32x24", "--backend", "egl"]);
    stays_flat("api::Renderer open/close", 20, 200, |i| {
        let mut r = api::Renderer::new(o.clone()).expect("EGL context");
        if i % 10 == 0 {
            r.render(&o, Outputs::default()).unwrap();
        }
        r.close();
    });
}

/// Two threads calling `api::render` at once both get their pictures (the one that finds the
/// shared renderer busy draws in a temporary one, which is closed and freed), and after
/// `api::release` the next call makes a new renderer.
#[test]
fn one_shot_renders_from_two_threads_and_release() {
    let _serial = serial();
    let o = api_options(&["--size", "32x24", "--backend", "egl", "--yaw", "30"]);
    let first = api::render(&o, Outputs::default()).expect("EGL context");
    stays_flat("one-shot api::render from two threads", 8, 20, |_| {
        std::thread::scope(|s| {
            let threads: Vec<_> = (0..2)
                .map(|_| s.spawn(|| api::render(&o, Outputs::default())))
                .collect();
            for t in threads {
                let f = t.join().unwrap().unwrap();
                assert!(f.color.data == first.color.data);
            }
        });
    });
    api::release();
    api::release();
    let again = api::render(&o, Outputs::default()).unwrap();
    assert!(again.color.data == first.color.data);
}
