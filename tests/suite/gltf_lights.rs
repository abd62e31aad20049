//! KHR_lights_punctual (issue 37): a file's point and spot lights against the CPU reference
//! in both tiers on every context; the range's and the cone's edges exact against the
//! formula at each pixel's point; `--light kit` drawing what a file without lights draws;
//! `--check` listing the lights and warning of malformed ones. Generated files: a floor
//! (and a sphere on it) with the lights on their own nodes.
use crate::common::*;
use crate::gltf_khr::{Context, CONTEXTS};
use crate::gltf_materials::b64;
use glam::DVec3;
use glview::image_out::Rgba;
use glview::pbr::env::Environment;
use glview::reference::PbrEnv;
use std::path::{Path, PathBuf};
use std::sync::Arc;

const N: u32 = 64;

/// Positions, normals and indices of a floor at y = 0 (±`half`, `cells`² quads, facing +Y)
/// and, with `sphere`, a sphere of radius 0.5 standing on it at the origin.
fn geometry(half: f32, cells: u32, sphere: bool) -> Vec<(Vec<f32>, Vec<f32>, Vec<u32>)> {
    let mut floor = (Vec::new(), Vec::new(), Vec::new());
    for i in 0..=cells {
        for j in 0..=cells {
            let f = |k: u32| -half + 2.0 * half * k as f32 / cells as f32;
            floor.0.extend([f(j), 0.0, f(i)]);
            floor.1.extend([0.0, 1.0, 0.0]);
        }
    }
    let w = cells + 1;
    for i in 0..cells {
        for j in 0..cells {
            let (a, b) = (i * w + j, (i + 1) * w + j);
            // Counter-clockwise seen from above: the floor's front faces +Y.
            floor.2.extend([a, b, b + 1, a, b + 1, a + 1]);
        }
    }
    let mut out = vec![floor];
    if sphere {
        let (rings, segs) = (16u32, 32u32);
        let mut s = (Vec::new(), Vec::new(), Vec::new());
        for i in 0..=rings {
            let th = std::f32::consts::PI * i as f32 / rings as f32;
            for j in 0..=segs {
                let ph = 2.0 * std::f32::consts::PI * j as f32 / segs as f32;
                let n = [th.sin() * ph.cos(), th.cos(), th.sin() * ph.sin()];
                s.0.extend([0.5 * n[0], 0.5 + 0.5 * n[1], 0.5 * n[2]]);
                s.1.extend(n);
            }
        }
        let w = segs + 1;
        for i in 0..rings {
            for j in 0..segs {
                let (a, b) = (i * w + j, (i + 1) * w + j);
                s.2.extend([a, a + 1, b, a + 1, b + 1, b]);
            }
        }
        out.push(s);
    }
    out
}

/// A glTF of the floor (and sphere) with `lights` (JSON objects of KHR_lights_punctual) on
/// `light_nodes` (JSON node objects without the extension, one per light, in order); no
/// extension at all when `lights` is empty.
fn model(dir: &Path, name: &str, sphere: bool, lights: &[&str], light_nodes: &[&str]) -> PathBuf {
    model_of(dir, name, (sphere, 16), lights, light_nodes)
}

/// [`model`] with the floor's cells per side.
fn model_of(
    dir: &Path,
    name: &str,
    (sphere, cells): (bool, u32),
    lights: &[&str],
    light_nodes: &[&str],
) -> PathBuf {
    let meshes = geometry(2.0, cells, sphere);
    let (mut bin, mut views, mut accessors, mut mesh_json, mut nodes) = (
        Vec::<u8>::new(),
        Vec::new(),
        Vec::new(),
        Vec::new(),
        Vec::new(),
    );
    for (m, (pos, nrm, idx)) in meshes.iter().enumerate() {
        let first = accessors.len();
        let nv = pos.len() / 3;
        let (lo, hi) = (0..3).fold(([f32::MAX; 3], [f32::MIN; 3]), |(mut lo, mut hi), k| {
            for p in pos.chunks_exact(3) {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
            (lo, hi)
        });
        for (data, ty, extra) in [
            (pos, "VEC3", format!(r#", "min": {lo:?}, "max": {hi:?}"#)),
            (nrm, "VEC3", String::new()),
        ] {
            views.push(format!(
                r#"{{"buffer": 0, "byteOffset": {}, "byteLength": {}}}"#,
                bin.len(),
                data.len() * 4
            ));
            bin.extend(data.iter().flat_map(|x| x.to_le_bytes()));
            accessors.push(format!(
                r#"{{"bufferView": {}, "componentType": 5126, "count": {nv}, "type": "{ty}"{extra}}}"#,
                views.len() - 1
            ));
        }
        views.push(format!(
            r#"{{"buffer": 0, "byteOffset": {}, "byteLength": {}}}"#,
            bin.len(),
            idx.len() * 4
        ));
        bin.extend(idx.iter().flat_map(|x| x.to_le_bytes()));
        accessors.push(format!(
            r#"{{"bufferView": {}, "componentType": 5125, "count": {}, "type": "SCALAR"}}"#,
            views.len() - 1,
            idx.len()
        ));
        mesh_json.push(format!(
            r#"{{"primitives": [{{"attributes": {{"POSITION": {first}, "NORMAL": {}}},
                "indices": {}, "material": {m}}}]}}"#,
            first + 1,
            first + 2
        ));
        nodes.push(format!(r#"{{"mesh": {m}}}"#));
    }
    for (i, n) in light_nodes.iter().enumerate() {
        let n = n.trim_end().trim_end_matches('}');
        let comma = if n.trim_end().ends_with('{') { "" } else { "," };
        nodes.push(format!(
            r#"{n}{comma} "extensions": {{"KHR_lights_punctual": {{"light": {i}}}}}}}"#
        ));
    }
    let roots: Vec<String> = (0..nodes.len()).map(|i| i.to_string()).collect();
    let ext = if lights.is_empty() {
        String::new()
    } else {
        format!(
            r#""extensionsUsed": ["KHR_lights_punctual"],
               "extensions": {{"KHR_lights_punctual": {{"lights": [{}]}}}},"#,
            lights.join(",")
        )
    };
    let json = format!(
        r#"{{"asset": {{"version": "2.0"}}, {ext} "scene": 0, "scenes": [{{"nodes": [{}]}}],
      "nodes": [{}], "meshes": [{}],
      "materials": [
        {{"pbrMetallicRoughness": {{"baseColorFactor": [0.8, 0.8, 0.8, 1], "metallicFactor": 0,
          "roughnessFactor": 0.7}}}},
        {{"pbrMetallicRoughness": {{"baseColorFactor": [0.8, 0.3, 0.2, 1], "metallicFactor": 0,
          "roughnessFactor": 0.4}}}}],
      "buffers": [{{"uri": "data:application/octet-stream;base64,{}", "byteLength": {}}}],
      "bufferViews": [{}], "accessors": [{}]}}"#,
        roots.join(","),
        nodes.join(","),
        mesh_json.join(","),
        b64(&bin),
        bin.len(),
        views.join(","),
        accessors.join(",")
    );
    let p = dir.join(format!("{name}.gltf"));
    std::fs::write(&p, json).unwrap();
    p
}

/// Rotation turning −Z (a light's direction) to −Y: −90° about X.
const DOWN: &str = "[-0.70710678, 0, 0, 0.70710678]";

/// A point light (range 4: its window crosses the floor's far corner) and a spot shining
/// down past the sphere onto the floor.
fn point_and_spot(dir: &Path) -> [(&'static str, PathBuf); 2] {
    let point = model(
        dir,
        "point",
        true,
        &[
            r#"{"type": "point", "name": "Bulb", "intensity": 8, "range": 4, "color": [1, 0.9, 0.8]}"#,
        ],
        &[r#"{"translation": [1.2, 1.8, 0.8]}"#],
    );
    let spot = model(
        dir,
        "spot",
        true,
        &[
            r#"{"type": "spot", "intensity": 12, "color": [0.9, 0.95, 1],
              "spot": {"innerConeAngle": 0.3, "outerConeAngle": 0.55}}"#,
        ],
        &[&format!(
            r#"{{"translation": [0.6, 2, 0.3], "rotation": {DOWN}}}"#
        )],
    );
    [("point", point), ("spot", spot)]
}

fn view_args(model: &Path, shading: &str, extra: &[&str]) -> Vec<String> {
    let size = format!("{N}x{N}");
    let mut v: Vec<String> = [
        model.to_str().unwrap(),
        "--size",
        &size,
        "--shading",
        shading,
        "--no-bloom",
        "--yaw",
        "30",
        "--pitch",
        "35",
        "--env-color",
        "0.1,0.1,0.1",
        "--tonemap",
        "none",
    ]
    .map(String::from)
    .to_vec();
    v.extend(extra.iter().map(|s| s.to_string()));
    v
}

fn shot(dir: &Path, name: &str, args: &[String], ctx: &Context) -> Rgba {
    let mut all: Vec<&str> = args.iter().map(String::as_str).collect();
    all.extend_from_slice(ctx.1);
    render(dir, name, &all, ctx.2)
}

/// Mean and largest channel difference over every pixel, in 1/255.
fn mean_max(a: &Rgba, b: &Rgba) -> (f64, u8) {
    let (mut sum, mut max) = (0u64, 0u8);
    for (x, y) in a.data.iter().zip(&b.data) {
        let d = x.abs_diff(*y);
        sum += u64::from(d);
        max = max.max(d);
    }
    (sum as f64 / (a.data.len() as f64 * 0.75), max)
}

/// A file's point light and spot light, with their shadows, in each tier (Phong, Gouraud and
/// PBR) on GL 3.3, ES 3.0, GL 2.1 and OSMesa, against the CPU reference of the same frame
/// (exact shadows; Monte Carlo in a uniform environment of 0.1 for PBR): mean ≤ 1/255 over
/// the picture, like glview's own lights (the differences are the shadow map's edges).
#[test]
fn file_point_and_spot_lights_match_the_reference_on_every_context() {
    let dir = out_dir("gltf-lights-reference");
    for (light, model) in point_and_spot(&dir) {
        for shading in ["phong", "gouraud", "pbr"] {
            let args = view_args(&model, shading, &[]);
            let words: Vec<&str> = args.iter().map(String::as_str).collect();
            let (settings, scene) = settings_for(&words);
            assert_eq!(
                settings.lights.len(),
                1,
                "the file's light replaces the kit"
            );
            let truth = if shading == "pbr" {
                let pe = PbrEnv {
                    env: Arc::new(Environment::uniform([0.1; 3])),
                    samples: 256,
                };
                glview::reference::render_env_with_info(&scene, &settings, Some(&pe), N, N).0
            } else {
                glview::reference::render(&scene, &settings, N, N)
            };
            for ctx in &CONTEXTS {
                let label = format!("{light}-{shading}-{}", ctx.0);
                let img = shot(&dir, &label, &args, ctx);
                let (mean, max) = mean_max(&img, &truth);
                eprintln!("{label}: mean {mean:.3}/255, max {max}/255");
                if mean > 1.0 {
                    write_diff(&dir, &label, &img, &truth);
                }
                assert!(
                    mean <= 1.0,
                    "{label}: mean {mean:.3}/255 from the reference"
                );
            }
        }
    }
}

/// The largest channel of each pixel's colour, 0..1 (the floor's own colour is grey).
fn pixel(img: &Rgba, x: u32, y: u32) -> [u8; 3] {
    let i = 4 * (y * img.width + x) as usize;
    [img.data[i], img.data[i + 1], img.data[i + 2]]
}

/// Light and geometry of an edge case: the frame's light, and the floor point under each
/// pixel (None off the floor).
fn floor_points(args: &[String]) -> (glview::light::Light, Vec<Option<DVec3>>) {
    let words: Vec<&str> = args.iter().map(String::as_str).collect();
    let (settings, scene) = settings_for(&words);
    assert_eq!(settings.lights.len(), 1);
    let rays = PixelRays::new(&settings, &scene, N, N);
    let mut points = Vec::new();
    for y in 0..N {
        for x in 0..N {
            let (o, d) = rays.ray(x, y);
            let t = -o.y / d.y;
            let p = o + t * d;
            let on = t > 0.0 && p.x.abs() < 1.98 && p.z.abs() < 1.98;
            points.push(on.then_some(p));
        }
    }
    (settings.lights[0], points)
}

/// The edge of a point light's range and of a spot's cone, exact: on a floor lit from 1
/// unit above by a very bright light (so any light at all shows), every pixel whose floor
/// point lies outside (by more than f32's rounding of the edge: 10⁻⁴ relative) equals the
/// picture without the light byte for byte, and every pixel the formula lights by 4/255 or
/// more is lit; the pixels in between (the edge's own ring, and the cone's penumbra where it
/// lights by less) are few. Both tiers, every context.
#[test]
fn range_and_cone_edges_are_exact() {
    let dir = out_dir("gltf-lights-edges");
    let range = model(
        &dir,
        "range",
        false,
        &[r#"{"type": "point", "intensity": 2000, "range": 2}"#],
        &[r#"{"translation": [0, 1, 0]}"#],
    );
    let cone = model(
        &dir,
        "cone",
        false,
        &[r#"{"type": "spot", "intensity": 2000,
              "spot": {"innerConeAngle": 0.5, "outerConeAngle": 0.9}}"#],
        &[&format!(
            r#"{{"translation": [0, 1, 0], "rotation": {DOWN}}}"#
        )],
    );
    for (name, model) in [("range", &range), ("cone", &cone)] {
        for shading in ["phong", "pbr"] {
            let args = view_args(model, shading, &["--no-shadows"]);
            let (light, points) = floor_points(&args);
            let q = match light.kind {
                glview::light::LightKind::Point(q) => q.as_dvec3(),
                k => panic!("{k:?}"),
            };
            // Outside beyond rounding: the range (d ≥ range·(1 + 1e-4)) or the cone
            // (cos θ ≤ cos outer − 1e-4).
            let outside = |p: DVec3| {
                let f = light.falloff;
                let d = (q - p).length();
                match f.spot {
                    None => d * d * f64::from(f.inv_range2) >= (1.0 + 1e-4f64).powi(2),
                    Some(s) => {
                        let cos = s.dir.as_dvec3().dot((p - q) / d);
                        let cos_outer = -f64::from(s.offset) / f64::from(s.scale);
                        cos <= cos_outer - 1e-4
                    }
                }
            };
            let unlit_args = [&args[..], &["--light".into(), "none".into()]].concat();
            for ctx in &CONTEXTS {
                let label = format!("{name}-{shading}-{}", ctx.0);
                let lit = shot(&dir, &label, &args, ctx);
                let dark = shot(&dir, &format!("{label}-none"), &unlit_args, ctx);
                let (mut inside, mut out, mut between) = (0, 0, 0);
                for (i, p) in points.iter().enumerate() {
                    let Some(p) = *p else { continue };
                    let (x, y) = (i as u32 % N, i as u32 / N);
                    let (a, b) = (pixel(&lit, x, y), pixel(&dark, x, y));
                    // The light's colour at the point on a grey floor lit at N·L.
                    let nl = (q - p).normalize().y.max(0.0);
                    let c = light.color_at(p).max_element() * nl * 0.5;
                    if outside(p) {
                        out += 1;
                        assert_eq!(a, b, "{label}: pixel {x},{y} outside the light is lit");
                    } else if c >= 4.0 / 255.0 {
                        inside += 1;
                        assert!(a != b, "{label}: pixel {x},{y} inside the light is unlit");
                    } else {
                        between += 1;
                    }
                }
                eprintln!("{label}: {inside} lit, {out} unlit, {between} on the edge");
                assert!(inside > 200 && out > 200, "{label}: the edge is in view");
                // Measured 4 (range) and 6 (cone) in the PBR tier; 20 and 58 in the legacy
                // tier, whose exposure (docs/gltf/lights.md) dims the soft edge.
                assert!(between <= 64, "{label}: {between} pixels on the edge");
            }
        }
    }
}

/// `--light kit` draws the default kit over a file's lights: the same picture as the file
/// without them, byte for byte; the file's own lights (the default) draw another.
#[test]
fn light_kit_restores_the_default_kit() {
    let dir = out_dir("gltf-lights-kit");
    let [(_, with), _] = point_and_spot(&dir);
    let without = model(&dir, "no-lights", true, &[], &[]);
    let ctx = &CONTEXTS[0];
    for shading in ["phong", "pbr"] {
        let kit = shot(
            &dir,
            &format!("kit-{shading}"),
            &view_args(&with, shading, &["--light", "kit"]),
            ctx,
        );
        let plain = shot(
            &dir,
            &format!("plain-{shading}"),
            &view_args(&without, shading, &[]),
            ctx,
        );
        assert_eq!(
            kit.data, plain.data,
            "{shading}: --light kit is the default kit"
        );
        let file = shot(
            &dir,
            &format!("file-{shading}"),
            &view_args(&with, shading, &[]),
            ctx,
        );
        let named = shot(
            &dir,
            &format!("named-{shading}"),
            &view_args(&with, shading, &["--light", "file"]),
            ctx,
        );
        assert_eq!(
            file.data, named.data,
            "{shading}: --light file is the default"
        );
        assert!(
            max_diff(&file, &kit) > 40,
            "{shading}: the file's light is not the kit"
        );
    }
    // A file without lights has none to name.
    let o = run(
        &[
            without.to_str().unwrap(),
            "--light",
            "file",
            "--size",
            "8x8",
            "--output",
            dir.join("x.png").to_str().unwrap(),
        ],
        &[],
    );
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        !o.status.success() && err.contains("has no lights"),
        "{err}"
    );
}

fn max_diff(a: &Rgba, b: &Rgba) -> u8 {
    mean_max(a, b).1
}

/// `--check` lists a file's lights (kind, name, node, intensity, colour, range, cone, place,
/// direction); malformed lights are warnings, not errors; of six good lights the four
/// brightest at the model's centre are kept and the others named.
#[test]
fn check_lists_the_lights_and_warns_of_bad_ones() {
    let dir = out_dir("gltf-lights-check");
    let m = model(
        &dir,
        "lights",
        false,
        &[
            r#"{"type": "point", "name": "Bulb", "intensity": 8, "range": 4, "color": [1, 0.5, 0.25]}"#,
            r#"{"type": "spot", "name": "Lamp", "intensity": 12, "spot": {"innerConeAngle": 0.5, "outerConeAngle": 0.25}}"#,
            r#"{"type": "directional", "name": "Sun", "intensity": 3}"#,
            r#"{"type": "point", "name": "Negative", "intensity": -1}"#,
            r#"{"type": "area", "name": "Panel"}"#,
            r#"{"type": "point", "name": "Dim", "intensity": 0.001}"#,
            r#"{"type": "point", "name": "Far", "intensity": 8, "range": 0.5}"#,
            r#"{"type": "directional", "name": "Moon", "intensity": 0.5, "range": -3}"#,
        ],
        &[
            r#"{"translation": [1, 2, 3]}"#,
            &format!(r#"{{"translation": [0, 1, 0], "rotation": {DOWN}}}"#),
            &format!(r#"{{"rotation": {DOWN}}}"#),
            "{}",
            "{}",
            r#"{"translation": [0, 10, 0]}"#,
            r#"{"translation": [0, 5, 0]}"#,
            "{}",
        ],
    );
    let o = run(&[m.to_str().unwrap(), "--check"], &[]);
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(
        o.status.success(),
        "{out}\n{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let lines: Vec<&str> = out.lines().filter(|l| l.starts_with("light: ")).collect();
    assert_eq!(lines.len(), 4, "{out}");
    assert!(
        lines.contains(
            &"light: point \"Bulb\" (node 1): 8 cd, colour 1,0.5,0.25, range 4, at 1,2,3"
        ),
        "{out}"
    );
    assert!(lines.iter().any(|l| l.starts_with(
        "light: spot \"Lamp\" (node 2): 12 cd, colour 1,1,1, cone 14.3239°-14.3239°, at 0,1,0, towards "
    )), "{out}");
    assert!(
        lines
            .iter()
            .any(|l| l.starts_with("light: directional \"Sun\" (node 3): 3 lux")),
        "{out}"
    );
    assert!(
        lines
            .iter()
            .any(|l| l.starts_with("light: directional \"Moon\"")),
        "{out}"
    );
    for w in [
        "light 1: cone angles 0.5 and 0.25",
        "light 3: intensity -1",
        "light 4: unknown type \"area\"",
        "light 7: range -3 is not a number > 0",
        "6 lights, glview draws at most 4",
        "\"Dim\", \"Far\"",
    ] {
        assert!(
            out.lines()
                .any(|l| l.starts_with("warning: ") && l.contains(w)),
            "{w}: {out}"
        );
    }
}

/// A file's lights come back from the mesh cache as they were read: `--check` lists the same
/// lights from the entry (a 5 MB file: large enough to be cached) as from the file.
#[test]
fn lights_come_back_from_the_mesh_cache() {
    let dir = out_dir("gltf-lights-cache");
    let entries = dir.join("entries");
    let _ = std::fs::remove_dir_all(&entries);
    let m = model_of(
        &dir,
        "big",
        (false, 400),
        &[
            r#"{"type": "spot", "name": "Lamp", "intensity": 12, "range": 9,
              "spot": {"innerConeAngle": 0.2, "outerConeAngle": 0.6}}"#,
        ],
        &[&format!(
            r#"{{"translation": [0, 1, 0], "rotation": {DOWN}}}"#
        )],
    );
    let env = [("GLVIEW_CACHE_DIR", entries.to_str().unwrap())];
    let check = || {
        let o = run(&[m.to_str().unwrap(), "--check"], &env);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        String::from_utf8_lossy(&o.stdout).into_owned()
    };
    let (fresh, cached) = (check(), check());
    let lights = |s: &str| -> Vec<String> {
        s.lines()
            .filter(|l| l.starts_with("light: "))
            .map(String::from)
            .collect()
    };
    assert!(
        cached.contains("(mesh cache)"),
        "the second load is a hit: {cached}"
    );
    assert!(!fresh.contains("(mesh cache)"), "{fresh}");
    assert_eq!(lights(&fresh).len(), 1, "{fresh}");
    assert_eq!(lights(&fresh), lights(&cached));
}
