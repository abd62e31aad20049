//! Level of detail by screen-space error. A large mesh's clusters ([`crate::lod::clusters`]) are
//! taken [`GROUP`] at a time (consecutive runs, so a group is one compact patch); each group
//! is simplified with meshopt, its border locked, into up to [`LEVELS`] coarser levels, each
//! with a bound on how far its surface lies from the original one (object units). A pass
//! then draws, per group, the coarsest level whose error seen from the view is at most the
//! bound in pixels, or the group's own clusters. Borders never move, so groups at different
//! levels still meet edge to edge: no cracks. Simplified from a small patch rather than a
//! cluster: a 256-triangle cluster's locked border is a third of its vertices and stops the
//! simplifier early. No GL here.
use crate::lod::clusters::{cluster, Cluster, ClusterView};
use crate::model::Vertex;
use meshopt::{SimplifyOptions, SimplifyVertex, VertexDataAdapter};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

/// Clusters simplified together.
pub(crate) const GROUP: usize = 16;
/// Coarser levels per group at most, each about half the triangles of the one before.
pub(crate) const LEVELS: usize = 6;
/// A level must save at least this share of its predecessor's triangles to be kept.
const MIN_SAVING: f32 = 0.15;

/// The coarser levels of one mesh's groups.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Lod {
    pub groups: Vec<Group>,
    pub levels: Vec<Level>,
    /// Levels of the whole mesh, errors increasing: simplified from the groups' coarsest
    /// levels with the groups' borders free, for views where the whole mesh's error fits
    /// (a group's locked border keeps a fifth of its triangles at best).
    #[serde(default)]
    pub(crate) whole: Vec<Level>,
    /// Every level's triangles, drawn from the same index buffer after the mesh's own: a
    /// level's `part.first` counts triangles from the start of the mesh's indices. Stored in
    /// the mesh cache's payload, not its header.
    #[serde(skip)]
    pub indices: Vec<u32>,
    /// `indices.len()`, for reading the payload back.
    pub index_count: usize,
}

/// A run of clusters simplified together, its bounds, and its levels (finest first).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Group {
    /// Its clusters: `first..end` in [`crate::lod::clusters::Clusters::list`].
    pub(crate) clusters: [u32; 2],
    /// Bounding sphere (and cone) of all its triangles.
    pub(crate) bound: Cluster,
    /// Its levels: `first..end` in [`Lod::levels`], errors increasing.
    pub(crate) levels: [u32; 2],
}

/// One simplified version of a group: its triangles (with their own bounds and cone, for
/// culling) and how far, at most, its surface lies from the original (object units).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Level {
    pub(crate) error: f32,
    pub part: Cluster,
}

/// The screen-space error of a view: pixels per object unit at a point of clip-space depth
/// `w` are `scale / w` (perspective: the focal length in pixels; orthographic: `w` = 1).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Pixels {
    /// Row 3 of the view-projection matrix (clip w) and the length of its xyz part.
    w_row: glam::Vec4,
    w_len: f32,
    scale: f32,
    /// The bound, in pixels.
    pub(crate) bound: f32,
}

impl Pixels {
    /// For `view_proj` drawn into `width` × `height` pixels, with `bound` pixels of error.
    pub(crate) fn new(view_proj: glam::Mat4, width: u32, height: u32, bound: f32) -> Pixels {
        use glam::Vec4Swizzles;
        let w_row = view_proj.row(3);
        // The larger of the two axes' scales: an error along either is at most this many pixels.
        let scale = (view_proj.row(0).xyz().length() * width as f32 * 0.5)
            .max(view_proj.row(1).xyz().length() * height as f32 * 0.5);
        Pixels {
            w_row,
            w_len: w_row.xyz().length(),
            scale,
            bound,
        }
    }

    /// Pixels per object unit anywhere in the sphere (its nearest point's depth); infinite
    /// when the sphere reaches the eye's plane.
    pub(crate) fn per_unit(&self, center: glam::Vec3, radius: f32) -> f32 {
        let w = self.w_row.truncate().dot(center) + self.w_row.w - self.w_len * radius;
        if w > 1e-6 {
            self.scale / w
        } else {
            f32::INFINITY
        }
    }
}

impl Lod {
    /// The coarsest level of `g` whose error is within the view's bound, if any.
    pub(crate) fn choose(&self, g: &Group, px: &Pixels) -> Option<&Level> {
        let per_unit = px.per_unit(g.bound.center, g.bound.radius);
        self.levels[g.levels[0] as usize..g.levels[1] as usize]
            .iter()
            .rev()
            .find(|l| l.error * per_unit <= px.bound)
    }

    /// Whether every level's triangles lie within `triangles` (the mesh's, then these).
    pub(crate) fn fits(&self, triangles: u64, clusters: usize) -> bool {
        self.indices.len() == self.index_count && self.tables_fit(triangles, clusters)
    }

    /// As [`Lod::fits`] before the indices are read (a mesh the cache kept compact): the
    /// tables against `index_count`.
    pub(crate) fn tables_fit(&self, triangles: u64, clusters: usize) -> bool {
        let all = triangles + self.index_count as u64 / 3;
        self.index_count.is_multiple_of(3)
            && self.groups.iter().all(|g| {
                g.clusters[0] <= g.clusters[1]
                    && g.clusters[1] as usize <= clusters
                    && g.levels[0] <= g.levels[1]
                    && g.levels[1] as usize <= self.levels.len()
            })
            && self
                .levels
                .iter()
                .chain(&self.whole)
                .all(|l| u64::from(l.part.first) + u64::from(l.part.count) <= all)
    }

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

    /// The coarsest level of the whole mesh whose error is within the view's bound, if any.
    pub(crate) fn choose_whole(&self, px: &Pixels) -> Option<&Level> {
        let b = &self.whole.first()?.part;
        let per_unit = px.per_unit(b.center, b.radius);
        self.whole
            .iter()
            .rev()
            .find(|l| l.error * per_unit <= px.bound)
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

/// Whether `view` may skip `c` (see [`crate::lod::clusters::Clusters::visible`]).
pub(crate) fn hidden(view: &ClusterView, c: &Cluster, hide_back_faces: bool) -> bool {
    view.outside(c.center, c.radius) || (hide_back_faces && view.faces_away(c))
}

#[cfg(test)]
#[path = "levels_tests.rs"]
mod tests;
