//! Mesh builders on top of the writer: revolved profiles, swept tubes and boxes.

use crate::generate::math::{add, cross, scale, V2, V3};
use crate::generate::path::PathPt;
use crate::generate::writer::{ObjWriter, Vert};
use std::f64::consts::TAU;

/// Revolves a profile in the (r, y) half-plane around the Y axis. Normals come from the
/// profile tangents, so they are exact for the analytic profile rather than averaged facets.
/// Profile points on the axis become one pole vertex with a triangle fan around it; a point
/// equal to the previous run's end (a crease) or to the very first point (a closed loop)
/// reuses those positions, so the shell is also closed by index, not only by position.
pub(super) fn revolve(w: &mut ObjWriter, runs: &[Vec<PathPt>], segs: usize) {
    let mut first: Option<(V2, Vec<u32>)> = None;
    let mut last: Option<(V2, Vec<u32>)> = None;
    for run in runs {
        let mut prev: Option<Vec<Vert>> = None;
        for pt in run {
            let same = |ring: &Option<(V2, Vec<u32>)>| {
                ring.as_ref()
                    .filter(|(p, _)| (p[0] - pt.p[0]).hypot(p[1] - pt.p[1]) < 1e-9)
                    .map(|(_, idx)| idx.clone())
            };
            let positions = same(&last)
                .or_else(|| same(&first))
                .unwrap_or_else(|| ring_positions(w, pt.p, segs));
            let ring = ring_normals(w, pt, &positions);
            if let Some(prev) = &prev {
                band(w, prev, &ring);
            }
            prev = Some(ring);
            if first.is_none() {
                first = Some((pt.p, positions.clone()));
            }
            last = Some((pt.p, positions));
        }
    }
}

fn ring_positions(w: &mut ObjWriter, p: V2, segs: usize) -> Vec<u32> {
    if p[0].abs() < 1e-9 {
        return vec![w.v([0.0, p[1], 0.0]); segs];
    }
    (0..segs)
        .map(|j| {
            let (s, c) = (TAU * j as f64 / segs as f64).sin_cos();
            w.v([p[0] * c, p[1], p[0] * s])
        })
        .collect()
}

fn ring_normals(w: &mut ObjWriter, pt: &PathPt, positions: &[u32]) -> Vec<Vert> {
    let n = pt.normal();
    let segs = positions.len();
    let pole = positions.iter().all(|&v| v == positions[0]);
    let pole_vn = pole.then(|| w.vn([0.0, n[1], 0.0]));
    let mut ring = Vec::with_capacity(segs);
    for (j, &v) in positions.iter().enumerate() {
        let vn = pole_vn.unwrap_or_else(|| {
            let (s, c) = (TAU * j as f64 / segs as f64).sin_cos();
            w.vn([n[0] * c, n[1], n[0] * s])
        });
        ring.push(Vert { v, vt: None, vn });
    }
    ring
}

/// Triangles between two consecutive rings; with x = r·cos θ, z = r·sin θ the order
/// (profile step, then angle step) faces outward. Pole rings collapse into a fan.
fn band(w: &mut ObjWriter, a: &[Vert], b: &[Vert]) {
    let segs = a.len();
    for j in 0..segs {
        let k = (j + 1) % segs;
        if b[j].v != b[k].v {
            w.tri(a[j], b[j], b[k]);
        }
        if a[j].v != a[k].v {
            w.tri(a[j], b[k], a[k]);
        }
    }
}

/// A cross-section frame of a swept tube: centre, unit tangent, and a unit normal ⟂ tangent.
#[derive(Clone, Copy)]
pub(super) struct Frame {
    pub(super) c: V3,
    pub(super) t: V3,
    pub(super) n: V3,
}

/// Sweeps an elliptic cross-section (half-axes `ha` along `n`, `hb` along `t × n`) along
/// the frames and caps both ends, giving a closed tube. For a cross-section kept ⟂ to a planar
/// path (or any circular one) the exact surface normal is the ellipse's own normal, which is
/// what is written here.
pub(super) fn tube(w: &mut ObjWriter, frames: &[Frame], ha: f64, hb: f64, sides: usize) {
    let mut rings = Vec::with_capacity(frames.len());
    for f in frames {
        let b = cross(f.t, f.n);
        let mut ring = Vec::with_capacity(sides);
        for j in 0..sides {
            let (s, c) = (TAU * j as f64 / sides as f64).sin_cos();
            let p = add(f.c, add(scale(f.n, ha * c), scale(b, hb * s)));
            let n = add(scale(f.n, c / ha), scale(b, s / hb));
            ring.push(Vert {
                v: w.v(p),
                vt: None,
                vn: w.vn(n),
            });
        }
        rings.push(ring);
    }
    for pair in rings.windows(2) {
        for j in 0..sides {
            let k = (j + 1) % sides;
            w.quad([pair[0][j], pair[0][k], pair[1][k], pair[1][j]]);
        }
    }
    cap(w, &frames[0], &rings[0], false);
    cap(w, &frames[frames.len() - 1], &rings[rings.len() - 1], true);
}

/// A flat fan closing a tube end. The ring runs counter-clockwise seen from +t, so the start
/// cap (facing −t) walks it backwards.
fn cap(w: &mut ObjWriter, f: &Frame, ring: &[Vert], at_end: bool) {
    let facing = if at_end { f.t } else { scale(f.t, -1.0) };
    let vn = w.vn(facing);
    let centre = Vert {
        v: w.v(f.c),
        vt: None,
        vn,
    };
    for j in 0..ring.len() {
        let a = Vert { vn, ..ring[j] };
        let b = Vert {
            vn,
            ..ring[(j + 1) % ring.len()]
        };
        if at_end {
            w.tri(centre, a, b);
        } else {
            w.tri(centre, b, a);
        }
    }
}

/// Axis-aligned box with flat faces: 4 own vertices per face (24 in all) and unit-square UVs.
pub(super) fn add_box(w: &mut ObjWriter, min: V3, max: V3) {
    let uv = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]].map(|t| w.vt(t));
    for axis in 0..3 {
        for sign in [-1.0, 1.0] {
            // (u, v, normal) must be right-handed for the corners to run counter-clockwise.
            let (u, v) = if sign > 0.0 {
                ((axis + 1) % 3, (axis + 2) % 3)
            } else {
                ((axis + 2) % 3, (axis + 1) % 3)
            };
            let mut normal = [0.0; 3];
            normal[axis] = sign;
            let vn = w.vn(normal);
            let corner = |su: usize, sv: usize| {
                let mut p = [0.0; 3];
                p[axis] = if sign > 0.0 { max[axis] } else { min[axis] };
                p[u] = [min[u], max[u]][su];
                p[v] = [min[v], max[v]][sv];
                p
            };
            let ps = [corner(0, 0), corner(1, 0), corner(1, 1), corner(0, 1)];
            let q = std::array::from_fn(|k| Vert {
                v: w.v(ps[k]),
                vt: Some(uv[k]),
                vn,
            });
            w.quad(q);
        }
    }
}
