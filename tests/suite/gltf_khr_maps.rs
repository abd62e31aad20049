//! The glTF PBR extensions' texture slots (issue 32): one-value textures equal their
//! factors, UV sets and KHR_texture_transform equal the reference's, the mesh cache keeps
//! every extension and slot, and KHR_materials_pbrSpecularGlossiness equals its
//! metallic-roughness twin. Helpers in `gltf_khr.rs`.
use crate::common::*;
use crate::gltf_khr::{material, max_diff, shot, sphere, sphere_of, view, BASE, CONTEXTS, N};
use glview::pbr::env::Environment;
use glview::reference::{render_env_with_info, PbrEnv};
use std::sync::Arc;

/// The extensions' texture slots: a one-texel texture of value t with factor 1 draws as the
/// factor t without a texture (sampler, UV set, colour space: the clearcoat's and specular's
/// data linear, the sheen's and specular's colours sRGB, the iridescence's and anisotropy's
/// data linear), on GL 3.3 and GL 2.1.
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
        (
            // The factor's red, the thickness's green (linear) from the minimum to the maximum.
            "iridescence",
            r#""KHR_materials_iridescence": {"iridescenceFactor": 1, "iridescenceTexture": {"index": 0},
               "iridescenceThicknessMinimum": 100, "iridescenceThicknessMaximum": 500,
               "iridescenceThicknessTexture": {"index": 0}}"#
                .to_string(),
            format!(
                r#""KHR_materials_iridescence": {{"iridescenceFactor": 0.6,
                   "iridescenceThicknessMaximum": {}}}"#,
                100.0 + 400.0 * 188.0 / 255.0
            ),
        ),
        (
            // The direction's red and green mapped to [-1, 1] (linear), the strength's blue:
            // as the rotation atan2(g, r) and the strength times blue.
            "anisotropy",
            r#""KHR_materials_anisotropy": {"anisotropyStrength": 1,
               "anisotropyTexture": {"index": 0}}"#
                .to_string(),
            format!(
                r#""KHR_materials_anisotropy": {{"anisotropyStrength": {},
                   "anisotropyRotation": {}}}"#,
                60.0 / 255.0,
                (188.0f64 / 255.0 * 2.0 - 1.0).atan2(153.0 / 255.0 * 2.0 - 1.0)
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
            // Within 1/255 of the factor's picture, else both and their difference are kept.
            assert_close(&dir, &format!("{name}-{}", ctx.0), &a, &want, 1, 0, 1);
        }
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
         "KHR_materials_ior": {"ior": 1.6},
         "KHR_materials_iridescence": {"iridescenceFactor": 1, "iridescenceTexture": {"index": 0},
           "iridescenceThicknessTexture": {"index": 0}},
         "KHR_materials_anisotropy": {"anisotropyStrength": 0.7, "anisotropyRotation": 0.3,
           "anisotropyTexture": {"index": 0}}"#;
    let m = format!(
        r#"{{"pbrMetallicRoughness": {{"baseColorFactor": [0.8, 0.25, 0.1, 1],
        "metallicFactor": 0, "roughnessFactor": 0.45}},
        "extensions": {{{ext}}}}}],
        "textures": [{{"source": 0}}], "images": [{{"uri": "{png}"}}"#
    );
    // A small sphere in a file padded past the cache's size threshold (top-level `extras`):
    // a sphere that large by its triangles spent ~15 s of the test making its tangents in
    // the tests' opt-level 1 build, and the cache keys on the file, not on what makes it big.
    let model = sphere_of(&dir, "big", &m, (40, 80));
    let json = std::fs::read_to_string(&model).unwrap();
    let pad = "x".repeat(glview::scene::cache::MIN_SIZE as usize);
    let json = json.replacen('{', &format!(r#"{{"extras": {{"padding": "{pad}"}}, "#), 1);
    std::fs::write(&model, json).unwrap();
    assert!(std::fs::metadata(&model).unwrap().len() >= glview::scene::cache::MIN_SIZE);
    let size = format!("{N}x{N}");
    // Every triangle (levels of detail are the entry's too, and change pixels by design).
    let args = [
        model.to_str().unwrap(),
        "--size",
        &size,
        "--shading",
        "pbr",
        "--lod",
        "off",
    ];
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
    assert!(
        bytes.windows(13).any(|w| w == b"thickness_max"),
        "the entry has no iridescence film"
    );
    assert!(
        bytes.windows(14).any(|w| w == b"\"anisotropy\":{"),
        "the entry has no anisotropy"
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
