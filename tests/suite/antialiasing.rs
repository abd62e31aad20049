//! Anti-aliasing and the transparent background against exact area coverage: a white square
//! rotated 30° on black, flat (ambient only), seen orthographically; each pixel's exact
//! coverage comes from 64×64 point samples per pixel in f64 (error < 2.5·10⁻⁴).
use crate::common;
use common::*;
use glview::image_out::Rgba;
use glview::image_out::RgbaFiles;

const N: u32 = 64;

fn square(dir: &std::path::Path) -> String {
    let (c, s) = (30f64.to_radians().cos(), 30f64.to_radians().sin());
    let mut obj = String::from("mtllib sq.mtl\nusemtl w\n");
    for (x, y) in [(-0.5, -0.5), (0.5, -0.5), (0.5, 0.5), (-0.5, 0.5)] {
        obj += &format!("v {} {} 0\n", c * x - s * y, s * x + c * y);
    }
    obj += "vn 0 0 1\nf 1//1 2//1 3//1\nf 1//1 3//1 4//1\n";
    // A far corner marker keeps the bounds centred on the origin.
    std::fs::write(dir.join("sq.mtl"), "newmtl w\nKa 1 1 1\nKd 0 0 0\n").unwrap();
    let p = dir.join("sq.obj");
    std::fs::write(&p, obj).unwrap();
    p.to_str().unwrap().to_string()
}

/// Exact coverage of pixel (x, y): the view is 1.6 units high over N pixels, centred.
fn coverage(x: u32, y: u32) -> f64 {
    let (c, s) = (30f64.to_radians().cos(), 30f64.to_radians().sin());
    let px = 1.6 / f64::from(N);
    let k = 64;
    let mut inside = 0;
    for j in 0..k {
        for i in 0..k {
            let wx = (f64::from(x) + (f64::from(i) + 0.5) / f64::from(k)) * px - 0.8;
            let wy = 0.8 - (f64::from(y) + (f64::from(j) + 0.5) / f64::from(k)) * px;
            // Rotate back by −30°: inside the axis-aligned unit square?
            let (u, v) = (c * wx + s * wy, -s * wx + c * wy);
            if u.abs() <= 0.5 && v.abs() <= 0.5 {
                inside += 1;
            }
        }
    }
    f64::from(inside) / f64::from(k * k)
}

fn shot(dir: &std::path::Path, model: &str, name: &str, extra: &[&str]) -> Rgba {
    shot_env(dir, model, name, extra, &[])
}

fn shot_env(
    dir: &std::path::Path,
    model: &str,
    name: &str,
    extra: &[&str],
    env: &[(&str, &str)],
) -> Rgba {
    let out = dir.join(format!("{name}.png"));
    let mut a = vec![
        model,
        "--size",
        "64x64",
        "--yaw",
        "0",
        "--pitch",
        "0",
        "--ortho",
        "1.6",
        "--light",
        "none",
        "--ambient",
        "1,1,1",
        "--background",
        "0,0,0",
        "--no-shadows",
        "-o",
        out.to_str().unwrap(),
    ];
    a.extend_from_slice(extra);
    let o = run(&a, env);
    assert!(
        o.status.success(),
        "{name}: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    Rgba::load_png(&out).unwrap()
}

/// Mean |value − coverage| over the edge pixels (0 < coverage < 1), channel `c`.
fn edge_error(img: &Rgba, c: usize) -> f64 {
    let (mut sum, mut n) = (0.0, 0);
    for y in 0..N {
        for x in 0..N {
            let cov = coverage(x, y);
            if cov > 0.0 && cov < 1.0 {
                sum += (f64::from(img.pixel(x, y)[c]) / 255.0 - cov).abs();
                n += 1;
            }
        }
    }
    assert!(n > 100, "only {n} edge pixels");
    sum / f64::from(n)
}

#[test]
fn edge_coverage_per_mode() {
    let dir = out_dir("antialiasing");
    let model = square(&dir);
    let none = edge_error(&shot(&dir, &model, "none", &["--aa", "none"]), 0);
    let msaa = edge_error(
        &shot(
            &dir,
            &model,
            "msaa4",
            &["--aa", "msaa", "--aa-samples", "4"],
        ),
        0,
    );
    let ssaa = edge_error(
        &shot(
            &dir,
            &model,
            "ssaa4",
            &["--aa", "ssaa", "--aa-samples", "4"],
        ),
        0,
    );
    let fxaa = edge_error(&shot(&dir, &model, "fxaa", &["--aa", "fxaa"]), 0);
    eprintln!("edge coverage error (mean over edge pixels): none {none:.4}, msaa 4 {msaa:.4}, ssaa 4x4 {ssaa:.4}, fxaa {fxaa:.4}");
    assert!(
        fxaa < none,
        "FXAA made the edges worse: {fxaa} against {none}"
    );
    assert!(
        none > 0.15,
        "aliased edges should be off by ~0.25 on average: {none}"
    );
    // Four samples give five coverage levels: a mean quantisation error near 1/10 remains.
    assert!(
        msaa < 0.12 && msaa < none * 0.6 && ssaa < none / 3.0,
        "none {none}, msaa {msaa}, ssaa {ssaa}"
    );
    assert!(
        ssaa < 0.06,
        "4×4 supersampling is within 1/16 of the exact coverage: {ssaa}"
    );
    // Alpha is the coverage with --transparent, and the colour stays white (straight alpha).
    let t = shot(
        &dir,
        &model,
        "transparent",
        &["--aa", "ssaa", "--aa-samples", "4", "--transparent"],
    );
    let alpha = edge_error(&t, 3);
    eprintln!("transparent: alpha against coverage {alpha:.4}");
    assert!(alpha < 0.06, "alpha is not the coverage: {alpha}");
    assert_eq!(t.pixel(0, 0)[3], 0, "the background is not transparent");
    let p = t.pixel(32, 32);
    assert_eq!(p, [255, 255, 255, 255]);
    // MSAA is refused clearly where there are no multisampled framebuffers (OSMesa).
    let o = run(
        &[
            &model,
            "--aa",
            "msaa",
            "--gl",
            "2.1",
            "--backend",
            "osmesa",
            "-o",
            dir.join("x.png").to_str().unwrap(),
        ],
        GL21_NO_FBO,
    );
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        !o.status.success() && err.contains("use --aa ssaa"),
        "{err}"
    );
}

/// FXAA on GL 2.1 without framebuffer objects: the frame is copied into a texture and FXAA
/// drawn back; its edge error equals the float path's within 0.01, and SSAA works there too.
#[test]
fn fxaa_and_ssaa_without_framebuffer_objects() {
    let dir = out_dir("antialiasing-no-fbo");
    let model = square(&dir);
    let no_fbo = |name: &str, aa: &[&str]| {
        let mut a = vec!["--gl", "2.1", "--backend", "osmesa"];
        a.extend_from_slice(aa);
        shot_env(&dir, &model, name, &a, GL21_NO_FBO)
    };
    let none = edge_error(&no_fbo("none", &["--aa", "none"]), 0);
    let fxaa = edge_error(&no_fbo("fxaa", &["--aa", "fxaa"]), 0);
    let ssaa = edge_error(&no_fbo("ssaa4", &["--aa", "ssaa", "--aa-samples", "4"]), 0);
    let fbo = edge_error(&shot(&dir, &model, "fxaa-fbo", &["--aa", "fxaa"]), 0);
    eprintln!(
        "no FBOs: edge error none {none:.4}, fxaa {fxaa:.4} (float path {fbo:.4}), ssaa 4x4 {ssaa:.4}"
    );
    assert!(
        fxaa < none,
        "FXAA made the edges worse: {fxaa} against {none}"
    );
    assert!(
        (fxaa - fbo).abs() < 0.01,
        "copy path {fxaa}, float path {fbo}"
    );
    assert!(ssaa < 0.06, "{ssaa}");
}
