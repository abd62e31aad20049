//! Test scenes: a unit sphere, a box above or on a floor, and a textured quad.

use crate::generate::shapes::add_box;
use crate::generate::writer::{mtl, Material, ObjWriter, Vert};
use crate::generate::GeneratedModel;
use std::f64::consts::{PI, TAU};

pub(super) fn sphere() -> GeneratedModel {
    const AROUND: usize = 192;
    const RINGS: usize = 96;
    let mut w = ObjWriter::new("sphere");
    w.object("sphere", "sphere");
    // Rings run south (i = 0) to north (i = RINGS); rings 0 and RINGS are single poles.
    let mut ring_v = Vec::with_capacity(RINGS + 1);
    for i in 0..=RINGS {
        let (sin_p, cos_p) = (PI * i as f64 / RINGS as f64).sin_cos();
        let count = if i == 0 || i == RINGS { 1 } else { AROUND };
        let ring: Vec<(u32, u32)> = (0..count)
            .map(|j| {
                // z = −r·sin θ makes u grow to the right seen from outside (no mirrored text).
                let (s, c) = (TAU * j as f64 / AROUND as f64).sin_cos();
                let p = [sin_p * c, -cos_p, -sin_p * s];
                // Radius 1: the exact normal is the position itself.
                (w.v(p), w.vn(p))
            })
            .collect();
        ring_v.push(ring);
    }
    // Pole rows get one UV per segment, centred on it, so the fans are not sheared.
    let mut ring_vt = Vec::with_capacity(RINGS + 1);
    for i in 0..=RINGS {
        let pole = i == 0 || i == RINGS;
        let v = i as f64 / RINGS as f64;
        let row: Vec<u32> = (0..=AROUND)
            .filter(|&j| !(pole && j == AROUND))
            .map(|j| w.vt([(j as f64 + if pole { 0.5 } else { 0.0 }) / AROUND as f64, v]))
            .collect();
        ring_vt.push(row);
    }
    let vert = |i: usize, j: usize| {
        let vs = &ring_v[i];
        let (v, vn) = vs[j % vs.len()];
        let vt = if vs.len() == 1 {
            ring_vt[i][j % AROUND]
        } else {
            ring_vt[i][j]
        };
        Vert {
            v,
            vt: Some(vt),
            vn,
        }
    };
    for i in 0..RINGS {
        for j in 0..AROUND {
            let (a, b) = (vert(i, j), vert(i, j + 1));
            let (c, d) = (vert(i + 1, j + 1), vert(i + 1, j));
            if i + 1 == RINGS {
                w.tri(a, b, Vert { vt: d.vt, ..c });
            } else if i == 0 {
                w.tri(a, c, d);
            } else {
                w.quad([a, b, c, d]);
            }
        }
    }
    GeneratedModel {
        name: "sphere",
        obj: w.finish(),
        mtl: mtl(&[Material::phong(
            "sphere",
            [0.2, 0.2, 0.2],
            [0.7, 0.5, 0.3],
            [0.6, 0.6, 0.6],
            40.0,
        )]),
    }
}

/// The shared floor: a 6×6 square at y = 0 as a 16×16 grid, UVs 0..1 across it.
fn floor(w: &mut ObjWriter) {
    const N: usize = 16;
    const HALF: f64 = 3.0;
    w.object("floor", "floor");
    let vn = w.vn([0.0, 1.0, 0.0]);
    let mut grid = Vec::with_capacity((N + 1) * (N + 1));
    for i in 0..=N {
        for j in 0..=N {
            let (u, s) = (j as f64 / N as f64, i as f64 / N as f64);
            let v = w.v([-HALF + 2.0 * HALF * u, 0.0, -HALF + 2.0 * HALF * s]);
            grid.push(Vert {
                v,
                vt: Some(w.vt([u, 1.0 - s])),
                vn,
            });
        }
    }
    let at = |i: usize, j: usize| grid[i * (N + 1) + j];
    for i in 0..N {
        for j in 0..N {
            // Seen from +Y, +Z then +X is counter-clockwise.
            w.quad([at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)]);
        }
    }
}

fn box_scene(name: &'static str, min_y: f64) -> GeneratedModel {
    let mut w = ObjWriter::new(name);
    floor(&mut w);
    w.object("box", "box");
    add_box(&mut w, [-0.5, min_y, -0.5], [0.5, min_y + 1.0, 0.5]);
    GeneratedModel {
        name,
        obj: w.finish(),
        mtl: mtl(&[
            Material::phong(
                "floor",
                [0.2, 0.2, 0.2],
                [0.8, 0.8, 0.8],
                [0.0, 0.0, 0.0],
                1.0,
            ),
            Material::phong(
                "box",
                [0.2, 0.2, 0.2],
                [0.8, 0.2, 0.2],
                [0.3, 0.3, 0.3],
                16.0,
            ),
        ]),
    }
}

pub(super) fn box_floor() -> GeneratedModel {
    box_scene("box_floor", 1.0)
}

pub(super) fn box_on_floor() -> GeneratedModel {
    box_scene("box_on_floor", 0.0)
}

pub(super) fn textured_quad() -> GeneratedModel {
    let mut w = ObjWriter::new("textured_quad");
    w.object("quad", "checker");
    let vn = w.vn([0.0, 0.0, 1.0]);
    let corners = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
    let q = corners.map(|uv| {
        let v = w.v([uv[0] * 2.0 - 1.0, uv[1] * 2.0 - 1.0, 0.0]);
        Vert {
            v,
            vt: Some(w.vt(uv)),
            vn,
        }
    });
    w.quad(q);
    GeneratedModel {
        name: "textured_quad",
        obj: w.finish(),
        mtl: mtl(&[Material {
            map_kd: Some("checker.png"),
            ..Material::phong(
                "checker",
                [0.2, 0.2, 0.2],
                [1.0, 1.0, 1.0],
                [0.0, 0.0, 0.0],
                1.0,
            )
        }]),
    }
}
