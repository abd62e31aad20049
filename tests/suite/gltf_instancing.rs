//! `EXT_mesh_gpu_instancing` (issue 37): Khronos' SimpleInstancing (125 instances of one cube,
//! tests/data/khronos/instancing) draws the same picture as the same file with its instances
//! written out as child nodes, and `--stats` counts 125 times the one cube's triangles. The
//! scene holds every instance written out; GL 3.3 and ES 3.0 draw them instanced (one copy
//! uploaded, a matrix per instance), GL 2.1 and OSMesa draw the copies.
use crate::common::*;
use glview::image_out::RgbaFiles;
use glview::scene::{load, LoadOptions};
use serde_json::{json, Value};
use std::path::{Path, PathBuf};

fn data() -> PathBuf {
    repo().join("tests/data/khronos/instancing")
}

/// Rows of `dims` f32 of accessor `a` (tightly packed floats, as this file has them).
fn rows(doc: &Value, bin: &[u8], a: &Value, dims: usize) -> Vec<Vec<f32>> {
    let acc = &doc["accessors"][a.as_u64().unwrap() as usize];
    assert_eq!(acc["componentType"], 5126);
    let view = &doc["bufferViews"][acc["bufferView"].as_u64().unwrap() as usize];
    let at = view["byteOffset"].as_u64().unwrap_or(0) + acc["byteOffset"].as_u64().unwrap_or(0);
    let n = acc["count"].as_u64().unwrap() as usize;
    (0..n)
        .map(|k| {
            (0..dims)
                .map(|c| {
                    let o = at as usize + 4 * (k * dims + c);
                    f32::from_le_bytes(bin[o..o + 4].try_into().unwrap())
                })
                .collect()
        })
        .collect()
}

/// `doc` with node 0's instances written out as its child nodes (and `single`: with the
/// extension removed, one cube).
fn written_out(doc: &Value, bin: &[u8]) -> (Value, Value) {
    let attrs = &doc["nodes"][0]["extensions"]["EXT_mesh_gpu_instancing"]["attributes"];
    let t = rows(doc, bin, &attrs["TRANSLATION"], 3);
    let r = rows(doc, bin, &attrs["ROTATION"], 4);
    let s = rows(doc, bin, &attrs["SCALE"], 3);
    let mut twin = doc.clone();
    let mut nodes = vec![json!({"children": (1..=t.len()).collect::<Vec<_>>()})];
    for k in 0..t.len() {
        nodes.push(json!({"mesh": 0, "translation": t[k], "rotation": r[k], "scale": s[k]}));
    }
    twin["nodes"] = Value::Array(nodes);
    twin.as_object_mut().unwrap().remove("extensionsUsed");
    let mut single = doc.clone();
    single["nodes"] = json!([{"mesh": 0}]);
    single.as_object_mut().unwrap().remove("extensionsUsed");
    (twin, single)
}

fn shot(dir: &Path, name: &str, model: &Path) -> (glview::image_out::Rgba, u64) {
    let (img, stats) = shot_stats(dir, name, model, &[], &[]);
    (img, stats["triangles"].as_u64().unwrap())
}

/// `shot` on the context `env` and `args` ask for.
fn shot_on(
    dir: &Path,
    name: &str,
    model: &Path,
    env: &[(&str, &str)],
    args: &[&str],
) -> (glview::image_out::Rgba, u64) {
    let (img, stats) = shot_stats(dir, name, model, env, args);
    (img, stats["triangles"].as_u64().unwrap())
}

/// The picture and the `--stats` line.
fn shot_stats(
    dir: &Path,
    name: &str,
    model: &Path,
    env: &[(&str, &str)],
    args: &[&str],
) -> (glview::image_out::Rgba, Value) {
    let out = dir.join(format!("{name}.png"));
    let mut all = vec![
        model.to_str().unwrap(),
        "--size",
        "128x128",
        "--stats",
        "-o",
        out.to_str().unwrap(),
    ];
    all.extend_from_slice(args);
    let o = run(&all, env);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let stats: Value = String::from_utf8_lossy(&o.stdout)
        .lines()
        .chain(String::from_utf8_lossy(&o.stderr).lines())
        .find_map(|l| {
            serde_json::from_str::<Value>(l)
                .ok()
                .filter(|v| v.get("triangles").is_some())
        })
        .expect("a --stats line");
    let img = glview::image_out::Rgba::load_png(&out).unwrap();
    check_frame(&img, name);
    (img, stats)
}

#[test]
fn instanced_file_equals_its_instances_written_out_as_nodes() {
    let dir = out_dir("gltf-instancing");
    let doc: Value = serde_json::from_str(
        &std::fs::read_to_string(data().join("SimpleInstancing.gltf")).unwrap(),
    )
    .unwrap();
    let bin = std::fs::read(data().join("SimpleInstancing_data.bin")).unwrap();
    std::fs::write(dir.join("SimpleInstancing_data.bin"), &bin).unwrap();
    let (twin, single) = written_out(&doc, &bin);
    let write = |name: &str, v: &Value| {
        let p = dir.join(name);
        std::fs::write(&p, serde_json::to_string(v).unwrap()).unwrap();
        p
    };
    let (inst, twin, single) = (
        write("instanced.gltf", &doc),
        write("twin.gltf", &twin),
        write("single.gltf", &single),
    );
    let opts = LoadOptions::default();
    let (a, b, one) = (
        load(&inst, &opts).unwrap(),
        load(&twin, &opts).unwrap(),
        load(&single, &opts).unwrap(),
    );
    assert!(a.warnings.is_empty(), "{:?}", a.warnings);
    assert_eq!(a.triangle_count(), 125 * one.triangle_count());
    assert_eq!(
        (a.triangle_count(), a.bounds),
        (b.triangle_count(), b.bounds)
    );
    let ((ia, ta), (ib, tb), (_, t1)) = (
        shot(&dir, "instanced", &inst),
        shot(&dir, "twin", &twin),
        shot(&dir, "single", &single),
    );
    assert_eq!(
        diff(&ia, &ib, 0).max,
        0,
        "instanced and written-out pictures differ"
    );
    assert_eq!((ta, tb), (125 * t1, 125 * t1), "--stats triangles");
    let o = run(&["--check", inst.to_str().unwrap()], &[]);
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(
        out.contains("instances: node 0 draws mesh 0 125 times"),
        "{out}"
    );
}

#[test]
fn hostile_instancing_is_a_one_line_error() {
    let dir = out_dir("gltf-instancing-hostile");
    let doc: Value = serde_json::from_str(
        &std::fs::read_to_string(data().join("SimpleInstancing.gltf")).unwrap(),
    )
    .unwrap();
    std::fs::copy(
        data().join("SimpleInstancing_data.bin"),
        dir.join("SimpleInstancing_data.bin"),
    )
    .unwrap();
    let attrs = "/nodes/0/extensions/EXT_mesh_gpu_instancing/attributes";
    type Edit<'a> = &'a dyn Fn(&mut Value);
    let cases: [(&str, Edit, &str); 4] = [
        (
            "dangling",
            &|d| d.pointer_mut(attrs).unwrap()["SCALE"] = json!(99),
            "SCALE names no accessor",
        ),
        (
            "counts",
            &|d| d["accessors"][4]["count"] = json!(124),
            "attribute counts differ",
        ),
        (
            "huge",
            &|d| d["accessors"][3]["count"] = json!(4000000),
            "4000000 elements",
        ),
        (
            "none",
            &|d| *d.pointer_mut(attrs).unwrap() = json!({}),
            "no TRANSLATION",
        ),
    ];
    for (name, edit, expect) in cases {
        let mut d = doc.clone();
        edit(&mut d);
        let p = dir.join(format!("{name}.gltf"));
        std::fs::write(&p, serde_json::to_string(&d).unwrap()).unwrap();
        let e = load(&p, &LoadOptions::default()).unwrap_err().to_string();
        assert!(
            e.contains(&format!("{name}.gltf: node 0: EXT_mesh_gpu_instancing"))
                && e.contains(expect),
            "{name}: {e}"
        );
        assert!(!e.contains('\n'), "{e}");
    }
}

/// The expansion happens in the loader, so every context draws it: the instanced file equals
/// its written-out twin on GL 2.1 and on OSMesa without framebuffer objects too.
#[test]
fn instancing_is_the_same_on_every_context() {
    let dir = out_dir("gltf-instancing-contexts");
    let doc: Value = serde_json::from_str(
        &std::fs::read_to_string(data().join("SimpleInstancing.gltf")).unwrap(),
    )
    .unwrap();
    let bin = std::fs::read(data().join("SimpleInstancing_data.bin")).unwrap();
    std::fs::write(dir.join("SimpleInstancing_data.bin"), &bin).unwrap();
    let (inst, twin) = (dir.join("instanced.gltf"), dir.join("twin.gltf"));
    std::fs::write(&inst, serde_json::to_string(&doc).unwrap()).unwrap();
    std::fs::write(
        &twin,
        serde_json::to_string(&written_out(&doc, &bin).0).unwrap(),
    )
    .unwrap();
    // ES 3.0 is left out for CI time: the expansion happens in the loader, before any context.
    // (name, environment, extra arguments)
    type Context<'a> = (&'a str, &'a [(&'a str, &'a str)], &'a [&'a str]);
    let contexts: [Context; 2] = [
        ("gl21", GL21, &[]),
        ("osmesa_nofbo", GL21_NO_FBO, &["--backend", "osmesa"]),
    ];
    for (name, env, args) in contexts {
        let a = shot_on(&dir, &format!("{name}-instanced"), &inst, env, args);
        let b = shot_on(&dir, &format!("{name}-twin"), &twin, env, args);
        assert_eq!(diff(&a.0, &b.0, 0).max, 0, "{name}: pictures differ");
        assert_eq!(a.1, b.1, "{name}: --stats triangles");
    }
}

/// The generated 400-cube file (each cube turned and scaled unevenly) against its twin with
/// the instances written out as nodes, on every context: GL 3.3 core and ES 3.0 draw it
/// instanced (fewer draw calls, one cube's buffers plus 64 bytes an instance uploaded), GL 2.1
/// and OSMesa draw the copies (the same draws as the twin, the same picture byte for byte).
/// Close up, the instanced draw sends only the instances in view, the twin's triangles.
/// Instanced pictures differ from the twin's only by f32 rounding: the copies' vertices are
/// made in f64 at load, the instanced ones by a f32 matrix on the GPU.
#[test]
fn generated_instances_match_their_nodes_on_every_context() {
    let dir = out_dir("gltf-instancing-generated");
    let n = 400;
    let g = glview::scene::generate::instanced_gltf(n);
    std::fs::write(dir.join(g.uri), &g.bin).unwrap();
    let (inst, twin) = (dir.join("instanced.gltf"), dir.join("twin.gltf"));
    std::fs::write(&inst, &g.instanced).unwrap();
    std::fs::write(&twin, &g.twin).unwrap();
    // (name, environment, extra arguments, drawn instanced)
    type Context<'a> = (&'a str, &'a [(&'a str, &'a str)], &'a [&'a str], bool);
    let contexts: [Context; 4] = [
        ("core", &[], &["--gl", "core"], true),
        ("es3", &[], &["--gl", "es3"], true),
        ("gl21", GL21, &["--gl", "2.1"], false),
        ("osmesa", GL21_NO_FBO, &["--backend", "osmesa"], false),
    ];
    for (name, env, args, instanced) in contexts {
        let args: Vec<&str> = args.iter().copied().chain(["--pitch", "35"]).collect();
        let (a, sa) = shot_stats(&dir, &format!("{name}-instanced"), &inst, env, &args);
        let (b, sb) = shot_stats(&dir, &format!("{name}-twin"), &twin, env, &args);
        let cube = 12;
        assert_eq!(
            sb["triangles"], sa["triangles"],
            "{name}: --stats triangles"
        );
        assert_eq!(
            sa["triangles"].as_u64().unwrap() % (n as u64 * cube),
            0,
            "{name}: triangles drawn are instances x mesh triangles, per pass"
        );
        let calls = |s: &Value| s["draw_calls"].as_u64().unwrap();
        let bytes = |s: &Value| s["mesh_bytes_uploaded"].as_u64().unwrap();
        let d = diff(&a, &b, 0);
        if instanced {
            assert!(
                calls(&sa) * 10 < calls(&sb),
                "{name}: not drawn instanced: {sa} {sb}"
            );
            // One cube (24 vertices of 32 bytes, 36 16-bit indices) and a matrix each.
            assert_eq!(bytes(&sa), 24 * 32 + 36 * 2 + 64 * n as u64, "{name}");
            let d1 = diff(&a, &b, 1);
            eprintln!(
                "{name}: instanced vs twin: max {}, {} pixels differ, {} by more than 1",
                d.max, d.over, d1.over
            );
            // f32 rounding moves a few edge pixels (a cube's edge landing on the other
            // side of a pixel centre) and nothing else.
            let pixels = u64::from(a.width) * u64::from(a.height);
            assert!(
                d1.over as u64 * 500 <= pixels,
                "{name}: {} pixels differ by more than 1",
                d1.over
            );
            // Close up, most instances are off screen: culled one by one like the copies,
            // so the triangles sent are the twin's.
            let near: Vec<&str> = args.iter().copied().chain(["--distance", "3"]).collect();
            let (_, na) = shot_stats(&dir, &format!("{name}-near-inst"), &inst, env, &near);
            let (_, nb) = shot_stats(&dir, &format!("{name}-near-twin"), &twin, env, &near);
            assert_eq!(na["triangles"], nb["triangles"], "{name}: culled triangles");
            assert!(na["triangles"].as_u64() < sa["triangles"].as_u64(), "{na}");
        } else {
            assert_eq!((calls(&sa), bytes(&sa)), (calls(&sb), bytes(&sb)), "{name}");
            assert_eq!(d.max, 0, "{name}: the copies must draw the twin's picture");
        }
    }
}

/// The mesh cache keeps the instanced nodes: a hit draws instanced like the miss and an
/// uncached load, the same picture. (The file is padded with JSON whitespace past the
/// cache's minimum size.)
#[test]
fn instanced_draws_survive_the_mesh_cache() {
    let dir = out_dir("gltf-instancing-cache");
    let entries = dir.join("entries");
    let _ = std::fs::remove_dir_all(&entries);
    let env = [("GLVIEW_CACHE_DIR", entries.to_str().unwrap())];
    let g = glview::scene::generate::instanced_gltf(64);
    std::fs::write(dir.join(g.uri), &g.bin).unwrap();
    let model = dir.join("padded.gltf");
    let min = glview::scene::cache::MIN_SIZE as usize;
    std::fs::write(&model, format!("{}{}", g.instanced, " ".repeat(min))).unwrap();
    let shot = |name: &str, extra: &[&str]| {
        let args: Vec<&str> = ["--gl", "core"].iter().chain(extra).copied().collect();
        shot_stats(&dir, name, &model, &env, &args)
    };
    let (fresh, sf) = shot("fresh", &["--no-cache"]);
    let (miss, sm) = shot("miss", &[]);
    assert_eq!(std::fs::read_dir(&entries).unwrap().count(), 1, "one entry");
    let (hit, sh) = shot("hit", &[]);
    for (what, img, s) in [("miss", &miss, &sm), ("hit", &hit, &sh)] {
        assert_eq!(diff(&fresh, img, 0).max, 0, "{what}: pictures differ");
        for k in ["draw_calls", "triangles", "mesh_bytes_uploaded"] {
            assert_eq!(s[k], sf[k], "{what}: {k}");
        }
    }
    // Drawn instanced: one cube's buffers and 64 matrices.
    assert_eq!(sf["mesh_bytes_uploaded"], 24 * 32 + 36 * 2 + 64 * 64);
}
