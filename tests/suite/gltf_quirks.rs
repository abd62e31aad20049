//! Real exporters' quirks (issue 50, docs/gltf/quirks.md): each is a file generated here from
//! a Khronos sample with the quirk written in, which loads with one warning naming what was
//! off, and draws byte for byte the picture of the same file with the quirk corrected by
//! hand. The Draco counts are in gltf_draco.rs, the equal key times' sampling rule in the
//! library's unit tests (motion/sample.rs).
use crate::common::*;
use glview::image_out::RgbaFiles;
use glview::scene::{load, LoadOptions};
use serde_json::{json, Value};
use std::path::{Path, PathBuf};

fn box_textured() -> Glb {
    Glb::read(&shared().join("gltf-samples/BoxTextured/BoxTextured.glb"))
}

fn box_animated() -> Glb {
    Glb::read(&repo().join("tests/data/khronos/motion/BoxAnimated.glb"))
}

/// An edit of a file's JSON (and buffer).
type Edit = fn(&mut Glb);

struct Quirk {
    name: &'static str,
    base: fn() -> Glb,
    quirk: Edit,
    /// The hand-corrected file: what the quirk means.
    corrected: Edit,
    /// Words of the one warning.
    warning: &'static str,
    /// Extra options of both pictures (a moment).
    args: &'static [&'static str],
}

fn nothing(_: &mut Glb) {}

fn json(g: &mut Glb) -> &mut Value {
    &mut g.json
}

fn remove(v: &mut Value, key: &str) {
    v.as_object_mut().unwrap().remove(key);
}

fn q(
    name: &'static str,
    base: fn() -> Glb,
    quirk: Edit,
    corrected: Edit,
    warning: &'static str,
) -> Quirk {
    Quirk {
        name,
        base,
        quirk,
        corrected,
        warning,
        args: &[],
    }
}

/// Every quirk glview tolerates that a JSON edit can write (the GLB and buffer ones below).
fn quirks() -> Vec<Quirk> {
    let mut all = still_quirks();
    all.extend(motion_quirks());
    all
}

/// The quirks of a file's buffers, materials and scenes.
fn still_quirks() -> Vec<Quirk> {
    vec![
        q(
            "zero-stride",
            box_textured,
            |g| {
                for v in json(g)["bufferViews"].as_array_mut().unwrap() {
                    v["byteStride"] = 0.into();
                }
            },
            |g| {
                for v in json(g)["bufferViews"].as_array_mut().unwrap() {
                    remove(v, "byteStride");
                }
            },
            "bufferViews[0] and 3 more: byteStride 0, which glTF forbids",
        ),
        q(
            "position-without-bounds",
            box_textured,
            |g| {
                for a in json(g)["accessors"].as_array_mut().unwrap() {
                    remove(a, "min");
                    remove(a, "max");
                }
            },
            nothing,
            "attributes[\"POSITION\"]: POSITION accessor without min and max",
        ),
        q(
            "unknown-attribute",
            box_textured,
            |g| json(g)["meshes"][0]["primitives"][0]["attributes"]["texcoord_1"] = 3.into(),
            nothing,
            "meshes[0].primitives[0].attributes: attribute names glTF does not define",
        ),
        q(
            "view-target",
            box_textured,
            |g| json(g)["bufferViews"][1]["target"] = 1234.into(),
            |g| remove(&mut json(g)["bufferViews"][1], "target"),
            "bufferViews[1].target: a target glTF does not define; ignored",
        ),
        q(
            "sampler-missing",
            box_textured,
            |g| json(g)["textures"][0]["sampler"] = 7.into(),
            |g| remove(&mut json(g)["textures"][0], "sampler"),
            "textures[0].sampler: sampler index names no sampler; the default sampler",
        ),
        q(
            "texture-without-source",
            box_textured,
            |g| remove(&mut json(g)["textures"][0], "source"),
            |g| {
                remove(
                    &mut json(g)["materials"][0]["pbrMetallicRoughness"],
                    "baseColorTexture",
                )
            },
            "textures[0].source: texture without an image glview can read",
        ),
        q(
            "texture-missing",
            box_textured,
            |g| {
                json(g)["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]["index"] =
                    4.into()
            },
            |g| {
                remove(
                    &mut json(g)["materials"][0]["pbrMetallicRoughness"],
                    "baseColorTexture",
                )
            },
            "baseColorTexture.index: texture index names no texture",
        ),
        q(
            "material-missing",
            box_textured,
            |g| json(g)["meshes"][0]["primitives"][0]["material"] = 5.into(),
            |g| remove(&mut json(g)["meshes"][0]["primitives"][0], "material"),
            "meshes[0].primitives[0].material: material index names no material",
        ),
        q(
            "scene-missing",
            box_textured,
            |g| json(g)["scene"] = 3.into(),
            |g| json(g)["scene"] = 0.into(),
            "scene: the default scene index names no scene; scene 0 is drawn",
        ),
        q(
            "no-scenes",
            box_textured,
            |g| {
                remove(json(g), "scenes");
                remove(json(g), "scene");
            },
            nothing,
            "scenes: no scenes; every root node is drawn",
        ),
        q(
            "child-missing",
            box_textured,
            |g| json(g)["nodes"][0]["children"] = json!([1, 9]),
            nothing,
            "nodes[0].children[1]: child index names no node; ignored",
        ),
    ]
}

/// The quirks of a file's animations, each drawn at a moment.
fn motion_quirks() -> Vec<Quirk> {
    vec![
        Quirk {
            args: &["--time", "0.7"],
            ..q(
                "channel-node-missing",
                box_animated,
                |g| json(g)["animations"][0]["channels"][1]["target"]["node"] = 99.into(),
                |g| {
                    json(g)["animations"][0]["channels"]
                        .as_array_mut()
                        .unwrap()
                        .remove(1);
                },
                "animations[0].channels[1]: channel's sampler or node index names nothing",
            )
        },
        Quirk {
            args: &["--time", "0.7"],
            ..q(
                "channel-sampler-missing",
                box_animated,
                |g| json(g)["animations"][0]["channels"][1]["sampler"] = 99.into(),
                |g| {
                    json(g)["animations"][0]["channels"]
                        .as_array_mut()
                        .unwrap()
                        .remove(1);
                },
                "animations[0].channels[1]: channel's sampler or node index names nothing",
            )
        },
        Quirk {
            args: &["--time", "0.7"],
            ..q(
                "channel-without-node",
                box_animated,
                |g| {
                    remove(
                        &mut json(g)["animations"][0]["channels"][1]["target"],
                        "node",
                    )
                },
                |g| {
                    json(g)["animations"][0]["channels"]
                        .as_array_mut()
                        .unwrap()
                        .remove(1);
                },
                "animations[0].channels[1]: channel without a node",
            )
        },
        Quirk {
            args: &["--time", "0.7"],
            ..q(
                "interpolation",
                box_animated,
                |g| json(g)["animations"][0]["samplers"][0]["interpolation"] = "linear".into(),
                |g| json(g)["animations"][0]["samplers"][0]["interpolation"] = "LINEAR".into(),
                "animations[0].samplers[0].interpolation: interpolation other than STEP",
            )
        },
        Quirk {
            args: &["--time", "1.3"],
            ..q(
                "equal-key-times-step",
                box_textured,
                |g| moving_box(g, "STEP", &[0.0, 1.0, 1.0, 2.0], &[0.0, 0.3, 0.6, 0.2]),
                |g| moving_box(g, "STEP", &[0.0, 1.0, 2.0], &[0.0, 0.6, 0.2]),
                "channel 0 has equal neighbouring key times (channel 0: key 2 at 1 repeats key 1's",
            )
        },
        Quirk {
            args: &["--time", "1.1"],
            ..q(
                // FBX2glTF's RobotExpressive: sums up to 1.75. Doubled here (exact in f32), so
                // normalised they are the file's weights over their own sum, which the
                // corrected file holds (its sums within rounding of 1: left as they are).
                "skin-weights-off-one",
                rigged_simple,
                |g| reweigh(g, |w| w.map(|x| x * 2.0)),
                |g| {
                    reweigh(g, |w| {
                        let s: f32 = w.iter().sum();
                        w.map(|x| x / s)
                    })
                },
                "vertices do not sum to 1 (sums from 2.000 to 2.000), which glTF requires; normalised",
            )
        },
        Quirk {
            args: &["--time", "0.6"],
            ..q(
                "equal-key-times-linear",
                box_textured,
                |g| moving_box(g, "LINEAR", &[0.0, 1.0, 1.0, 2.0], &[0.0, 0.5, 0.5, 0.2]),
                |g| moving_box(g, "LINEAR", &[0.0, 1.0, 2.0], &[0.0, 0.5, 0.2]),
                "equal neighbouring key times",
            )
        },
    ]
}

fn rigged_simple() -> Glb {
    Glb::read(&repo().join("tests/data/khronos/motion/RiggedSimple.glb"))
}

/// RiggedSimple's WEIGHTS_0 (four f32 per vertex, tightly packed) through `f`, per vertex.
fn reweigh(g: &mut Glb, f: fn([f32; 4]) -> [f32; 4]) {
    let a = g.json["meshes"][0]["primitives"][0]["attributes"]["WEIGHTS_0"]
        .as_u64()
        .unwrap();
    let acc = &g.json["accessors"][a as usize];
    let view = &g.json["bufferViews"][acc["bufferView"].as_u64().unwrap() as usize];
    let start = view["byteOffset"].as_u64().unwrap_or(0) as usize
        + acc["byteOffset"].as_u64().unwrap_or(0) as usize;
    for k in 0..acc["count"].as_u64().unwrap() as usize {
        let at = start + k * 16;
        let w: [f32; 4] = std::array::from_fn(|c| {
            f32::from_le_bytes(g.bin[at + c * 4..at + c * 4 + 4].try_into().unwrap())
        });
        for (c, v) in f(w).iter().enumerate() {
            g.bin[at + c * 4..at + c * 4 + 4].copy_from_slice(&v.to_le_bytes());
        }
    }
}

/// BoxTextured's box node moved along x by `xs` at `times` (`interp`), in a new animation.
fn moving_box(g: &mut Glb, interp: &str, times: &[f32], xs: &[f32]) {
    let input = g.add_f32(times, "SCALAR", 1);
    let values: Vec<f32> = xs.iter().flat_map(|&x| [x, 0.0, 0.0]).collect();
    let output = g.add_f32(&values, "VEC3", 3);
    g.json["animations"] = json!([{
        "channels": [{"sampler": 0, "target": {"node": 1, "path": "translation"}}],
        "samplers": [{"input": input, "output": output, "interpolation": interp}],
    }]);
}

fn written(dir: &Path, name: &str, g: &Glb) -> PathBuf {
    let p = dir.join(format!("{name}.glb"));
    g.write(&p);
    p
}

fn picture(dir: &Path, name: &str, model: &Path, args: &[&str]) -> Vec<u8> {
    let out = dir.join(format!("{name}.png"));
    let mut all = vec![
        model.to_str().unwrap(),
        "--size",
        "96x96",
        "-o",
        out.to_str().unwrap(),
    ];
    all.extend(args);
    let o = run(&all, &[]);
    assert!(
        o.status.success(),
        "{name}: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    glview::image_out::Rgba::load_png(&out).unwrap().data
}

fn messages(p: &Path) -> Vec<String> {
    let s = load(p, &LoadOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    s.warnings.iter().map(|w| w.message.clone()).collect()
}

#[test]
fn each_quirk_is_one_warning_and_the_corrected_files_picture() {
    let dir = out_dir("gltf-quirks");
    for q in quirks() {
        let (mut bad, mut good) = ((q.base)(), (q.base)());
        (q.quirk)(&mut bad);
        (q.corrected)(&mut good);
        let bad = written(&dir, q.name, &bad);
        let good = written(&dir, &format!("{}-corrected", q.name), &good);
        assert_ne!(
            std::fs::read(&bad).unwrap(),
            std::fs::read(&good).unwrap(),
            "{}",
            q.name
        );
        let w = messages(&bad);
        assert_eq!(w.len(), 1, "{}: {w:?}", q.name);
        assert!(w[0].contains(q.warning), "{}: {}", q.name, w[0]);
        assert!(
            messages(&good).is_empty(),
            "{}: the corrected file warns",
            q.name
        );
        let a = picture(&dir, q.name, &bad, q.args);
        let b = picture(&dir, &format!("{}-corrected", q.name), &good, q.args);
        assert!(
            a == b,
            "{}: the picture differs from the corrected file's",
            q.name
        );
    }
}

/// Valid glTF the crate's types refused: application attributes (`_BATCHID`, as Cesium's
/// tools write) and `extras` that are not objects load without a warning.
#[test]
fn application_attributes_and_any_extras_are_read_silently() {
    let dir = out_dir("gltf-quirks");
    let mut g = box_textured();
    g.json["meshes"][0]["primitives"][0]["attributes"]["_BATCHID"] = 3.into();
    g.json["nodes"][0]["extras"] = "exported by hand".into();
    g.json["extras"] = json!([1, 2]);
    let p = written(&dir, "valid-oddities", &g);
    assert!(messages(&p).is_empty(), "{:?}", messages(&p));
    let plain = written(&dir, "valid-oddities-plain", &box_textured());
    assert!(picture(&dir, "valid-oddities", &p, &[]) == picture(&dir, "valid-plain", &plain, &[]));
}

/// A GLB whose header length is not its chunks' end, and a buffer shorter than its
/// byteLength: read as what is there, with a warning, as three.js reads them.
#[test]
fn glb_lengths_and_short_buffers_are_read_as_what_is_there() {
    let dir = out_dir("gltf-quirks");
    let plain = written(&dir, "lengths-plain", &box_textured());
    let want = picture(&dir, "lengths-plain", &plain, &[]);
    let bytes = std::fs::read(&plain).unwrap();
    for (name, delta) in [("glb-length-long", 8i64), ("glb-length-short", -8)] {
        let mut b = bytes.clone();
        let len = (b.len() as i64 + delta) as u32;
        b[8..12].copy_from_slice(&len.to_le_bytes());
        let p = dir.join(format!("{name}.glb"));
        std::fs::write(&p, b).unwrap();
        let w = messages(&p);
        assert_eq!(w.len(), 1, "{name}: {w:?}");
        assert!(
            w[0].contains("the GLB header says the file has"),
            "{name}: {}",
            w[0]
        );
        assert!(picture(&dir, name, &p, &[]) == want, "{name}");
    }
    // The buffer's byteLength 100 bytes past its chunk (written by hand: `write` sets it).
    let mut g = box_textured();
    let real = g.bin.len();
    g.json["buffers"][0]["byteLength"] = (real + 100).into();
    let p = dir.join("buffer-long.glb");
    write_glb(&g.json, &g.bin, &p);
    let w = messages(&p);
    assert_eq!(w.len(), 1, "{w:?}");
    assert!(w[0].contains("byteLength is"), "{}", w[0]);
    assert!(w[0].contains("read as those bytes"), "{}", w[0]);
    assert!(picture(&dir, "buffer-long", &p, &[]) == want);
    // An accessor past the bytes there is still refused, naming it.
    let mut g = box_textured();
    g.bin.truncate(700);
    g.json["buffers"][0]["byteLength"] = 5000.into();
    let p = dir.join("buffer-cut.glb");
    write_glb(&g.json, &g.bin, &p);
    let e = load(&p, &LoadOptions::default()).unwrap_err().to_string();
    assert!(
        e.contains("buffer-cut.glb") && e.contains("lie beyond buffer 0 (700 bytes)"),
        "{e}"
    );
}
