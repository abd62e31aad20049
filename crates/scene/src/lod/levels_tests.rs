//! Tests of [`super`]: no cracks between groups at mixed levels, error 0 is every triangle.
use super::*;
use crate::lod::clusters::{prepare, Clusters};
use crate::model::Vertex;
use glam::{Mat4, Vec3};
use {crate::geometry::closure::closure, crate::model::Mesh, crate::model::Scene};

/// A unit UV sphere of 2·segments·(rings − 1) triangles, outward, with a UV seam.
fn sphere(rings: u32, segments: u32) -> Mesh {
    let mut vertices = Vec::new();
    for j in 0..=rings {
        let th = std::f32::consts::PI * j as f32 / rings as f32;
        for i in 0..=segments {
            // The seam column repeats the first one's positions exactly (its own UVs).
            let ph = std::f32::consts::TAU * (i % segments) as f32 / segments as f32;
            let p = [th.sin() * ph.sin(), th.cos(), th.sin() * ph.cos()];
            vertices.push(Vertex {
                position: p,
                normal: p,
                uv: [i as f32 / segments as f32, j as f32 / rings as f32],
            });
        }
    }
    let at = |j: u32, i: u32| j * (segments + 1) + i;
    let mut indices = Vec::new();
    for j in 0..rings {
        for i in 0..segments {
            let (a, b, c, d) = (at(j, i), at(j + 1, i), at(j + 1, i + 1), at(j, i + 1));
            // The pole rows' other triangle would be degenerate.
            if j + 1 < rings {
                indices.extend([a, b, c]);
            }
            if j > 0 {
                indices.extend([a, c, d]);
            }
        }
    }
    Mesh {
        name: "sphere".into(),
        vertices,
        indices,
        has_uv: true,
        ..Default::default()
    }
}

fn prepared(rings: u32, segments: u32) -> (Mesh, Clusters) {
    let mut scene = Scene::from_meshes("s", vec![sphere(rings, segments)], vec![]);
    let c = prepare(&mut scene)
        .remove(0)
        .expect("large enough for clusters");
    (scene.meshes.remove(0), c)
}

/// The triangles a view draws, culling aside: per group its chosen level or its clusters.
fn chosen(m: &Mesh, c: &Clusters, px: &Pixels) -> (Vec<u32>, usize) {
    let all: Vec<u32> = [&m.indices[..], &c.lod.indices].concat();
    let (mut out, mut coarse) = (Vec::new(), 0);
    for g in &c.lod.groups {
        let (first, count) = match c.lod.choose(g, px) {
            Some(l) => {
                coarse += 1;
                (l.part.first, l.part.count)
            }
            None => {
                let k = &c.list[g.clusters[0] as usize..g.clusters[1] as usize];
                (k[0].first, k.iter().map(|k| k.count).sum())
            }
        };
        out.extend_from_slice(&all[first as usize * 3..(first + count) as usize * 3]);
    }
    (out, coarse)
}

/// Groups at different levels still close the sphere: no cracks, no lost group, from a
/// close perspective view (near groups fine, far ones coarse) and an orthographic one.
#[test]
fn mixed_levels_leave_no_cracks() {
    let (m, c) = prepared(160, 320);
    assert!(!c.lod.levels.is_empty());
    assert!(c.lod.fits(m.indices.len() as u64 / 3, c.list.len()));
    let persp = Mat4::perspective_rh_gl(0.8, 1.0, 0.05, 10.0)
        * Mat4::look_at_rh(Vec3::new(0.0, 0.3, 1.6), Vec3::ZERO, Vec3::Y);
    let ortho = Mat4::orthographic_rh_gl(-1.2, 1.2, -1.2, 1.2, 0.1, 10.0)
        * Mat4::look_at_rh(Vec3::new(0.0, 0.0, 3.0), Vec3::ZERO, Vec3::Y);
    for (vp, size, bound) in [(persp, 4000, 1.0), (persp, 2000, 0.5), (ortho, 100, 1.0)] {
        let px = Pixels::new(vp, size, size, bound);
        let (tris, coarse) = chosen(&m, &c, &px);
        assert!(
            coarse > 0 && coarse < c.lod.groups.len() || size == 100,
            "{coarse} of {} groups coarse: not a mix",
            c.lod.groups.len()
        );
        // Closure counts a vertex no triangle uses as a piece of its own: keep the used.
        let mut used: Vec<u32> = tris.clone();
        used.sort_unstable();
        used.dedup();
        let vertices: Vec<Vertex> = used.iter().map(|&i| m.vertices[i as usize]).collect();
        let tris: Vec<u32> = tris
            .iter()
            .map(|i| used.binary_search(i).unwrap() as u32)
            .collect();
        let closed = closure(&vertices, &tris);
        assert!(closed.is_closed(), "{closed:?} at {size} px, bound {bound}");
        assert!(tris.len() < m.indices.len());
    }
}

/// Error 0 (or below) turns level of detail off: the view is the plain one.
#[test]
fn error_zero_is_every_triangle() {
    let (m, c) = prepared(100, 200);
    let vp = Mat4::perspective_rh_gl(0.8, 1.0, 0.1, 10.0)
        * Mat4::look_at_rh(Vec3::new(0.0, 0.0, 3.0), Vec3::ZERO, Vec3::Y);
    let plain = ClusterView::new(vp);
    let zero = plain.with_lod(vp, 64, 64, 0.0);
    assert!(zero.lod.is_none());
    let (mut a, mut b) = (Vec::new(), Vec::new());
    assert_eq!(
        c.visible(&plain, true, &mut a),
        c.visible(&zero, true, &mut b)
    );
    assert_eq!(a, b);
    // And a level is only chosen when its error, seen from the view, is within the bound.
    let px = Pixels::new(vp, 64, 64, 1.0);
    for g in &c.lod.groups {
        if let Some(l) = c.lod.choose(g, &px) {
            assert!(l.error * px.per_unit(g.bound.center, g.bound.radius) <= 1.0);
        }
    }
    assert!(m.indices.len() / 3 >= crate::lod::clusters::MIN_TRIANGLES);
}
