//! The BVH's build: binned surface area heuristic, object median past a depth limit, large
//! subtrees on separate threads.
use super::Node;
use glam::DVec3;
use rayon::prelude::*;

const LEAF_SIZE: usize = 4;
const BINS: usize = 16;
/// Past this depth the build splits at the object median, which bounds the depth (and the
/// recursion) even for distributions that make SAH peel off one triangle at a time.
pub(super) const SAH_DEPTH: usize = 48;

struct BuildPrim {
    min: DVec3,
    max: DVec3,
    centroid: DVec3,
}

/// Nodes (root first) and the primitive order their leaves refer to.
pub(super) fn build<'a>(
    triangles: impl IndexedParallelIterator<Item = &'a [DVec3; 3]>,
) -> (Vec<Node>, Vec<usize>) {
    let prims: Vec<BuildPrim> = triangles
        .map(|p| {
            let (min, max) = (p[0].min(p[1]).min(p[2]), p[0].max(p[1]).max(p[2]));
            BuildPrim {
                min,
                max,
                centroid: (min + max) * 0.5,
            }
        })
        .collect();
    let mut order: Vec<usize> = (0..prims.len()).collect();
    let nodes = if prims.is_empty() {
        Vec::new()
    } else {
        build_parallel(&prims, &mut order, 0, 0)
    };
    (nodes, order)
}

/// Bounds of the primitives in `order` and the index to split it at (after partitioning it),
/// or None for a leaf.
fn plan(prims: &[BuildPrim], order: &mut [usize], depth: usize) -> (DVec3, DVec3, Option<usize>) {
    let (mut min, mut max) = (DVec3::INFINITY, DVec3::NEG_INFINITY);
    let (mut cmin, mut cmax) = (DVec3::INFINITY, DVec3::NEG_INFINITY);
    for &i in order.iter() {
        min = min.min(prims[i].min);
        max = max.max(prims[i].max);
        cmin = cmin.min(prims[i].centroid);
        cmax = cmax.max(prims[i].centroid);
    }
    let extent = cmax - cmin;
    let axis = if extent.x >= extent.y && extent.x >= extent.z {
        0
    } else if extent.y >= extent.z {
        1
    } else {
        2
    };
    // All centroids in one point (or NaN coordinates): no split can separate them.
    let separable = extent[axis] > 0.0;
    if order.len() <= LEAF_SIZE || !separable {
        return (min, max, None);
    }
    let split = if depth < SAH_DEPTH {
        sah_split(
            prims,
            order,
            axis,
            cmin[axis],
            extent[axis],
            area(max - min),
        )
    } else {
        let mid = order.len() / 2;
        order.select_nth_unstable_by(mid, |&a, &b| {
            prims[a].centroid[axis].total_cmp(&prims[b].centroid[axis])
        });
        Some(mid)
    };
    (min, max, split)
}

fn build_into(
    prims: &[BuildPrim],
    order: &mut [usize],
    offset: usize,
    nodes: &mut Vec<Node>,
    depth: usize,
) {
    let (min, max, split) = plan(prims, order, depth);
    let me = nodes.len();
    nodes.push(Node {
        min,
        max,
        first: offset as u32,
        count: order.len() as u32,
    });
    let Some(mid) = split else {
        return;
    };
    let (left, right) = order.split_at_mut(mid);
    nodes[me].count = 0;
    build_into(prims, left, offset, nodes, depth + 1);
    nodes[me].first = nodes.len() as u32;
    build_into(prims, right, offset + mid, nodes, depth + 1);
}

/// Subtrees this large are built on separate threads (a 1M-triangle model builds in about
/// 1.4 s on one core), each into its own vector, and concatenated.
const PARALLEL_MIN: usize = 16 * 1024;

fn build_parallel(
    prims: &[BuildPrim],
    order: &mut [usize],
    offset: usize,
    depth: usize,
) -> Vec<Node> {
    let mut nodes = Vec::new();
    if order.len() < PARALLEL_MIN {
        build_into(prims, order, offset, &mut nodes, depth);
        return nodes;
    }
    let (min, max, split) = plan(prims, order, depth);
    let Some(mid) = split else {
        build_into(prims, order, offset, &mut nodes, depth);
        return nodes;
    };
    let (left, right) = order.split_at_mut(mid);
    let (l, r) = rayon::join(
        || build_parallel(prims, left, offset, depth + 1),
        || build_parallel(prims, right, offset + mid, depth + 1),
    );
    nodes.reserve_exact(1 + l.len() + r.len());
    nodes.push(Node {
        min,
        max,
        first: (1 + l.len()) as u32,
        count: 0,
    });
    // Interior nodes name their right child by index within their own vector.
    let shift = |base: usize| {
        move |n: &Node| Node {
            first: n.first + if n.count == 0 { base as u32 } else { 0 },
            ..*n
        }
    };
    nodes.extend(l.iter().map(shift(1)));
    nodes.extend(r.iter().map(shift(1 + l.len())));
    nodes
}

fn area(e: DVec3) -> f64 {
    2.0 * (e.x * e.y + e.y * e.z + e.z * e.x)
}

/// Partitions `order` at the cheapest of the bin boundaries along `axis` and returns the
/// split index, or None when keeping a leaf is cheaper.
fn sah_split(
    prims: &[BuildPrim],
    order: &mut [usize],
    axis: usize,
    start: f64,
    extent: f64,
    parent_area: f64,
) -> Option<usize> {
    let bin_of = |i: usize| {
        let b = ((prims[i].centroid[axis] - start) / extent * BINS as f64) as usize;
        b.min(BINS - 1)
    };
    let mut bins = [(0usize, DVec3::INFINITY, DVec3::NEG_INFINITY); BINS];
    for &i in order.iter() {
        let b = &mut bins[bin_of(i)];
        b.0 += 1;
        b.1 = b.1.min(prims[i].min);
        b.2 = b.2.max(prims[i].max);
    }
    // Cost of the split after bin k: count · area on each side (sweeps from both ends).
    let mut right_cost = [0.0; BINS];
    let (mut n, mut lo, mut hi) = (0, DVec3::INFINITY, DVec3::NEG_INFINITY);
    for k in (1..BINS).rev() {
        n += bins[k].0;
        lo = lo.min(bins[k].1);
        hi = hi.max(bins[k].2);
        right_cost[k - 1] = if n > 0 { n as f64 * area(hi - lo) } else { 0.0 };
    }
    let (mut best, mut best_cost) = (None, f64::INFINITY);
    let (mut n, mut lo, mut hi) = (0, DVec3::INFINITY, DVec3::NEG_INFINITY);
    for k in 0..BINS - 1 {
        n += bins[k].0;
        lo = lo.min(bins[k].1);
        hi = hi.max(bins[k].2);
        if n == 0 || n == order.len() {
            continue;
        }
        let cost = n as f64 * area(hi - lo) + right_cost[k];
        if cost < best_cost {
            (best, best_cost) = (Some(k), cost);
        }
    }
    let k = best?;
    // Traversal step ≈ one triangle test; a leaf costs one test per triangle.
    let leaf_cost = order.len() as f64 * parent_area;
    if order.len() <= 16 && best_cost + parent_area >= leaf_cost {
        return None;
    }
    let mut mid = 0;
    for j in 0..order.len() {
        if bin_of(order[j]) <= k {
            order.swap(j, mid);
            mid += 1;
        }
    }
    Some(mid)
}
