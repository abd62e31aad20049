//! `KHR_texture_basisu` (issue 37): KTX2 textures (Basis Universal ETC1S with BasisLZ, UASTC
//! with zstd) transcoded to RGBA8 on load. Oracle: the PNG twins Khronos ships for
//! StainedGlassLamp (tests/data/khronos/ktx2). BasisU is lossy, so the texels are held to a
//! measured mean difference (docs/gltf/compression.md); broken KTX2 files are a warning naming
//! the image, and the model renders without them.
use crate::common::*;
use glview::image_out::RgbaFiles;
use glview::scene::{load, LoadOptions, Scene};
use serde_json::{json, Value};
use std::path::{Path, PathBuf};

const KTX2: &str = "tests/data/khronos/ktx2";

/// The Duck (Draco geometry, tests/data) in `dir` with its base colour texture from image 1
/// (`ktx2`, through the extension) and image 0 (`png`, the fallback) copied beside it.
fn duck(dir: &Path, name: &str, ktx2: &str, png: &str, required: bool) -> PathBuf {
    let duck = repo().join("tests/data/khronos/draco/Duck");
    std::fs::copy(duck.join("Duck.bin"), dir.join("Duck.bin")).unwrap();
    for f in [ktx2, png] {
        std::fs::copy(repo().join(KTX2).join(f), dir.join(f)).unwrap();
    }
    let mut doc: Value =
        serde_json::from_str(&std::fs::read_to_string(duck.join("Duck.gltf")).unwrap()).unwrap();
    doc["images"] = json!([{"uri": png}, {"uri": ktx2}]);
    doc["textures"][0]["extensions"] = json!({"KHR_texture_basisu": {"source": 1}});
    doc["extensionsUsed"] = json!(["KHR_draco_mesh_compression", "KHR_texture_basisu"]);
    if required {
        doc["textures"][0].as_object_mut().unwrap().remove("source");
        doc["extensionsRequired"] = json!(["KHR_draco_mesh_compression", "KHR_texture_basisu"]);
    }
    let p = dir.join(name);
    std::fs::write(&p, serde_json::to_string(&doc).unwrap()).unwrap();
    p
}

/// A textured triangle in `dir` whose base colour texture is image 1 (`ktx2`, through the
/// extension, required) with image 0 (`png`) beside it: the hostile test loads it ~450
/// times, where the Duck's Draco decode (an unoptimised crate in test builds) took most of
/// its time.
fn triangle(dir: &Path, name: &str, ktx2: &str, png: &str) -> PathBuf {
    for f in [ktx2, png] {
        std::fs::copy(repo().join(KTX2).join(f), dir.join(f)).unwrap();
    }
    let floats: [f32; 15] = [
        0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, // positions
        0.0, 0.0, 1.0, 0.0, 0.0, 1.0, // UVs
    ];
    let bin: Vec<u8> = floats.iter().flat_map(|f| f.to_le_bytes()).collect();
    std::fs::write(dir.join("triangle.bin"), &bin).unwrap();
    let doc = json!({
        "asset": {"version": "2.0"},
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 1}, "material": 0}]}],
        "materials": [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}],
        "textures": [{"extensions": {"KHR_texture_basisu": {"source": 1}}}],
        "images": [{"uri": png}, {"uri": ktx2}],
        "buffers": [{"uri": "triangle.bin", "byteLength": 60}],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": 36},
            {"buffer": 0, "byteOffset": 36, "byteLength": 24}
        ],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
             "min": [0.0, 0.0, 0.0], "max": [1.0, 1.0, 0.0]},
            {"bufferView": 1, "componentType": 5126, "count": 3, "type": "VEC2"}
        ],
        "extensionsUsed": ["KHR_texture_basisu"],
        "extensionsRequired": ["KHR_texture_basisu"]
    });
    let p = dir.join(name);
    std::fs::write(&p, serde_json::to_string(&doc).unwrap()).unwrap();
    p
}

fn base_texture(s: &Scene) -> &glview::scene::Texture {
    &s.materials[0]
        .base_color_texture
        .as_ref()
        .expect("a base colour texture")
        .image
}

/// Mean absolute difference per channel (RGBA, in 1/255) of two equal-sized RGBA8 images.
fn mean_diff(a: &[u8], b: &[u8]) -> f64 {
    assert_eq!(a.len(), b.len());
    let sum: u64 = a
        .iter()
        .zip(b)
        .map(|(x, y)| u64::from(x.abs_diff(*y)))
        .sum();
    sum as f64 / a.len() as f64
}

#[test]
fn ktx2_textures_transcode_close_to_their_png_twins() {
    let dir = out_dir("gltf-ktx2");
    let opts = LoadOptions::default();
    // (KTX2, its PNG twin, codec, bound on the mean texel difference in 1/255).
    for (ktx2, png, codec, bound) in [
        (
            "StainedGlassLamp_steel_occlusion-rough-metal.ktx2",
            "StainedGlassLamp_steel_occlusion-rough-metal.png",
            "UASTC + zstd",
            UASTC_BOUND,
        ),
        (
            "StainedGlassLamp_hardware_basecolor.ktx2",
            "StainedGlassLamp_hardware_basecolor_512.png",
            "ETC1S + BasisLZ",
            ETC1S_BOUND,
        ),
    ] {
        for required in [false, true] {
            let name = format!("{codec}-{required}.gltf").replace([' ', '+'], "");
            let s = load(&duck(&dir, &name, ktx2, png, required), &opts)
                .unwrap_or_else(|e| panic!("{codec}: {e}"));
            assert!(s.warnings.is_empty(), "{codec}: {:?}", s.warnings);
            let t = base_texture(&s);
            assert!(t.path.ends_with(ktx2), "{codec}: {}", t.path.display());
            let twin = glview::image_out::Rgba::load_png(&repo().join(KTX2).join(png)).unwrap();
            assert_eq!((t.width, t.height), (twin.width, twin.height), "{codec}");
            let d = mean_diff(&t.rgba, &twin.data);
            eprintln!("{codec}: KTX2 vs PNG texels, mean {d:.3}/255");
            assert!(
                d <= bound,
                "{codec}: mean texel difference {d:.3}/255 > {bound}"
            );
        }
    }
}

/// Measured 0.333/255 (UASTC is near-lossless and zstd lossless). The transcoder is
/// bit-exact to the reference one, so the number is fixed for these files; the bound leaves
/// room for a transcoder fix, not for a wrong channel order or colour space (those are tens).
const UASTC_BOUND: f64 = 0.5;
/// Measured 1.276/255 (ETC1S is the low-rate mode; the twin is Khronos' 2048² PNG
/// box-filtered to the KTX2's 512², `convert -filter box -resize 512x512`).
const ETC1S_BOUND: f64 = 2.0;

#[test]
fn broken_ktx2_files_are_warnings_naming_the_image() {
    let dir = out_dir("gltf-ktx2-hostile");
    for (ktx2, png) in [
        (
            "StainedGlassLamp_steel_occlusion-rough-metal.ktx2",
            "StainedGlassLamp_steel_occlusion-rough-metal.png",
        ),
        (
            "StainedGlassLamp_hardware_basecolor.ktx2",
            "StainedGlassLamp_hardware_basecolor_512.png",
        ),
    ] {
        let good = std::fs::read(repo().join(KTX2).join(ktx2)).unwrap();
        let p = triangle(&dir, "broken.gltf", ktx2, png);
        // The good file decodes on this triangle: the cuts below are what fails.
        let s = load(&p, &LoadOptions::default()).unwrap();
        assert!(s.materials[0].base_color_texture.is_some(), "{ktx2} intact");
        let n = good.len();
        let mut cuts: Vec<usize> = vec![0, 11, 12, 47, 48, 80, 200, n / 2, n - 1];
        cuts.extend((0..n).step_by(997));
        for cut in cuts {
            std::fs::write(dir.join(ktx2), &good[..cut]).unwrap();
            let s = load(&p, &LoadOptions::default()).unwrap_or_else(|e| panic!("cut {cut}: {e}"));
            assert!(
                s.materials[0].base_color_texture.is_none(),
                "cut {cut} decoded"
            );
            let w: Vec<String> = s.warnings.iter().map(|w| w.message.clone()).collect();
            assert!(
                w.iter().any(|m| m.contains("image 1") && m.contains(ktx2)),
                "cut {cut}: {w:?}"
            );
        }
        // Every byte of the header and of level 0's index entry set to 0x00 and to 0xFF (huge
        // sizes, offsets and counts; the entry's uncompressed size once aborted the process),
        // and every 1999th byte after: loads, with or without the texture, never a panic or an
        // abort. (About 450 loads: a few seconds.)
        let bytes = (12..104).chain((104..n).step_by(1999));
        for k in bytes {
            for v in [0x00, 0xFF] {
                let mut b = good.clone();
                b[k] = v;
                std::fs::write(dir.join(ktx2), &b).unwrap();
                load(&p, &LoadOptions::default()).unwrap_or_else(|e| panic!("byte {k}: {e}"));
            }
        }
    }
}
