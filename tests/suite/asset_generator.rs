//! The Khronos glTF Asset Generator's own models (tests/data/asset_generator: data nobody
//! here made). Compatibility_00–05: what a glTF 2.0 reader loads and what it refuses.
//! Material_AlphaBlend_00/01/02/04: alpha from nothing, from COLOR_0, from the base colour
//! factor and from both, each held to its exact blend weight. Every model is drawn over two
//! flat backgrounds; their difference in a pixel is (1 − α)·(B₁ − B₂) whatever colour the lit
//! surface has, so the background's weight is measured per pixel without knowing the lighting.
//! The expected α comes from the model's own buffer, read here, not through glview: the
//! vertex alpha interpolated over each of the quad's two triangles, times the factor.
use crate::common::*;
use glview::image_out::Rgba;
use std::path::{Path, PathBuf};

const N: u32 = 48;
/// The two backgrounds (grey levels; not black, which the frame check reserves for NaN).
const DARK: f64 = 0.2;
const LIGHT: f64 = 1.0;
/// Each of the two pictures is within ½ step of its exact value and the blend's own
/// rounding adds ½ step: 2/255 of (LIGHT − DARK) = 0.8 in weight is 0.0098; a little over.
const TOLERANCE: f64 = 0.012;

fn data(name: &str) -> PathBuf {
    // Absolute, so it holds from whichever folder the test runs.
    std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../tests/data/asset_generator")
        .join(name)
}

/// A triangle of the quad: (x, y) and alpha at each corner.
type Corner = ([f64; 2], f64);

/// The quad's triangles with their vertex alpha (1 without COLOR_0), from the .gltf/.bin.
fn triangles(model: &Path) -> Vec<[Corner; 3]> {
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(model).unwrap()).unwrap();
    let bin = std::fs::read(model.with_extension("bin")).unwrap();
    let prim = &json["meshes"][0]["primitives"][0];
    // The floats (or u32s) of accessor `a`: these files use tightly packed views.
    let read = |a: &serde_json::Value| -> Vec<f64> {
        let acc = &json["accessors"][a.as_u64().unwrap() as usize];
        let view = &json["bufferViews"][acc["bufferView"].as_u64().unwrap() as usize];
        let start = view["byteOffset"].as_u64().unwrap_or(0) as usize;
        let len = view["byteLength"].as_u64().unwrap() as usize;
        let float = acc["componentType"].as_u64() == Some(5126);
        bin[start..start + len]
            .chunks_exact(4)
            .map(|b| {
                let b = [b[0], b[1], b[2], b[3]];
                if float {
                    f64::from(f32::from_le_bytes(b))
                } else {
                    f64::from(u32::from_le_bytes(b))
                }
            })
            .collect()
    };
    let pos = read(&prim["attributes"]["POSITION"]);
    let colors = prim["attributes"].get("COLOR_0").map(&read);
    let idx = read(&prim["indices"]);
    let corner = |i: f64| {
        let i = i as usize;
        let alpha = colors.as_ref().map_or(1.0, |c| c[4 * i + 3]);
        ([pos[3 * i], pos[3 * i + 1]], alpha)
    };
    idx.chunks_exact(3)
        .map(|t| [corner(t[0]), corner(t[1]), corner(t[2])])
        .collect()
}

/// The vertex alpha at (x, y) by barycentric interpolation over the triangle holding it,
/// `None` within `margin` of a triangle's edge (where a pixel may take either side).
fn vertex_alpha(tris: &[[Corner; 3]], x: f64, y: f64, margin: f64) -> Option<f64> {
    for [(a, aa), (b, ab), (c, ac)] in tris {
        let area = (b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1]);
        let w = |p: &[f64; 2], q: &[f64; 2]| {
            ((q[0] - p[0]) * (y - p[1]) - (x - p[0]) * (q[1] - p[1])) / area
        };
        let (wa, wb, wc) = (w(b, c), w(c, a), w(a, b));
        let edge = |w: f64, p: &[f64; 2], q: &[f64; 2]| w * area.abs() / p_dist(p, q);
        let min = edge(wa, b, c).min(edge(wb, c, a)).min(edge(wc, a, b));
        if min >= margin {
            return Some(wa * aa + wb * ab + wc * ac);
        }
        if min >= -margin {
            return None;
        }
    }
    None
}

fn p_dist(p: &[f64; 2], q: &[f64; 2]) -> f64 {
    ((q[0] - p[0]).powi(2) + (q[1] - p[1]).powi(2)).sqrt()
}

/// The view's height in model units: the unit quad covers the middle 80 % of the picture,
/// seen from +Z, with background around it (a picture of one flat colour would be blank).
const ORTHO: f64 = 1.25;

/// Every picture option but the background.
fn view(model: &Path) -> Vec<String> {
    let m = model.to_str().unwrap();
    [
        m, "--size", "48x48", "--ortho", "1.25", "--yaw", "0", "--pitch", "0",
    ]
    .into_iter()
    .chain(["--no-bloom", "--no-shadows"])
    .map(String::from)
    .collect()
}

fn grey(v: f64) -> String {
    format!("{v},{v},{v}")
}

/// The background's weight in every pixel, from the pictures over DARK and LIGHT.
fn weights(dark: &Rgba, light: &Rgba) -> Vec<f64> {
    let mut w = Vec::new();
    for y in 0..N {
        for x in 0..N {
            let (d, l) = (dark.pixel(x, y), light.pixel(x, y));
            let diff: f64 = (0..3).map(|c| f64::from(l[c]) - f64::from(d[c])).sum();
            w.push(diff / 3.0 / 255.0 / (LIGHT - DARK));
        }
    }
    w
}

/// Worst distance of the measured background weight from 1 − factor·(vertex alpha) on the
/// quad and from 1 around it, over the pixels away from the triangles' edges; and how many
/// pixels that was.
fn worst(w: &[f64], tris: &[[Corner; 3]], factor: f64) -> (f64, usize) {
    let px = ORTHO / f64::from(N);
    let (mut worst, mut n) = (0.0f64, 0);
    for y in 0..N {
        for x in 0..N {
            let half = f64::from(N) / 2.0;
            let (mx, my) = (
                (f64::from(x) + 0.5 - half) * px,
                (half - f64::from(y) - 0.5) * px,
            );
            let expect = if mx.abs().max(my.abs()) > 0.5 + px {
                Some(1.0)
            } else {
                vertex_alpha(tris, mx, my, px).map(|a| 1.0 - factor * a)
            };
            if let Some(e) = expect {
                worst = worst.max((w[(y * N + x) as usize] - e).abs());
                n += 1;
            }
        }
    }
    (worst, n)
}

/// (model, base colour factor alpha).
const MODELS: [(&str, f64); 4] = [
    ("Material_AlphaBlend_00", 1.0),
    ("Material_AlphaBlend_01", 1.0),
    ("Material_AlphaBlend_02", 0.7),
    ("Material_AlphaBlend_04", 0.7),
];

/// A context: (name, arguments, environment).
type Context = (
    &'static str,
    Vec<&'static str>,
    &'static [(&'static str, &'static str)],
);

/// The contexts: the gradient model runs on all three,
/// the others on GL 3.3 core (the rule is one shader line; the contexts are for the blend).
fn contexts(all: bool) -> Vec<Context> {
    let mut c = vec![("core", vec!["--gl", "core", "--backend", "egl"], &[][..])];
    if all {
        c.push(("gl21", vec!["--gl", "2.1", "--backend", "egl"], GL21));
        c.push((
            "gl21-nofbo",
            vec!["--gl", "2.1", "--backend", "osmesa"],
            GL21_NO_FBO,
        ));
    }
    c
}

#[test]
fn blend_weights_are_the_models_alpha_in_both_tiers_and_the_reference() {
    let dir = out_dir("asset-generator-alpha");
    let mut failures = Vec::new();
    for (name, factor) in MODELS {
        let model = data(&format!("{name}.gltf"));
        let tris = triangles(&model);
        let gradient = name.ends_with("_01");
        for (ctx, gl, env) in contexts(gradient) {
            for tier in ["phong", "pbr"] {
                let modes: &[&str] = if gradient && ctx == "core" {
                    &["nearest", "sorted"]
                } else {
                    &["nearest"]
                };
                for mode in modes {
                    let run = format!("{name}-{tier}-{mode}-{ctx}");
                    let shot = |bg: f64, label: &str| {
                        let mut args = view(&model);
                        args.extend(gl.iter().map(|a| a.to_string()));
                        let opts = ["--shading", tier, "--translucency", mode, "--background"];
                        args.extend(opts.map(String::from));
                        args.push(grey(bg));
                        let words: Vec<&str> = args.iter().map(String::as_str).collect();
                        render(&dir, &format!("{run}-{label}"), &words, env)
                    };
                    let w = weights(&shot(DARK, "dark"), &shot(LIGHT, "light"));
                    let (err, n) = worst(&w, &tris, factor);
                    eprintln!("{run}: background weight within {err:.4} of 1 − {factor}·α over {n} pixels");
                    if n < 1500 || err > TOLERANCE {
                        failures.push(format!("{run}: {err:.4} over {n} pixels"));
                    }
                }
            }
        }
        // The CPU reference composites the same rule.
        let pic = |bg: f64| {
            let mut args = view(&model);
            args.extend(["--background".to_string(), grey(bg)]);
            let words: Vec<&str> = args.iter().map(String::as_str).collect();
            let (settings, scene) = settings_for(&words);
            glview::reference::render(&scene, &settings, N, N)
        };
        let (err, n) = worst(&weights(&pic(DARK), &pic(LIGHT)), &tris, factor);
        eprintln!("{name}-reference: within {err:.4} over {n} pixels");
        if n < 1500 || err > TOLERANCE {
            failures.push(format!("{name}-reference: {err:.4} over {n} pixels"));
        }
    }
    assert!(
        failures.is_empty(),
        "blend weights off the models' alpha: {failures:#?}"
    );
}

#[test]
fn compatibility_models_load_or_are_refused_as_the_generator_says() {
    for (i, loads, says) in [
        (0, true, ""),
        (1, true, ""),
        (2, true, ""),
        (3, true, ""),
        (4, false, "minVersion"),
        (5, false, "EXT_QuantumRendering"),
    ] {
        let model = data(&format!("Compatibility_0{i}.gltf"));
        let o = run(&[model.to_str().unwrap(), "--check"], &[]);
        let err = String::from_utf8_lossy(&o.stderr);
        eprintln!("Compatibility_0{i}: {}", err.trim());
        assert_eq!(o.status.success(), loads, "Compatibility_0{i}: {err}");
        if !loads {
            let line = err.trim();
            assert!(
                line.lines().count() == 1
                    && line.contains(&format!("Compatibility_0{i}.gltf"))
                    && line.contains(says),
                "Compatibility_0{i}: want one line naming the file and {says}: {err}"
            );
        }
    }
}
