//! Area-weighted vertex normals for meshes whose file has none (or broken ones): smooth across
//! edges flatter than the crease angle or inside one smoothing group, sharp elsewhere.
use crate::model::Vertex;
use glam::Vec3;
use std::collections::HashMap;

/// Maps keyed by positions and normals from the file: foldhash is several times faster than
/// std's SipHash here (normal generation was most of the dragon's load) and keeps a random
/// seed, so a file cannot be built to collide.
type FastMap<K, V> = HashMap<K, V, foldhash::fast::RandomState>;

fn fast_map<K, V>(capacity: usize) -> FastMap<K, V> {
    FastMap::with_capacity_and_hasher(capacity, Default::default())
}

fn key(p: [f32; 3]) -> [u32; 3] {
    // +0.0 and -0.0 are the same point.
    p.map(|x| (x + 0.0).to_bits())
}

/// Welds corners by position: an id per distinct position (+0.0 and −0.0 alike) per vertex,
/// and how many positions there are. A parallel sort of the position bits (a hash map of
/// them took twice as long on the 1M-triangle sphere's 500k vertices, on one thread).
pub(crate) fn weld(vertices: &[Vertex]) -> (Vec<u32>, usize) {
    use rayon::prelude::*;
    let mut keyed: Vec<(u128, u32)> = vertices
        .par_iter()
        .enumerate()
        .map(|(i, v)| {
            let [x, y, z] = key(v.position);
            let bits = (u128::from(x) << 64) | (u128::from(y) << 32) | u128::from(z);
            (bits, i as u32)
        })
        .collect();
    keyed.par_sort_unstable();
    let mut weld = vec![0u32; vertices.len()];
    let mut ids = 0usize;
    for (k, &(bits, i)) in keyed.iter().enumerate() {
        if k == 0 || bits != keyed[k - 1].0 {
            ids += 1;
        }
        weld[i as usize] = ids as u32 - 1;
    }
    (weld, ids)
}

/// Face normals weighted by area (the un-normalised cross product), summed per position, so
/// vertices split by UV seams still share one normal. Returns the unit normal per position
/// key; a position touched only by zero-area faces gets +Y rather than NaN.
fn smooth_normals(vertices: &[Vertex], indices: &[u32]) -> FastMap<[u32; 3], Vec3> {
    let mut acc: FastMap<[u32; 3], glam::DVec3> = fast_map(vertices.len());
    for t in indices.chunks_exact(3) {
        let t = [t[0], t[1], t[2]];
        let p: [glam::DVec3; 3] =
            std::array::from_fn(|k| Vec3::from(vertices[t[k] as usize].position).as_dvec3());
        let n = (p[1] - p[0]).cross(p[2] - p[0]);
        for i in t {
            *acc.entry(key(vertices[i as usize].position)).or_default() += n;
        }
    }
    acc.into_iter()
        .map(|(k, n)| {
            let n = n.normalize_or_zero().as_vec3();
            (k, if n == Vec3::ZERO { Vec3::Y } else { n })
        })
        .collect()
}

/// In f64: a normal like (0, 0, 1e20) is finite in f32 but squares to infinity there.
fn usable(n: [f32; 3]) -> bool {
    let v = Vec3::from(n).as_dvec3();
    v.is_finite() && v.length_squared() > 1e-20
}

/// Fills in normals that are missing (`all`), zero or not finite; normalises the rest.
/// Returns how many normals were generated.
pub(crate) fn repair_normals(vertices: &mut [Vertex], indices: &[u32], all: bool) -> usize {
    let _timer = crate::profile::nested(crate::profile::Stage::Normals);
    let need = all || vertices.iter().any(|v| !usable(v.normal));
    let smooth = if need {
        smooth_normals(vertices, indices)
    } else {
        fast_map(0)
    };
    let mut generated = 0;
    for v in vertices.iter_mut() {
        if all || !usable(v.normal) {
            v.normal = smooth
                .get(&key(v.position))
                .copied()
                .unwrap_or(Vec3::Y)
                .into();
            generated += 1;
        } else {
            v.normal = Vec3::from(v.normal).as_dvec3().normalize().as_vec3().into();
        }
    }
    generated
}

/// How generated normals treat edges.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Creases {
    /// Smooth across edges whose faces differ by at most this many degrees.
    Angle(f32),
    /// One normal per face.
    Flat,
}

/// The default crease angle (README, Loading: chosen on the shared models).
pub const DEFAULT_CREASE_DEG: f32 = 60.0;

impl Default for Creases {
    fn default() -> Self {
        Creases::Angle(DEFAULT_CREASE_DEG)
    }
}

/// Generates every normal of a mesh. A corner's normal sums the area-weighted normals of the
/// faces around its position that may be smoothed with its own face: with smoothing `groups`
/// (one per triangle, from `s N`; 0 = off), those in the same non-zero group; without, those
/// within the crease angle. Vertices are split where corners sharing one get different
/// normals. Returns the new vertices, the new indices and, per new vertex, its old index.
pub(crate) fn generate(
    vertices: &[Vertex],
    indices: &[u32],
    groups: Option<&[u32]>,
    creases: Creases,
) -> (Vec<Vertex>, Vec<u32>, Vec<u32>) {
    let _timer = crate::profile::nested(crate::profile::Stage::Normals);
    let tris: Vec<[u32; 3]> = indices
        .chunks_exact(3)
        .map(|t| [t[0], t[1], t[2]])
        .collect();
    let face: Vec<glam::DVec3> = tris
        .iter()
        .map(|t| {
            let p: [glam::DVec3; 3] =
                std::array::from_fn(|k| Vec3::from(vertices[t[k] as usize].position).as_dvec3());
            (p[1] - p[0]).cross(p[2] - p[0])
        })
        .collect();
    let unit: Vec<glam::DVec3> = face.iter().map(|n| n.normalize_or_zero()).collect();
    // The faces around each position, in face order, each face once (even where it is
    // degenerate there): positions numbered, then a counting sort of (position, face).
    let (pos, positions) = weld(vertices);
    let corners = |t: &[u32; 3]| -> [Option<u32>; 3] {
        let p = t.map(|i| pos[i as usize]);
        [
            Some(p[0]),
            (p[1] != p[0]).then_some(p[1]),
            (p[2] != p[0] && p[2] != p[1]).then_some(p[2]),
        ]
    };
    let (start, faces) = crate::geometry::buckets::group(
        positions,
        tris.iter().enumerate().flat_map(|(f, t)| {
            corners(t)
                .into_iter()
                .flatten()
                .map(move |p| (p as usize, f as u32))
        }),
    );
    let around = |p: u32| &faces[start[p as usize]..start[p as usize + 1]];
    let cos = match creases {
        // 180° joins everything, also exactly opposite faces whose dot rounds below -1.
        Creases::Angle(deg) if deg >= 180.0 => -2.0,
        Creases::Angle(deg) => f64::from(deg).to_radians().cos(),
        Creases::Flat => 2.0,
    };
    let groups = groups.filter(|g| g.len() == tris.len());
    let mut out = Vec::with_capacity(vertices.len());
    let mut old = Vec::with_capacity(vertices.len());
    let mut out_idx = Vec::with_capacity(indices.len());
    // The first copy of each vertex made (u32::MAX: none yet); further copies with other
    // normals (a crease through the vertex) are found in `more`.
    let mut first = vec![u32::MAX; vertices.len()];
    let mut more: FastMap<(u32, [u32; 3]), u32> = fast_map(0);
    // Which faces join a corner depends only on the position, the face's unit normal and its
    // group. Around a busy position (a file repeating one triangle 2,000,000 times shares one
    // position among 2,000,000 faces: k² took hours) corners alike share one memoised sum;
    // around an ordinary one the sum is cheaper than the lookup (the table's cache misses
    // were most of the dragon's normal generation).
    let mut memo: FastMap<(u32, [u64; 3], u32), Vec3> = fast_map(0);
    const BUSY: usize = 32;
    for (f, t) in tris.iter().enumerate() {
        for &i in t {
            let v = vertices[i as usize];
            let p = pos[i as usize];
            let sum = || {
                let mut n = glam::DVec3::ZERO;
                for &g in around(p) {
                    let g = g as usize;
                    let joins = g == f
                        || unit[f] == glam::DVec3::ZERO
                        || match groups {
                            Some(s) => creases != Creases::Flat && s[f] != 0 && s[g] == s[f],
                            None => unit[f].dot(unit[g]) >= cos,
                        };
                    if joins {
                        n += face[g];
                    }
                }
                n.normalize_or_zero().as_vec3()
            };
            let n = if around(p).len() <= BUSY {
                sum()
            } else {
                let group = groups.map_or(0, |s| s[f]);
                let key = (p, unit[f].to_array().map(|x| (x + 0.0).to_bits()), group);
                *memo.entry(key).or_insert_with(sum)
            };
            let n = if n == Vec3::ZERO { Vec3::Y } else { n };
            let bits = key(n.to_array());
            let add = |out: &mut Vec<Vertex>, old: &mut Vec<u32>| {
                out.push(Vertex {
                    normal: n.into(),
                    ..v
                });
                old.push(i);
                out.len() as u32 - 1
            };
            let made = first[i as usize];
            let idx = if made == u32::MAX {
                let idx = add(&mut out, &mut old);
                first[i as usize] = idx;
                idx
            } else if key(out[made as usize].normal) == bits {
                made
            } else {
                *more
                    .entry((i, bits))
                    .or_insert_with(|| add(&mut out, &mut old))
            };
            out_idx.push(idx);
        }
    }
    (out, out_idx, old)
}

impl crate::model::Mesh {
    /// Normals for a freshly loaded mesh, the same for every format: where the file gave
    /// them, broken ones are regenerated; where it did not, they are generated with the crease
    /// rule (and smoothing `groups`, one per triangle), splitting vertices (colours follow).
    pub(crate) fn finish_normals(
        &mut self,
        file_has_normals: bool,
        groups: Option<&[u32]>,
        creases: Creases,
    ) {
        if file_has_normals {
            self.generated_normals = repair_normals(&mut self.vertices, &self.indices, false);
        } else {
            let (v, i, old) = generate(&self.vertices, &self.indices, groups, creases);
            // Streams beside the vertices follow the vertices they were read with.
            if !self.colors.is_empty() {
                self.colors = old.iter().map(|&o| self.colors[o as usize]).collect();
            }
            if !self.color_alpha.is_empty() {
                self.color_alpha = old.iter().map(|&o| self.color_alpha[o as usize]).collect();
            }
            if !self.uv1.is_empty() {
                self.uv1 = old.iter().map(|&o| self.uv1[o as usize]).collect();
            }
            if !self.tangents.is_empty() {
                self.tangents = old.iter().map(|&o| self.tangents[o as usize]).collect();
            }
            self.vertices = v;
            self.indices = i;
            self.generated_normals = self.vertices.len();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn vtx(p: [f32; 3], n: [f32; 3]) -> Vertex {
        Vertex {
            position: p,
            normal: n,
            uv: [0.0; 2],
        }
    }

    #[test]
    fn flat_quad_gets_plus_z() {
        let mut v = vec![
            vtx([0., 0., 0.], [0.; 3]),
            vtx([1., 0., 0.], [0.; 3]),
            vtx([1., 1., 0.], [0.; 3]),
            vtx([0., 1., 0.], [0.; 3]),
        ];
        assert_eq!(repair_normals(&mut v, &[0, 1, 2, 0, 2, 3], true), 4);
        for x in &v {
            assert_eq!(x.normal, [0., 0., 1.]);
        }
    }

    #[test]
    fn area_weighting() {
        // A big triangle facing +Z and a tiny one facing +X share vertex 0.
        let mut v = vec![
            vtx([0., 0., 0.], [0.; 3]),
            vtx([10., 0., 0.], [0.; 3]),
            vtx([0., 10., 0.], [0.; 3]),
            vtx([0., 0.1, 0.], [0.; 3]),
            vtx([0., 0., -0.1], [0.; 3]),
        ];
        repair_normals(&mut v, &[0, 1, 2, 0, 3, 4], true);
        let n = Vec3::from(v[0].normal);
        // The big face dominates; the tiny one (facing -X) only tilts it slightly.
        assert!(n.z > 0.99 && n.x < 0.0 && n.x > -0.01, "{n}");
    }

    #[test]
    fn only_broken_normals_replaced() {
        let mut v = vec![
            vtx([0., 0., 0.], [0., 0., 2.]),
            vtx([1., 0., 0.], [f32::NAN, 0., 0.]),
            vtx([0., 1., 0.], [0., 0., 0.]),
        ];
        assert_eq!(repair_normals(&mut v, &[0, 1, 2], false), 2);
        assert_eq!(v[0].normal, [0., 0., 1.]);
        assert_eq!(v[1].normal, [0., 0., 1.]);
    }

    #[test]
    fn huge_normals_normalise() {
        let mut v = vec![
            vtx([0., 0., 0.], [0., 0., 1e20]),
            vtx([1., 0., 0.], [0., 0., 1e20]),
            vtx([0., 1., 0.], [3e38, 0., 0.]),
        ];
        assert_eq!(repair_normals(&mut v, &[0, 1, 2], false), 0);
        assert_eq!(v[0].normal, [0., 0., 1.]);
        assert_eq!(v[2].normal, [1., 0., 0.]);
    }

    fn cube() -> (Vec<Vertex>, Vec<u32>) {
        let v: Vec<Vertex> = (0..8)
            .map(|i| {
                let c = |b| if i & b != 0 { 1.0 } else { 0.0 };
                vtx([c(1), c(2), c(4)], [0.; 3])
            })
            .collect();
        let quads = [
            [0, 2, 3, 1],
            [4, 5, 7, 6],
            [0, 1, 5, 4],
            [2, 6, 7, 3],
            [0, 4, 6, 2],
            [1, 3, 7, 5],
        ];
        let idx = quads
            .iter()
            .flat_map(|q| [q[0], q[1], q[2], q[0], q[2], q[3]])
            .collect();
        (v, idx)
    }

    #[test]
    fn cube_corners_get_three_flat_normals() {
        let (v, i) = cube();
        let (out, idx, old) = generate(&v, &i, None, Creases::default());
        assert_eq!(out.len(), 24);
        assert_eq!(idx.len(), 36);
        for corner in 0..8u32 {
            let ns: Vec<[f32; 3]> = out
                .iter()
                .zip(&old)
                .filter(|(_, &o)| o == corner)
                .map(|(v, _)| v.normal)
                .collect();
            assert_eq!(ns.len(), 3);
            for n in ns {
                assert_eq!(n.iter().filter(|x| x.abs() == 1.0).count(), 1, "{n:?}");
            }
        }
        // one smoothing group overrides the angle: 8 smooth corners
        let g = vec![1; 12];
        let (out, _, old) = generate(&v, &i, Some(&g), Creases::default());
        assert_eq!(out.len(), 8);
        let seven = old.iter().position(|&o| o == 7).unwrap();
        let n = Vec3::from(out[seven].normal);
        assert!((n - Vec3::ONE.normalize()).length() < 1e-6, "{n}");
        // s off: flat
        let g = vec![0; 12];
        assert_eq!(generate(&v, &i, Some(&g), Creases::default()).0.len(), 24);
    }

    #[test]
    fn sphere_stays_smooth() {
        let (seg, rings) = (32u32, 16u32);
        let mut v = Vec::new();
        for r in 0..=rings {
            for s in 0..seg {
                let th = std::f32::consts::PI * r as f32 / rings as f32;
                let ph = std::f32::consts::TAU * s as f32 / seg as f32;
                // exact poles: sin(π) is not 0 in f32
                let st = if r == rings { 0.0 } else { th.sin() };
                let p = [st * ph.cos(), th.cos(), st * ph.sin()];
                v.push(vtx(p, [0.; 3]));
            }
        }
        let mut idx = Vec::new();
        for r in 0..rings {
            for s in 0..seg {
                let a = r * seg + s;
                let b = r * seg + (s + 1) % seg;
                let (c, d) = (a + seg, b + seg);
                idx.extend([a, b, c, b, d, c]);
            }
        }
        let (out, _, _) = generate(&v, &idx, None, Creases::default());
        // no vertex is split (the poles are one position repeated; they stay as they are)
        assert_eq!(out.len(), v.len());
        for w in &out[seg as usize..(rings * seg) as usize] {
            let n = Vec3::from(w.normal);
            let p = Vec3::from(w.position).normalize();
            assert!(n.dot(p) > 0.995, "{n} at {p}");
        }
        assert!(generate(&v, &idx, None, Creases::Flat).0.len() > 3 * v.len());
    }

    #[test]
    fn zero_area_gives_finite_normal() {
        let mut v = vec![
            vtx([0., 0., 0.], [0.; 3]),
            vtx([1., 0., 0.], [0.; 3]),
            vtx([2., 0., 0.], [0.; 3]),
        ];
        repair_normals(&mut v, &[0, 1, 2], true);
        assert!(v.iter().all(|x| Vec3::from(x.normal).is_finite()));
    }
}
