//! Building the levels of detail ([`super::levels::Lod`]): each group of clusters simplified
//! by meshoptimizer with its border locked, then the whole mesh's levels from the groups'
//! coarsest. Native builds only (meshoptimizer is C++): the browser build receives scenes
//! whose levels were built here (the mesh cache's entry), and without them draws every
//! triangle.
use crate::lod::clusters::{cluster, Cluster};
use crate::lod::levels::{Group, Level, Lod, GROUP, LEVELS, MIN_SAVING};
use crate::model::Vertex;
use meshopt::{SimplifyOptions, SimplifyVertex, VertexDataAdapter};
use rayon::prelude::*;

impl Lod {
    /// The levels of `clusters` (runs of `indices`, a mesh of `vertices` and optional
    /// per-vertex `colors`), simplified in parallel. Normals, UVs and colours weigh in the
    /// simplifier's error, and vertices that share a position but not those (seams: UV,
    /// crease, colour) stay seams.
    pub(crate) fn build(
        vertices: &[Vertex],
        colors: &[[f32; 3]],
        has_uv: bool,
        indices: &[u32],
        clusters: &[Cluster],
    ) -> Lod {
        let attrs = Attributes::new(vertices, colors, has_uv);
        let adapter = VertexDataAdapter::new(
            bytemuck::cast_slice(vertices),
            std::mem::size_of::<Vertex>(),
            0,
        )
        .expect("Vertex starts with its position");
        let locks = shared_corners(vertices, indices, clusters);
        let groups: Vec<(Group, Simplified)> = clusters
            .par_chunks(GROUP)
            .enumerate()
            .map(|(k, run)| {
                let first = run[0].first as usize * 3;
                let end = (run[run.len() - 1].first + run[run.len() - 1].count) as usize * 3;
                let tris = &indices[first..end];
                let levels = simplify(&adapter, &attrs, &locks, tris);
                let group = Group {
                    clusters: [(k * GROUP) as u32, (k * GROUP + run.len()) as u32],
                    bound: cluster(vertices, tris, run[0].first),
                    levels: [0, 0],
                };
                (group, levels)
            })
            .collect();
        let mut lod = Lod::default();
        let base = indices.len() as u32 / 3;
        for (mut g, levels) in groups {
            g.levels[0] = lod.levels.len() as u32;
            for (error, tris) in levels {
                let first = base + lod.indices.len() as u32 / 3;
                lod.levels.push(Level {
                    error,
                    part: cluster(vertices, &tris, first),
                });
                lod.indices.extend_from_slice(&tris);
            }
            g.levels[1] = lod.levels.len() as u32;
            lod.groups.push(g);
        }
        lod.whole_levels(&adapter, &attrs, vertices, indices);
        lod.index_count = lod.indices.len();
        lod
    }

    /// Appends the whole mesh's levels: the groups' coarsest levels (or their triangles),
    /// simplified together with only the mesh's own border locked; each level's error adds
    /// the largest of theirs.
    fn whole_levels(
        &mut self,
        adapter: &VertexDataAdapter,
        attrs: &Attributes,
        vertices: &[Vertex],
        original: &[u32],
    ) {
        let base = original.len() as u32 / 3;
        // Per group, its coarsest level within the groups' median coarsest error (its own
        // triangles when none is): the worst group (a pole's fan) would otherwise set the
        // error of every whole level.
        let mut coarsest: Vec<f32> = self
            .groups
            .iter()
            .map(|g| {
                self.levels[g.levels[0] as usize..g.levels[1] as usize]
                    .last()
                    .map_or(0.0, |l| l.error)
            })
            .collect();
        if coarsest.is_empty() {
            return;
        }
        coarsest.sort_by(f32::total_cmp);
        let tau = coarsest[coarsest.len() / 10];
        let mut start = Vec::new();
        let mut error = 0.0f32;
        for g in &self.groups {
            let levels = &self.levels[g.levels[0] as usize..g.levels[1] as usize];
            let (first, count) = match levels.iter().rev().find(|l| l.error <= tau) {
                Some(l) => {
                    error = error.max(l.error);
                    (
                        (l.part.first - base) as usize * 3,
                        l.part.count as usize * 3,
                    )
                }
                None => {
                    let first = g.bound.first as usize * 3;
                    start.extend_from_slice(&original[first..first + g.bound.count as usize * 3]);
                    continue;
                }
            };
            start.extend_from_slice(&self.indices[first..first + count]);
        }
        let locks = vec![SimplifyVertex::None; vertices.len()];
        let mut current = start;
        while current.len() / 3 > 2 * WHOLE_MIN {
            let Some((next, e)) = halve(adapter, attrs, &locks, &current) else {
                break;
            };
            error += e;
            let first = base + self.indices.len() as u32 / 3;
            self.whole.push(Level {
                error,
                part: cluster(vertices, &next, first),
            });
            self.indices.extend_from_slice(&next);
            current = next;
        }
    }
}

/// The whole mesh's coarsest level has at least this many triangles.
const WHOLE_MIN: usize = 512;

/// A group's levels as simplified: (error, triangles), finest first.
type Simplified = Vec<(f32, Vec<u32>)>;

/// Per-vertex attributes the simplifier weighs, interleaved, and their weights.
struct Attributes {
    values: Vec<f32>,
    weights: Vec<f32>,
}

impl Attributes {
    fn new(vertices: &[Vertex], colors: &[[f32; 3]], has_uv: bool) -> Attributes {
        let colors = (colors.len() == vertices.len()).then_some(colors);
        // Normals at meshoptimizer's suggested weight; UVs and colours a little less (a
        // texel's worth of UV drift is not a pixel of shape).
        let mut weights = vec![0.5; 3];
        if has_uv {
            weights.extend([0.25; 2]);
        }
        if colors.is_some() {
            weights.extend([0.25; 3]);
        }
        let mut values = Vec::with_capacity(vertices.len() * weights.len());
        for (i, v) in vertices.iter().enumerate() {
            values.extend_from_slice(&v.normal);
            if has_uv {
                values.extend_from_slice(&v.uv);
            }
            if let Some(c) = colors {
                values.extend_from_slice(&c[i]);
            }
        }
        Attributes { values, weights }
    }
}

/// Every vertex whose position is used by two groups, locked: the groups' common border.
/// meshopt's own border lock misses a border vertex that is also on a seam (it may then
/// slide along the seam, away from the neighbour: a crack), so the lock is by position.
fn shared_corners(
    vertices: &[Vertex],
    indices: &[u32],
    clusters: &[Cluster],
) -> Vec<SimplifyVertex> {
    let (weld, ids) = crate::geometry::normals::weld(vertices);
    let mut owner = vec![u32::MAX; ids];
    let mut shared = vec![false; ids];
    for (g, run) in clusters.chunks(GROUP).enumerate() {
        let first = run[0].first as usize * 3;
        let end = (run[run.len() - 1].first + run[run.len() - 1].count) as usize * 3;
        for &i in &indices[first..end] {
            let w = weld[i as usize] as usize;
            if owner[w] == u32::MAX {
                owner[w] = g as u32;
            } else if owner[w] != g as u32 {
                shared[w] = true;
            }
        }
    }
    weld.iter()
        .map(|&w| {
            if shared[w as usize] {
                SimplifyVertex::Lock
            } else {
                SimplifyVertex::None
            }
        })
        .collect()
}

/// `tris` simplified to about half its triangles, its border and `locks`' vertices kept, with
/// the simplifier's error (object units); None when that saves less than [`MIN_SAVING`].
fn halve(
    adapter: &VertexDataAdapter,
    attrs: &Attributes,
    locks: &[SimplifyVertex],
    tris: &[u32],
) -> Option<(Vec<u32>, f32)> {
    let options =
        SimplifyOptions::LockBorder | SimplifyOptions::Sparse | SimplifyOptions::ErrorAbsolute;
    let mut e = 0.0f32;
    let next = meshopt::simplify_with_attributes_and_locks(
        tris,
        adapter,
        &attrs.values,
        &attrs.weights,
        attrs.weights.len() * 4,
        locks,
        tris.len() / 6 * 3,
        f32::MAX,
        options,
        Some(&mut e),
    );
    if next.len() as f32 > tris.len() as f32 * (1.0 - MIN_SAVING) {
        None
    } else {
        Some((next, e))
    }
}

/// Coarser and coarser versions of the patch `tris`, each simplified from the one before to
/// about half its triangles with its border locked, with the sum of the simplifier's errors
/// so far (a bound on the distance to the original surface).
fn simplify(
    adapter: &VertexDataAdapter,
    attrs: &Attributes,
    locks: &[SimplifyVertex],
    tris: &[u32],
) -> Simplified {
    let mut out: Vec<(f32, Vec<u32>)> = Vec::new();
    let mut error = 0.0f32;
    let mut current = tris;
    for _ in 0..LEVELS {
        if current.len() / 6 * 3 < 3 * 16 {
            break;
        }
        let Some((next, e)) = halve(adapter, attrs, locks, current) else {
            break;
        };
        error += e;
        out.push((error, next));
        current = &out[out.len() - 1].1;
    }
    out
}
