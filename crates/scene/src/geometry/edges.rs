//! The edges drawn over a model (`--edges`, `--wireframe`), as line segments between welded
//! corners; no GL, shared by the GPU's edges pass and the CPU reference.
//!
//! Corners are welded by exact position first: a loader splits a vertex wherever normals or
//! UVs differ (a cube has 24 vertices, 8 corners), and an edge is a pair of corners, not of
//! vertices. Feature edges are the boundary edges (one face), non-manifold ones (more than
//! two) and those whose two faces' normals differ by more than the crease angle, the same
//! angle the loader keeps sharp in generated normals (`--crease`, default 60°): so the edges
//! drawn are where the shading shows a crease. Wireframe is every triangle edge once.
use crate::model::Mesh;
use glam::DVec3;
use std::collections::HashMap;

/// Which edges of a mesh.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum EdgeSet {
    /// Boundary, non-manifold and creased edges (faces' normals more than this many degrees
    /// apart).
    Feature { crease_deg: f32 },
    /// Every triangle edge.
    All,
}

/// Line segments over a mesh's welded corners.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct EdgeLines {
    pub positions: Vec<[f32; 3]>,
    /// Pairs of indices into `positions`, each edge once, in a fixed order.
    pub segments: Vec<[u32; 2]>,
}

/// The edges of `mesh` in `set`.
pub fn extract(mesh: &Mesh, set: EdgeSet) -> EdgeLines {
    let (_, positions, segments) = classify(mesh, set);
    compact(positions, segments)
}

/// Per triangle, which of its edges are in `set` (bit k: the edge opposite corner k), for
/// the barycentric method (`--edge-method barycentric`), which draws on the triangles; and
/// how many edges are in `set` (what [`extract`] would give as segments, without a second
/// weld).
pub fn triangle_masks(mesh: &Mesh, set: EdgeSet) -> (Vec<u8>, usize) {
    let (weld, _, segments) = classify(mesh, set);
    let n = segments.len();
    let kept: std::collections::HashSet<[u32; 2]> = segments.into_iter().collect();
    let masks = mesh
        .indices
        .chunks_exact(3)
        .map(|t| {
            let c = [t[0], t[1], t[2]].map(|i| weld.get(i as usize).copied().unwrap_or(0));
            (0..3).fold(0u8, |m, k| {
                let (a, b) = (c[(k + 1) % 3], c[(k + 2) % 3]);
                if kept.contains(&[a.min(b), a.max(b)]) {
                    m | 1 << k
                } else {
                    m
                }
            })
        })
        .collect();
    (masks, n)
}

/// A mesh's edges over welded corners: the corner of each vertex, the corners' positions,
/// every triangle's normal (unnormalised) and its edges as (low corner, high corner, face),
/// sorted so an edge's faces are adjacent: deterministic, and no hash map of edges.
struct Welded {
    weld: Vec<u32>,
    positions: Vec<[f32; 3]>,
    normals: Vec<DVec3>,
    half: Vec<(u32, u32, u32)>,
}

fn weld(mesh: &Mesh) -> Welded {
    let mut corner_of: HashMap<[u32; 3], u32> = HashMap::new();
    let mut positions: Vec<[f32; 3]> = Vec::new();
    let weld: Vec<u32> = mesh
        .vertices
        .iter()
        .map(|v| {
            // -0.0 and 0.0 are one corner.
            let key = v.position.map(|x| (x + 0.0).to_bits());
            *corner_of.entry(key).or_insert_with(|| {
                positions.push(v.position);
                (positions.len() - 1) as u32
            })
        })
        .collect();
    let p = |c: u32| DVec3::from(positions[c as usize].map(f64::from));
    let mut half: Vec<(u32, u32, u32)> = Vec::with_capacity(mesh.indices.len());
    let mut normals: Vec<DVec3> = Vec::with_capacity(mesh.indices.len() / 3);
    for (f, t) in mesh.indices.chunks_exact(3).enumerate() {
        let c = [t[0], t[1], t[2]].map(|i| weld.get(i as usize).copied().unwrap_or(0));
        normals.push((p(c[1]) - p(c[0])).cross(p(c[2]) - p(c[0])));
        for (a, b) in [(c[0], c[1]), (c[1], c[2]), (c[2], c[0])] {
            if a != b {
                half.push((a.min(b), a.max(b), f as u32));
            }
        }
    }
    half.sort_unstable();
    Welded {
        weld,
        positions,
        normals,
        half,
    }
}

/// What an edge is, from its faces (one run of [`Welded::half`]).
#[derive(Clone, Copy, PartialEq, Eq)]
enum Kind {
    Boundary,
    NonManifold,
    Creased,
    Smooth,
}

fn kind(w: &Welded, run: &[(u32, u32, u32)], cos_crease: f64) -> Kind {
    match run {
        [_] => Kind::Boundary,
        [x, y] => {
            let (n1, n2) = (w.normals[x.2 as usize], w.normals[y.2 as usize]);
            let len = n1.length() * n2.length();
            // A degenerate face has no normal: its edges show no crease.
            if len > 0.0 && n1.dot(n2) < cos_crease * len {
                Kind::Creased
            } else {
                Kind::Smooth
            }
        }
        _ => Kind::NonManifold,
    }
}

/// Welded corner per vertex, the corners' positions, and the kept edges (low, high corner).
#[allow(clippy::type_complexity)]
fn classify(mesh: &Mesh, set: EdgeSet) -> (Vec<u32>, Vec<[f32; 3]>, Vec<[u32; 2]>) {
    let w = weld(mesh);
    let cos_crease = match set {
        EdgeSet::Feature { crease_deg } => f64::from(crease_deg).to_radians().cos(),
        EdgeSet::All => 0.0,
    };
    let mut segments = Vec::new();
    for run in w.half.chunk_by(|x, y| (x.0, x.1) == (y.0, y.1)) {
        let keep = set == EdgeSet::All || kind(&w, run, cos_crease) != Kind::Smooth;
        if keep {
            segments.push([run[0].0, run[0].1]);
        }
    }
    (w.weld, w.positions, segments)
}

/// How many edges of a mesh are of each kind (`--check`), over welded corners.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct EdgeCounts {
    /// Every distinct triangle edge (the wireframe).
    pub(crate) total: usize,
    /// Edges of one face.
    pub(crate) boundary: usize,
    /// Edges of more than two faces.
    pub(crate) non_manifold: usize,
    /// Edges of two faces whose normals differ by more than the crease angle.
    pub(crate) creased: usize,
}

impl EdgeCounts {
    /// The feature edges `--edges` draws: boundary, non-manifold and creased.
    pub(crate) fn feature(&self) -> usize {
        self.boundary + self.non_manifold + self.creased
    }
}

impl std::ops::AddAssign for EdgeCounts {
    fn add_assign(&mut self, o: EdgeCounts) {
        self.total += o.total;
        self.boundary += o.boundary;
        self.non_manifold += o.non_manifold;
        self.creased += o.creased;
    }
}

/// The edges of `mesh` by kind, creases at `crease_deg` (the feature set's rule), in one
/// pass over its sorted edges.
pub(crate) fn count(mesh: &Mesh, crease_deg: f32) -> EdgeCounts {
    let w = weld(mesh);
    let cos_crease = f64::from(crease_deg).to_radians().cos();
    let mut c = EdgeCounts::default();
    for run in w.half.chunk_by(|x, y| (x.0, x.1) == (y.0, y.1)) {
        c.total += 1;
        match kind(&w, run, cos_crease) {
            Kind::Boundary => c.boundary += 1,
            Kind::NonManifold => c.non_manifold += 1,
            Kind::Creased => c.creased += 1,
            Kind::Smooth => {}
        }
    }
    c
}

/// Keeps only the corners the segments use, renumbered in order of first use.
fn compact(positions: Vec<[f32; 3]>, segments: Vec<[u32; 2]>) -> EdgeLines {
    let mut new_index = vec![u32::MAX; positions.len()];
    let mut kept = Vec::new();
    let segments = segments
        .into_iter()
        .map(|s| {
            s.map(|c| {
                let slot = &mut new_index[c as usize];
                if *slot == u32::MAX {
                    *slot = kept.len() as u32;
                    kept.push(positions[c as usize]);
                }
                *slot
            })
        })
        .collect();
    EdgeLines {
        positions: kept,
        segments,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::Vertex;

    /// A unit cube as a loader leaves it: 24 vertices (4 per face, split for the normals),
    /// 12 triangles.
    fn cube() -> Mesh {
        let mut vertices = Vec::new();
        let mut indices = Vec::new();
        for axis in 0..3 {
            for sign in [-1.0f32, 1.0] {
                let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
                let base = vertices.len() as u32;
                for (a, b) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
                    let mut p = [0.0f32; 3];
                    p[axis] = sign;
                    p[u] = a;
                    p[v] = b * sign;
                    let mut n = [0.0; 3];
                    n[axis] = sign;
                    vertices.push(Vertex {
                        position: p,
                        normal: n,
                        uv: [0.0; 2],
                    });
                }
                indices.extend([base, base + 1, base + 2, base, base + 2, base + 3]);
            }
        }
        Mesh {
            vertices,
            indices,
            ..Default::default()
        }
    }

    fn lengths(e: &EdgeLines) -> Vec<f32> {
        let mut l: Vec<f32> = e
            .segments
            .iter()
            .map(|s| {
                let [a, b] = s.map(|c| glam::Vec3::from(e.positions[c as usize]));
                (a - b).length()
            })
            .collect();
        l.sort_by(f32::total_cmp);
        l
    }

    #[test]
    fn counts_by_kind() {
        let mut m = cube();
        let c = count(&m, 60.0);
        assert_eq!(
            (c.total, c.boundary, c.creased, c.non_manifold),
            (18, 0, 12, 0)
        );
        assert_eq!(c.feature(), 12);
        // No lid: its four edges become boundaries, its diagonal goes.
        m.indices.truncate(30);
        let c = count(&m, 60.0);
        assert_eq!(
            (c.total, c.boundary, c.creased, c.non_manifold),
            (17, 4, 8, 0)
        );
        // Above 90° no cube edge is a crease.
        assert_eq!(count(&m, 95.0).creased, 0);
    }

    #[test]
    fn a_cube_has_twelve_feature_edges_and_eighteen_triangle_edges() {
        let m = cube();
        let f = extract(&m, EdgeSet::Feature { crease_deg: 60.0 });
        assert_eq!(f.segments.len(), 12);
        assert_eq!(f.positions.len(), 8);
        assert!(lengths(&f).iter().all(|&l| (l - 2.0).abs() < 1e-6));
        // The face diagonals are coplanar (0°): no crease below 90° keeps them.
        let all = extract(&m, EdgeSet::All);
        assert_eq!(all.segments.len(), 18);
        assert_eq!(lengths(&all).iter().filter(|&&l| l > 2.5).count(), 6);
        // A crease above the cube's 90° shows none of its edges.
        let none = extract(&m, EdgeSet::Feature { crease_deg: 95.0 });
        assert!(none.segments.is_empty());
    }

    #[test]
    fn boundary_edges_of_an_open_mesh_are_feature_edges() {
        let mut m = cube();
        // Drop the +Z face (two triangles): its four edges become the boundary; they were
        // creases anyway, so still 12, but with a 95° crease only the boundary's 4 remain.
        let keep: Vec<u32> = m
            .indices
            .chunks_exact(3)
            .filter(|t| !t.iter().all(|&i| m.vertices[i as usize].position[2] == 1.0))
            .flatten()
            .copied()
            .collect();
        m.indices = keep;
        assert_eq!(
            extract(&m, EdgeSet::Feature { crease_deg: 60.0 })
                .segments
                .len(),
            12
        );
        let boundary = extract(&m, EdgeSet::Feature { crease_deg: 95.0 });
        assert_eq!(boundary.segments.len(), 4);
        assert!(boundary.positions.iter().all(|p| p[2] == 1.0));
    }

    #[test]
    fn triangle_masks_mark_the_kept_edges() {
        let m = cube();
        // Each face's two triangles share the diagonal: the feature set leaves it out, so
        // each triangle has its two cube edges; the wireframe keeps all three.
        let (f, n) = triangle_masks(&m, EdgeSet::Feature { crease_deg: 60.0 });
        assert_eq!(f.len(), 12);
        assert!(f.iter().all(|&x| x.count_ones() == 2), "{f:?}");
        let (all, n_all) = triangle_masks(&m, EdgeSet::All);
        assert!(all.iter().all(|&x| x == 7));
        // The counts are extract's segments: the cube's 12 edges, 18 with the diagonals.
        assert_eq!((n, n_all), (12, 18));
    }

    #[test]
    fn degenerate_triangles_add_no_edges_of_zero_length() {
        let mut m = cube();
        m.indices.extend([0, 0, 1]);
        let all = extract(&m, EdgeSet::All);
        assert_eq!(all.segments.len(), 18);
        assert!(all.segments.iter().all(|s| s[0] != s[1]));
    }
}
