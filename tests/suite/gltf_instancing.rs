//! `EXT_mesh_gpu_instancing` (issue 37), expanded on the CPU at load: Khronos' SimpleInstancing
//! (125 instances of one cube, tests/data/khronos/instancing) draws the same picture, pixel
//! for pixel, as the same file with its instances written out as child nodes, and `--stats`
//! counts 125 times the one cube's triangles.
use crate::common::*;
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
    shot_on(dir, name, model, &[], &[])
}

/// `shot` on the context `env` and `args` ask for.
fn shot_on(
    dir: &Path,
    name: &str,
    model: &Path,
    env: &[(&str, &str)],
    args: &[&str],
) -> (glview::image_out::Rgba, u64) {
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
    (img, stats["triangles"].as_u64().unwrap())
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
