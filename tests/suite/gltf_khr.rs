//! The glTF PBR extensions (issue 32) on a generated sphere, against exact expectations:
//! each extension at its neutral value draws the core model (a clearcoat of factor 0, a
//! sheen of colour 0, transmission 0, ior 1.5 with the default specular: pixel for pixel
//! within 1/255, on every context); a transmissive thin sphere shows the background, a
//! volume attenuates it by Beer–Lambert; a layer switched off by `--terms` equals the material without it; the
//! GPU's permutations equal the CPU reference's Monte Carlo truth in a uniform environment
//! with a light; a white-furnace sphere with a clearcoat or a sheen reflects no more than
//! arrives, on the GPU and in the reference; `--check` names the extensions.
use crate::common::*;
use crate::gltf_materials::b64;
use glview::image_out::Rgba;
use glview::pbr::env::Environment;
use glview::reference::{render_env_with_info, PbrEnv};
use std::path::{Path, PathBuf};
use std::sync::Arc;

const N: u32 = 64;

/// A UV sphere of radius 1 (positions, normals, UVs) with one material (JSON object).
fn sphere(dir: &Path, name: &str, material: &str) -> PathBuf {
    sphere_of(dir, name, material, (24, 48))
}

/// [`sphere`] with (rings, segments).
fn sphere_of(dir: &Path, name: &str, material: &str, (rings, segs): (u32, u32)) -> PathBuf {
    let (mut pos, mut uv, mut idx) = (Vec::new(), Vec::new(), Vec::new());
    for i in 0..=rings {
        let th = std::f32::consts::PI * i as f32 / rings as f32;
        for j in 0..=segs {
            let ph = 2.0 * std::f32::consts::PI * j as f32 / segs as f32;
            pos.extend([th.sin() * ph.cos(), th.cos(), th.sin() * ph.sin()]);
            uv.extend([j as f32 / segs as f32, i as f32 / rings as f32]);
        }
    }
    let w = segs + 1;
    for i in 0..rings {
        for j in 0..segs {
            let (a, b) = (i * w + j, (i + 1) * w + j);
            idx.extend([a, a + 1, b, a + 1, b + 1, b]);
        }
    }
    let nv = pos.len() / 3;
    let mut bin: Vec<u8> = Vec::new();
    for x in pos.iter().chain(&pos).chain(&uv) {
        bin.extend(x.to_le_bytes());
    }
    for i in &idx {
        bin.extend(i.to_le_bytes());
    }
    let json = format!(
        r#"{{"asset": {{"version": "2.0"}}, "scene": 0, "scenes": [{{"nodes": [0]}}],
      "nodes": [{{"mesh": 0}}],
      "meshes": [{{"primitives": [{{"attributes": {{"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2}},
        "indices": 3, "material": 0}}]}}],
      "buffers": [{{"uri": "data:application/octet-stream;base64,{}", "byteLength": {}}}],
      "bufferViews": [{{"buffer": 0, "byteOffset": 0, "byteLength": {v3}}},
        {{"buffer": 0, "byteOffset": {v3}, "byteLength": {v3}}},
        {{"buffer": 0, "byteOffset": {}, "byteLength": {}}},
        {{"buffer": 0, "byteOffset": {}, "byteLength": {}}}],
      "accessors": [{{"bufferView": 0, "componentType": 5126, "count": {nv}, "type": "VEC3",
          "min": [-1, -1, -1], "max": [1, 1, 1]}},
        {{"bufferView": 1, "componentType": 5126, "count": {nv}, "type": "VEC3"}},
        {{"bufferView": 2, "componentType": 5126, "count": {nv}, "type": "VEC2"}},
        {{"bufferView": 3, "componentType": 5125, "count": {}, "type": "SCALAR"}}],
      "materials": [{material}]}}"#,
        b64(&bin),
        bin.len(),
        2 * nv * 12,
        nv * 8,
        2 * nv * 12 + nv * 8,
        idx.len() * 4,
        idx.len(),
        v3 = nv * 12,
    );
    let p = dir.join(format!("{name}.gltf"));
    std::fs::write(&p, json).unwrap();
    p
}

/// A material of the core model with `extensions` (JSON members of "extensions").
fn material(base: [f64; 3], metallic: f64, roughness: f64, extensions: &str) -> String {
    format!(
        r#"{{"pbrMetallicRoughness": {{"baseColorFactor": [{}, {}, {}, 1],
        "metallicFactor": {metallic}, "roughnessFactor": {roughness}}},
        "extensions": {{{extensions}}}}}"#,
        base[0], base[1], base[2]
    )
}

/// A context: (name, arguments, environment).
type Context = (
    &'static str,
    &'static [&'static str],
    &'static [(&'static str, &'static str)],
);

const CONTEXTS: [Context; 4] = [
    ("gl33", &["--gl", "core", "--backend", "egl"], &[]),
    ("es30", &["--gl", "es3", "--backend", "egl"], &[]),
    ("gl21", &["--gl", "2.1", "--backend", "egl"], GL21),
    (
        "osmesa",
        &["--gl", "2.1", "--backend", "osmesa"],
        GL21_NO_FBO,
    ),
];

fn view(model: &Path, extra: &[&str]) -> Vec<String> {
    let size = format!("{N}x{N}");
    let mut v: Vec<String> = [
        model.to_str().unwrap(),
        "--size",
        &size,
        "--shading",
        "pbr",
        "--no-bloom",
        "--yaw",
        "30",
        "--pitch",
        "20",
    ]
    .map(String::from)
    .to_vec();
    v.extend(extra.iter().map(|s| s.to_string()));
    v
}

fn shot(dir: &Path, name: &str, model: &Path, extra: &[&str], ctx: &Context) -> Rgba {
    let mut args = view(model, extra);
    args.extend(ctx.1.iter().map(|s| s.to_string()));
    let all: Vec<&str> = args.iter().map(String::as_str).collect();
    render(dir, name, &all, ctx.2)
}

/// Largest channel difference between two pictures (in 1/255).
fn max_diff(a: &Rgba, b: &Rgba) -> u8 {
    a.data
        .iter()
        .zip(&b.data)
        .map(|(x, y)| x.abs_diff(*y))
        .max()
        .unwrap_or(0)
}

const BASE: [f64; 3] = [0.8, 0.25, 0.1];

/// Clearcoat factor 0, sheen colour 0, transmission 0, ior 1.5 (with specular factor 1 and
/// colour 1) each draw the core material: the program differs, the picture may not (within 1/255), on the
/// built-in sky with the default light and tone mapping, on every context.
#[test]
fn neutral_extensions_equal_the_core_model_on_every_context() {
    let dir = out_dir("gltf-khr-neutral");
    let core = sphere(&dir, "core", &material(BASE, 0.0, 0.45, ""));
    let cases = [
        (
            "clearcoat0",
            r#""KHR_materials_clearcoat": {"clearcoatFactor": 0, "clearcoatRoughnessFactor": 0.1}"#,
        ),
        (
            "sheen0",
            r#""KHR_materials_sheen": {"sheenColorFactor": [0, 0, 0], "sheenRoughnessFactor": 0.5}"#,
        ),
        (
            "transmission0",
            r#""KHR_materials_transmission": {"transmissionFactor": 0}"#,
        ),
        (
            "ior15",
            r#""KHR_materials_ior": {"ior": 1.5},
               "KHR_materials_specular": {"specularFactor": 1, "specularColorFactor": [1, 1, 1]}"#,
        ),
    ];
    let models: Vec<(&str, PathBuf)> = cases
        .iter()
        .map(|(name, ext)| (*name, sphere(&dir, name, &material(BASE, 0.0, 0.45, ext))))
        .collect();
    for ctx in &CONTEXTS {
        let want = shot(&dir, &format!("core-{}", ctx.0), &core, &[], ctx);
        for (name, model) in &models {
            let got = shot(&dir, &format!("{name}-{}", ctx.0), model, &[], ctx);
            let d = max_diff(&got, &want);
            eprintln!("{name} on {}: max difference {d}/255", ctx.0);
            if d > 1 {
                write_diff(&dir, &format!("{name}-{}", ctx.0), &got, &want);
            }
            assert!(d <= 1, "{name} on {}: {d}/255 from the core model", ctx.0);
        }
    }
}

/// `--terms` without `clearcoat` (or `sheen`) draws the material as if it had no such layer.
#[test]
fn a_layer_switched_off_equals_the_material_without_it() {
    let dir = out_dir("gltf-khr-terms");
    let core = sphere(&dir, "core", &material(BASE, 0.0, 0.45, ""));
    let coated = sphere(
        &dir,
        "coated",
        &material(
            BASE,
            0.0,
            0.45,
            r#""KHR_materials_clearcoat": {"clearcoatFactor": 1, "clearcoatRoughnessFactor": 0.1},
               "KHR_materials_sheen": {"sheenColorFactor": [1, 1, 1], "sheenRoughnessFactor": 0.5}"#,
        ),
    );
    let ctx = &CONTEXTS[0];
    let want = shot(&dir, "core", &core, &[], ctx);
    let on = shot(&dir, "coated", &coated, &[], ctx);
    assert!(max_diff(&on, &want) > 20, "the layers change the picture");
    let base_terms =
        "direct-diffuse,direct-specular,ibl-diffuse,ibl-specular,ao,shadows,emissive,normal-map";
    let off = format!("{base_terms},transmission");
    let got = shot(&dir, "coated-off", &coated, &["--terms", &off], ctx);
    let d = max_diff(&got, &want);
    assert!(d <= 1, "both layers off: {d}/255 from the core model");
    // One layer off: the picture differs from both (the other layer is still drawn).
    let sheen_only = format!("{base_terms},sheen");
    let got = shot(
        &dir,
        "coated-sheen",
        &coated,
        &["--terms", &sheen_only],
        ctx,
    );
    assert!(max_diff(&got, &want) > 5 && max_diff(&got, &on) > 5);
}

/// The GPU's reference twin: the sphere in a uniform environment of radiance 0.5 with the
/// default light, no tone mapping, rendered by the CPU reference (Monte Carlo, 1024 samples
/// per lobe) — the split sum is exact in a uniform environment, so each extension's
/// permutation must equal the truth to rounding (mean ≤ 0.5/255, max ≤ 3/255; measured: max
/// 1/255 on every path). Transmission with a volume too: the reference traces the opaque
/// frame where the refracted ray leaves and undoes the output step as the GPU's copy is read.
#[test]
fn gpu_equals_the_reference_for_each_extension() {
    let dir = out_dir("gltf-khr-reference");
    let cases = [
        (
            "clearcoat",
            [0.8, 0.2, 0.2],
            0.0,
            0.6,
            r#""KHR_materials_clearcoat": {"clearcoatFactor": 0.9, "clearcoatRoughnessFactor": 0.2}"#,
        ),
        (
            "sheen",
            [0.2, 0.02, 0.02],
            0.0,
            0.8,
            r#""KHR_materials_sheen": {"sheenColorFactor": [1, 0.3, 0.3], "sheenRoughnessFactor": 0.4}"#,
        ),
        (
            "specular-ior",
            [0.8, 0.2, 0.2],
            0.0,
            0.3,
            r#""KHR_materials_specular": {"specularColorFactor": [0.2, 1, 0.5], "specularFactor": 0.7},
               "KHR_materials_ior": {"ior": 2.0}"#,
        ),
        (
            "transmission-volume",
            [0.9, 0.9, 0.6],
            0.0,
            0.0,
            r#""KHR_materials_transmission": {"transmissionFactor": 0.8},
               "KHR_materials_volume": {"thicknessFactor": 0.5, "attenuationDistance": 0.8,
                 "attenuationColor": [0.4, 0.7, 0.9]},
               "KHR_materials_ior": {"ior": 1.4}"#,
        ),
    ];
    // Transmission lit from behind (through the surface: the punctual BTDF), rough; the
    // lights dim, as a light seen through glass is bright (0.1 already clips to white).
    let backlit = (
        "transmission-backlit",
        [0.9, 0.9, 0.6],
        0.0,
        0.3,
        r#""KHR_materials_transmission": {"transmissionFactor": 1}"#,
    );
    let cases: Vec<_> = cases
        .into_iter()
        .map(|c| (c, &[][..]))
        .chain([(
            backlit,
            &[
                "--light",
                "dir:0.47,0.34,0.81",
                "--light",
                "point:-0.3,0.2,-3",
                "--light-color",
                "0.01,0.01,0.01",
            ][..],
        )])
        .collect();
    let env = Environment::uniform([0.5; 3]);
    let furnace = ["--env-color", "0.5,0.5,0.5", "--tonemap", "none"];
    for ((name, base, metal, rough, ext), lights) in cases {
        let model = sphere(&dir, name, &material(base, metal, rough, ext));
        let furnace = [&furnace[..], lights].concat();
        let args = view(&model, &furnace);
        let all: Vec<&str> = args.iter().map(String::as_str).collect();
        let (settings, scene) = settings_for(&all);
        let pe = PbrEnv {
            env: Arc::new(env.clone()),
            samples: 1024,
        };
        let (truth, info) = render_env_with_info(&scene, &settings, Some(&pe), N, N);
        let hit: Vec<bool> = info.iter().map(|i| i.hit()).collect();
        // The full-float path and the RGBM path of GL 2.1 (8-bit maps, split-byte table).
        for (ctx, extra) in [
            (&CONTEXTS[0], &[][..]),
            (&CONTEXTS[2], &["--ibl-encoding", "rgbm"][..]),
        ] {
            let img = shot(
                &dir,
                &format!("{name}-{}", ctx.0),
                &model,
                &[&furnace[..], extra].concat(),
                ctx,
            );
            let (mut sum, mut max, mut n) = (0.0f64, 0u8, 0usize);
            for (i, h) in hit.iter().enumerate() {
                if !*h {
                    continue;
                }
                for c in 0..3 {
                    let d = img.data[4 * i + c].abs_diff(truth.data[4 * i + c]);
                    sum += f64::from(d);
                    max = max.max(d);
                }
                n += 3;
            }
            let mean = sum / n as f64;
            eprintln!("{name} on {}: mean {mean:.3}/255, max {max}/255", ctx.0);
            if max > 3 {
                write_diff(&dir, &format!("{name}-{}", ctx.0), &img, &truth);
            }
            assert!(
                mean <= 0.5 && max <= 3,
                "{name} on {}: mean {mean:.3}, max {max}",
                ctx.0
            );
        }
    }
}

/// The white furnace: a white dielectric sphere in a uniform environment of radiance L = 0.5,
/// no light, no tone mapping. A layer takes from what lies under it the share it reflects
/// itself: the coat Fresnel F_cc for a lobe whose albedo is at most F_cc, 1 − max(sheen)·E
/// for a sheen of albedo E. So each pixel is at most max(core, L), the core sphere's value
/// or the light arriving, whichever is larger (the core model itself reflects a little more
/// than arrives at grazing angles: its diffuse term is not weighted by 1 − F), plus one
/// 8-bit step; on the GPU and in the reference. What is lost is bounded too: at least 85 %
/// of min(core, L) under the smooth coat and the sheen; under the rough coat at least 35 %
/// (measured 40 % at the rim: the Sample Viewer's layering takes the coat's Fresnel at
/// N·V, 0.9 at the rim, and a rough lobe's albedo there is far lower — the formula's own
/// loss, the same in the reference).
#[test]
fn white_furnace_with_clearcoat_and_sheen_conserves_energy() {
    let dir = out_dir("gltf-khr-furnace");
    let cases = [
        (
            "coat-smooth",
            r#""KHR_materials_clearcoat": {"clearcoatFactor": 1, "clearcoatRoughnessFactor": 0.05}"#,
        ),
        (
            "coat-rough",
            r#""KHR_materials_clearcoat": {"clearcoatFactor": 1, "clearcoatRoughnessFactor": 0.8}"#,
        ),
        (
            "sheen",
            r#""KHR_materials_sheen": {"sheenColorFactor": [1, 1, 1], "sheenRoughnessFactor": 0.5}"#,
        ),
    ];
    let env = Environment::uniform([0.5; 3]);
    let furnace = [
        "--env-color",
        "0.5,0.5,0.5",
        "--tonemap",
        "none",
        "--light",
        "none",
    ];
    // Linear value of an 8-bit sRGB output.
    let linear = |v: u8| glview::pbr::srgb_decode(f64::from(v) / 255.0);
    let step = linear(200) - linear(199);
    let both = |name: &str, ext: &str| {
        let model = sphere(&dir, name, &material([1.0; 3], 0.0, 0.5, ext));
        let args = view(&model, &furnace);
        let all: Vec<&str> = args.iter().map(String::as_str).collect();
        let (settings, scene) = settings_for(&all);
        let pe = PbrEnv {
            env: Arc::new(env.clone()),
            samples: 1024,
        };
        let (truth, info) = render_env_with_info(&scene, &settings, Some(&pe), N, N);
        let gpu = shot(&dir, name, &model, &furnace, &CONTEXTS[0]);
        let hit: Vec<bool> = info.iter().map(|i| i.hit()).collect();
        (gpu, truth, hit)
    };
    let (core_gpu, core_truth, hit) = both("core", "");
    for ((name, ext), least) in cases.into_iter().zip([0.85, 0.35, 0.85]) {
        let (gpu, truth) = {
            let (g, t, _) = both(name, ext);
            (g, t)
        };
        for (what, img, core) in [("gpu", &gpu, &core_gpu), ("reference", &truth, &core_truth)] {
            let (mut over, mut lost) = (f64::MIN, f64::MAX);
            for (i, h) in hit.iter().enumerate() {
                if !*h {
                    continue;
                }
                for c in 0..3 {
                    let (v, k) = (linear(img.data[4 * i + c]), linear(core.data[4 * i + c]));
                    over = over.max(v - k.max(0.5));
                    lost = lost.min(v / k.min(0.5));
                }
            }
            eprintln!(
                "furnace {name} ({what}): at most {over:+.4} above max(core, L), at least {lost:.3} of min(core, L)"
            );
            assert!(over <= step, "{name} ({what}): {over} above max(core, L)");
            assert!(
                lost >= least,
                "{name} ({what}): only {lost} of min(core, L)"
            );
        }
    }
}

/// `--check` names each material's extensions with their factors.
#[test]
fn check_lists_the_extensions_of_each_material() {
    let dir = out_dir("gltf-khr-check");
    let model = sphere(
        &dir,
        "all",
        &material(
            BASE,
            0.0,
            0.5,
            r#""KHR_materials_clearcoat": {"clearcoatFactor": 0.5},
               "KHR_materials_sheen": {"sheenColorFactor": [1, 0, 0]},
               "KHR_materials_specular": {"specularFactor": 0.5},
               "KHR_materials_ior": {"ior": 1.33}"#,
        ),
    );
    let o = run(&["--check", model.to_str().unwrap()], &[]);
    let out = String::from_utf8_lossy(&o.stdout).to_string() + &String::from_utf8_lossy(&o.stderr);
    for x in [
        "KHR_materials_clearcoat: clearcoatFactor 0.5",
        "KHR_materials_sheen: sheenColorFactor [1.0, 0.0, 0.0]",
        "KHR_materials_specular: specularFactor 0.5",
        "KHR_materials_ior: ior 1.33",
    ] {
        assert!(out.contains(x), "--check lacks {x:?}:\n{out}");
    }
    assert!(!out.contains("which glview ignores"), "{out}");
}

/// The extensions' texture slots: a one-texel texture of value t with factor 1 draws as the
/// factor t without a texture (sampler, UV set, colour space: the clearcoat's and specular's
/// data linear, the sheen's and specular's colours sRGB), on GL 3.3 and GL 2.1.
#[test]
fn an_extension_texture_of_one_value_equals_its_factor() {
    let dir = out_dir("gltf-khr-textures");
    let png = crate::gltf_draw::png(1, 1, &[[153, 188, 60, 102]]);
    // Linear values of the texel: 153/255 = 0.6 (r), 102/255 = 0.4 (a); sRGB 188 and 60.
    let srgb = |v: u8| glview::pbr::srgb_decode(f64::from(v) / 255.0);
    let (g, b) = (srgb(188), srgb(60));
    let tex = |ext: &str| {
        format!(
            r#"{{"pbrMetallicRoughness": {{"baseColorFactor": [0.8, 0.25, 0.1, 1],
            "metallicFactor": 0, "roughnessFactor": 0.45}},
            "extensions": {{{ext}}}}}],
            "textures": [{{"source": 0}}], "images": [{{"uri": "{png}"}}"#
        )
    };
    let cases = [
        (
            "clearcoat",
            r#""KHR_materials_clearcoat": {"clearcoatFactor": 1, "clearcoatTexture": {"index": 0},
               "clearcoatRoughnessFactor": 1, "clearcoatRoughnessTexture": {"index": 0}}"#
                .to_string(),
            format!(
                r#""KHR_materials_clearcoat": {{"clearcoatFactor": 0.6,
                   "clearcoatRoughnessFactor": {}}}"#,
                188.0 / 255.0
            ),
        ),
        (
            "sheen",
            r#""KHR_materials_sheen": {"sheenColorFactor": [1, 1, 1], "sheenColorTexture": {"index": 0},
               "sheenRoughnessFactor": 1, "sheenRoughnessTexture": {"index": 0}}"#
                .to_string(),
            format!(
                r#""KHR_materials_sheen": {{"sheenColorFactor": [{}, {g}, {b}],
                   "sheenRoughnessFactor": 0.4}}"#,
                srgb(153)
            ),
        ),
        (
            "specular",
            r#""KHR_materials_specular": {"specularFactor": 1, "specularTexture": {"index": 0},
               "specularColorFactor": [1, 1, 1], "specularColorTexture": {"index": 0}}"#
                .to_string(),
            format!(
                r#""KHR_materials_specular": {{"specularFactor": 0.4,
                   "specularColorFactor": [{}, {g}, {b}]}}"#,
                srgb(153)
            ),
        ),
    ];
    for (name, textured, factors) in cases {
        let t = sphere(&dir, &format!("{name}-tex"), &tex(&textured));
        let f = sphere(
            &dir,
            &format!("{name}-factor"),
            &material(BASE, 0.0, 0.45, &factors),
        );
        for ctx in [&CONTEXTS[0], &CONTEXTS[2]] {
            let a = shot(&dir, &format!("{name}-tex-{}", ctx.0), &t, &[], ctx);
            let want = shot(&dir, &format!("{name}-factor-{}", ctx.0), &f, &[], ctx);
            let d = max_diff(&a, &want);
            eprintln!("{name} texture on {}: {d}/255 from the factor", ctx.0);
            if d > 1 {
                write_diff(&dir, &format!("{name}-{}", ctx.0), &a, &want);
            }
            assert!(d <= 1, "{name} on {}: {d}/255", ctx.0);
        }
    }
}

/// KHR_materials_transmission, thin-walled: a white, smooth, fully transmissive sphere over a
/// flat background B in a uniform environment of B's linear value shows nothing but B (what
/// the specular lobe reflects of the environment, the transmission lets through of the
/// frame behind: the two add up to the light arriving); over a red background in a grey
/// environment its centre is the red, less the 4 % the surface reflects (of the grey); with
/// KHR_materials_volume (thickness = attenuation distance) the centre keeps
/// attenuationColor of the light behind. On every context (OSMesa without a mip chain: a
/// smooth sphere reads level 0 anyway).
#[test]
fn a_transmissive_thin_sphere_shows_the_background() {
    let dir = out_dir("gltf-khr-transmission");
    let model = sphere(
        &dir,
        "thin",
        &material(
            [1.0; 3],
            0.0,
            0.0,
            r#""KHR_materials_transmission": {"transmissionFactor": 1}"#,
        ),
    );
    const ATT: [f64; 3] = [0.5, 0.8, 1.0];
    let volume = sphere(
        &dir,
        "volume",
        &material(
            [1.0; 3],
            0.0,
            0.0,
            &format!(
                r#""KHR_materials_transmission": {{"transmissionFactor": 1}},
                   "KHR_materials_volume": {{"thicknessFactor": 0.7, "attenuationDistance": 0.7,
                     "attenuationColor": [{}, {}, {}]}}"#,
                ATT[0], ATT[1], ATT[2]
            ),
        ),
    );
    let srgb = |v: f64| glview::pbr::srgb_decode(v);
    let bg = [0.6, 0.45, 0.3];
    let env = bg.map(|c| format!("{}", srgb(c))).join(",");
    let bg_arg = bg.map(|c| c.to_string()).join(",");
    let flat = [
        "--tonemap",
        "none",
        "--exposure",
        "0",
        "--light",
        "none",
        "--env-color",
        &env,
        "--background",
        &bg_arg,
    ];
    let red = [
        "--tonemap",
        "none",
        "--exposure",
        "0",
        "--light",
        "none",
        "--env-color",
        "0.2,0.2,0.2",
        "--background",
        "0.9,0.1,0.1",
    ];
    for ctx in &CONTEXTS {
        // A uniform picture is the expectation here (`render` refuses those as blank).
        let out = dir.join(format!("flat-{}.png", ctx.0));
        let mut args = view(&model, &flat);
        args.extend(ctx.1.iter().map(|s| s.to_string()));
        args.extend(["--output".to_string(), out.to_str().unwrap().to_string()]);
        let all: Vec<&str> = args.iter().map(String::as_str).collect();
        let o = run(&all, ctx.2);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let img = Rgba::load_png(&out).unwrap();
        let mut worst = 0.0f64;
        for p in img.data.chunks_exact(4) {
            for c in 0..3 {
                worst = worst.max((f64::from(p[c]) - bg[c] * 255.0).abs());
            }
        }
        eprintln!(
            "thin sphere over a flat background on {}: {worst:.1}/255",
            ctx.0
        );
        assert!(worst <= 2.0, "{}: {worst}/255 from the background", ctx.0);
        let img = shot(&dir, &format!("red-{}", ctx.0), &model, &red, ctx);
        let want = [0.9, 0.1, 0.1]
            .map(|b: f64| glview::pbr::srgb_encode(0.96 * srgb(b) + 0.04 * 0.2) * 255.0);
        let mut worst = 0.0f64;
        for y in N / 2 - 3..N / 2 + 3 {
            for x in N / 2 - 3..N / 2 + 3 {
                let p = img.pixel(x, y);
                for c in 0..3 {
                    worst = worst.max((f64::from(p[c]) - want[c]).abs());
                }
            }
        }
        eprintln!(
            "thin sphere over red on {}: centre {worst:.1}/255 from 0.96 red + 0.04 grey",
            ctx.0
        );
        assert!(worst <= 3.0, "{}: centre {worst}/255", ctx.0);
        // KHR_materials_volume: through a thickness of one attenuation distance the light
        // keeps attenuationColor of itself (Beer–Lambert); the centre's ray is not bent.
        let img = shot(&dir, &format!("volume-{}", ctx.0), &volume, &flat, ctx);
        let want: Vec<f64> = (0..3)
            .map(|c| {
                let l = srgb(bg[c]);
                glview::pbr::srgb_encode(0.04 * l + 0.96 * l * ATT[c]) * 255.0
            })
            .collect();
        let mut worst = 0.0f64;
        for y in N / 2 - 2..N / 2 + 2 {
            for x in N / 2 - 2..N / 2 + 2 {
                let p = img.pixel(x, y);
                for c in 0..3 {
                    worst = worst.max((f64::from(p[c]) - want[c]).abs());
                }
            }
        }
        eprintln!(
            "volume on {}: centre {worst:.1}/255 from Beer-Lambert",
            ctx.0
        );
        assert!(worst <= 3.0, "{}: volume centre {worst}/255", ctx.0);
    }
}

/// KHR_materials_pbrSpecularGlossiness converted to the one model: diffuse D, specular 0.04
/// (grey) and glossiness g draw as the core material of base colour D, metallic 0 and
/// roughness 1 − g; a coloured specular draws as KHR_materials_specular of that F0.
#[test]
fn specular_glossiness_equals_its_metallic_roughness_twin() {
    let dir = out_dir("gltf-khr-specgloss");
    let sg = |spec: &str| {
        format!(
            r#"{{"extensions": {{"KHR_materials_pbrSpecularGlossiness": {{
                "diffuseFactor": [0.8, 0.25, 0.1, 1], "specularFactor": {spec},
                "glossinessFactor": 0.6}}}}}}"#
        )
    };
    let pairs = [
        (
            "grey",
            sg("[0.04, 0.04, 0.04]"),
            material(BASE, 0.0, 0.4, ""),
        ),
        (
            "coloured",
            sg("[0.3, 0.2, 0.05]"),
            material(
                BASE,
                0.0,
                0.4,
                r#""KHR_materials_specular": {"specularColorFactor": [7.5, 5, 1.25]}"#,
            ),
        ),
    ];
    for (name, a, b) in pairs {
        let a = sphere(&dir, &format!("{name}-sg"), &a);
        let b = sphere(&dir, &format!("{name}-mr"), &b);
        for ctx in [&CONTEXTS[0], &CONTEXTS[2]] {
            let x = shot(&dir, &format!("{name}-sg-{}", ctx.0), &a, &[], ctx);
            let y = shot(&dir, &format!("{name}-mr-{}", ctx.0), &b, &[], ctx);
            let d = max_diff(&x, &y);
            eprintln!("spec-gloss {name} on {}: {d}/255 from its twin", ctx.0);
            assert!(d <= 1, "{name} on {}: {d}/255", ctx.0);
        }
    }
}

/// The mesh cache keeps the extensions: a sphere large enough for an entry (above
/// `cache::MIN_SIZE`), with every extension and a texture in each kind of slot, renders from
/// the entry (the miss that writes it and the hit that reads it) exactly as uncached.
#[test]
fn the_mesh_cache_keeps_the_extensions_and_their_textures() {
    let dir = out_dir("gltf-khr-cache");
    let entries = dir.join("entries");
    let _ = std::fs::remove_dir_all(&entries);
    let env = [("GLVIEW_CACHE_DIR", entries.to_str().unwrap())];
    let png = crate::gltf_draw::png(2, 1, &[[200, 120, 60, 90], [80, 220, 160, 200]]);
    let ext = r#""KHR_materials_clearcoat": {"clearcoatFactor": 1, "clearcoatTexture": {"index": 0},
           "clearcoatRoughnessTexture": {"index": 0}},
         "KHR_materials_sheen": {"sheenColorFactor": [1, 1, 1], "sheenColorTexture": {"index": 0},
           "sheenRoughnessFactor": 1, "sheenRoughnessTexture": {"index": 0}},
         "KHR_materials_specular": {"specularTexture": {"index": 0},
           "specularColorTexture": {"index": 0}},
         "KHR_materials_ior": {"ior": 1.6}"#;
    let m = format!(
        r#"{{"pbrMetallicRoughness": {{"baseColorFactor": [0.8, 0.25, 0.1, 1],
        "metallicFactor": 0, "roughnessFactor": 0.45}},
        "extensions": {{{ext}}}}}],
        "textures": [{{"source": 0}}], "images": [{{"uri": "{png}"}}"#
    );
    let model = sphere_of(&dir, "big", &m, (300, 600));
    assert!(std::fs::metadata(&model).unwrap().len() >= glview::scene::cache::MIN_SIZE);
    let size = format!("{N}x{N}");
    let args = [model.to_str().unwrap(), "--size", &size, "--shading", "pbr"];
    let fresh = render(&dir, "fresh", &[&args[..], &["--no-cache"]].concat(), &env);
    for what in ["first", "hit"] {
        let img = render(&dir, what, &args, &env);
        let d = max_diff(&fresh, &img);
        if d != 0 {
            write_diff(&dir, what, &fresh, &img);
        }
        assert_eq!(d, 0, "{what}: {d}/255 from the uncached picture");
    }
    // The entry holds the material's extensions (its header is JSON).
    let entry = std::fs::read_dir(&entries)
        .unwrap()
        .filter_map(|e| e.ok().map(|e| e.path()))
        .find(|p| p.extension().is_some_and(|x| x == "glvc"))
        .expect("a cache entry");
    let bytes = std::fs::read(entry).unwrap();
    assert!(
        bytes.windows(9).any(|w| w == b"clearcoat"),
        "the entry has no clearcoat"
    );
}

/// The extension slots' UV sets and KHR_texture_transform on the GPU against the reference:
/// a 2×2 texture, nearest-sampled, read by the clearcoat (through a transform), the sheen
/// colour and the specular colour (TEXCOORD_1, the sphere's UVs doubled) slots, in the
/// furnace with a light. The texels land on the same pixels (mean ≤ 0.5/255; a few pixels
/// on texel edges may round to either texel: at most 1 % of them more than 8/255 apart).
#[test]
fn extension_slots_read_their_uv_sets_and_transforms_as_the_reference() {
    let dir = out_dir("gltf-khr-slots");
    let png = crate::gltf_draw::png(
        2,
        2,
        &[
            [255, 40, 40, 255],
            [40, 255, 40, 60],
            [40, 40, 255, 160],
            [250, 250, 40, 20],
        ],
    );
    let m = format!(
        r#"{{"pbrMetallicRoughness": {{"baseColorFactor": [0.5, 0.5, 0.5, 1],
        "metallicFactor": 0, "roughnessFactor": 0.5}},
        "extensions": {{
          "KHR_materials_clearcoat": {{"clearcoatFactor": 1, "clearcoatRoughnessFactor": 0.3,
            "clearcoatTexture": {{"index": 0, "extensions": {{"KHR_texture_transform":
              {{"scale": [3, 2], "offset": [0.25, 0], "rotation": 0.3}}}}}}}},
          "KHR_materials_sheen": {{"sheenColorFactor": [1, 1, 1], "sheenRoughnessFactor": 0.5,
            "sheenColorTexture": {{"index": 0, "extensions": {{"KHR_texture_transform":
              {{"scale": [4, 4]}}}}}}}},
          "KHR_materials_specular": {{"specularColorTexture": {{"index": 0, "texCoord": 1}}}}}}}}],
        "samplers": [{{"magFilter": 9728, "minFilter": 9728}}],
        "textures": [{{"source": 0, "sampler": 0}}], "images": [{{"uri": "{png}"}}"#
    );
    let model = sphere(&dir, "slots", &m);
    // TEXCOORD_1: the sphere's UVs doubled (added to the file after it is written).
    let text = std::fs::read_to_string(&model).unwrap();
    let json: serde_json::Value = serde_json::from_str(&text).unwrap();
    let mut json = json;
    let uv_acc = json["accessors"][2].clone();
    json["accessors"].as_array_mut().unwrap().push(uv_acc);
    json["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_1"] = 4.into();
    let texture_transform = serde_json::json!(["KHR_texture_transform"]);
    json["extensionsUsed"] = texture_transform;
    std::fs::write(&model, json.to_string()).unwrap();
    let furnace = ["--env-color", "0.5,0.5,0.5", "--tonemap", "none"];
    let args = view(&model, &furnace);
    let all: Vec<&str> = args.iter().map(String::as_str).collect();
    let (settings, scene) = settings_for(&all);
    let pe = PbrEnv {
        env: Arc::new(Environment::uniform([0.5; 3])),
        samples: 1024,
    };
    let (truth, info) = render_env_with_info(&scene, &settings, Some(&pe), N, N);
    for ctx in [&CONTEXTS[0], &CONTEXTS[2]] {
        let img = shot(&dir, &format!("slots-{}", ctx.0), &model, &furnace, ctx);
        let (mut sum, mut n, mut over) = (0.0f64, 0usize, 0usize);
        for (i, inf) in info.iter().enumerate() {
            if !inf.hit() {
                continue;
            }
            let d = (0..3)
                .map(|c| img.data[4 * i + c].abs_diff(truth.data[4 * i + c]))
                .max()
                .unwrap_or(0);
            sum += f64::from(d);
            n += 1;
            over += usize::from(d > 8);
        }
        let (mean, share) = (sum / n as f64, over as f64 / n as f64);
        eprintln!(
            "slots on {}: mean {mean:.3}/255, {:.2} % > 8/255",
            ctx.0,
            share * 100.0
        );
        if share > 0.01 {
            write_diff(&dir, &format!("slots-{}", ctx.0), &img, &truth);
        }
        assert!(
            mean <= 0.5 && share <= 0.01,
            "{}: mean {mean}, {share} over 8",
            ctx.0
        );
    }
}
