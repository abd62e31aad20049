//! Whether a mesh is a closed surface facing outwards, so that from outside it a ray meets a
//! front face first and cluster culling may skip the clusters facing away — and when not, why.
//!
//! Exporters rarely write a closed mesh with exactly shared corners: a UV sphere's seam column
//! is written twice (sin 2π is −2.4e-16, not 0), pole rows repeat the pole once per segment
//! with degenerate triangles, and triangle strips are joined by zero-area triangles. Corners
//! are therefore welded by exact position first, and the corners still left on an open edge
//! are then welded to each other within a tolerance relative to the model's size. No GL here.
use crate::model::Vertex;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

/// Corners closer than this fraction of the mesh's bounding-box diagonal (per axis) are one
/// corner for the closedness decision: ~8 float ulps of a model's extent, far below a pixel
/// at any zoom that frames it, far above the rounding of a seam written by an exporter.
pub(crate) const WELD_TOLERANCE: f32 = 1.0 / (1 << 20) as f32;

/// What [`closure`] found.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum Closure {
    /// Every edge is run once each way and each connected piece encloses a positive volume.
    Closed,
    /// Fewer than four triangles cannot enclose anything.
    #[default]
    TooSmall,
    /// Some edge is not matched by exactly one edge running the other way (a hole, a
    /// boundary, an edge shared by three faces, or two neighbours wound oppositely), at this
    /// many corners (after welding).
    OpenEdges(usize),
    /// Closed, but some connected piece encloses a negative volume (its faces point inwards).
    InvertedPiece,
}

impl Closure {
    pub(crate) fn is_closed(self) -> bool {
        self == Closure::Closed
    }

    /// Why back faces of the mesh must be drawn, for `--stats` and `--check`.
    pub fn reason(self) -> String {
        match self {
            Closure::Closed => "closed, faces outwards".into(),
            Closure::TooSmall => "fewer than 4 triangles".into(),
            Closure::OpenEdges(n) => {
                format!("open edges at {n} corners (holes, boundaries or non-manifold edges)")
            }
            Closure::InvertedPiece => "a closed piece faces inwards (negative volume)".into(),
        }
    }
}

/// Pairing is tested per corner as a multiset: each corner sums a 64-bit hash of its outgoing
/// edges and subtracts that of its incoming ones (reversed), which is zero exactly when every
/// edge leaving it comes back (w.h.p.). A degenerate triangle (two corners welded together)
/// runs its edges both ways and cancels itself; a face and its reverse both kept pair up too
/// (they tie in depth, and the front one is the one drawn).
pub(crate) fn closure(vertices: &[Vertex], indices: &[u32]) -> Closure {
    if indices.len() < 12 {
        return Closure::TooSmall;
    }
    let (mut weld, mut ids) = crate::geometry::normals::weld(vertices);
    let mut open = imbalance(&weld, ids, indices);
    if open.iter().any(|&h| h != 0) {
        (weld, ids) = weld_open_corners(vertices, &weld, ids, &open);
        open = imbalance(&weld, ids, indices);
        let corners = open.iter().filter(|&&h| h != 0).count();
        if corners > 0 {
            return Closure::OpenEdges(corners);
        }
    }
    if pieces_face_outwards(vertices, indices, &weld, ids) {
        Closure::Closed
    } else {
        Closure::InvertedPiece
    }
}

/// Per welded corner: hashes of outgoing edges minus hashes of incoming edges reversed.
fn imbalance(weld: &[u32], ids: usize, indices: &[u32]) -> Vec<u64> {
    let mut acc = vec![0u64; ids];
    for t in indices.chunks_exact(3) {
        let w = [
            weld[t[0] as usize],
            weld[t[1] as usize],
            weld[t[2] as usize],
        ];
        for k in 0..3 {
            let (x, y) = (w[k], w[(k + 1) % 3]);
            acc[x as usize] = acc[x as usize].wrapping_add(edge_hash(x, y));
            acc[y as usize] = acc[y as usize].wrapping_sub(edge_hash(y, x));
        }
    }
    acc
}

/// Welds the corners with unpaired edges (`open[id] != 0`) to each other when within
/// [`WELD_TOLERANCE`] of the bounding-box diagonal: a hash grid of that cell size, each corner
/// compared with those of its 27 neighbouring cells. Only open corners take part, so a closed
/// mesh welded exactly pays nothing and a seamed one pays for its seam.
fn weld_open_corners(
    vertices: &[Vertex],
    weld: &[u32],
    ids: usize,
    open: &[u64],
) -> (Vec<u32>, usize) {
    let (lo, hi) = vertices
        .par_iter()
        .map(|v| (v.position, v.position))
        .reduce(
            || ([f32::MAX; 3], [f32::MIN; 3]),
            |a, b| {
                (
                    std::array::from_fn(|k| a.0[k].min(b.0[k])),
                    std::array::from_fn(|k| a.1[k].max(b.1[k])),
                )
            },
        );
    let diagonal = glam::Vec3::from(hi).distance(glam::Vec3::from(lo));
    let tol = diagonal * WELD_TOLERANCE;
    if !(tol > 0.0 && tol.is_finite()) {
        return (weld.to_vec(), ids);
    }
    let mut at = vec![[0.0f32; 3]; ids];
    for (v, &w) in vertices.iter().zip(weld) {
        at[w as usize] = v.position;
    }
    let cell = |p: [f32; 3]| p.map(|x| (x / tol).floor() as i64);
    let mut grid: std::collections::HashMap<[i64; 3], Vec<u32>, foldhash::fast::RandomState> =
        Default::default();
    for id in (0..ids).filter(|&id| open[id] != 0) {
        grid.entry(cell(at[id])).or_default().push(id as u32);
    }
    let mut parent: Vec<u32> = (0..ids as u32).collect();
    for (c, members) in &grid {
        for d in 0..27i64 {
            let n = [c[0] + d % 3 - 1, c[1] + d / 3 % 3 - 1, c[2] + d / 9 - 1];
            let Some(others) = grid.get(&n) else { continue };
            for &a in members {
                for &b in others {
                    let near = (0..3).all(|k| (at[a as usize][k] - at[b as usize][k]).abs() <= tol);
                    if a < b && near {
                        let (ra, rb) = (root(&mut parent, a), root(&mut parent, b));
                        if ra != rb {
                            parent[ra.max(rb) as usize] = ra.min(rb);
                        }
                    }
                }
            }
        }
    }
    // Renumber densely so later passes can index by id.
    let mut new_id = vec![u32::MAX; ids];
    let mut count = 0u32;
    for id in 0..ids as u32 {
        let r = root(&mut parent, id) as usize;
        if new_id[r] == u32::MAX {
            new_id[r] = count;
            count += 1;
        }
        new_id[id as usize] = new_id[r];
    }
    (
        weld.iter().map(|&w| new_id[w as usize]).collect(),
        count as usize,
    )
}

fn root(parent: &mut [u32], mut x: u32) -> u32 {
    while parent[x as usize] != x {
        let up = parent[parent[x as usize] as usize];
        parent[x as usize] = up;
        x = up;
    }
    x
}

/// Connected pieces (union-find over welded corners), and whether each encloses a positive
/// volume, so an inside-out part makes the whole mesh "not closed".
fn pieces_face_outwards(vertices: &[Vertex], indices: &[u32], weld: &[u32], ids: usize) -> bool {
    let mut parent: Vec<u32> = (0..ids as u32).collect();
    for t in indices.chunks_exact(3) {
        let a = root(&mut parent, weld[t[0] as usize]);
        for &i in &t[1..] {
            let b = root(&mut parent, weld[i as usize]);
            if a != b {
                parent[b as usize] = a;
            }
        }
    }
    let mut volume = vec![0.0f64; ids];
    let p = |i: u32| glam::DVec3::from(vertices[i as usize].position.map(f64::from));
    for t in indices.chunks_exact(3) {
        let r = root(&mut parent, weld[t[0] as usize]);
        volume[r as usize] += p(t[0]).dot(p(t[1]).cross(p(t[2])));
    }
    (0..ids).all(|i| parent[i] != i as u32 || volume[i] > 0.0)
}

/// A 64-bit mix of a directed edge (splitmix64's finaliser).
fn edge_hash(a: u32, b: u32) -> u64 {
    let mut z = ((u64::from(a) << 32) | u64::from(b)).wrapping_add(0x9e37_79b9_7f4a_7c15);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A UV sphere as exporters write it: a (rings + 1) × (segments + 1) grid of f64 angles
    /// rounded to f32, so the seam column is written twice (sin 2π ≠ 0) and each pole once per
    /// segment (the south one off by ulps: sin π ≠ 0), with a degenerate triangle per pole
    /// quad. Outward winding.
    pub(crate) fn exported_sphere(rings: u32, segments: u32) -> (Vec<Vertex>, Vec<u32>) {
        let mut v = Vec::new();
        for j in 0..=rings {
            let th = std::f64::consts::PI * f64::from(j) / f64::from(rings);
            for i in 0..=segments {
                let ph = std::f64::consts::TAU * f64::from(i) / f64::from(segments);
                let p = [th.sin() * ph.sin(), th.cos(), th.sin() * ph.cos()];
                v.push(Vertex {
                    position: p.map(|x| x as f32),
                    ..Default::default()
                });
            }
        }
        let at = |j: u32, i: u32| j * (segments + 1) + i;
        let mut idx = Vec::new();
        for j in 0..rings {
            for i in 0..segments {
                idx.extend([at(j, i), at(j + 1, i), at(j + 1, i + 1)]);
                idx.extend([at(j, i), at(j + 1, i + 1), at(j, i + 1)]);
            }
        }
        (v, idx)
    }

    #[test]
    fn an_exported_sphere_with_an_ulp_seam_and_repeated_poles_is_closed() {
        let (v, idx) = exported_sphere(40, 64);
        let seam = |j: u32| {
            (
                v[(j * 65) as usize].position,
                v[(j * 65 + 64) as usize].position,
            )
        };
        assert!(
            (1..40).any(|j| seam(j).0 != seam(j).1),
            "the seam differs by ulps, as written by exporters"
        );
        let (_, exact_ids) = crate::geometry::normals::weld(&v);
        let exact = imbalance(&crate::geometry::normals::weld(&v).0, exact_ids, &idx);
        assert!(exact.iter().any(|&h| h != 0), "not closed by exact welding");
        assert_eq!(closure(&v, &idx), Closure::Closed);
        let flipped: Vec<u32> = idx
            .chunks_exact(3)
            .flat_map(|t| [t[0], t[2], t[1]])
            .collect();
        assert_eq!(closure(&v, &flipped), Closure::InvertedPiece);
        // A quad missing in the middle band: a hole.
        let mut holed = idx.clone();
        holed.drain(20 * 64 * 6..20 * 64 * 6 + 6);
        assert_eq!(closure(&v, &holed), Closure::OpenEdges(4));
        assert_eq!(closure(&v, &idx[..9]), Closure::TooSmall);
    }

    #[test]
    fn degenerate_strip_joins_change_nothing_and_a_visible_gap_stays_open() {
        let (v, mut idx) = exported_sphere(24, 32);
        // Strip joins: triangles repeating a corner, as strips converted to lists carry.
        idx.extend([5, 5, 40, 40, 41, 41, 100, 100, 100]);
        assert_eq!(closure(&v, &idx), Closure::Closed);
        // The seam column moved by 1e-4 of the radius: a real crack, not rounding.
        let mut cracked = v.clone();
        for j in 1..24 {
            cracked[(j * 33 + 32) as usize].position[0] += 1e-4;
        }
        assert!(matches!(closure(&cracked, &idx), Closure::OpenEdges(n) if n >= 2 * 23));
    }
}
