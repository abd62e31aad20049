//! Bloom against its definition: a single bright pixel blurs into the discrete Gaussian the
//! kernel is; a threshold above the image leaves the picture unchanged to the bit; only what
//! exceeds the threshold contributes.
use crate::common;
use common::*;
use glview::frame::Bloom;
use glview::headless::Headless;
use glview::image_out::RgbaFiles;
use glview::platform::{Backend, GlRequest};
use glview::render::post::{bloom_buffer, gaussian};

fn ctx() -> Headless {
    Headless::new(Backend::Egl, GlRequest::Core, 8, 8).expect("EGL context")
}

#[test]
fn a_bright_pixel_gives_the_gaussian() {
    let hl = ctx();
    let (w, h) = (64u32, 64u32);
    let mut img = vec![0f32; (w * h * 3) as usize];
    let c = ((32 * w + 32) * 3) as usize;
    img[c..c + 3].copy_from_slice(&[101.0, 101.0, 101.0]);
    let b = Bloom {
        strength: 1.0,
        threshold: 1.0,
        knee: 0.0,
        sigma: 3.0,
        levels: 0,
    };
    let (bw, bh, out) = bloom_buffer(&hl.gpu, &img, w, h, &b).unwrap();
    assert_eq!((bw, bh), (w, h));
    let g = gaussian(3.0);
    let mut worst = 0f64;
    for y in 0..h {
        for x in 0..w {
            let (dx, dy) = (
                (x as i32 - 32).unsigned_abs() as usize,
                (y as i32 - 32).unsigned_abs() as usize,
            );
            let expect = if dx < g.len() && dy < g.len() {
                100.0 * f64::from(g[dx] * g[dy])
            } else {
                0.0
            };
            let got = f64::from(out[((y * w + x) * 3) as usize]);
            worst = worst.max((got - expect).abs());
        }
    }
    eprintln!("single pixel (100 above the threshold), σ 3: worst error {worst:.5} against 100·g(dx)·g(dy) (peak {:.4})", 100.0 * g[0] * g[0]);
    // 16-bit float storage: ~1e-3 relative of the peak (≈ 0.3) per pass.
    assert!(worst < 0.01, "{worst}");
}

#[test]
fn only_what_exceeds_the_threshold_contributes() {
    let hl = ctx();
    let (w, h) = (32u32, 32u32);
    let below = vec![0.9f32; (w * h * 3) as usize];
    let b = Bloom {
        strength: 1.0,
        threshold: 1.0,
        knee: 0.0,
        sigma: 2.0,
        levels: 1,
    };
    let (_, _, out) = bloom_buffer(&hl.gpu, &below, w, h, &b).unwrap();
    assert!(
        out.iter().all(|&v| v == 0.0),
        "energy from pixels below the threshold"
    );
    // The soft knee lets values within `knee` below the threshold in, quadratically.
    let knee = Bloom { knee: 0.2, ..b };
    let (_, _, out) = bloom_buffer(&hl.gpu, &below, w, h, &knee).unwrap();
    // b = 0.9, t = 1, k = 0.2: soft = (0.1)^2 / 0.8 = 0.0125; w = 0.0125/0.9; out = 0.0125.
    let mid = out[((8 * 16 + 8) * 3) as usize];
    assert!((mid - 0.0125).abs() < 2e-4, "{mid}");
}

#[test]
fn a_threshold_above_the_image_changes_nothing() {
    let dir = out_dir("bloom");
    let sphere = models().join("sphere.obj");
    let base = [
        sphere.to_str().unwrap(),
        "--size",
        "96x72",
        "--shading",
        "pbr",
    ];
    let plain = render(&dir, "plain", &base, &[]);
    let mut a = base.to_vec();
    a.extend_from_slice(&["--bloom", "1", "--bloom-threshold", "1000000"]);
    let offscreen = render(&dir, "threshold-high", &a, &[]);
    assert_close(&dir, "bloom-nothing", &plain, &offscreen, 0, 0, 0);
    let mut a = base.to_vec();
    a.extend_from_slice(&["--bloom", "1", "--bloom-threshold", "0.2"]);
    let glow = render(&dir, "glow", &a, &[]);
    assert!(
        diff(&plain, &glow, 8).over > 500,
        "a low threshold added no glow"
    );
    // The legacy tier blooms too when asked.
    let legacy = render(
        &dir,
        "legacy-glow",
        &[
            "--size",
            "96x72",
            "--bloom",
            "1",
            "--bloom-threshold",
            "0.5",
        ],
        &[],
    );
    let legacy_plain = render(&dir, "legacy-plain", &["--size", "96x72"], &[]);
    assert!(diff(&legacy, &legacy_plain, 8).over > 100);
}

/// `--show bloom` draws the bloom buffer alone where there are float render targets; GL 2.1
/// without framebuffer objects blooms through the copy-to-texture path and says so in
/// `--stats` (tests/post_copy.rs checks what it draws).
#[test]
fn bloom_view_and_gl21_fallback() {
    let dir = out_dir("bloom-view");
    for gl in ["core", "es3"] {
        let out = dir.join(format!("{gl}.png"));
        let o = run(
            &[
                "--show",
                "bloom",
                "--bloom-threshold",
                "0.6",
                "--size",
                "96x72",
                "--gl",
                gl,
                "--backend",
                "egl",
                "-o",
                out.to_str().unwrap(),
            ],
            &[],
        );
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let img = glview::image_out::Rgba::load_png(&out).unwrap();
        assert!(!img.is_uniform(), "{gl}: blank bloom view");
        // The bloom buffer alone (no --bloom strength needed): the dark background is black.
        assert_eq!(
            img.pixel(0, 0)[..3],
            [0, 0, 0],
            "{gl}: the scene, not its bloom"
        );
    }
    let o = run(
        &[
            "--bloom",
            "0.5",
            "--stats",
            "--size",
            "64x48",
            "--gl",
            "2.1",
            "--backend",
            "osmesa",
            "-o",
            dir.join("gl21.png").to_str().unwrap(),
        ],
        GL21_NO_FBO,
    );
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(
        o.status.success() && out.contains("post: ran (copy-to-texture path"),
        "{out}"
    );
}
