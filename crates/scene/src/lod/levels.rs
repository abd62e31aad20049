//! Level of detail by screen-space error. A large mesh's clusters ([`crate::lod::clusters`]) are
//! taken [`GROUP`] at a time (consecutive runs, so a group is one compact patch); each group
//! is simplified with meshopt, its border locked, into up to [`LEVELS`] coarser levels, each
//! with a bound on how far its surface lies from the original one (object units). A pass
//! then draws, per group, the coarsest level whose error seen from the view is at most the
//! bound in pixels, or the group's own clusters. Borders never move, so groups at different
//! levels still meet edge to edge: no cracks. Simplified from a small patch rather than a
//! cluster: a 256-triangle cluster's locked border is a third of its vertices and stops the
//! simplifier early. No GL here.
use crate::lod::clusters::{Cluster, ClusterView};
use serde::{Deserialize, Serialize};

/// Clusters simplified together.
pub(crate) const GROUP: usize = 16;
#[cfg_attr(not(feature = "native"), allow(dead_code))]
/// Coarser levels per group at most, each about half the triangles of the one before.
pub(crate) const LEVELS: usize = 6;
#[cfg_attr(not(feature = "native"), allow(dead_code))]
/// A level must save at least this share of its predecessor's triangles to be kept.
pub(crate) const MIN_SAVING: f32 = 0.15;

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

    #[cfg_attr(not(feature = "native"), allow(dead_code))]
    /// Whether every level's triangles lie within `triangles` (the mesh's, then these).
    pub(crate) fn fits(&self, triangles: u64, clusters: usize) -> bool {
        self.indices.len() == self.index_count && self.tables_fit(triangles, clusters)
    }

    #[cfg_attr(not(feature = "native"), allow(dead_code))]
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

    /// The coarsest level of the whole mesh whose error is within the view's bound, if any.
    pub(crate) fn choose_whole(&self, px: &Pixels) -> Option<&Level> {
        let b = &self.whole.first()?.part;
        let per_unit = px.per_unit(b.center, b.radius);
        self.whole
            .iter()
            .rev()
            .find(|l| l.error * per_unit <= px.bound)
    }
}

/// Whether `view` may skip `c` (see [`crate::lod::clusters::Clusters::visible`]).
pub(crate) fn hidden(view: &ClusterView, c: &Cluster, hide_back_faces: bool) -> bool {
    view.outside(c.center, c.radius) || (hide_back_faces && view.faces_away(c))
}

#[cfg(test)]
#[path = "levels_tests.rs"]
mod tests;
