//! Quirky but valid STL, PLY and glTF files (issue 20) load with their exact geometry and
//! render: a binary STL whose header starts with "solid", zero facet normals, CRLF ASCII STL,
//! big-endian PLY with extra properties, `vertex_index`, comments and `obj_info`, and a glTF
//! hierarchy 10,000 nodes deep.
use crate::common::*;
use glview::scene::{load, LoadOptions};
use std::path::PathBuf;

/// Triangle (0,0,0) (1,0,0) (0,1,0) and (1,0,0) (1,1,0) (0,1,0): the unit square.
const SQUARE: [[f32; 3]; 6] = [
    [0., 0., 0.],
    [1., 0., 0.],
    [0., 1., 0.],
    [1., 0., 0.],
    [1., 1., 0.],
    [0., 1., 0.],
];

fn write(name: &str, bytes: &[u8]) -> PathBuf {
    let p = out_dir("quirky-formats").join(name);
    std::fs::write(&p, bytes).unwrap();
    p
}

fn area(s: &glview::scene::Scene) -> f64 {
    s.meshes
        .iter()
        .flat_map(|m| {
            m.indices.chunks_exact(3).map(|t| {
                let p = |i: u32| glam::Vec3::from(m.vertices[i as usize].position).as_dvec3();
                0.5 * (p(t[1]) - p(t[0])).cross(p(t[2]) - p(t[0])).length()
            })
        })
        .sum()
}

/// Loads in process (exact triangle count and area), then renders through the binary.
fn loads_and_renders(p: &std::path::Path, triangles: usize, want_area: f64) {
    let s = load(p, &LoadOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(s.triangle_count(), triangles, "{}", p.display());
    assert!(
        (area(&s) - want_area).abs() < 1e-6,
        "{}: area {}",
        p.display(),
        area(&s)
    );
    assert!(s.warnings.is_empty(), "{}: {:?}", p.display(), s.warnings);
    let png = p.with_extension("png");
    let o = run(
        &[
            p.to_str().unwrap(),
            "--output",
            png.to_str().unwrap(),
            "--size",
            "32x24",
        ],
        &[],
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}

#[test]
fn quirky_stl_files_render() {
    // Binary, header beginning with "solid" (SolidWorks and others), zero normals.
    let mut b = b"solid exported by a CAD tool".to_vec();
    b.resize(80, b' ');
    b.extend(2u32.to_le_bytes());
    for t in SQUARE.chunks_exact(3) {
        b.extend([0u8; 12]);
        for x in t.iter().flatten() {
            b.extend(x.to_le_bytes());
        }
        b.extend([0u8; 2]);
    }
    loads_and_renders(&write("solid-header.stl", &b), 2, 1.0);
    // ASCII with CRLF line ends and a facet normal of zero.
    let mut a = String::from("solid square\r\n");
    for t in SQUARE.chunks_exact(3) {
        a += "  facet normal 0 0 0\r\n    outer loop\r\n";
        for v in t {
            a += &format!("      vertex {} {} {}\r\n", v[0], v[1], v[2]);
        }
        a += "    endloop\r\n  endfacet\r\n";
    }
    a += "endsolid square\r\n";
    loads_and_renders(&write("crlf.stl", a.as_bytes()), 2, 1.0);
}

#[test]
fn quirky_ply_files_render() {
    // Big-endian, comments and obj_info, extra vertex properties (double, short, a list),
    // `vertex_index` as the face list's name, a quad.
    let mut b = b"ply\nformat binary_big_endian 1.0\ncomment made by a scanner\n\
                  obj_info scanner 7\nelement vertex 4\nproperty double x\nproperty double y\n\
                  property double z\nproperty short confidence\nproperty list uchar float extra\n\
                  element face 1\nproperty list uchar uint vertex_index\n\
                  property uchar flags\nend_header\n"
        .to_vec();
    for p in [[0., 0., 0.], [2., 0., 0.], [2., 3., 0.], [0., 3., 0.]] {
        for x in p {
            b.extend(f64::to_be_bytes(x));
        }
        b.extend(7i16.to_be_bytes());
        b.push(2);
        b.extend(1f32.to_be_bytes());
        b.extend(2f32.to_be_bytes());
    }
    b.push(4);
    for i in [0u32, 1, 2, 3] {
        b.extend(i.to_be_bytes());
    }
    b.push(9);
    loads_and_renders(&write("big-endian.ply", &b), 2, 6.0);
    let ascii = "ply\r\nformat ascii 1.0\r\ncomment CRLF too\r\nelement vertex 3\r\n\
                 property float x\r\nproperty float y\r\nproperty float z\r\n\
                 property uchar alpha\r\nelement face 1\r\n\
                 property list uchar int vertex_indices\r\nend_header\r\n\
                 0 0 0 1\r\n1 0 0 1\r\n0 1 0 1\r\n3 0 1 2\r\n";
    loads_and_renders(&write("crlf.ply", ascii.as_bytes()), 1, 0.5);
}

#[test]
fn deep_gltf_hierarchy_renders() {
    // 10,000 nested nodes, each translated by 1/10000 in x; the last holds the triangle.
    let dir = out_dir("quirky-formats");
    let depth = 10_000;
    let nodes: Vec<String> = (0..depth)
        .map(|k| {
            if k + 1 < depth {
                format!(
                    "{{\"translation\": [0.0001, 0, 0], \"children\": [{}]}}",
                    k + 1
                )
            } else {
                "{\"translation\": [0.0001, 0, 0], \"mesh\": 0}".to_string()
            }
        })
        .collect();
    let p = crate::hostile_formats::tri_gltf(&dir, "deep.gltf", &|s| {
        s.replace(
            r#""nodes": [{"mesh": 0}]"#,
            &format!("\"nodes\": [{}]", nodes.join(",")),
        )
    });
    loads_and_renders(&p, 1, 0.5);
    let s = load(&p, &LoadOptions::default()).unwrap();
    assert!(
        (s.file_bounds.0.x - 1.0).abs() < 1e-5,
        "{:?}",
        s.file_bounds
    );
}
