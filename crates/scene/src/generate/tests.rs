//! Checks what the generator writes with a minimal OBJ reader: indices, normals, winding,
//! closed shells, sizes and determinism.

use super::*;
use crate::generate::glass_holder::{glass_profile, saucer_profile};
use crate::generate::math::{add, cross, dot, sub, sub2, unit2, V2, V3};
use std::collections::BTreeMap;
use std::f64::consts::PI;

/// A triangle corner as 0-based indices.
type Corner = (usize, Option<usize>, usize);

struct Object {
    name: String,
    materials: Vec<String>,
    tris: Vec<[Corner; 3]>,
}

/// Just enough of an OBJ reader to check what this module writes; it panics on anything
/// else (non-triangles, missing normals, index 0), which is part of what is tested.
struct Obj {
    v: Vec<V3>,
    vt: Vec<V2>,
    vn: Vec<V3>,
    mtllib: Vec<String>,
    objects: Vec<Object>,
}

fn parse(text: &str) -> Obj {
    let mut obj = Obj {
        v: vec![],
        vt: vec![],
        vn: vec![],
        mtllib: vec![],
        objects: vec![],
    };
    let nums = |rest: &str| -> Vec<f64> { rest.split(' ').map(|x| x.parse().unwrap()).collect() };
    let index = |s: &str| s.parse::<usize>().unwrap().checked_sub(1).expect("1-based");
    for line in text.lines() {
        let (tag, rest) = line.split_once(' ').unwrap_or((line, ""));
        match tag {
            "#" => {}
            "v" | "vn" => {
                let n = nums(rest);
                assert_eq!(n.len(), 3, "{line}");
                let list = if tag == "v" { &mut obj.v } else { &mut obj.vn };
                list.push([n[0], n[1], n[2]]);
            }
            "vt" => {
                let n = nums(rest);
                assert_eq!(n.len(), 2, "{line}");
                obj.vt.push([n[0], n[1]]);
            }
            "mtllib" => obj.mtllib.push(rest.to_string()),
            "o" => obj.objects.push(Object {
                name: rest.to_string(),
                materials: vec![],
                tris: vec![],
            }),
            "usemtl" => obj
                .objects
                .last_mut()
                .unwrap()
                .materials
                .push(rest.to_string()),
            "f" => {
                let corners: Vec<Corner> = rest
                    .split(' ')
                    .map(|c| {
                        let parts: Vec<&str> = c.split('/').collect();
                        assert_eq!(parts.len(), 3, "{line}");
                        let vt = (!parts[1].is_empty()).then(|| index(parts[1]));
                        (index(parts[0]), vt, index(parts[2]))
                    })
                    .collect();
                let tri: [Corner; 3] = corners.try_into().expect("triangles only");
                obj.objects.last_mut().expect("f before o").tris.push(tri);
            }
            _ => panic!("unexpected line {line:?}"),
        }
    }
    obj
}

fn models() -> Vec<(GeneratedModel, Obj)> {
    all()
        .into_iter()
        .map(|m| {
            let obj = parse(&m.obj);
            (m, obj)
        })
        .collect()
}

fn model(name: &str) -> Obj {
    parse(&all().into_iter().find(|m| m.name == name).unwrap().obj)
}

fn object<'a>(obj: &'a Obj, name: &str) -> &'a Object {
    obj.objects.iter().find(|o| o.name == name).unwrap()
}

fn positions(obj: &Obj, o: &Object) -> Vec<V3> {
    o.tris.iter().flatten().map(|c| obj.v[c.0]).collect()
}

#[test]
fn headers_materials_and_names() {
    let names: Vec<_> = all().iter().map(|m| m.name).collect();
    assert_eq!(
        names,
        [
            "glass_holder",
            "sphere",
            "box_floor",
            "box_on_floor",
            "textured_quad"
        ]
    );
    for (m, obj) in models() {
        assert!(m.obj.starts_with(&format!("{HEADER}\n")), "{}", m.name);
        assert!(m.mtl.starts_with(&format!("{HEADER}\n")), "{}", m.name);
        assert_eq!(obj.mtllib, [format!("{}.mtl", m.name)]);
        assert!(!obj.objects.is_empty());
        for o in &obj.objects {
            assert_eq!(o.materials.len(), 1, "{}/{}", m.name, o.name);
            let newmtl = format!("\nnewmtl {}\n", o.materials[0]);
            assert!(m.mtl.contains(&newmtl), "{}: {newmtl:?} missing", m.name);
            assert!(!o.tris.is_empty(), "{}/{}", m.name, o.name);
        }
    }
}

#[test]
fn face_indices_in_range() {
    for (m, obj) in models() {
        for o in &obj.objects {
            for &(v, vt, vn) in o.tris.iter().flatten() {
                assert!(v < obj.v.len(), "{}: v {v}", m.name);
                assert!(vn < obj.vn.len(), "{}: vn {vn}", m.name);
                assert!(vt.is_none_or(|t| t < obj.vt.len()), "{}: vt", m.name);
            }
        }
    }
}

#[test]
fn normals_are_unit() {
    for (m, obj) in models() {
        for n in &obj.vn {
            assert!((dot(*n, *n).sqrt() - 1.0).abs() < 1e-5, "{}: {n:?}", m.name);
        }
    }
}

#[test]
fn no_degenerate_triangles_and_winding_matches_normals() {
    for (m, obj) in models() {
        for o in &obj.objects {
            for t in &o.tris {
                let [a, b, c] = t.map(|k| obj.v[k.0]);
                let g = cross(sub(b, a), sub(c, a));
                assert!(dot(g, g).sqrt() > 1e-10, "{}/{}: {t:?}", m.name, o.name);
                let n = t.iter().fold([0.0; 3], |s, k| add(s, obj.vn[k.2]));
                // Counter-clockwise from outside means the face normal agrees with the
                // vertex normals.
                assert!(
                    dot(g, n) > 0.0,
                    "{}/{}: {t:?} is wound backwards",
                    m.name,
                    o.name
                );
            }
        }
    }
}

/// Closed and consistently oriented: every directed edge (by position, so that seams
/// and creases with separate vertices count as joined) appears once and its reverse once.
fn assert_closed(obj: &Obj, o: &Object) {
    let key = |p: V3| p.map(|x| (x * 1e6).round() as i64);
    let mut edges: BTreeMap<([i64; 3], [i64; 3]), i32> = BTreeMap::new();
    let mut volume = 0.0;
    for t in &o.tris {
        let p = t.map(|k| obj.v[k.0]);
        volume += dot(p[0], cross(p[1], p[2])) / 6.0;
        for e in 0..3 {
            *edges.entry((key(p[e]), key(p[(e + 1) % 3]))).or_default() += 1;
        }
    }
    for (&(a, b), &n) in &edges {
        assert_eq!(n, 1, "{}: edge {a:?}-{b:?} used {n} times", o.name);
        assert_eq!(
            edges.get(&(b, a)),
            Some(&1),
            "{}: open edge {a:?}-{b:?}",
            o.name
        );
    }
    assert!(volume > 0.0, "{}: inside out", o.name);
}

#[test]
fn glass_holder_parts_and_boxes_are_closed_shells() {
    let scene = model("glass_holder");
    for o in &scene.objects {
        assert_closed(&scene, o);
    }
    for name in ["box_floor", "box_on_floor"] {
        let obj = model(name);
        assert_closed(&obj, object(&obj, "box"));
    }
}

#[test]
fn glass_holder_size_and_budget() {
    let scene = model("glass_holder");
    let names: Vec<_> = scene.objects.iter().map(|o| o.name.as_str()).collect();
    assert_eq!(
        names,
        ["saucer", "holder", "holder_cage", "holder_handle", "glass"]
    );
    let total: usize = scene.objects.iter().map(|o| o.tris.len()).sum();
    assert!((10_000..=40_000).contains(&total), "{total} triangles");
    let all_p: Vec<V3> = scene
        .objects
        .iter()
        .flat_map(|o| positions(&scene, o))
        .collect();
    let min_y = all_p.iter().map(|p| p[1]).fold(f64::MAX, f64::min);
    assert!(min_y.abs() < 1e-9, "rests on y = 0, lowest {min_y}");
    let saucer = positions(&scene, object(&scene, "saucer"));
    let r = saucer.iter().map(|p| p[0].hypot(p[2])).fold(0.0, f64::max);
    assert!((r - 1.0).abs() < 0.01, "saucer radius {r}");
    let glass = positions(&scene, object(&scene, "glass"));
    let lo = glass.iter().map(|p| p[1]).fold(f64::MAX, f64::min);
    let hi = glass.iter().map(|p| p[1]).fold(f64::MIN, f64::max);
    assert!((hi - lo - 1.2).abs() < 1e-6, "glass height {}", hi - lo);
}

#[test]
fn sphere_is_unit_with_exact_normals() {
    let obj = model("sphere");
    let s = object(&obj, "sphere");
    assert_eq!(s.tris.len(), 2 * 192 + 94 * 192 * 2);
    assert_eq!(obj.v.len(), 95 * 192 + 2);
    for p in &obj.v {
        assert!((dot(*p, *p).sqrt() - 1.0).abs() < 1e-6, "{p:?}");
    }
    for &(v, vt, vn) in s.tris.iter().flatten() {
        assert_eq!(obj.v[v], obj.vn[vn]);
        let [u, t] = obj.vt[vt.unwrap()];
        assert!((0.0..=1.0).contains(&u) && (0.0..=1.0).contains(&t));
    }
    assert_closed(&obj, s);
}

#[test]
fn box_scenes_match_spec() {
    for (name, y0) in [("box_floor", 1.0), ("box_on_floor", 0.0)] {
        let obj = model(name);
        let floor = object(&obj, "floor");
        assert_eq!(floor.tris.len(), 16 * 16 * 2);
        for &(v, _, vn) in floor.tris.iter().flatten() {
            assert_eq!(obj.vn[vn], [0.0, 1.0, 0.0]);
            assert_eq!(obj.v[v][1], 0.0);
            assert!(obj.v[v][0].abs() <= 3.0 && obj.v[v][2].abs() <= 3.0);
        }
        let cube = object(&obj, "box");
        assert_eq!(cube.tris.len(), 12);
        let mut used: Vec<usize> = cube.tris.iter().flatten().map(|c| c.0).collect();
        used.sort_unstable();
        used.dedup();
        assert_eq!(used.len(), 24);
        for v in used {
            let p = obj.v[v];
            assert!(p[0].abs() == 0.5 && p[2].abs() == 0.5);
            assert!(p[1] == y0 || p[1] == y0 + 1.0);
        }
    }
}

#[test]
fn textured_quad_and_checker() {
    let m = all()
        .into_iter()
        .find(|m| m.name == "textured_quad")
        .unwrap();
    assert!(m.mtl.contains("\nmap_Kd checker.png\n"));
    let obj = parse(&m.obj);
    let quad = object(&obj, "quad");
    assert_eq!(quad.tris.len(), 2);
    for &(v, vt, vn) in quad.tris.iter().flatten() {
        let (p, uv) = (obj.v[v], obj.vt[vt.unwrap()]);
        assert_eq!(obj.vn[vn], [0.0, 0.0, 1.0]);
        assert_eq!([p[0], p[1]], [uv[0] * 2.0 - 1.0, uv[1] * 2.0 - 1.0]);
    }
    let (w, h, rgba) = checker_png_rgba();
    assert_eq!((w, h, rgba.len()), (64, 64, 64 * 64 * 4));
    let px = |x: usize, y: usize| &rgba[(y * 64 + x) * 4..][..4];
    assert_eq!(px(0, 0), [255, 255, 255, 255]);
    assert_eq!(px(7, 7), [255, 255, 255, 255]);
    assert_eq!(px(8, 0), [0, 0, 0, 255]);
    assert_eq!(px(0, 8), [0, 0, 0, 255]);
    assert_eq!(px(63, 63), [255, 255, 255, 255]);
}

#[test]
fn output_is_deterministic_and_clean() {
    let (a, b) = (all(), all());
    assert!(a == b, "two runs differ");
    for m in &a {
        for text in [&m.obj, &m.mtl] {
            assert!(!text.contains("-0.000000"), "{}: negative zero", m.name);
            assert!(!text.contains("NaN") && !text.contains("inf"), "{}", m.name);
            assert!(!text.contains('\r') && text.ends_with('\n'), "{}", m.name);
        }
    }
}

#[test]
fn rounded_path_is_smooth_within_runs() {
    for run in glass_profile().iter().chain(&saucer_profile()) {
        for pair in run.windows(2) {
            let (a, b) = (pair[0], pair[1]);
            let chord = unit2(sub2(b.p, a.p));
            // No crease inside a run: each step turns the tangent by less than 60°.
            for t in [a.t, b.t] {
                assert!(chord[0] * t[0] + chord[1] * t[1] > (PI / 6.0).cos());
            }
        }
    }
}
