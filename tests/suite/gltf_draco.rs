//! `KHR_draco_mesh_compression` (issue 37): Khronos' Draco files render like their plain twins
//! in ../shared (the repository keeps only the small compressed geometry, tests/data/khronos/
//! draco), and hostile streams (every truncation and byte of a real one, lying counts, claims
//! beyond the buffer) are a one-line error naming the file, never a panic.
use crate::common::*;
use glview::image_out::RgbaFiles;
use glview::scene::{load, LoadOptions};
use std::path::{Path, PathBuf};

fn data(model: &str) -> PathBuf {
    repo().join("tests/data/khronos/draco").join(model)
}

/// The Draco model's files copied into `dir`, with the images of its plain twin in
/// ../shared/gltf-samples/`model` that it names (Avocado's 8 MB of textures stay there).
fn staged(dir: &Path, model: &str) -> PathBuf {
    let dir = dir.join(model);
    std::fs::create_dir_all(&dir).unwrap();
    for e in std::fs::read_dir(data(model)).unwrap() {
        let e = e.unwrap();
        std::fs::copy(e.path(), dir.join(e.file_name())).unwrap();
    }
    let twin = shared().join("gltf-samples").join(model);
    for e in std::fs::read_dir(&twin).unwrap() {
        let name = e.unwrap().file_name();
        if name.to_string_lossy().ends_with(".png") && !name.to_string_lossy().contains("reference")
        {
            std::fs::copy(twin.join(&name), dir.join(&name)).unwrap();
        }
    }
    dir.join(format!("{model}.gltf"))
}

/// The default picture of `model` at 160×160. Not `render`: the Duck's eyes are black
/// texels, which its NaN check would take for NaN.
fn shot(dir: &Path, name: &str, model: &Path) -> glview::image_out::Rgba {
    let out = dir.join(format!("{name}.png"));
    let o = run(
        &[
            model.to_str().unwrap(),
            "--size",
            "160x160",
            "-o",
            out.to_str().unwrap(),
        ],
        &[],
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let img = glview::image_out::Rgba::load_png(&out).unwrap();
    assert!(!img.is_uniform(), "{name}: blank frame");
    img
}

#[test]
fn draco_files_render_like_their_plain_twins() {
    let dir = out_dir("gltf-draco");
    for (model, plain) in [
        ("Box", "Box.glb"),
        ("Duck", "Duck.glb"),
        ("Avocado", "Avocado.gltf"),
    ] {
        let draco = staged(&dir, model);
        let twin = shared().join("gltf-samples").join(model).join(plain);
        let (a, b) = (
            load(&draco, &LoadOptions::default()).unwrap_or_else(|e| panic!("{e}")),
            load(&twin, &LoadOptions::default()).unwrap_or_else(|e| panic!("{e}")),
        );
        assert_eq!(a.triangle_count(), b.triangle_count(), "{model}");
        assert!(a.warnings.is_empty(), "{model}: {:?}", a.warnings);
        let (ra, rb) = (
            shot(&dir, &format!("{model}-draco"), &draco),
            shot(&dir, &format!("{model}-plain"), &twin),
        );
        let d = diff(&ra, &rb, 8);
        // Draco quantizes positions (11 to 14 bits here): silhouettes move by a pixel at
        // most, which the mean over the frame keeps under the 1/255.
        if d.mean > 1.0 {
            let p = write_diff(&dir, model, &ra, &rb);
            panic!(
                "{model}: mean difference {:.3}/255 > 1; see {}",
                d.mean,
                p.display()
            );
        }
        eprintln!(
            "{model}: Draco vs plain mean {:.4}/255, max {}",
            d.mean, d.max
        );
    }
}

/// `Box.gltf` with `edit` applied to its JSON and `bin` as its buffer, in `dir`.
fn box_variant(dir: &Path, name: &str, bin: &[u8], edit: &dyn Fn(String) -> String) -> PathBuf {
    let json = std::fs::read_to_string(data("Box").join("Box.gltf")).unwrap();
    let bin_name = format!("{name}.bin");
    // The buffer says its length and the stream's view (118 of its 120 bytes) shrinks with it.
    let json = json
        .replace("\"Box.bin\"", &format!("\"{bin_name}\""))
        .replace(
            "\"byteLength\": 120",
            &format!("\"byteLength\": {}", bin.len()),
        )
        .replace(
            "\"byteLength\": 118",
            &format!("\"byteLength\": {}", bin.len().min(118)),
        );
    std::fs::write(dir.join(&bin_name), bin).unwrap();
    let p = dir.join(format!("{name}.gltf"));
    std::fs::write(&p, edit(json)).unwrap();
    p
}

/// Loads `p`: a scene, or an error that is one line naming the file (a panic fails the test).
fn loads_or_names(p: &Path) -> Result<(), String> {
    match load(p, &LoadOptions::default()) {
        Ok(_) => Ok(()),
        Err(e) => {
            let e = e.to_string();
            assert!(!e.contains('\n'), "{e}");
            assert!(
                e.contains(&p.file_name().unwrap().to_string_lossy().to_string()),
                "{e}"
            );
            Err(e)
        }
    }
}

#[test]
fn hostile_draco_streams_are_one_line_errors() {
    let dir = out_dir("gltf-draco-hostile");
    let bin = std::fs::read(data("Box").join("Box.bin")).unwrap();
    let json = std::fs::read_to_string(data("Box").join("Box.gltf")).unwrap();
    assert!(json.contains("\"byteLength\": 118") && json.contains("\"byteLength\": 120,"));
    // Every truncation: the view shrinks with the buffer, so the stream itself is short.
    for n in 0..118 {
        let p = box_variant(&dir, "cut", &bin[..n], &|s| s);
        let e = loads_or_names(&p).expect_err("a truncated stream decodes");
        assert!(
            e.contains("KHR_draco_mesh_compression: cannot decode"),
            "{e}"
        );
    }
    // Every byte replaced by 0x00 and by 0xFF (huge varint counts): loads or one line.
    let mut refused = 0;
    for k in 0..bin.len() {
        for v in [0x00, 0xFF] {
            let mut b = bin.clone();
            b[k] = v;
            refused += usize::from(loads_or_names(&box_variant(&dir, "byte", &b, &|s| s)).is_err());
        }
    }
    assert!(refused > 0);
    // A view beyond its buffer (counts that lie are drawn as decoded: below).
    let p = box_variant(&dir, "view", &bin, &|s| {
        s.replace("\"byteOffset\": 0", "\"byteOffset\": 100")
    });
    let e = loads_or_names(&p).expect_err("view");
    assert!(e.contains("outside"), "view: {e}");
}

/// Draco parts whose accessors say another count than the stream decodes (FBX2glTF writes
/// the source mesh's count: a car's 20 of 51 parts decode more points) draw the decoded
/// geometry, as three.js's DRACOLoader does, with one warning naming the first; the picture
/// is the file's with the counts corrected by hand. An index past the decoded points is
/// still refused.
#[test]
fn draco_counts_other_than_the_streams_draw_the_decoded_geometry() {
    let dir = out_dir("gltf-draco-counts");
    let bin = std::fs::read(data("Box").join("Box.bin")).unwrap();
    let right = box_variant(&dir, "right", &bin, &|s| s);
    let want = shot(&dir, "right", &right);
    type Edit<'a> = &'a dyn Fn(String) -> String;
    let cases: [(&str, Edit, &str); 4] = [
        // Fewer points than decoded (the stream's 24), on every attribute.
        (
            "fewer",
            &|s| s.replace("\"count\": 24", "\"count\": 20"),
            "24 points where accessor",
        ),
        (
            "more",
            &|s| s.replacen("\"count\": 24", "\"count\": 25", 1),
            "says 25",
        ),
        (
            "huge",
            &|s| s.replacen("\"count\": 24", "\"count\": 4000000000", 1),
            "says 4000000000",
        ),
        (
            "indices",
            &|s| s.replace("\"count\": 36", "\"count\": 30"),
            "36 indices where accessor",
        ),
    ];
    for (name, edit, expect) in cases {
        let p = box_variant(&dir, name, &bin, edit);
        assert_ne!(
            std::fs::read(&p).unwrap(),
            std::fs::read(&right).unwrap(),
            "{name}"
        );
        let s = load(&p, &LoadOptions::default()).unwrap_or_else(|e| panic!("{name}: {e}"));
        let w: Vec<String> = s.warnings.iter().map(|w| w.message.clone()).collect();
        assert_eq!(w.len(), 1, "{name}: {w:?}");
        assert!(
            w[0].contains(expect) && w[0].contains("the decoded geometry is drawn"),
            "{name}: {}",
            w[0]
        );
        let got = shot(&dir, name, &p);
        assert!(
            got == want,
            "{name}: the picture is not the corrected file's"
        );
    }
}
