//! Sidedness (issue 19, render side): a single-sided glTF triangle seen from behind draws
//! nothing; a double-sided one draws the mirror image of its front, lit through the flipped
//! normal.
use crate::common::*;
use crate::gltf_materials::b64;
use glview::image_out::Rgba;
use glview::image_out::RgbaFiles;
use std::path::{Path, PathBuf};

/// A right triangle in z = 0, counter-clockwise seen from +Z (normals +Z), asymmetric so
/// that its mirror image is distinguishable.
fn triangle(dir: &Path, double_sided: bool) -> PathBuf {
    let mut bin = Vec::new();
    for x in [
        -1f32, -1., 0., 1., -1., 0., -1., 1., 0., 0., 0., 1., 0., 0., 1., 0., 0., 1.,
    ] {
        bin.extend(x.to_le_bytes());
    }
    let json = format!(
        r#"{{"asset": {{"version": "2.0"}}, "scene": 0, "scenes": [{{"nodes": [0]}}],
      "nodes": [{{"mesh": 0}}],
      "meshes": [{{"primitives": [{{"attributes": {{"POSITION": 0, "NORMAL": 1}}, "material": 0}}]}}],
      "materials": [{{"doubleSided": {double_sided}}}],
      "buffers": [{{"uri": "data:application/octet-stream;base64,{}", "byteLength": 72}}],
      "bufferViews": [{{"buffer": 0, "byteLength": 36}}, {{"buffer": 0, "byteOffset": 36, "byteLength": 36}}],
      "accessors": [{{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [-1, -1, 0], "max": [1, 1, 0]}},
                    {{"bufferView": 1, "componentType": 5126, "count": 3, "type": "VEC3"}}]}}"#,
        b64(&bin)
    );
    let p = dir.join(format!("tri_{double_sided}.gltf"));
    std::fs::write(&p, json).unwrap();
    p
}

fn shot(dir: &Path, model: &Path, yaw: &str, name: &str) -> Rgba {
    let out = dir.join(format!("{name}.png"));
    let o = run(
        &[
            model.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
            "--size",
            "64x64",
            "--yaw",
            yaw,
            "--pitch",
            "0",
            "--light",
            "head",
            "--no-shadows",
            "--transparent",
        ],
        &[],
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    Rgba::load_png(&out).unwrap()
}

#[test]
fn single_sided_back_draws_nothing_double_sided_back_is_the_mirror() {
    let dir = out_dir("gltf_sidedness");
    let single = triangle(&dir, false);
    let double = triangle(&dir, true);
    let front = shot(&dir, &single, "0", "single_front");
    let covered = |i: &Rgba| i.data.chunks(4).filter(|p| p[3] > 0).count();
    assert!(covered(&front) > 500, "the front face draws");
    let back = shot(&dir, &single, "180", "single_back");
    assert_eq!(covered(&back), 0, "a single-sided back face draws nothing");
    let dback = shot(&dir, &double, "180", "double_back");
    let (w, h) = (front.width, front.height);
    let (mut worst, mut edge) = (0, 0);
    for y in 0..h {
        for x in 0..w {
            let a = front.pixel(x, y);
            let b = dback.pixel(w - 1 - x, y);
            // The fill rule is not mirror-symmetric: only pixels on the diagonal edge may differ.
            if (a[3] > 0) != (b[3] > 0) {
                edge += 1;
                continue;
            }
            if a[3] < 255 || b[3] < 255 {
                continue;
            }
            for c in 0..3 {
                worst = worst.max(a[c].abs_diff(b[c]));
            }
        }
    }
    assert!(edge <= w as usize, "{edge} pixels of coverage not mirrored");
    assert!(
        worst <= 2,
        "back lit as the front (worst channel difference {worst})"
    );
}
