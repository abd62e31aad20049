//! `EXT_texture_webp` (issue 37): a texture takes its image from the extension's `source` when
//! it has one (the texture's own `source`, often a PNG, is the fallback for readers without
//! WebP, and may be absent when the extension is required); an extension `source` that names
//! no image falls back to the own one. Oracle: a lossless WebP of the Duck's PNG, so the
//! decoded texels and the picture equal the PNG's exactly.
use crate::common::*;
use glview::image_out::RgbaFiles;
use glview::scene::{load, LoadOptions, Scene};
use serde_json::{json, Value};
use std::path::{Path, PathBuf};

/// The Duck (Draco geometry, tests/data) in `dir`, with DuckCM.webp beside DuckCM.png.
fn duck(dir: &Path) -> Value {
    let src = repo().join("tests/data/khronos/draco/Duck");
    for f in ["Duck.bin", "DuckCM.png"] {
        std::fs::copy(src.join(f), dir.join(f)).unwrap();
    }
    let png = image::open(src.join("DuckCM.png")).unwrap().to_rgba8();
    png.save_with_format(dir.join("DuckCM.webp"), image::ImageFormat::WebP)
        .unwrap();
    serde_json::from_str(&std::fs::read_to_string(src.join("Duck.gltf")).unwrap()).unwrap()
}

fn write(dir: &Path, name: &str, doc: &Value) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, serde_json::to_string(doc).unwrap()).unwrap();
    p
}

/// The base colour texture's file name and texels.
fn base_texture(s: &Scene) -> (String, &[u8]) {
    let t = &s.materials[0]
        .base_color_texture
        .as_ref()
        .expect("a base colour texture")
        .image;
    (
        t.path.file_name().unwrap().to_string_lossy().into_owned(),
        &t.rgba,
    )
}

#[test]
fn webp_textures_decode_to_the_pngs_texels_and_picture() {
    let dir = out_dir("gltf-webp");
    let plain = duck(&dir);
    assert_eq!(
        plain["images"],
        json!([{"name": "DuckCM", "uri": "DuckCM.png"}]),
        "the Duck changed"
    );
    let plain_path = write(&dir, "plain.gltf", &plain);
    let opts = LoadOptions::default();
    let png = load(&plain_path, &opts).unwrap();

    // Used with a fallback: the fallback names a file that is not there, so a texture from
    // it would be a warning and no texture.
    let mut used = plain.clone();
    used["images"] = json!([{"uri": "missing.png"}, {"uri": "DuckCM.webp"}]);
    used["textures"][0]["extensions"] = json!({"EXT_texture_webp": {"source": 1}});
    used["extensionsUsed"] = json!(["KHR_draco_mesh_compression", "EXT_texture_webp"]);
    // Required, with no own source.
    let mut required = used.clone();
    required["textures"][0]
        .as_object_mut()
        .unwrap()
        .remove("source");
    required["extensionsRequired"] = json!(["KHR_draco_mesh_compression", "EXT_texture_webp"]);
    // The extension's source names no image: the own (PNG) source is used.
    let mut dangling = plain.clone();
    dangling["textures"][0]["extensions"] = json!({"EXT_texture_webp": {"source": 7}});
    for (name, doc, file) in [
        ("used.gltf", &used, "DuckCM.webp"),
        ("required.gltf", &required, "DuckCM.webp"),
        ("dangling.gltf", &dangling, "DuckCM.png"),
    ] {
        let s = load(&write(&dir, name, doc), &opts).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert!(s.warnings.is_empty(), "{name}: {:?}", s.warnings);
        let (texture_file, texels) = base_texture(&s);
        assert_eq!(texture_file, file, "{name}");
        assert_eq!(texels, base_texture(&png).1, "{name}: texels differ");
    }
    let shot = |p: &Path, name: &str| {
        let out = dir.join(format!("{name}.png"));
        let o = run(
            &[
                p.to_str().unwrap(),
                "--size",
                "96x96",
                "-o",
                out.to_str().unwrap(),
            ],
            &[],
        );
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        glview::image_out::Rgba::load_png(&out).unwrap()
    };
    let (a, b) = (
        shot(&plain_path, "png"),
        shot(&dir.join("required.gltf"), "webp"),
    );
    assert!(!a.is_uniform());
    assert_eq!(
        diff(&a, &b, 0).max,
        0,
        "the WebP picture differs from the PNG's"
    );
}
