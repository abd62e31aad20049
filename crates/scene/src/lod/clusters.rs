//! Large meshes drawn in parts. Their triangles are put in an order that is both
//! vertex-cache friendly and spatially coherent ([`crate::lod::reorder`]: blocks along a Morton
//! curve, each in meshopt's FIFO cache order), and the index buffer is cut into runs of
//! `MIN_RUN`–`RUN` triangles ("clusters") with a bounding sphere and a normal cone each. A pass then skips, on the CPU,
//! the runs outside its frustum (any mesh) and, for closed outward-facing meshes seen from
//! outside or for draws that cull back faces anyway, the runs that face away from the
//! viewer: llvmpipe shades vertices and sets up triangles on one thread, so triangles never
//! sent are the only ones that cost nothing. No GL here.
use crate::geometry::closure::{closure, Closure};
use crate::lod::levels::{hidden, Lod, Pixels};
use crate::model::Vertex;
use glam::{Mat4, Vec3, Vec4, Vec4Swizzles};
use rayon::prelude::*;

/// Meshes with fewer triangles are drawn whole: one draw call is cheaper than the test.
pub const MIN_TRIANGLES: usize = 1 << 14;
/// Triangles per cluster at most: small enough that a sphere's silhouette band is a few
/// percent of it, large enough that a 1M-triangle mesh has only ~4,000 to test.
pub(crate) const RUN: usize = 256;
/// Triangles per cluster at least: a smaller mesh gets smaller runs (up to [`CLUSTERS`] of
/// them), whose tighter normal cones let a noisy scan skip more of its far side.
pub(crate) const MIN_RUN: usize = 64;
/// How many clusters a mesh is cut into at most, while runs can shrink towards [`MIN_RUN`].
pub(crate) const CLUSTERS: usize = 4096;

/// Triangles per cluster for a mesh of `triangles`: the power of two between [`MIN_RUN`] and
/// [`RUN`] that keeps the count near [`CLUSTERS`].
pub(crate) fn run_length(triangles: usize) -> usize {
    triangles
        .div_ceil(CLUSTERS)
        .next_power_of_two()
        .clamp(MIN_RUN, RUN)
}
pub use crate::lod::reorder::reorder;

/// Reorders every large mesh of `scene` and builds its clusters and their levels of detail
/// (None for small meshes), in mesh order: pure CPU work, done on the loading thread. The
/// levels cost more than they save in one frame (1.2 s against ~0.1 s on the 2M-triangle
/// sphere), but a picture that draws them must have them (the renderer builds those it
/// lacks before such a picture): built here for the mesh cache's entry and a renderer.
pub fn prepare(scene: &mut crate::model::Scene) -> Vec<Option<Clusters>> {
    prepare_with(scene, true)
}

/// As [`prepare`] without levels of detail: for a model not in the cache, whose picture may
/// not need them (the renderer builds them, with [`levels_of`] as [`add_lod`] does, before
/// the first picture that draws them, so the pictures are those of [`prepare`]'s clusters).
pub fn prepare_without_lod(scene: &mut crate::model::Scene) -> Vec<Option<Clusters>> {
    prepare_with(scene, false)
}

/// Adds the levels of detail to clusters [`prepare_without_lod`] made for `scene`.
pub fn add_lod(scene: &crate::model::Scene, clusters: &mut [Option<Clusters>]) {
    for (m, c) in scene.meshes.iter().zip(clusters) {
        if let Some(c) = c {
            c.lod = levels_of(m, c);
        }
    }
}

/// The levels of detail of mesh `m` cut into `clusters`: the one call every builder makes
/// (the loader, the mesh cache's writer, the renderer before a picture), so a picture's
/// levels are the same whoever built them.
pub fn levels_of(m: &crate::model::Mesh, clusters: &Clusters) -> Lod {
    #[cfg(feature = "native")]
    {
        Lod::build(&m.vertices, &m.colors, m.has_uv, &m.indices, &clusters.list)
    }
    // No simplifier in the browser build: a scene there brings its levels or has none.
    #[cfg(not(feature = "native"))]
    {
        let _ = (m, clusters);
        Lod::default()
    }
}

fn prepare_with(scene: &mut crate::model::Scene, lod: bool) -> Vec<Option<Clusters>> {
    // The meshes a rig poses move their triangles at every pose: clusters made here would
    // bound where they were (the renderer draws them whole; render/posed.rs).
    let moves: Vec<bool> = (0..scene.meshes.count())
        .map(|i| scene.mesh_moves(i))
        .collect();
    scene
        .meshes
        .iter_mut()
        .enumerate()
        .map(|(i, m)| {
            let large = m.triangle_count() >= MIN_TRIANGLES;
            (large && !moves[i]).then(|| {
                reorder(&m.vertices, &mut m.indices);
                let mut c = Clusters::build(&m.vertices, &m.indices);
                if lod {
                    c.lod = levels_of(m, &c);
                }
                c
            })
        })
        .collect()
}

/// One run of triangles: `count` triangles from triangle `first`.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Cluster {
    pub(crate) first: u32,
    pub count: u32,
    pub(crate) center: Vec3,
    pub(crate) radius: f32,
    /// Mean facet normal (unit), and the sine of the largest angle between it and a facet
    /// normal; `sin_spread` > 1 means the facets do not fit in a half-space cone.
    pub(crate) axis: Vec3,
    pub(crate) sin_spread: f32,
    pub(crate) cos_spread: f32,
}

/// The clusters of one mesh, and whether back faces can never be seen from outside it.
/// Stored in the mesh cache's entry with the reordered indices, so a hit builds nothing.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Clusters {
    pub list: Vec<Cluster>,
    /// Whether back faces can be seen from outside, and if so why ([`closure`]).
    pub closure: Closure,
    /// Coarser levels of groups of clusters (empty: none built).
    #[serde(default)]
    pub lod: Lod,
}

impl Clusters {
    /// Bounds and cones of every run of `indices`, and whether the mesh is closed.
    pub fn build(vertices: &[Vertex], indices: &[u32]) -> Clusters {
        let run = run_length(indices.len() / 3);
        let list = indices
            .par_chunks(run * 3)
            .enumerate()
            .map(|(k, r)| cluster(vertices, r, (k * run) as u32))
            .collect();
        Clusters {
            list,
            closure: closure(vertices, indices),
            lod: Lod::default(),
        }
    }

    /// A closed surface facing outwards: from outside, only its front faces can be seen.
    pub fn closed(&self) -> bool {
        self.closure.is_closed()
    }

    /// The index ranges (first index, count) of the clusters `view` may see, adjacent ones
    /// merged, and the triangles in them. With `hide_back_faces` clusters whose every facet
    /// faces away from the viewer are skipped too: the caller has checked that no back face
    /// could show (the draw culls back faces, or `view` sees this closed mesh from outside).
    pub fn visible(
        &self,
        view: &ClusterView,
        hide_back_faces: bool,
        out: &mut Vec<(u32, u32)>,
    ) -> u64 {
        out.clear();
        let mut triangles = 0u64;
        let mut push = |c: &Cluster| {
            if hidden(view, c, hide_back_faces) {
                return;
            }
            triangles += u64::from(c.count);
            let (first, count) = (c.first * 3, c.count * 3);
            match out.last_mut() {
                Some((f, n)) if *f + *n == first => *n += count,
                _ => out.push((first, count)),
            }
        };
        let whole = view.lod.as_ref().and_then(|px| self.lod.choose_whole(px));
        match (&view.lod, whole) {
            // The whole mesh at one coarser level when its error fits.
            (_, Some(level)) => push(&level.part),
            // Per group: its coarsest level within the bound, else its own clusters.
            (Some(px), None) if !self.lod.groups.is_empty() => {
                for g in &self.lod.groups {
                    if view.outside(g.bound.center, g.bound.radius) {
                        continue;
                    }
                    match self.lod.choose(g, px) {
                        Some(level) => push(&level.part),
                        None => self.list[g.clusters[0] as usize..g.clusters[1] as usize]
                            .iter()
                            .for_each(&mut push),
                    }
                }
            }
            _ => self.list.iter().for_each(push),
        }
        triangles
    }
}

/// The bounds and normal cone of the triangles `run`, the first of which is triangle `first`.
pub(crate) fn cluster(vertices: &[Vertex], run: &[u32], first: u32) -> Cluster {
    let p = |i: u32| Vec3::from(vertices[i as usize].position);
    let (mut lo, mut hi) = (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN));
    let mut sum = Vec3::ZERO;
    let mut normals = Vec::with_capacity(run.len() / 3);
    for t in run.chunks_exact(3) {
        let (a, b, c) = (p(t[0]), p(t[1]), p(t[2]));
        lo = lo.min(a).min(b).min(c);
        hi = hi.max(a).max(b).max(c);
        let n = (b - a).cross(c - a);
        if let Some(n) = n.try_normalize() {
            sum += n;
            normals.push(n);
        }
    }
    let center = (lo + hi) * 0.5;
    let radius = run
        .iter()
        .map(|&i| p(i).distance(center))
        .fold(0.0f32, f32::max);
    // The cone: the mean normal, and the widest facet from it. Degenerate facets draw
    // nothing and so do not widen it.
    let (axis, cos_spread) = match sum.try_normalize() {
        Some(axis) => (
            axis,
            normals.iter().map(|n| n.dot(axis)).fold(1.0f32, f32::min),
        ),
        None => (Vec3::Z, -1.0),
    };
    let cos_spread = cos_spread.clamp(-1.0, 1.0);
    Cluster {
        first,
        count: (run.len() / 3) as u32,
        center,
        radius,
        axis,
        sin_spread: if cos_spread > 0.0 {
            (1.0 - cos_spread * cos_spread).sqrt()
        } else {
            2.0
        },
        cos_spread,
    }
}

/// Whom a pass draws for: a point (perspective) or a direction (orthographic), and its
/// frustum.
#[derive(Clone, Copy, Debug)]
pub struct ClusterView {
    pub(crate) viewer: Viewer,
    planes: [Vec4; 6],
    /// Level of detail: the view's pixels and error bound (None: every triangle).
    pub(crate) lod: Option<Pixels>,
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Viewer {
    Point(Vec3),
    /// The direction the view looks (from the viewer into the scene).
    Direction(Vec3),
}

/// Relative slack on every test, so float rounding can only keep a cluster.
const SLACK: f32 = 1e-4;

impl ClusterView {
    /// The view of a view-projection matrix (mesh coordinates → clip space).
    pub fn new(view_proj: Mat4) -> ClusterView {
        let r = [
            view_proj.row(0),
            view_proj.row(1),
            view_proj.row(2),
            view_proj.row(3),
        ];
        // Gribb–Hartmann: clip-space planes as rows; normalised so distances are true.
        let planes = [
            r[3] + r[0],
            r[3] - r[0],
            r[3] + r[1],
            r[3] - r[1],
            r[3] + r[2],
            r[3] - r[2],
        ]
        .map(|p| p / p.xyz().length().max(f32::MIN_POSITIVE));
        // The eye maps to clip (0, 0, B, 0) under a perspective projection, so the inverse
        // of NDC's depth direction is the eye as a point; under an orthographic one it is a
        // direction (w = 0), the one the view looks along.
        let h = view_proj.inverse() * Vec4::new(0.0, 0.0, 1.0, 0.0);
        let viewer = if h.w.abs() > 1e-12 * h.xyz().length() {
            Viewer::Point(h.xyz() / h.w)
        } else {
            Viewer::Direction(h.xyz().normalize_or_zero())
        };
        ClusterView {
            viewer,
            planes,
            lod: None,
        }
    }

    /// The view drawn into `width` × `height` pixels with level of detail at `bound` pixels
    /// of error (0 or less: none).
    pub fn with_lod(self, view_proj: Mat4, width: u32, height: u32, bound: f32) -> ClusterView {
        ClusterView {
            lod: (bound > 0.0).then(|| Pixels::new(view_proj, width, height, bound)),
            ..self
        }
    }

    /// The same view drawing every triangle.
    pub fn without_lod(self) -> ClusterView {
        ClusterView { lod: None, ..self }
    }

    /// The sphere lies entirely outside one plane of the frustum.
    pub fn outside(&self, center: Vec3, radius: f32) -> bool {
        self.planes
            .iter()
            .any(|p| p.xyz().dot(center) + p.w < -radius * (1.0 + SLACK) - SLACK)
    }

    /// The sphere lies entirely beyond the near plane, so rays start outside it and nothing
    /// of it is clipped open: then only front faces of a closed mesh inside it can be seen.
    pub fn sees_from_outside(&self, center: Vec3, radius: f32) -> bool {
        let p = self.planes[4];
        p.xyz().dot(center) + p.w > radius * (1.0 + SLACK) + SLACK
    }

    /// Every facet of `c` faces away from the viewer (with slack): cos(φ + θ) > 0 where φ is
    /// the angle between the view ray and the cone axis and θ the cone's half-angle, the
    /// sphere's radius bounding how far the ray to each facet can turn.
    pub(crate) fn faces_away(&self, c: &Cluster) -> bool {
        if c.sin_spread > 1.0 {
            return false;
        }
        match self.viewer {
            Viewer::Direction(d) => {
                let cos_phi = d.dot(c.axis);
                let sin_phi = (1.0 - cos_phi * cos_phi).max(0.0).sqrt();
                cos_phi * c.cos_spread - sin_phi * c.sin_spread > SLACK
            }
            Viewer::Point(e) => {
                // For a facet with normal n and a point q on it: n·(q − e) ≥ n·(center − e) − r,
                // and n·v ≥ |v|·cos(φ + θ) for v = center − e.
                let v = c.center - e;
                let along = v.dot(c.axis);
                let across = (v.length_squared() - along * along).max(0.0).sqrt();
                along * c.cos_spread - across * c.sin_spread
                    > c.radius * (1.0 + SLACK) + SLACK * v.length()
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn closed_outward(v: &[Vertex], idx: &[u32]) -> bool {
        closure(v, idx).is_closed()
    }

    fn sphere(rings: u32, segments: u32) -> (Vec<Vertex>, Vec<u32>) {
        let mut v = vec![Vertex {
            position: [0.0, 1.0, 0.0],
            ..Default::default()
        }];
        for j in 1..rings {
            let th = std::f32::consts::PI * j as f32 / rings as f32;
            for i in 0..segments {
                let ph = std::f32::consts::TAU * i as f32 / segments as f32;
                v.push(Vertex {
                    position: [th.sin() * ph.sin(), th.cos(), th.sin() * ph.cos()],
                    ..Default::default()
                });
            }
        }
        v.push(Vertex {
            position: [0.0, -1.0, 0.0],
            ..Default::default()
        });
        let at = |j: u32, i: u32| 1 + (j - 1) * segments + i % segments;
        let south = v.len() as u32 - 1;
        let mut idx = Vec::new();
        for i in 0..segments {
            idx.extend([0, at(1, i), at(1, i + 1)]);
            idx.extend([south, at(rings - 1, i + 1), at(rings - 1, i)]);
        }
        for j in 1..rings - 1 {
            for i in 0..segments {
                idx.extend([at(j, i), at(j + 1, i), at(j + 1, i + 1)]);
                idx.extend([at(j, i), at(j + 1, i + 1), at(j, i + 1)]);
            }
        }
        (v, idx)
    }

    fn triangles(idx: &[u32]) -> Vec<[u32; 3]> {
        let mut t: Vec<[u32; 3]> = idx
            .chunks_exact(3)
            .map(|t| {
                // Same triangle and winding whatever corner it starts at.
                let k = (0..3).min_by_key(|&k| t[k]).unwrap();
                [t[k], t[(k + 1) % 3], t[(k + 2) % 3]]
            })
            .collect();
        t.sort();
        t
    }

    #[test]
    fn reorder_keeps_every_triangle_and_its_winding() {
        let (v, idx) = sphere(100, 200);
        let mut re = idx.clone();
        reorder(&v, &mut re);
        assert_ne!(re, idx, "a mesh this large is reordered");
        assert_eq!(triangles(&re), triangles(&idx));
    }

    #[test]
    fn a_sphere_is_closed_and_an_open_or_inverted_one_is_not() {
        let (v, idx) = sphere(12, 24);
        assert!(closed_outward(&v, &idx));
        let flipped: Vec<u32> = idx
            .chunks_exact(3)
            .flat_map(|t| [t[0], t[2], t[1]])
            .collect();
        assert!(!closed_outward(&v, &flipped), "inward-facing");
        assert!(!closed_outward(&v, &idx[3..]), "one triangle missing");
        let mut with_sheet = idx.clone();
        with_sheet.extend_from_slice(&[0, 1, 2]);
        assert!(!closed_outward(&v, &with_sheet), "an edge used three times");
        // A second, inside-out sphere beside it: closed, positive total volume, but one
        // piece faces inwards.
        let mut two = v.clone();
        two.extend(v.iter().map(|x| Vertex {
            position: [
                x.position[0] * 0.5 + 3.0,
                x.position[1] * 0.5,
                x.position[2] * 0.5,
            ],
            ..*x
        }));
        let mut both = idx.clone();
        both.extend(flipped.iter().map(|&i| i + v.len() as u32));
        assert!(!closed_outward(&two, &both), "one piece inside out");
        let mut both_out = idx.clone();
        both_out.extend(idx.iter().map(|&i| i + v.len() as u32));
        assert!(closed_outward(&two, &both_out), "two outward pieces");
        // Vertices split at a seam (same positions, other numbers) still close the surface.
        let mut split = v.clone();
        split.extend(v.iter().copied());
        let n = v.len() as u32;
        let half: Vec<u32> = idx
            .chunks_exact(3)
            .enumerate()
            .flat_map(|(k, t)| {
                t.iter()
                    .map(move |&i| if k % 2 == 0 { i } else { i + n })
                    .collect::<Vec<_>>()
            })
            .collect();
        assert!(closed_outward(&split, &half));
    }

    /// Every triangle of a skipped cluster faces away from the viewer or lies outside the
    /// frustum: checked triangle by triangle from many viewpoints, perspective and ortho, on a
    /// closed sphere and on an open bowl (what a back-face-culling draw may skip), from
    /// outside and from inside.
    #[test]
    fn skipped_clusters_hold_only_invisible_triangles() {
        let (v, sphere_idx) = sphere(120, 240);
        let bowl: Vec<u32> = sphere_idx
            .chunks_exact(3)
            .filter(|t| t.iter().all(|&i| v[i as usize].position[1] <= 0.0))
            .flatten()
            .copied()
            .collect();
        for (closed, mut idx) in [(true, sphere_idx), (false, bowl)] {
            reorder(&v, &mut idx);
            let c = Clusters::build(&v, &idx);
            assert_eq!(c.closed(), closed);
            skipped_only_invisible(&v, &idx, &c);
        }
    }

    fn skipped_only_invisible(v: &[Vertex], idx: &[u32], c: &Clusters) {
        let p = |i: u32| Vec3::from(v[i as usize].position);
        let mut skipped_any = 0;
        for k in 0..24 {
            let yaw = k as f32 * 0.7;
            let pitch = (k as f32 * 0.37).sin();
            let dir = Vec3::new(
                pitch.cos() * yaw.sin(),
                pitch.sin(),
                pitch.cos() * yaw.cos(),
            );
            // Every fifth view from inside the unit sphere.
            let eye = dir
                * if k % 5 == 4 {
                    0.5
                } else {
                    1.5 + k as f32 * 0.3
                };
            let view = Mat4::look_at_rh(eye, Vec3::new(0.2, 0.0, 0.0), Vec3::Y);
            let proj = if k % 3 == 0 {
                Mat4::orthographic_rh_gl(-1.5, 1.5, -1.0, 1.0, 0.1, 20.0)
            } else {
                Mat4::perspective_rh_gl(0.8, 1.5, 0.1, 20.0)
            };
            let vp = proj * view;
            let cv = ClusterView::new(vp);
            let mut ranges = Vec::new();
            let drawn = c.visible(&cv, true, &mut ranges);
            let mut kept = vec![false; idx.len() / 3];
            for (f, n) in &ranges {
                for t in *f / 3..(f + n) / 3 {
                    kept[t as usize] = true;
                }
            }
            assert_eq!(drawn, kept.iter().filter(|&&k| k).count() as u64);
            skipped_any += kept.iter().filter(|&&k| !k).count();
            for (t, tri) in idx.chunks_exact(3).enumerate() {
                if kept[t] {
                    continue;
                }
                let (a, b, cc) = (
                    vp * p(tri[0]).extend(1.0),
                    vp * p(tri[1]).extend(1.0),
                    vp * p(tri[2]).extend(1.0),
                );
                let outside = (0..3).any(|axis| {
                    let pts = [a, b, cc];
                    pts.iter().all(|q| q[axis] > q.w) || pts.iter().all(|q| q[axis] < -q.w)
                });
                // Front-facing in window space: counter-clockwise after the divide.
                let (a2, b2, c2) = (a.xy() / a.w, b.xy() / b.w, cc.xy() / cc.w);
                let area = (b2 - a2).perp_dot(c2 - a2);
                let behind = a.w <= 0.0 || b.w <= 0.0 || cc.w <= 0.0;
                assert!(
                    outside || (!behind && area <= 0.0),
                    "view {k}: triangle {t} skipped but front-facing (area {area})"
                );
            }
        }
        assert!(skipped_any > 0, "nothing was ever skipped");
    }

    #[test]
    fn sees_from_outside_needs_the_whole_sphere_past_the_near_plane() {
        let view = Mat4::look_at_rh(Vec3::new(0.0, 0.0, 3.0), Vec3::ZERO, Vec3::Y);
        let cv = ClusterView::new(Mat4::perspective_rh_gl(0.8, 1.0, 0.5, 10.0) * view);
        assert!(cv.sees_from_outside(Vec3::ZERO, 1.0));
        assert!(
            !cv.sees_from_outside(Vec3::ZERO, 2.6),
            "near plane at z = 2.5 cuts it"
        );
        assert!(
            matches!(cv.viewer, Viewer::Point(e) if e.distance(Vec3::new(0.0, 0.0, 3.0)) < 1e-4)
        );
        let ortho =
            ClusterView::new(Mat4::orthographic_rh_gl(-1.0, 1.0, -1.0, 1.0, 0.5, 10.0) * view);
        assert!(matches!(ortho.viewer, Viewer::Direction(d) if d.distance(-Vec3::Z) < 1e-5));
    }
}
