//! The loader against peers' parser test corpora (../shared/conformance, ../shared/tricky) and
//! the shared real models, with the expectations listed in ../shared/MANIFEST.md. Where glview
//! deliberately differs from tobj or tinyobjloader, the test says so.
use crate::common;
use common::shared;
use glview::scene::Scene;
use glview::scene::{load, LoadOptions};
use std::path::{Path, PathBuf};

fn tiny(name: &str) -> PathBuf {
    shared().join("conformance/tinyobjloader/models").join(name)
}

fn ok(p: &Path) -> Scene {
    load(p, &LoadOptions::default()).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

fn err(p: &Path) -> String {
    match load(p, &LoadOptions::default()) {
        Ok(_) => panic!("{} should not load", p.display()),
        Err(e) => e.to_string(),
    }
}

#[test]
fn shared_models_load_with_the_manifest_counts() {
    // (path, triangles, de-duplicated vertices as tobj's single_index gives them)
    for (p, tris, verts) in [
        ("models/teapot-small/teapot.obj", 992, 792),
        ("models/bunny-small/bunny.obj", 3674, 1839),
        ("models/spot/spot_triangulated.obj", 5856, 3225),
        ("models/suzanne/suzanne.obj", 968, 507),
        ("models/stanford-bunny/stanford-bunny.obj", 69451, 34834),
        // The file has 202,520 faces, 86 of them duplicates, which the loader drops (with a
        // warning); the de-duplicated vertices are tobj's.
        ("models/dragon-200k/dragon_vrip_res2.obj", 202434, 100207),
    ] {
        // Creases off (180°): tobj's count is for smooth normals. The default crease angle
        // splits vertices at sharp edges (tests/loading.rs).
        let opts = LoadOptions {
            creases: glview::scene::geometry::normals::Creases::Angle(180.0),
            ..Default::default()
        };
        let s = load(&shared().join(p), &opts).unwrap_or_else(|e| panic!("{p}: {e}"));
        assert_eq!(s.triangle_count(), tris, "{p}");
        assert_eq!(s.vertex_count(), verts, "{p}");
        for m in &s.meshes {
            for v in &m.vertices {
                let n = glam::Vec3::from(v.normal);
                assert!((n.length() - 1.0).abs() < 1e-4, "{p}: normal {n}");
            }
        }
    }
    // No normals in the file → all generated; suzanne has its own.
    assert!(ok(&shared().join("models/teapot-small/teapot.obj")).meshes[0].generated_normals > 0);
    assert_eq!(
        ok(&shared().join("models/suzanne/suzanne.obj")).meshes[0].generated_normals,
        0
    );
}

#[test]
fn tinyobjloader_expectations() {
    let s = ok(&tiny("cornell_box.obj"));
    assert!(s.warnings.is_empty(), "{:?}", s.warnings);
    assert!(s.materials.len() > 1);

    let s = ok(&tiny("issue-295-trianguation-failure.obj"));
    assert_eq!(s.triangle_count(), 28);

    let s = ok(&tiny("tr-and-d-issue-43.obj"));
    assert!(s
        .materials
        .iter()
        .filter(|m| m.name != "default")
        .all(|m| m.opacity == Some(0.75)));

    let s = ok(&tiny("usemtl-issue-104.obj"));
    assert_eq!(s.meshes.len(), 1);

    // Index 0 and out-of-range relative indices: an error naming the line.
    let e = err(&tiny("issue-140-zero-face-idx.obj"));
    assert!(
        e.contains("issue-140-zero-face-idx.obj:") && e.contains("face index 0"),
        "{e}"
    );
    let e = err(&tiny("invalid-relative-vertex-index.obj"));
    assert!(e.contains("out of range"), "{e}");

    // 1- and 2-corner faces are dropped (tinyobjloader: 0 indices). glview differs: a file
    // left with no triangles cannot be shown, so it is an error, not an empty model.
    let e = err(&tiny("invalid-face-definition.obj"));
    assert!(e.contains("no triangles"), "{e}");

    // Non-finite positions: tobj fails without a line; glview names it.
    let e = err(&tiny("test-nan.obj"));
    assert!(
        e.contains("test-nan.obj:") && e.contains("not finite"),
        "{e}"
    );

    // Lines and points (tinyobjloader: 8 line indices in 2 polylines; 8 point indices).
    let s = ok(&tiny("line-prim.obj"));
    assert_eq!(s.wire.segments.len(), 6);
    let s = ok(&tiny("points-prim.obj"));
    assert_eq!(s.wire.points.len(), 8);

    // Vertex colours: 8 coloured vertices (tinyobjloader: 24 colour floats).
    let s = ok(&tiny("cube-vertexcol.obj"));
    let mut c: Vec<[f32; 3]> = s.meshes.iter().flat_map(|m| m.colors.clone()).collect();
    c.sort_by(|a, b| a.partial_cmp(b).unwrap());
    c.dedup();
    assert_eq!(c.len(), 8);
    assert_eq!((c[0], c[7]), ([0.0; 3], [1.0; 3]));

    // A missing .mtl: renders with the default material and a warning.
    let s = ok(&tiny("missing_material_file.obj"));
    assert!(!s.warnings.is_empty());
}

#[test]
fn tobj_expectations() {
    let dir = shared().join("conformance/tobj/obj");
    let s = ok(&dir.join("cornell_box.obj"));
    assert_eq!(s.meshes.len(), 8);
    // Five materials from the two libraries, plus glview's default.
    assert_eq!(s.materials.len(), 6);
    let names: Vec<&str> = s.meshes.iter().map(|m| m.name.as_str()).collect();
    assert_eq!(
        names,
        [
            "floor",
            "light",
            "ceiling",
            "back_wall",
            "green_wall",
            "red_wall",
            "short_block",
            "tall_block"
        ]
    );
    let light = s.materials.iter().find(|m| m.name == "light").unwrap();
    assert_eq!(light.opacity, Some(0.8));
    assert_eq!(light.phong_terms().ambient, [20.0; 3]);
    let white = s.materials.iter().find(|m| m.name == "white").unwrap();
    assert_eq!(white.emissive, [1.0; 3]);

    let s = ok(&dir.join("triangle.obj"));
    assert_eq!(s.triangle_count(), 1);
    assert_eq!(s.meshes[0].name, "Triangle");

    let s = ok(&dir.join("quad.obj"));
    assert_eq!(s.meshes.len(), 3);
    assert_eq!(s.triangle_count(), 5);
    assert!(s.meshes[0].has_uv);

    let e = err(&dir.join("invalid_index.obj"));
    assert!(e.contains("out of range"), "{e}");
    // Lines only: loads as lines (issue 13: never refuse a file with only lines).
    let s = ok(&dir.join("lines.obj"));
    assert_eq!(s.triangle_count(), 0);
    assert_eq!(s.wire.segments, [[0, 1], [1, 2], [2, 0]]);
    assert_eq!(
        s.wire.positions,
        [[-0.5, -0.5, 0.0], [0.5, -0.5, 0.0], [-0.5, 0.5, 0.0]]
    );
}

/// PyWavefront runs the same assertions on `simple.obj.gz` as on `simple.obj`.
#[test]
fn gzipped_obj_loads_like_the_plain_file() {
    let dir = shared().join("tricky/pywavefront/tests/fixtures");
    let (a, b) = (ok(&dir.join("simple.obj")), ok(&dir.join("simple.obj.gz")));
    assert_eq!(b.meshes.len(), 2);
    assert_eq!(
        (a.triangle_count(), a.vertex_count(), a.materials.len()),
        (b.triangle_count(), b.vertex_count(), b.materials.len())
    );
}

/// Every file of the corpora: loads, or fails with a one-line error that names the file.
/// Never a panic.
#[test]
fn every_corpus_file_has_a_clean_outcome() {
    let mut files = Vec::new();
    for d in [
        "conformance/tinyobjloader/models",
        "conformance/tobj/obj",
        "tricky/pywavefront/tests/fixtures",
    ] {
        let dir = shared().join(d);
        for e in std::fs::read_dir(&dir).unwrap().flatten() {
            if e.path().extension().is_some_and(|x| x == "obj") {
                files.push(e.path());
            }
        }
    }
    assert!(files.len() > 60, "corpus incomplete: {}", files.len());
    let (mut loaded, mut failed) = (0, 0);
    for f in &files {
        let result = std::panic::catch_unwind(|| load(f, &LoadOptions::default()));
        match result.unwrap_or_else(|_| panic!("panic on {}", f.display())) {
            Ok(s) => {
                loaded += 1;
                assert!(s.triangle_count() > 0 || !s.wire.is_empty());
            }
            Err(e) => {
                failed += 1;
                let msg = e.to_string();
                assert!(
                    !msg.contains('\n'),
                    "multi-line error for {}: {msg}",
                    f.display()
                );
                let name = f.file_name().unwrap().to_string_lossy();
                assert!(
                    msg.contains(name.as_ref()),
                    "error does not name {name}: {msg}"
                );
            }
        }
    }
    eprintln!("{loaded} loaded, {failed} refused with a clear error");
}
