//! Far from the origin and at extreme scales, a model renders like the same model at the
//! origin: positions are read as f64 and re-centred before they become f32.
use crate::common;
use common::*;
use std::path::{Path, PathBuf};

/// Writes `src` with every vertex position p replaced by p * scale + offset (in f64).
fn transformed(src: &Path, dir: &Path, name: &str, scale: f64, offset: [f64; 3]) -> PathBuf {
    let text = std::fs::read_to_string(src).unwrap();
    let mut out = String::new();
    for line in text.lines() {
        let mut w = line.split_whitespace();
        if w.next() == Some("v") {
            let p: Vec<f64> = w.take(3).map(|x| x.parse().unwrap()).collect();
            out += &format!(
                "v {:.17e} {:.17e} {:.17e}\n",
                p[0] * scale + offset[0],
                p[1] * scale + offset[1],
                p[2] * scale + offset[2]
            );
        } else {
            out += line;
            out.push('\n');
        }
    }
    let p = dir.join(name);
    std::fs::write(&p, out).unwrap();
    p
}

#[test]
fn far_and_scaled_models_render_like_the_original() {
    compare_transformed("precision", false, 0);
}

/// Shadow edges are the most sensitive part of the picture: a PCF tap on a depth edge flips
/// with the last bit of the compared depth, so a one-pixel shift of a shadow boundary at
/// another scale is expected. Allowed: 0.2 % of the pixels (154 of 76,800) off by more than
/// 8/255; the shading itself is checked without shadows above.
#[test]
fn far_and_scaled_models_with_shadows() {
    compare_transformed("precision-shadows", true, 154);
}

fn compare_transformed(test: &str, shadows: bool, allowed: usize) {
    let dir = out_dir(test);
    let src = shared().join("models/suzanne/suzanne.obj");
    let mut args = vec![
        "--size", "320x240", "--yaw", "-30", "--pitch", "15", "--gl", "es3",
    ];
    if !shadows {
        args.push("--no-shadows");
    }
    let render_model = |p: &Path, name: &str| {
        let mut a = vec![p.to_str().unwrap()];
        a.extend_from_slice(&args);
        render(&dir, name, &a, &[])
    };
    let base = render_model(&transformed(&src, &dir, "base.obj", 1.0, [0.0; 3]), "base");
    for (name, scale, offset) in [
        ("far-1e6", 1.0, [1e6, -2e6, 3e6]),
        ("far-1e7", 1.0, [1e7, 1e7, -1e7]),
        ("scale-1e-4", 1e-4, [0.0; 3]),
        ("scale-1e5", 1e5, [0.0; 3]),
    ] {
        let img = render_model(
            &transformed(&src, &dir, &format!("{name}.obj"), scale, offset),
            name,
        );
        // Re-centring makes a far model's local coordinates equal to the original's up to
        // the f64 rounding of the offset, far below f32 precision: the same image bit for bit.
        // Scaling changes the f32 rounding of every position, so shading may move by a
        // rounding step (8/255 threshold) and shadow edges by a pixel (see above).
        let allowed = if name.starts_with("far") { 0 } else { allowed };
        assert_close(&dir, name, &base, &img, 8, allowed, 255);
    }
}
