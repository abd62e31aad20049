//! The glTF material model drawn (issue 19, render side), against exact expectations on a
//! generated quad that fills an orthographic picture, so pixel (x, y) reads the texture at a
//! known UV: wrap modes texel for texel, unlit equals the base colour texture, an emissive
//! texture alone equals the texture, MASK coverage equals the cutoff region, TEXCOORD_1 and
//! KHR_texture_transform equal UVs moved on the CPU, supplied
//! tangents equal the normal they imply, a mirroring node the mirror image. Every check runs
//! on all five contexts (3.3 core, ES 3.0, 2.1, 2.1 without FBOs, OSMesa) and in both tiers
//! where the tier draws the slot.
use crate::common::*;
use crate::gltf_materials::b64;
use glview::image_out::Rgba;
use glview::image_out::RgbaFiles;
use std::path::{Path, PathBuf};

/// Side of the square pictures; the quad spans it exactly.
const N: u32 = 48;

/// A w×h RGBA PNG as a data: URI.
pub(crate) fn png(w: u32, h: u32, px: &[[u8; 4]]) -> String {
    let img = image::RgbaImage::from_raw(w, h, px.concat()).unwrap();
    let mut out = std::io::Cursor::new(Vec::new());
    img.write_to(&mut out, image::ImageFormat::Png).unwrap();
    format!("data:image/png;base64,{}", b64(&out.into_inner()))
}

/// The quad's optional vertex streams and its node's x scale.
#[derive(Clone)]
pub(crate) struct Quad {
    /// TEXCOORD_0 at the top-left, top-right, bottom-right and bottom-left corners.
    pub uv0: [[f32; 2]; 4],
    pub uv1: Option<[[f32; 2]; 4]>,
    pub normal: [f32; 3],
    pub tangent: Option<[f32; 4]>,
    /// COLOR_0 (RGBA) at the corners, in the order of `uv0`.
    pub color: Option<[[f32; 4]; 4]>,
    pub scale_x: f32,
}

impl Default for Quad {
    fn default() -> Self {
        Quad {
            uv0: [[0., 0.], [1., 0.], [1., 1.], [0., 1.]],
            uv1: None,
            normal: [0., 0., 1.],
            tangent: None,
            color: None,
            scale_x: 1.0,
        }
    }
}

/// Writes `name.gltf`: the quad (-1..1)² in z = 0 facing +Z, with `materials` (JSON fields:
/// materials, textures, samplers, images).
pub(crate) fn quad(dir: &Path, name: &str, q: &Quad, materials: &str) -> PathBuf {
    // Corners top-left, top-right, bottom-right, bottom-left (picture order).
    let pos = [[-1f32, 1., 0.], [1., 1., 0.], [1., -1., 0.], [-1., -1., 0.]];
    let mut bin: Vec<u8> = Vec::new();
    let mut views = Vec::new();
    let mut attrs = Vec::new();
    let mut accessors = Vec::new();
    let mut push = |name: &str, kind: &str, data: Vec<f32>, bin: &mut Vec<u8>| {
        let off = bin.len();
        for x in &data {
            bin.extend(x.to_le_bytes());
        }
        let i = views.len();
        views.push(format!(
            r#"{{"buffer": 0, "byteOffset": {off}, "byteLength": {}}}"#,
            data.len() * 4
        ));
        let minmax = if name == "POSITION" {
            r#", "min": [-1, -1, 0], "max": [1, 1, 0]"#
        } else {
            ""
        };
        accessors.push(format!(
            r#"{{"bufferView": {i}, "componentType": 5126, "count": 4, "type": "{kind}"{minmax}}}"#
        ));
        attrs.push(format!(r#""{name}": {i}"#));
    };
    push("POSITION", "VEC3", pos.concat(), &mut bin);
    push("NORMAL", "VEC3", q.normal.repeat(4), &mut bin);
    push("TEXCOORD_0", "VEC2", q.uv0.concat(), &mut bin);
    if let Some(uv1) = q.uv1 {
        push("TEXCOORD_1", "VEC2", uv1.concat(), &mut bin);
    }
    if let Some(t) = q.tangent {
        push("TANGENT", "VEC4", t.repeat(4), &mut bin);
    }
    if let Some(c) = q.color {
        push("COLOR_0", "VEC4", c.concat(), &mut bin);
    }
    // Counter-clockwise seen from +Z: bottom-left, bottom-right, top-right, top-left.
    let index_off = bin.len();
    for i in [3u16, 2, 1, 3, 1, 0] {
        bin.extend(i.to_le_bytes());
    }
    views.push(format!(
        r#"{{"buffer": 0, "byteOffset": {index_off}, "byteLength": 12}}"#
    ));
    accessors.push(format!(
        r#"{{"bufferView": {}, "componentType": 5123, "count": 6, "type": "SCALAR"}}"#,
        views.len() - 1
    ));
    let json = format!(
        r#"{{"asset": {{"version": "2.0"}}, "scene": 0, "scenes": [{{"nodes": [0]}}],
      "extensionsUsed": ["KHR_texture_transform", "KHR_materials_unlit"],
      "nodes": [{{"mesh": 0, "scale": [{}, 1, 1]}}],
      "meshes": [{{"primitives": [{{"attributes": {{{}}}, "indices": {}, "material": 0}}]}}],
      "buffers": [{{"uri": "data:application/octet-stream;base64,{}", "byteLength": {}}}],
      "bufferViews": [{}], "accessors": [{}], {materials}}}"#,
        q.scale_x,
        attrs.join(", "),
        accessors.len() - 1,
        b64(&bin),
        bin.len(),
        views.join(", "),
        accessors.join(", ")
    );
    let p = dir.join(format!("{name}.gltf"));
    std::fs::write(&p, json).unwrap();
    p
}

/// A context every check runs on: (name, arguments, environment).
type Context = (
    &'static str,
    Vec<&'static str>,
    &'static [(&'static str, &'static str)],
);

fn contexts() -> Vec<Context> {
    vec![
        ("core", vec!["--gl", "core", "--backend", "egl"], &[]),
        ("es3", vec!["--gl", "es3", "--backend", "egl"], &[]),
        ("gl21", vec!["--gl", "2.1", "--backend", "egl"], GL21),
        // EGL headless draws into a framebuffer object: without FBOs only OSMesa draws.
        ("osmesa", vec!["--gl", "2.1", "--backend", "osmesa"], GL21),
        (
            "gl21-nofbo",
            vec!["--gl", "2.1", "--backend", "osmesa"],
            GL21_NO_FBO,
        ),
    ]
}

/// Renders `model` looking straight at the quad, which fills the picture, on context `ctx`.
fn shot(
    dir: &Path,
    name: &str,
    model: &Path,
    ctx: &(&str, Vec<&str>, &[(&str, &str)]),
    extra: &[&str],
) -> Rgba {
    let (out, args) = shot_words(dir, name, model, ctx, extra);
    let mut all = vec!["--output", out.to_str().unwrap()];
    all.extend(args.iter().map(String::as_str));
    let o = run(&all, ctx.2);
    assert!(
        o.status.success(),
        "glview {all:?} failed:\n{}",
        String::from_utf8_lossy(&o.stderr)
    );
    Rgba::load_png(&out).expect("read output")
}

/// [`shot`]'s output file and words (without `--output`).
fn shot_words(
    dir: &Path,
    name: &str,
    model: &Path,
    ctx: &(&str, Vec<&str>, &[(&str, &str)]),
    extra: &[&str],
) -> (std::path::PathBuf, Vec<String>) {
    let size = format!("{N}x{N}");
    let mut args = vec![
        model.to_str().unwrap(),
        "--size",
        &size,
        "--ortho",
        "2",
        "--yaw",
        "0",
        "--pitch",
        "0",
        "--no-bloom",
    ];
    args.extend(ctx.1.iter().copied());
    args.extend_from_slice(extra);
    let out = dir.join(format!("{name}-{}.png", ctx.0));
    (out, args.into_iter().map(String::from).collect())
}

/// [`shot`] of each of `jobs` (name, model, extra words) from one `glview batch` process
/// on context `ctx` (a batch job's picture is the same command line's run alone:
/// `batch::batch_equals_single_runs_and_reports_failures_by_line`): one process and one
/// context for many pictures, instead of one each.
fn shots(
    dir: &Path,
    jobs: &[(String, std::path::PathBuf, &[&str])],
    ctx: &(&str, Vec<&str>, &[(&str, &str)]),
) -> Vec<Rgba> {
    let quote = |w: &str| format!("'{}'", w.replace('\'', r"'\''"));
    let mut lines = Vec::new();
    let mut outs = Vec::new();
    for (name, model, extra) in jobs {
        let (out, args) = shot_words(dir, name, model, ctx, extra);
        let mut words = vec![quote("--output"), quote(out.to_str().unwrap())];
        words.extend(args.iter().map(|w| quote(w)));
        lines.push(words.join(" "));
        outs.push(out);
    }
    let file = dir.join(format!("jobs-{}-{}.txt", ctx.0, jobs[0].0));
    std::fs::write(&file, lines.join("\n")).unwrap();
    let o = run(&["batch", file.to_str().unwrap()], ctx.2);
    assert!(
        o.status.success(),
        "glview batch {} failed:\n{}",
        file.display(),
        String::from_utf8_lossy(&o.stderr)
    );
    outs.iter()
        .map(|out| Rgba::load_png(out).expect("read output"))
        .collect()
}

/// The UV at the centre of pixel (x, y) of the quad whose corners carry `uv` (picture
/// order: top-left, top-right, bottom-right, bottom-left; bilinear over an axis-aligned
/// rectangle of UVs).
fn uv_at(uv: &[[f32; 2]; 4], x: u32, y: u32) -> [f64; 2] {
    let fx = (f64::from(x) + 0.5) / f64::from(N);
    let fy = (f64::from(y) + 0.5) / f64::from(N);
    let (a, b) = (uv[0], uv[2]);
    [
        f64::from(a[0]) + fx * f64::from(b[0] - a[0]),
        f64::from(a[1]) + fy * f64::from(b[1] - a[1]),
    ]
}

/// Where a texel boundary is nearer than this (in texels) to a pixel's UV, rasterisation
/// rounding may pick either texel: those pixels are not checked.
const EDGE: f64 = 0.05;

fn near_edge(t: f64) -> bool {
    (t - t.round()).abs() < EDGE
}

/// glTF's wrap rules on one coordinate in texels (`size` texels): repeat, clamp, mirror.
fn wrap(t: f64, size: u32, mode: u32) -> u32 {
    let n = f64::from(size);
    let i = match mode {
        33071 => t.clamp(0.0, n - 1e-9).floor(),
        33648 => {
            let p = t.rem_euclid(2.0 * n);
            if p < n {
                p.floor()
            } else {
                (2.0 * n - p).floor().min(n - 1.0)
            }
        }
        _ => t.rem_euclid(n).floor(),
    };
    i as u32
}

/// Asserts that `img` equals `want(x, y)` (None: not checked) within `tol` per channel;
/// writes the picture beside its name on failure.
fn assert_pixels(
    img: &Rgba,
    name: &str,
    tol: u8,
    want: impl Fn(u32, u32) -> Option<[u8; 4]>,
) -> usize {
    let mut checked = 0;
    for y in 0..N {
        for x in 0..N {
            let Some(w) = want(x, y) else { continue };
            let got = img.pixel(x, y);
            let bad = (0..4).any(|c| got[c].abs_diff(w[c]) > tol);
            assert!(
                !bad,
                "{name}: pixel ({x}, {y}) is {got:?}, expected {w:?} (±{tol})"
            );
            checked += 1;
        }
    }
    checked
}

/// A 2×2 texture of four distinct colours (top-left red, top-right green, bottom-left blue,
/// bottom-right yellow).
pub(crate) const TEXELS: [[u8; 4]; 4] = [
    [230, 30, 40, 255],
    [20, 200, 60, 255],
    [30, 60, 220, 255],
    [240, 220, 20, 255],
];

fn unlit(sampler: &str, texture: &str, extra: &str) -> String {
    format!(
        r#""samplers": [{sampler}], "textures": [{{"source": 0, "sampler": 0}}],
      "images": [{{"uri": "{}"}}],
      "materials": [{{"pbrMetallicRoughness": {{"baseColorTexture": {texture}}},
        "extensions": {{"KHR_materials_unlit": {{}}}}{extra}}}]"#,
        png(2, 2, &TEXELS)
    )
}

pub(crate) const NEAREST: &str = r#""magFilter": 9728, "minFilter": 9728"#;

/// PBR output without tone mapping or exposure: sRGB(linear) is the texture again.
const PBR_PLAIN: &[&str] = &["--shading", "pbr", "--tonemap", "none", "--exposure", "0"];

#[test]
fn wrap_modes_are_texel_exact_and_unlit_is_the_texture() {
    let dir = out_dir("gltf-draw-wrap");
    // UVs from -1 to 2: three periods across the picture, so every rule shows.
    let q = Quad {
        uv0: [[-1., -1.], [2., -1.], [2., 2.], [-1., 2.]],
        ..Quad::default()
    };
    let modes = [(10497, "repeat"), (33071, "clamp"), (33648, "mirror")];
    // Every pair of modes in both tiers: (name, model, extra words) and the modes.
    let mut jobs = Vec::new();
    let mut wraps = Vec::new();
    for (s, sn) in modes {
        for (t, tn) in modes {
            let name = format!("wrap-{sn}-{tn}");
            let sampler = format!(r#"{{{NEAREST}, "wrapS": {s}, "wrapT": {t}}}"#);
            let m = quad(&dir, &name, &q, &unlit(&sampler, r#"{"index": 0}"#, ""));
            for (tier, extra) in [("legacy", &[][..]), ("pbr", PBR_PLAIN)] {
                jobs.push((format!("{name}-{tier}"), m.clone(), extra));
                wraps.push((s, t));
            }
        }
    }
    for ctx in contexts() {
        let imgs = shots(&dir, &jobs, &ctx);
        for ((img, (name, _, _)), &(s, t)) in imgs.iter().zip(&jobs).zip(&wraps) {
            let n = assert_pixels(img, &format!("{name} {}", ctx.0), 1, |x, y| {
                let [u, v] = uv_at(&q.uv0, x, y).map(|c| c * 2.0);
                if near_edge(u) || near_edge(v) {
                    return None;
                }
                let (i, j) = (wrap(u, 2, s), wrap(v, 2, t));
                Some(TEXELS[(j * 2 + i) as usize])
            });
            assert!(n > (N * N / 2) as usize, "{name}: only {n} pixels checked");
        }
    }
}

#[test]
fn emissive_texture_alone_is_the_texture() {
    let dir = out_dir("gltf-draw-emissive");
    let mats = format!(
        r#""samplers": [{{{NEAREST}}}], "textures": [{{"source": 0, "sampler": 0}}],
      "images": [{{"uri": "{}"}}],
      "materials": [{{"pbrMetallicRoughness": {{"baseColorFactor": [0, 0, 0, 1]}},
        "emissiveTexture": {{"index": 0}}, "emissiveFactor": [1, 1, 1]}}]"#,
        png(2, 2, &TEXELS)
    );
    let q = Quad::default();
    let m = quad(&dir, "emissive", &q, &mats);
    let legacy = ["--ambient", "0,0,0", "--light", "none"];
    let pbr = [PBR_PLAIN, &["--terms", "emissive"]].concat();
    for ctx in contexts() {
        for (tier, extra) in [("legacy", &legacy[..]), ("pbr", &pbr[..])] {
            let img = shot(&dir, &format!("emissive-{tier}"), &m, &ctx, extra);
            assert_pixels(&img, &format!("emissive {tier} {}", ctx.0), 1, |x, y| {
                let [u, v] = uv_at(&q.uv0, x, y).map(|c| c * 2.0);
                (!near_edge(u) && !near_edge(v)).then(|| TEXELS[(v as usize) * 2 + u as usize])
            });
        }
    }
}

/// Alpha 0.1, 0.3, 0.6, 0.9 across four texel columns.
pub(crate) fn alpha_ramp() -> String {
    let a = [26u8, 77, 153, 230];
    let px: Vec<[u8; 4]> = a.iter().map(|&a| [200, 200, 200, a]).collect();
    png(4, 1, &px)
}

#[test]
fn mask_coverage_is_the_cutoff_region() {
    let dir = out_dir("gltf-draw-mask");
    let q = Quad::default();
    for (cutoff, visible_from) in [(0.5, 2u32), (0.2, 1)] {
        let mats = format!(
            r#""samplers": [{{{NEAREST}}}], "textures": [{{"source": 0, "sampler": 0}}],
          "images": [{{"uri": "{}"}}],
          "materials": [{{"pbrMetallicRoughness": {{"baseColorTexture": {{"index": 0}}}},
            "alphaMode": "MASK", "alphaCutoff": {cutoff}, "doubleSided": true}}]"#,
            alpha_ramp()
        );
        let m = quad(&dir, &format!("mask-{cutoff}"), &q, &mats);
        for ctx in contexts() {
            for (tier, extra) in [("legacy", &[][..]), ("pbr", &["--shading", "pbr"][..])] {
                let args = [extra, &["--transparent", "--no-shadows"]].concat();
                let img = shot(&dir, &format!("mask-{cutoff}-{tier}"), &m, &ctx, &args);
                for y in 0..N {
                    for x in 0..N {
                        let u = uv_at(&q.uv0, x, y)[0] * 4.0;
                        if near_edge(u) {
                            continue;
                        }
                        let drawn = img.pixel(x, y)[3] == 255;
                        assert_eq!(
                            drawn,
                            u as u32 >= visible_from,
                            "{} {tier} cutoff {cutoff}: pixel ({x}, {y}) at u {u:.2} drawn {drawn}",
                            ctx.0
                        );
                    }
                }
            }
        }
    }
}

#[test]
fn second_uv_set_and_texture_transform_equal_uvs_moved_on_the_cpu() {
    let dir = out_dir("gltf-draw-uv");
    let base = Quad::default();
    let sampler = format!("{{{NEAREST}}}");
    // TEXCOORD_1 carries the layout, TEXCOORD_0 a constant (reading set 0 would be one colour).
    let q1 = Quad {
        uv0: [[0.75, 0.75]; 4],
        uv1: Some(base.uv0),
        ..Quad::default()
    };
    let set1 = quad(
        &dir,
        "set1",
        &q1,
        &unlit(&sampler, r#"{"index": 0, "texCoord": 1}"#, ""),
    );
    let plain = quad(&dir, "set0", &base, &unlit(&sampler, r#"{"index": 0}"#, ""));
    // KHR_texture_transform on set 0 against the same transform applied to the corners.
    let x = glview::scene::model::texture_slot::TexTransform {
        offset: [0.25, -0.5],
        rotation: 0.3,
        scale: [1.5, 2.0],
    };
    let moved = Quad {
        uv0: base.uv0.map(|uv| x.apply(uv)),
        ..Quad::default()
    };
    let transformed = quad(
        &dir,
        "transform",
        &base,
        &unlit(
            &sampler,
            r#"{"index": 0, "extensions": {"KHR_texture_transform":
                {"offset": [0.25, -0.5], "rotation": 0.3, "scale": [1.5, 2.0]}}}"#,
            "",
        ),
    );
    let cpu = quad(
        &dir,
        "moved",
        &moved,
        &unlit(&sampler, r#"{"index": 0}"#, ""),
    );
    for ctx in contexts() {
        for (tier, extra) in [("legacy", &[][..]), ("pbr", PBR_PLAIN)] {
            let a = shot(&dir, &format!("set1-{tier}"), &set1, &ctx, extra);
            let b = shot(&dir, &format!("set0-{tier}"), &plain, &ctx, extra);
            let d = diff(&a, &b, 1);
            assert_eq!(d.over, 0, "{} {tier}: TEXCOORD_1 differs from set 0", ctx.0);
            let c = shot(
                &dir,
                &format!("transform-{tier}"),
                &transformed,
                &ctx,
                extra,
            );
            let e = shot(&dir, &format!("moved-{tier}"), &cpu, &ctx, extra);
            // Nearest texels: the two may round a boundary pixel differently, no more.
            let d = diff(&c, &e, 1);
            assert!(
                d.over <= (N as usize) / 2,
                "{} {tier}: transform differs from moved UVs at {} pixels",
                ctx.0,
                d.over
            );
            // And the transform did something: the picture is not the untransformed one.
            assert!(diff(&c, &b, 1).over > (N * N / 4) as usize);
        }
    }
}

#[test]
fn supplied_tangents_bend_the_normal_they_imply() {
    let dir = out_dir("gltf-draw-tangents");
    // A constant normal map leaning along the tangent: m = (0.5, 0, 0.866).
    let texel = [191u8, 128, 238, 255];
    let m: [f64; 3] = [texel[0], texel[1], texel[2]].map(|c| f64::from(c) / 255.0 * 2.0 - 1.0);
    let map = png(1, 1, &[texel]);
    let mats = format!(
        r#""textures": [{{"source": 0}}], "images": [{{"uri": "{map}"}}],
      "materials": [{{"pbrMetallicRoughness": {{"baseColorFactor": [0.8, 0.8, 0.8, 1],
        "metallicFactor": 0, "roughnessFactor": 0.6}}, "normalTexture": {{"index": 0}}}}]"#
    );
    let plain_mats = r#""materials": [{"pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.8, 0.8, 1],
        "metallicFactor": 0, "roughnessFactor": 0.6}}]"#;
    // Tangent +Y (MikkTSpace would give +X for these UVs): bitangent cross(N, T) = -X, so
    // the bent normal is (-m.y, m.x, m.z).
    let q = Quad {
        tangent: Some([0., 1., 0., 1.]),
        ..Quad::default()
    };
    let bent = glam::DVec3::new(-m[1], m[0], m[2]).normalize().as_vec3();
    let supplied = quad(&dir, "supplied", &q, &mats);
    let generated = quad(&dir, "generated", &Quad::default(), &mats);
    let reference = quad(
        &dir,
        "reference",
        &Quad {
            normal: bent.into(),
            ..Quad::default()
        },
        plain_mats,
    );
    let light = [
        "--light",
        "dir:0.3,-0.8,-0.6",
        "--no-shadows",
        "--ambient",
        "0,0,0",
    ];
    for ctx in contexts() {
        for (tier, extra) in [("legacy", &[][..]), ("pbr", &["--shading", "pbr"][..])] {
            let args = [&light[..], extra].concat();
            let a = shot(&dir, &format!("supplied-{tier}"), &supplied, &ctx, &args);
            let r = shot(&dir, &format!("reference-{tier}"), &reference, &ctx, &args);
            let g = shot(&dir, &format!("generated-{tier}"), &generated, &ctx, &args);
            let d = diff(&a, &r, 2);
            assert_eq!(
                d.over, 0,
                "{} {tier}: the supplied tangent frame differs from its normal (max {})",
                ctx.0, d.max
            );
            // MikkTSpace's frame bends the normal elsewhere: the file's tangents were used.
            assert!(
                diff(&g, &r, 2).over > (N * N / 2) as usize,
                "{} {tier}",
                ctx.0
            );
        }
    }
}

#[test]
fn a_mirroring_node_draws_the_mirror_image() {
    let dir = out_dir("gltf-draw-mirror");
    let sampler = format!("{{{NEAREST}}}");
    let mats = unlit(&sampler, r#"{"index": 0}"#, r#", "doubleSided": false"#);
    let plain = quad(&dir, "plain", &Quad::default(), &mats);
    let mirrored = quad(
        &dir,
        "mirrored",
        &Quad {
            scale_x: -1.0,
            ..Quad::default()
        },
        &mats,
    );
    for ctx in contexts() {
        let a = shot(&dir, "plain", &plain, &ctx, &[]);
        let b = shot(&dir, "mirrored", &mirrored, &ctx, &[]);
        let mut flipped = a.clone();
        for y in 0..N {
            for x in 0..N {
                let i = ((y * N + x) * 4) as usize;
                flipped.data[i..i + 4].copy_from_slice(&a.pixel(N - 1 - x, y));
            }
        }
        let d = diff(&flipped, &b, 1);
        assert_eq!(
            d.over, 0,
            "{}: not the mirror image (single-sided, so front faces)",
            ctx.0
        );
        assert!(diff(&a, &b, 1).over > (N * N / 2) as usize);
    }
}

/// What a MASK material leaves out casts no shadow: light 0's depth map (a directional light
/// straight at the quad) covers the share of the quad the cutoff keeps — half of it at cutoff
/// 0.5, three quarters at 0.2 — of what the opaque quad covers.
#[test]
fn mask_cut_outs_cast_no_shadow() {
    let dir = out_dir("gltf-draw-mask-shadow");
    let covered = |alpha: &str, ctx: &(&str, Vec<&str>, &[(&str, &str)])| {
        let mats = format!(
            r#""samplers": [{{{NEAREST}}}], "textures": [{{"source": 0, "sampler": 0}}],
          "images": [{{"uri": "{}"}}],
          "materials": [{{"pbrMetallicRoughness": {{"baseColorTexture": {{"index": 0}}}},
            {alpha} "doubleSided": true}}]"#,
            alpha_ramp()
        );
        let name = format!(
            "shadow-{}",
            alpha.replace(|c: char| !c.is_ascii_digit(), "")
        );
        let m = quad(&dir, &name, &Quad::default(), &mats);
        let args = ["--show", "shadow-map", "--light", "dir:0,0,-1"];
        let img = shot(&dir, &name, &m, ctx, &args);
        // The cleared map is white (far); the quad is nearer, so darker.
        img.data.chunks_exact(4).filter(|p| p[0] < 250).count() as f64
    };
    for ctx in contexts() {
        let opaque = covered("", &ctx);
        assert!(opaque > 100.0, "{}: the quad casts no shadow at all", ctx.0);
        for (alpha, share) in [
            (r#""alphaMode": "MASK", "alphaCutoff": 0.5,"#, 0.5),
            (r#""alphaMode": "MASK", "alphaCutoff": 0.2,"#, 0.75),
        ] {
            let got = covered(alpha, &ctx) / opaque;
            assert!(
                (got - share).abs() < 0.05,
                "{}: {alpha} covers {got:.3} of the opaque quad's shadow, expected {share}",
                ctx.0
            );
        }
    }
}
