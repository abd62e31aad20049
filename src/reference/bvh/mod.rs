//! Bounding volume hierarchy over triangles, in f64: binned surface-area-heuristic build,
//! Möller–Trumbore intersection, and the three queries the reference renderer needs (nearest
//! hit, any hit for shadow rays, every hit for translucent layers).
mod build;

use glam::DVec3;
use rayon::prelude::*;

/// Which scene triangle a BVH primitive is: mesh index and triangle index within the mesh.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct TriRef {
    pub(crate) mesh: u32,
    pub(crate) tri: u32,
}

/// A ray–triangle hit: ray parameter and the barycentric weights of vertices 1 and 2.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Hit {
    pub(crate) t: f64,
    pub(crate) u: f64,
    pub(crate) v: f64,
    pub(crate) tri: TriRef,
}

/// Vertex 0 and the two edges from it, as Möller–Trumbore wants them.
#[derive(Clone, Copy, Debug)]
struct Tri {
    v0: DVec3,
    e1: DVec3,
    e2: DVec3,
}

/// `count == 0`: interior node whose left child follows it and whose right child is `first`;
/// otherwise a leaf holding primitives `first..first + count`.
#[derive(Clone, Copy, Debug)]
struct Node {
    min: DVec3,
    max: DVec3,
    first: u32,
    count: u32,
}

pub(crate) struct Bvh {
    nodes: Vec<Node>,
    tris: Vec<Tri>,
    refs: Vec<TriRef>,
}

/// Barycentric slack: a ray through a shared edge must hit at least one of its two triangles,
/// and rounding may put it just outside both; a sliver of overlap is harmless for nearest
/// hits and the translucent pass removes duplicate layers.
const EDGE_SLACK: f64 = 1e-10;
/// Deepest possible tree: SAH levels, then median splits of at most 2^32 primitives.
const MAX_DEPTH: usize = build::SAH_DEPTH + 33;

impl Bvh {
    /// Builds over the given triangles (positions in f64); zero-area ones are kept but are
    /// never hit (their determinant is zero).
    pub(crate) fn build(input: Vec<([DVec3; 3], TriRef)>) -> Bvh {
        let (nodes, order) = build::build(input.par_iter().map(|(p, _)| p));
        let tris = order
            .iter()
            .map(|&i| {
                let p = input[i].0;
                Tri {
                    v0: p[0],
                    e1: p[1] - p[0],
                    e2: p[2] - p[0],
                }
            })
            .collect();
        let refs = order.iter().map(|&i| input[i].1).collect();
        Bvh { nodes, tris, refs }
    }

    /// The nearest hit with `t_min <= t <= t_max`.
    #[cfg(test)] // only the unit tests call it
    pub(crate) fn closest(&self, o: DVec3, d: DVec3, t_min: f64, t_max: f64) -> Option<Hit> {
        self.closest_where(o, d, t_min, t_max, |_| true)
    }

    /// The nearest hit `accept` takes (the material model's cut-outs and culled back faces
    /// are hits the rasterizer does not draw).
    pub(crate) fn closest_where(
        &self,
        o: DVec3,
        d: DVec3,
        t_min: f64,
        t_max: f64,
        accept: impl Fn(&Hit) -> bool,
    ) -> Option<Hit> {
        let mut best: Option<Hit> = None;
        let mut t_max = t_max;
        self.traverse(o, d, t_min, &mut t_max, |hit, t_max| {
            if accept(&hit) {
                *t_max = hit.t;
                best = Some(hit);
            }
            false
        });
        best
    }

    /// Whether anything lies on the ray within `t_min < t < t_max` (shadow rays).
    #[cfg(test)] // only the unit tests call it
    pub(crate) fn occluded(&self, o: DVec3, d: DVec3, t_min: f64, t_max: f64) -> bool {
        self.occluded_where(o, d, t_min, t_max, |_| true)
    }

    /// Whether a hit `accept` takes lies on the ray within `t_min < t < t_max`.
    pub(crate) fn occluded_where(
        &self,
        o: DVec3,
        d: DVec3,
        t_min: f64,
        t_max: f64,
        accept: impl Fn(&Hit) -> bool,
    ) -> bool {
        let mut found = false;
        let mut t_max = t_max;
        self.traverse(o, d, t_min, &mut t_max, |hit, _| {
            found = accept(&hit);
            found
        });
        found
    }

    /// Appends every hit within `t_min <= t <= t_max`, unordered.
    pub(crate) fn all(&self, o: DVec3, d: DVec3, t_min: f64, t_max: f64, out: &mut Vec<Hit>) {
        let mut t_max = t_max;
        self.traverse(o, d, t_min, &mut t_max, |hit, _| {
            out.push(hit);
            false
        });
    }

    /// Visits every primitive hit within [t_min, t_max]; `on_hit` may shrink t_max and
    /// returns true to stop.
    fn traverse(
        &self,
        o: DVec3,
        d: DVec3,
        t_min: f64,
        t_max: &mut f64,
        mut on_hit: impl FnMut(Hit, &mut f64) -> bool,
    ) {
        if self.nodes.is_empty() {
            return;
        }
        // -0 becomes +0 so a zero component always gives +inf; see `slab` for the NaNs.
        let inv = (d + DVec3::ZERO).recip();
        // Each level of the tree leaves at most one node on the stack.
        let mut stack = [0u32; MAX_DEPTH + 1];
        let mut sp = 1;
        while sp > 0 {
            sp -= 1;
            let node = &self.nodes[stack[sp] as usize];
            if slab(node, o, inv, t_min, *t_max).is_none() {
                continue;
            }
            if node.count > 0 {
                let start = node.first as usize;
                for i in start..start + node.count as usize {
                    if let Some((t, u, v)) = intersect(&self.tris[i], o, d, t_min, *t_max) {
                        let hit = Hit {
                            t,
                            u,
                            v,
                            tri: self.refs[i],
                        };
                        if on_hit(hit, t_max) {
                            return;
                        }
                    }
                }
                continue;
            }
            let (left, right) = (stack[sp] + 1, node.first);
            let tl = slab(&self.nodes[left as usize], o, inv, t_min, *t_max);
            let tr = slab(&self.nodes[right as usize], o, inv, t_min, *t_max);
            // Push the farther child first so the nearer one is searched first and shrinks
            // t_max early.
            let (first, second) = match (tl, tr) {
                (Some(a), Some(b)) if b < a => (Some(left), Some(right)),
                (a, b) => (b.map(|_| right), a.map(|_| left)),
            };
            for child in [first, second].into_iter().flatten() {
                stack[sp] = child;
                sp += 1;
            }
        }
    }
}

/// Entry distance of the ray into the node's box, if it enters within [t_min, t_max].
fn slab(n: &Node, o: DVec3, inv: DVec3, t_min: f64, t_max: f64) -> Option<f64> {
    // With a zero direction component the ray lies in a plane of that axis: 0·inf = NaN
    // means it lies in the box's face plane, which must count as inside, not as a miss.
    let a = (n.min - o) * inv;
    let a = DVec3::select(a.is_nan_mask(), DVec3::NEG_INFINITY, a);
    let b = (n.max - o) * inv;
    let b = DVec3::select(b.is_nan_mask(), DVec3::INFINITY, b);
    let near = a.min(b).max_element().max(t_min);
    // Widened by a few ulps so a hit exactly on a box face is not lost to rounding.
    let far = a.max(b).min_element() * (1.0 + 1e-12);
    (near <= far.min(t_max)).then_some(near)
}

fn intersect(tri: &Tri, o: DVec3, d: DVec3, t_min: f64, t_max: f64) -> Option<(f64, f64, f64)> {
    let p = d.cross(tri.e2);
    let det = tri.e1.dot(p);
    if det == 0.0 || !det.is_finite() {
        return None;
    }
    let inv = 1.0 / det;
    let s = o - tri.v0;
    let u = s.dot(p) * inv;
    if !(-EDGE_SLACK..=1.0 + EDGE_SLACK).contains(&u) {
        return None;
    }
    let q = s.cross(tri.e1);
    let v = d.dot(q) * inv;
    if v < -EDGE_SLACK || u + v > 1.0 + EDGE_SLACK {
        return None;
    }
    let t = tri.e2.dot(q) * inv;
    (t >= t_min && t <= t_max).then_some((t, u, v))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A grid of unit squares (two triangles each) in the z = 0 plane.
    fn grid(n: u32) -> Vec<([DVec3; 3], TriRef)> {
        let mut v = Vec::new();
        for j in 0..n {
            for i in 0..n {
                let p = |a: u32, b: u32| DVec3::new(f64::from(i + a), f64::from(j + b), 0.0);
                let tri = 2 * (j * n + i);
                v.push(([p(0, 0), p(1, 0), p(1, 1)], TriRef { mesh: 0, tri }));
                v.push((
                    [p(0, 0), p(1, 1), p(0, 1)],
                    TriRef {
                        mesh: 0,
                        tri: tri + 1,
                    },
                ));
            }
        }
        v
    }

    /// Every ray onto a grid finds the square it aims at, including rays exactly through
    /// shared edges and vertices (which must never fall through a crack). 100 × 100 squares
    /// are above PARALLEL_MIN, so the parallel build is covered too.
    #[test]
    fn finds_every_grid_square_without_cracks() {
        for n in [20, 100] {
            let bvh = Bvh::build(grid(n));
            let d = DVec3::new(0.0, 0.0, -1.0);
            for k in 0..=4 * n {
                for l in 0..=4 * n {
                    let (x, y) = (f64::from(k) * 0.25, f64::from(l) * 0.25);
                    let o = DVec3::new(x, y, 5.0);
                    let h = bvh
                        .closest(o, d, 0.0, 10.0)
                        .unwrap_or_else(|| panic!("crack at {x},{y}"));
                    assert!((h.t - 5.0).abs() < 1e-12);
                    if k % 4 != 0 && l % 4 != 0 {
                        assert_eq!(h.tri.tri / 2, (l / 4) * n + k / 4, "at {x},{y}");
                    }
                    assert!(bvh.occluded(o, d, 0.0, 10.0));
                    assert!(!bvh.occluded(o, d, 0.0, 4.9));
                }
            }
            let outside = DVec3::new(-0.1, 3.0, 5.0);
            assert!(bvh.closest(outside, d, 0.0, 10.0).is_none());
            // A ray along the plane (zero determinant) hits nothing rather than NaN.
            let along = DVec3::new(-1.0, 3.0, 0.0);
            assert!(bvh.closest(along, DVec3::X, 0.0, 100.0).is_none());
        }
    }

    #[test]
    fn all_hits_and_degenerate_input() {
        let mut tris = grid(2);
        let a = DVec3::new(0.5, 0.5, 1.0);
        tris.push(([a, a, a], TriRef { mesh: 1, tri: 0 }));
        tris.push((
            [a, a + DVec3::X, a + 2.0 * DVec3::X],
            TriRef { mesh: 1, tri: 1 },
        ));
        let mut layer = grid(2);
        for (p, r) in &mut layer {
            p.iter_mut().for_each(|q| q.z = 2.0);
            r.mesh = 2;
        }
        tris.extend(layer);
        let bvh = Bvh::build(tris);
        let mut out = Vec::new();
        bvh.all(
            DVec3::new(0.3, 0.6, 9.0),
            DVec3::NEG_Z,
            0.0,
            100.0,
            &mut out,
        );
        let mut meshes: Vec<u32> = out.iter().map(|h| h.tri.mesh).collect();
        meshes.sort();
        assert_eq!(meshes, [0, 2]);
        assert!(Bvh::build(Vec::new())
            .closest(a, DVec3::X, 0.0, 1.0)
            .is_none());
    }
}
