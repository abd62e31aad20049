//! A point cloud's spacing: the mean distance from a point to its nearest distinct neighbour,
//! which sets the default point size (`--point-size`). Neighbours are found in a uniform grid
//! of about n cells (a sorted list of (cell, point): 16 bytes a point, no map), searched ring
//! by ring outwards until no nearer point can remain.
use glam::DVec3;

/// Points whose nearest neighbour is measured (evenly spread through the list).
const SAMPLES: usize = 2048;

/// The mean nearest-neighbour distance over a sample of `pts`; coincident points are skipped.
/// None without two distinct points.
pub(crate) fn mean_nearest(pts: &[[f32; 3]]) -> Option<f64> {
    let at = |i: usize| glam::Vec3::from(pts[i]).as_dvec3();
    if pts.len() < 2 {
        return None;
    }
    let (mut lo, mut hi) = (at(0), at(0));
    for i in 0..pts.len() {
        lo = lo.min(at(i));
        hi = hi.max(at(i));
    }
    let extent = (hi - lo).max_element();
    if !(extent > 0.0 && extent.is_finite()) {
        return None;
    }
    let per_axis = (pts.len() as f64).cbrt().ceil().clamp(1.0, 1024.0);
    let h = extent / per_axis;
    let side = per_axis as i64 + 1;
    let cell = |p: DVec3| {
        ((p - lo) / h)
            .floor()
            .as_i64vec3()
            .clamp(glam::I64Vec3::ZERO, glam::I64Vec3::splat(side - 1))
    };
    let key = |c: glam::I64Vec3| ((c.x * side + c.y) * side + c.z) as u64;
    let mut grid: Vec<(u64, u32)> = (0..pts.len())
        .map(|i| (key(cell(at(i))), i as u32))
        .collect();
    grid.sort_unstable();
    let in_cell = |c: glam::I64Vec3| {
        let k = key(c);
        let first = grid.partition_point(|e| e.0 < k);
        grid[first..].iter().take_while(move |e| e.0 == k)
    };
    let (mut sum, mut count) = (0.0, 0usize);
    for qi in (0..pts.len()).step_by(pts.len().div_ceil(SAMPLES)) {
        let q = at(qi);
        let c = cell(q);
        let mut best = f64::INFINITY;
        for r in 0..=side {
            for dx in -r..=r {
                for dy in -r..=r {
                    for dz in -r..=r {
                        if dx.abs().max(dy.abs()).max(dz.abs()) != r {
                            continue;
                        }
                        let n = c + glam::I64Vec3::new(dx, dy, dz);
                        if n.min_element() < 0 || n.max_element() >= side {
                            continue;
                        }
                        for &(_, j) in in_cell(n) {
                            let d = at(j as usize).distance(q);
                            if d > 0.0 && d < best {
                                best = d;
                            }
                        }
                    }
                }
            }
            // Every point outside ring r is more than r cells away.
            if best <= r as f64 * h {
                break;
            }
        }
        if best.is_finite() {
            sum += best;
            count += 1;
        }
    }
    (count > 0).then(|| sum / count as f64)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lattice_spacing_is_exact() {
        // A 20×20×5 lattice of pitch 0.25 with one point repeated: every nearest distance
        // is 0.25 (the duplicate is skipped, not counted as 0).
        let mut pts = Vec::new();
        for x in 0..20 {
            for y in 0..20 {
                for z in 0..5 {
                    pts.push([x as f32, y as f32, z as f32].map(|v| v * 0.25));
                }
            }
        }
        pts.push(pts[7]);
        let s = mean_nearest(&pts).unwrap();
        assert!((s - 0.25).abs() < 1e-12, "{s}");
        assert_eq!(mean_nearest(&[[1.0; 3], [1.0; 3]]), None);
        assert_eq!(mean_nearest(&[[1.0; 3]]), None);
    }

    #[test]
    fn far_apart_pairs() {
        // Two points at distance 3 and nothing else: the search must leave its first ring.
        let s = mean_nearest(&[[0.0; 3], [3.0, 0.0, 0.0]]).unwrap();
        assert_eq!(s, 3.0);
    }
}
