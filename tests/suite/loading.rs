//! Issue 13, loader side: polygons, creases, colours, lines, exporters' MTL quirks, up axis,
//! `--texture` and `--check`, on generated files with exact expectations and on ../shared/.
use crate::common;
use common::{box_obj, out_dir, run, shared};
use glam::{DVec3, Vec3};
use glview::scene::geometry::normals::Creases;
use glview::scene::{load, LoadOptions};
use glview::scene::{Scene, UpAxis};
use std::f64::consts::TAU;
use std::path::PathBuf;

fn write(test: &str, name: &str, text: &str) -> PathBuf {
    let dir = out_dir(test);
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

fn load_text(test: &str, name: &str, text: &str, opts: &LoadOptions) -> Scene {
    let p = write(test, name, text);
    load(&p, opts).unwrap_or_else(|e| panic!("{e}"))
}

/// Total area of the triangles, in f64 from the (re-centred) f32 positions.
fn area(s: &Scene) -> f64 {
    let mut a = 0.0;
    for m in &s.meshes {
        for t in m.indices.chunks_exact(3) {
            let p: [DVec3; 3] =
                std::array::from_fn(|k| Vec3::from(m.vertices[t[k] as usize].position).as_dvec3());
            a += (p[1] - p[0]).cross(p[2] - p[0]).length() / 2.0;
        }
    }
    a
}

/// One face through the given points (z = 0), as OBJ text.
fn face_obj(points: &[(f64, f64)]) -> String {
    let mut s = String::new();
    for (x, y) in points {
        s += &format!("v {x} {y} 0\n");
    }
    s += "f";
    for i in 1..=points.len() {
        s += &format!(" {i}");
    }
    s + "\n"
}

#[test]
fn concave_faces_cover_exactly_their_area() {
    let o = LoadOptions::default();
    // L-shape: area 3 (a fan from corner 1 would give 2.5 + overlap).
    let l = [(0., 0.), (2., 0.), (2., 1.), (1., 1.), (1., 2.), (0., 2.)];
    let s = load_text("loading-concave", "l.obj", &face_obj(&l), &o);
    assert_eq!(s.triangle_count(), 4);
    assert!((area(&s) - 3.0).abs() < 1e-9, "{}", area(&s));
    // A 4x3 wall with a 1x2 doorway in its bottom edge: 12 - 2 = 10.
    let wall = [
        (0., 0.),
        (1.5, 0.),
        (1.5, 2.),
        (2.5, 2.),
        (2.5, 0.),
        (4., 0.),
        (4., 3.),
        (0., 3.),
    ];
    let s = load_text("loading-concave", "wall.obj", &face_obj(&wall), &o);
    assert_eq!(s.triangle_count(), 6);
    assert!((area(&s) - 10.0).abs() < 1e-9, "{}", area(&s));
    // A ring as one 66-corner face: outer 32-gon, a bridge, the inner 32-gon backwards, the
    // bridge back. Area = 32/2 · sin(2π/32) · (R² − r²).
    let (n, big, small) = (32, 2.0, 1.0);
    let mut v = String::new();
    for k in 0..n {
        let a = TAU * k as f64 / n as f64;
        v += &format!("v {} {} 0\n", big * a.cos(), big * a.sin());
    }
    for k in 0..n {
        let a = TAU * k as f64 / n as f64;
        v += &format!("v {} {} 0\n", small * a.cos(), small * a.sin());
    }
    let mut f: Vec<usize> = (1..=n).collect();
    f.push(1);
    f.push(n + 1);
    f.extend((n + 2..=2 * n).rev());
    f.push(n + 1);
    assert_eq!(f.len(), 66);
    v += "f";
    for i in &f {
        v += &format!(" {i}");
    }
    v += "\n";
    let s = load_text("loading-concave", "ring.obj", &v, &o);
    let exact = n as f64 / 2.0 * (TAU / n as f64).sin() * (big * big - small * small);
    assert!(
        (area(&s) - exact).abs() < 1e-5,
        "ring area {} != {exact}",
        area(&s)
    );
    // Every triangle faces +Z like the face.
    for m in &s.meshes {
        for t in m.indices.chunks_exact(3) {
            let p: [Vec3; 3] = std::array::from_fn(|k| m.vertices[t[k] as usize].position.into());
            assert!((p[1] - p[0]).cross(p[2] - p[0]).z >= 0.0);
        }
    }
}

#[test]
fn creases_and_smoothing_groups() {
    let cube = box_obj([0.0; 3], [1.0; 3], 0);
    let corner_normals = |s: &Scene| {
        let mut ns: Vec<[i32; 3]> = s.meshes[0]
            .vertices
            .iter()
            .filter(|v| v.position == [0.5, 0.5, 0.5])
            .map(|v| v.normal.map(|x| (x * 1000.0).round() as i32))
            .collect();
        ns.sort();
        ns
    };
    let s = load_text("loading-crease", "cube.obj", &cube, &LoadOptions::default());
    assert_eq!(
        corner_normals(&s),
        [[0, 0, 1000], [0, 1000, 0], [1000, 0, 0]]
    );
    assert_eq!(s.vertex_count(), 24);
    // One smoothing group: smooth corners, whatever the angle.
    let grouped = format!("s 1\n{cube}");
    let s = load_text(
        "loading-crease",
        "cube-s1.obj",
        &grouped,
        &LoadOptions::default(),
    );
    // One normal, pointing out of the corner (area-weighted: the diagonals decide the mix).
    let n = corner_normals(&s);
    assert_eq!(n.len(), 1);
    assert!(n[0].iter().all(|&x| x > 300), "{n:?}");
    assert_eq!(s.vertex_count(), 8);
    // s off: flat again; --crease 100 smooths the cube; --flat faces it.
    let s = load_text(
        "loading-crease",
        "cube-off.obj",
        &format!("s off\n{cube}"),
        &LoadOptions::default(),
    );
    assert_eq!(s.vertex_count(), 24);
    let wide = LoadOptions {
        creases: Creases::Angle(100.0),
        ..Default::default()
    };
    assert_eq!(
        load_text("loading-crease", "cube.obj", &cube, &wide).vertex_count(),
        8
    );
    let flat = LoadOptions {
        creases: Creases::Flat,
        ..Default::default()
    };
    let s = load_text("loading-crease", "cube-s1.obj", &grouped, &flat);
    assert_eq!(s.vertex_count(), 24);
}

#[test]
fn shared_models_split_only_at_sharp_edges() {
    // Vertex counts with the default crease (60°) against tobj's smooth ones (conformance.rs):
    // the scans gain a few percent at noisy spots, nothing like the flat counts.
    for (p, smooth, flat) in [
        ("models/spot/spot_triangulated.obj", 3225, 17568),
        ("models/stanford-bunny/stanford-bunny.obj", 34834, 208343),
    ] {
        let s = load(&shared().join(p), &LoadOptions::default()).unwrap();
        let n = s.vertex_count();
        assert!(n >= smooth && n < smooth * 11 / 10, "{p}: {n}");
        let f = LoadOptions {
            creases: Creases::Flat,
            ..Default::default()
        };
        assert_eq!(load(&shared().join(p), &f).unwrap().vertex_count(), flat);
    }
}

#[test]
fn partial_vertex_colours_load_white() {
    let text = "v 0 0 0 1 0 0\nv 1 0 0\nv 0 1 0 0 0 1\nf 1 2 3\n";
    let s = load_text("loading-colours", "c.obj", text, &LoadOptions::default());
    let m = &s.meshes[0];
    assert_eq!(m.colors.len(), m.vertices.len());
    let mut c = m.colors.clone();
    c.sort_by(|a, b| a.partial_cmp(b).unwrap());
    assert_eq!(c, [[0., 0., 1.], [1., 0., 0.], [1., 1., 1.]]);
    assert!(s.warnings.iter().any(|w| w.message.contains("no colour")));
    // No colours anywhere: empty.
    let s = load_text(
        "loading-colours",
        "n.obj",
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
        &LoadOptions::default(),
    );
    assert!(s.meshes[0].colors.is_empty());
}

#[test]
fn invisible_materials_and_ns_zero() {
    let dir = out_dir("loading-mtl");
    std::fs::write(
        dir.join("m.mtl"),
        "newmtl glass\nKd 1 0 0\nTr 1\nnewmtl shiny\nKd 0 1 0\nKs 0.5 0.5 0.5\nNs 0\n",
    )
    .unwrap();
    let obj =
        "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl glass\nf 1 2 3\nusemtl shiny\nf 1 3 2\n";
    let p = write("loading-mtl", "m.obj", obj);
    let s = load(&p, &LoadOptions::default()).unwrap();
    let glass = s.materials.iter().find(|m| m.name == "glass").unwrap();
    assert_eq!(glass.opacity, None);
    let w = s
        .warnings
        .iter()
        .find(|w| w.message.contains("fully transparent"))
        .unwrap();
    assert_eq!(
        (w.file.file_name().unwrap(), w.line),
        ("m.mtl".as_ref(), Some(3))
    );
    let shiny = s.materials.iter().find(|m| m.name == "shiny").unwrap();
    let shiny = shiny.phong_terms();
    assert_eq!((shiny.specular, shiny.shininess), ([0.0; 3], 0.0));
    assert!(s.warnings.iter().any(|w| w.line == Some(7)));
    let honor = LoadOptions {
        honor_transparency: true,
        ..Default::default()
    };
    let s = load(&p, &honor).unwrap();
    let glass = s.materials.iter().find(|m| m.name == "glass").unwrap();
    assert_eq!(glass.opacity, Some(0.0));
}

#[test]
fn up_axis_rotates_exactly() {
    let text = box_obj([1.0, 2.0, 3.0], [2.0, 4.0, 7.0], 0);
    for (up, lo, hi) in [
        (UpAxis::PosY, [1., 2., 3.], [2., 4., 7.]),
        (UpAxis::PosZ, [1., 3., -4.], [2., 7., -2.]),
        (UpAxis::NegZ, [1., -7., 2.], [2., -3., 4.]),
        (UpAxis::PosX, [-4., 1., 3.], [-2., 2., 7.]),
        (UpAxis::NegX, [2., -2., 3.], [4., -1., 7.]),
        (UpAxis::NegY, [1., -4., -7.], [2., -2., -3.]),
    ] {
        let o = LoadOptions {
            up,
            ..Default::default()
        };
        let s = load_text("loading-up", "b.obj", &text, &o);
        assert_eq!(s.file_bounds, (DVec3::from(lo), DVec3::from(hi)), "{up:?}");
        // The box's outward normals still point outward (a rotation, not a mirror).
        for m in &s.meshes {
            for v in &m.vertices {
                assert!(Vec3::from(v.normal).dot(Vec3::from(v.position)) > 0.0);
            }
        }
    }
    let out = run(&["--check", "--up", "-Z", "x.obj"], &[]);
    assert!(
        !String::from_utf8_lossy(&out.stderr).contains("unexpected argument"),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

#[test]
fn check_reports_maps_colours_lines_and_texture() {
    let dir = out_dir("loading-check");
    std::fs::write(
        dir.join("m.mtl"),
        "newmtl a\nKd 1 1 1\nmap_Kd missing.png\nmap_Bump -bm 2 bump.png\nmap_Ns ns.png\nnorm n.png\nmap_Pr r.png\n",
    )
    .unwrap();
    let obj = "mtllib m.mtl\nv 0 0 0 1 0 0\nv 1 0 0\nv 0 1 0\nusemtl a\nf 1 2 3\nl 1 2 3\np 1\n";
    let p = write("loading-check", "m.obj", obj);
    let out = run(&["--check", p.to_str().unwrap()], &[]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{text}");
    for want in [
        "vertex colours: 3 vertices",
        "lines: 2  points: 1",
        "m.mtl:3: material a: map_Kd \"missing.png\" -> not loaded",
        "m.mtl:4: material a: map_Bump \"-bm 2 bump.png\" -> not used",
        "m.mtl:5: material a: map_Ns \"ns.png\" -> not used",
        "m.mtl:6: material a: norm \"n.png\" -> not used",
        "m.mtl:7: material a: map_Pr \"r.png\" -> not used",
    ] {
        assert!(text.contains(want), "missing {want:?} in\n{text}");
    }
    // --texture gives meshes without a material a base-colour map (spot has no mtllib).
    let spot = shared().join("models/spot");
    let o = LoadOptions {
        texture: Some(spot.join("spot_texture.png")),
        ..Default::default()
    };
    let s = load(&spot.join("spot_triangulated.obj"), &o).unwrap();
    let m = &s.materials[s.meshes[0].material];
    let t = &m.base_color_texture.as_ref().expect("texture loaded").image;
    assert!(t.width > 0 && t.height > 0);
    assert!(s.meshes[0].has_uv);
}

/// A unit cube as 12 STL facets (normals written as zero, as many exporters do).
fn stl_ascii_cube() -> String {
    let obj = box_obj([0.0; 3], [1.0; 3], 0);
    let v: Vec<[f64; 3]> = obj
        .lines()
        .filter_map(|l| l.strip_prefix("v "))
        .map(|l| {
            let n: Vec<f64> = l.split(' ').map(|x| x.parse().unwrap()).collect();
            [n[0], n[1], n[2]]
        })
        .collect();
    let mut s = String::from("solid cube\n");
    for f in obj.lines().filter_map(|l| l.strip_prefix("f ")) {
        s += "facet normal 0 0 0\nouter loop\n";
        for i in f.split(' ') {
            let p = v[i.parse::<usize>().unwrap() - 1];
            s += &format!("vertex {} {} {}\n", p[0], p[1], p[2]);
        }
        s += "endloop\nendfacet\n";
    }
    s + "endsolid cube\n"
}

fn stl_binary(ascii: &str) -> Vec<u8> {
    let verts: Vec<f32> = ascii
        .lines()
        .filter_map(|l| l.strip_prefix("vertex "))
        .flat_map(|l| {
            l.split(' ')
                .map(|x| x.parse::<f32>().unwrap())
                .collect::<Vec<_>>()
        })
        .collect();
    let n = verts.len() / 9;
    let mut b = vec![0u8; 80];
    b.extend((n as u32).to_le_bytes());
    for t in verts.chunks_exact(9) {
        b.extend([0u8; 12]);
        for x in t {
            b.extend(x.to_le_bytes());
        }
        b.extend([0u8; 2]);
    }
    b
}

#[test]
fn stl_and_ply_load_into_the_same_scene() {
    let o = LoadOptions::default();
    let ascii = stl_ascii_cube();
    let s = load(&write("loading-formats", "cube.stl", &ascii), &o).unwrap();
    assert_eq!(s.triangle_count(), 12);
    assert!((area(&s) - 6.0).abs() < 1e-9);
    // welded by position, then split at the 90° edges: 24 vertices, 3 normals per corner
    assert_eq!(s.vertex_count(), 24);
    let dir = out_dir("loading-formats");
    std::fs::write(dir.join("cube-bin.stl"), stl_binary(&ascii)).unwrap();
    let b = load(&dir.join("cube-bin.stl"), &o).unwrap();
    assert_eq!((b.triangle_count(), b.vertex_count()), (12, 24));
    assert_eq!(b.file_bounds, s.file_bounds);

    // PLY: an L-shaped face (concave, ear-clipped) and a coloured quad, ASCII and gzipped.
    let ply = "ply\nformat ascii 1.0\nelement vertex 6\nproperty float x\nproperty float y\n\
               property float z\nproperty uchar red\nproperty uchar green\nproperty uchar blue\n\
               element face 1\nproperty list uchar int vertex_indices\nend_header\n\
               0 0 0 255 0 0\n2 0 0 255 0 0\n2 1 0 0 255 0\n1 1 0 0 255 0\n1 2 0 0 0 255\n\
               0 2 0 255 255 255\n6 0 1 2 3 4 5\n";
    let s = load(&write("loading-formats", "l.ply", ply), &o).unwrap();
    assert_eq!(s.triangle_count(), 4);
    assert!((area(&s) - 3.0).abs() < 1e-9);
    assert_eq!(s.meshes[0].colors.len(), s.meshes[0].vertices.len());
    assert!(s.meshes[0].colors.contains(&[1.0, 0.0, 0.0]));
    let gz = dir.join("l.ply.gz");
    let mut e = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::default());
    std::io::Write::write_all(&mut e, ply.as_bytes()).unwrap();
    std::fs::write(&gz, e.finish().unwrap()).unwrap();
    let z = load(&gz, &o).unwrap();
    assert_eq!(z.triangle_count(), 4);

    // Bad input: one line naming the file, never a panic.
    for (name, bytes) in [
        ("trunc.stl", stl_binary(&ascii)[..200].to_vec()),
        ("junk.stl", b"hello".to_vec()),
        (
            "range.ply",
            ply.replace("6 0 1 2 3 4 5", "3 0 1 9").into_bytes(),
        ),
        (
            "bomb.ply",
            ply.replace("element vertex 6", "element vertex 4000000000")
                .into_bytes(),
        ),
        ("bad.ply.gz", b"not gzip".to_vec()),
        ("empty.ply", b"ply\nformat ascii 1.0\nend_header\n".to_vec()),
    ] {
        std::fs::write(dir.join(name), &bytes).unwrap();
        let e = load(&dir.join(name), &o).unwrap_err().to_string();
        assert!(e.contains(name) && !e.contains('\n'), "{name}: {e}");
    }
}

#[test]
fn gltf_quad_with_transform_and_pbr_material() {
    let dir = out_dir("loading-gltf");
    let mut bin = Vec::new();
    for p in [[0f32, 0., 0.], [1., 0., 0.], [1., 1., 0.], [0., 1., 0.]] {
        for x in p {
            bin.extend(x.to_le_bytes());
        }
    }
    for i in [0u16, 1, 2, 0, 2, 3] {
        bin.extend(i.to_le_bytes());
    }
    std::fs::write(dir.join("quad.bin"), &bin).unwrap();
    let json = r#"{
      "asset": {"version": "2.0"},
      "scene": 0,
      "scenes": [{"nodes": [0]}],
      "nodes": [{"mesh": 0, "translation": [10, 0, 0], "scale": [2, 3, 1]}],
      "meshes": [{"name": "quad", "primitives": [{"attributes": {"POSITION": 0}, "indices": 1, "material": 0}]}],
      "materials": [{"name": "paint", "pbrMetallicRoughness": {"baseColorFactor": [0.5, 0.25, 1, 1], "metallicFactor": 0.25, "roughnessFactor": 0.75}}],
      "buffers": [{"uri": "quad.bin", "byteLength": 60}],
      "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 48}, {"buffer": 0, "byteOffset": 48, "byteLength": 12}],
      "accessors": [
        {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [0,0,0], "max": [1,1,0]},
        {"bufferView": 1, "componentType": 5123, "count": 6, "type": "SCALAR"}
      ]
    }"#;
    let p = dir.join("quad.gltf");
    std::fs::write(&p, json).unwrap();
    let s = load(&p, &LoadOptions::default()).unwrap();
    assert_eq!(s.triangle_count(), 2);
    assert!((area(&s) - 6.0).abs() < 1e-9, "{}", area(&s));
    assert_eq!(
        s.file_bounds,
        (DVec3::new(10.0, 0.0, 0.0), DVec3::new(12.0, 3.0, 0.0))
    );
    let m = &s.materials[s.meshes[0].material];
    assert_eq!(
        (m.name.as_str(), m.base_color, m.metallic, m.roughness),
        ("paint", [0.5, 0.25, 1.0], 0.25, 0.75)
    );
    assert_eq!(s.meshes[0].vertices[0].normal, [0.0, 0.0, 1.0]);
    // Broken files: one line naming the file.
    std::fs::write(dir.join("broken.gltf"), "{\"asset\": ").unwrap();
    let e = load(&dir.join("broken.gltf"), &LoadOptions::default())
        .unwrap_err()
        .to_string();
    assert!(e.contains("broken.gltf") && !e.contains('\n'), "{e}");
    let bad_index = json.replace("\"count\": 6", "\"count\": 6, \"max\": [9]");
    std::fs::write(
        dir.join("missing-bin.gltf"),
        bad_index.replace("quad.bin", "nope.bin"),
    )
    .unwrap();
    let e = load(&dir.join("missing-bin.gltf"), &LoadOptions::default())
        .unwrap_err()
        .to_string();
    assert!(e.contains("missing-bin.gltf") && !e.contains('\n'), "{e}");
}
