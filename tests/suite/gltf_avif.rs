//! EXT_texture_avif (issue 50): AVIF images decode to their sources (lossless files exactly,
//! lossy ones within a bound of libavif's own decode), a glTF texture with an AVIF source
//! draws the picture of its PNG twin byte for byte, and one that does not decode draws its
//! texture's fallback image with a warning. The files are tests/data/avif
//! (scripts/make_avif_fixtures.sh). libdav1d is loaded at run time: CI installs it
//! (scripts/deps.sh), so there these tests never skip.
use crate::common::*;
use glview::image_out::Rgba;
use glview::image_out::RgbaFiles;
use glview::scene::{load, LoadOptions, Scene};
use std::path::{Path, PathBuf};

fn avif(name: &str) -> PathBuf {
    repo().join("tests/data/avif").join(name)
}

/// Whether AVIF can be decoded here; false (skipping) only outside CI.
fn decoder() -> bool {
    let here = glview::scene::textures::avif::available();
    assert!(here || !in_ci(), "CI installs libdav1d6 (scripts/deps.sh)");
    if !here {
        eprintln!("libdav1d is not installed: AVIF tests skipped");
    }
    here
}

/// The texture an OBJ quad with `map_Kd image` decodes (RGBA8, top row first).
fn decoded(dir: &Path, image: &Path) -> (u32, u32, Vec<u8>) {
    let name = image.file_stem().unwrap().to_string_lossy().to_string();
    let d = dir.join(&name);
    std::fs::create_dir_all(&d).unwrap();
    std::fs::copy(image, d.join(image.file_name().unwrap())).unwrap();
    std::fs::write(
        d.join("q.mtl"),
        format!(
            "newmtl m\nmap_Kd {}\n",
            image.file_name().unwrap().to_string_lossy()
        ),
    )
    .unwrap();
    std::fs::write(
        d.join("q.obj"),
        "mtllib q.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nusemtl m\nf 1/1 2/2 3/3\n",
    )
    .unwrap();
    let s: Scene = load(&d.join("q.obj"), &LoadOptions::default()).unwrap();
    assert!(s.warnings.is_empty(), "{name}: {:?}", s.warnings);
    let t = &s.materials[0]
        .base_color_texture
        .as_ref()
        .expect("a texture")
        .image;
    (t.width, t.height, t.rgba.clone())
}

fn png(p: &Path) -> Rgba {
    Rgba::load_png(p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

#[test]
fn avif_images_decode_to_their_sources() {
    if !decoder() {
        return;
    }
    let dir = out_dir("avif-decode");
    // Lossless (identity matrix, 4:4:4, full range): the source's pixels exactly.
    for (file, source) in [("opaque-lossless", "opaque"), ("alpha-lossless", "alpha")] {
        let (w, h, rgba) = decoded(&dir, &avif(&format!("{file}.avif")));
        let want = png(&avif(&format!("{source}.png")));
        assert_eq!((w, h), (want.width, want.height), "{file}");
        assert!(rgba == want.data, "{file}: not the source's pixels");
    }
    // Lossy: libavif's own 8-bit decode (avifdec, through libyuv's fixed-point matrices and
    // its chroma filter) within each file's bound; a wrong matrix, range or bit depth is
    // tens of levels off. Measured here: 4:2:0 limited max 3 (mean of the worst channel
    // 1.0, signed bias under 0.15), 10-bit max 2 (libavif's 10-to-8 rounding: bias 0.5),
    // 4:0:0 exact, premultiplied max 6 (un-premultiplying at alpha 64/255 multiplies a
    // level of difference by 4).
    for (file, bound) in [
        ("opaque-420-limited", 3),
        ("alpha-444-10bit", 2),
        ("grey-400", 0),
        ("alpha-premultiplied", 8),
    ] {
        let (w, h, rgba) = decoded(&dir, &avif(&format!("{file}.avif")));
        let want = png(&avif(&format!("ref-{file}.png")));
        assert_eq!((w, h), (want.width, want.height), "{file}");
        let got = Rgba {
            width: w,
            height: h,
            data: rgba,
        };
        let d = diff(&got, &want, 2);
        eprintln!(
            "{file}: max {} mean {:.3}, over 2: {}",
            d.max, d.mean, d.over
        );
        assert!(
            d.max <= bound,
            "{file}: off by {} (mean {:.3})",
            d.max,
            d.mean
        );
        let alpha_off = (got.data.iter().zip(&want.data).skip(3).step_by(4))
            .map(|(a, b)| a.abs_diff(*b))
            .max();
        assert!(alpha_off <= Some(1), "{file}: alpha off by {alpha_off:?}");
    }
}

/// BoxTextured with its texture's image also given as AVIF (EXT_texture_avif, the PNG kept
/// as the texture's own source, as gltf-transform writes it).
fn box_with_avif(dir: &Path, name: &str, avif_bytes: &[u8], required: bool) -> PathBuf {
    let mut g = Glb::read(&shared().join("gltf-samples/BoxTextured/BoxTextured.glb"));
    while !g.bin.len().is_multiple_of(4) {
        g.bin.push(0);
    }
    let views = g.json["bufferViews"].as_array_mut().unwrap();
    views.push(
        serde_json::json!({"buffer": 0, "byteOffset": g.bin.len(), "byteLength": avif_bytes.len()}),
    );
    let view = views.len() - 1;
    g.bin.extend_from_slice(avif_bytes);
    g.json["images"]
        .as_array_mut()
        .unwrap()
        .push(serde_json::json!({"bufferView": view, "mimeType": "image/avif"}));
    g.json["textures"][0]["extensions"] = serde_json::json!({"EXT_texture_avif": {"source": 1}});
    g.json["extensionsUsed"] = serde_json::json!(["EXT_texture_avif"]);
    if required {
        g.json["extensionsRequired"] = serde_json::json!(["EXT_texture_avif"]);
        g.json["textures"][0]
            .as_object_mut()
            .unwrap()
            .remove("source");
    }
    let p = dir.join(format!("{name}.glb"));
    g.write(&p);
    p
}

fn shot(dir: &Path, name: &str, model: &Path) -> Vec<u8> {
    let out = dir.join(format!("{name}.png"));
    let o = run(
        &[
            model.to_str().unwrap(),
            "--size",
            "128x128",
            "-o",
            out.to_str().unwrap(),
        ],
        &[],
    );
    assert!(
        o.status.success(),
        "{name}: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    png(&out).data
}

fn warnings(p: &Path) -> Vec<String> {
    let s = load(p, &LoadOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    s.warnings.iter().map(|w| w.message.clone()).collect()
}

#[test]
fn a_gltf_avif_texture_draws_its_png_twins_picture_and_falls_back_where_it_does_not_decode() {
    if !decoder() {
        return;
    }
    let dir = out_dir("avif-gltf");
    let plain = shared().join("gltf-samples/BoxTextured/BoxTextured.glb");
    let want = shot(&dir, "png", &plain);
    let lossless = std::fs::read(avif("box-lossless.avif")).unwrap();
    // The AVIF image is drawn (required: no PNG to fall back to).
    let p = box_with_avif(&dir, "avif-required", &lossless, true);
    assert!(warnings(&p).is_empty(), "{:?}", warnings(&p));
    assert!(
        shot(&dir, "avif-required", &p) == want,
        "the AVIF texture is not the PNG's"
    );
    // A broken AVIF (cut short): its texture's PNG, with one warning naming the image.
    let broken = lossless[..lossless.len() / 2].to_vec();
    let p = box_with_avif(&dir, "avif-broken", &broken, false);
    let w = warnings(&p);
    assert_eq!(w.len(), 1, "{w:?}");
    assert!(
        w[0].contains("image 1") && w[0].contains("fallback image 0 is drawn"),
        "{}",
        w[0]
    );
    assert!(
        shot(&dir, "avif-broken", &p) == want,
        "the fallback is not the PNG"
    );
    // Required and broken: no image at all, the material's factors alone.
    let p = box_with_avif(&dir, "avif-broken-required", &broken, true);
    let w = warnings(&p);
    assert!(w.iter().any(|w| w.contains("render without it")), "{w:?}");
    assert!(shot(&dir, "avif-broken-required", &p) != want);
}

/// Cut and corrupted AVIF files load, with one one-line warning where they do not decode
/// (a changed byte inside the AV1 data often decodes to other pixels, as it would anywhere),
/// never a panic or a hang; every cut file is refused.
#[test]
fn hostile_avif_files_are_warnings() {
    if !decoder() {
        return;
    }
    let dir = out_dir("avif-hostile");
    let bytes = std::fs::read(avif("opaque-420-limited.avif")).unwrap();
    let warned = |b: &[u8], what: &str| {
        let p = box_with_avif(&dir, "hostile", b, true);
        let s = load(&p, &LoadOptions::default()).unwrap_or_else(|e| panic!("{what}: {e}"));
        assert!(
            s.warnings.iter().all(|w| !w.message.contains('\n')),
            "{what}"
        );
        !s.warnings.is_empty()
    };
    for n in 0..bytes.len() {
        assert!(
            warned(&bytes[..n], &format!("cut at {n}")),
            "cut at {n} decodes"
        );
    }
    let mut refused = 0;
    for k in 0..bytes.len() {
        for v in [0x00, 0xFF] {
            let mut b = bytes.clone();
            b[k] = v;
            refused += usize::from(warned(&b, &format!("byte {k} = {v}")));
        }
    }
    assert!(refused > 0);
    // Found by the avif fuzz target: an `iloc` box saying 4 GB in a 251-byte file, which the
    // parser reserved before reading; now refused before the parser sees it.
    let bomb = std::fs::read(avif("fuzz-iloc-4gb.avif")).unwrap();
    let e = glview::scene::decode_image(&bomb).unwrap_err();
    assert!(
        e.contains("box says") && e.contains("past its container"),
        "{e}"
    );
}
