//! Polygons → triangles. Convex faces keep the fan (cheap, and the order tobj and most
//! viewers produce); concave ones are projected onto their best-fit plane (Newell normal) and
//! ear-clipped with `earcutr`, so an L-shape, a wall with a doorway or a ring bridged into one
//! face cover exactly their own area.
use glam::{DVec2, DVec3};

/// The Newell normal: robust for non-planar and concave polygons; its length is twice the
/// area of the projection onto the plane it defines.
pub(crate) fn newell_normal(p: &[DVec3]) -> DVec3 {
    let mut n = DVec3::ZERO;
    for (i, a) in p.iter().enumerate() {
        let b = p[(i + 1) % p.len()];
        n += DVec3::new(
            (a.y - b.y) * (a.z + b.z),
            (a.z - b.z) * (a.x + b.x),
            (a.x - b.x) * (a.y + b.y),
        );
    }
    n
}

/// The polygon in 2D coordinates of the plane with normal `n`, counter-clockwise seen from
/// the side `n` points to.
fn project(p: &[DVec3], n: DVec3) -> Vec<DVec2> {
    let n = n.normalize();
    let u = n.any_orthonormal_vector();
    let v = n.cross(u);
    p.iter().map(|q| DVec2::new(q.dot(u), q.dot(v))).collect()
}

/// Whether every turn of the projected polygon goes the same (counter-clockwise) way.
fn is_convex(q: &[DVec2]) -> bool {
    let n = q.len();
    (0..n).all(|i| {
        let (a, b, c) = (q[i], q[(i + 1) % n], q[(i + 2) % n]);
        (b - a).perp_dot(c - b) >= 0.0
    })
}

/// Triangles (indices into `p`) covering the polygon `p`, wound like `p`.
pub(crate) fn polygon(p: &[DVec3]) -> Vec<[usize; 3]> {
    let n = p.len();
    let fan = || (1..n.saturating_sub(1)).map(|i| [0, i, i + 1]).collect();
    if n <= 3 {
        return fan();
    }
    let normal = newell_normal(p);
    if normal.length_squared() == 0.0 || !normal.is_finite() {
        return fan();
    }
    let q = project(p, normal);
    if is_convex(&q) {
        return fan();
    }
    let flat: Vec<f64> = q.iter().flat_map(|v| [v.x, v.y]).collect();
    let tris = match earcutr::earcut(&flat, &[], 2) {
        Ok(t) if t.len() >= 3 => t,
        _ => return fan(),
    };
    tris.chunks_exact(3)
        .map(|t| {
            // earcut does not promise a winding: keep the polygon's, so normals and culling
            // agree with the file.
            let (a, b, c) = (q[t[0]], q[t[1]], q[t[2]]);
            if (b - a).perp_dot(c - a) < 0.0 {
                [t[0], t[2], t[1]]
            } else {
                [t[0], t[1], t[2]]
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn area(p: &[DVec3], t: &[[usize; 3]]) -> f64 {
        t.iter()
            .map(|t| (p[t[1]] - p[t[0]]).cross(p[t[2]] - p[t[0]]).length() / 2.0)
            .sum()
    }

    fn xy(v: &[(f64, f64)]) -> Vec<DVec3> {
        v.iter().map(|&(x, y)| DVec3::new(x, y, 0.0)).collect()
    }

    #[test]
    fn l_shape_has_its_area() {
        let p = xy(&[(0., 0.), (2., 0.), (2., 1.), (1., 1.), (1., 2.), (0., 2.)]);
        let t = polygon(&p);
        assert_eq!(t.len(), 4);
        assert!((area(&p, &t) - 3.0).abs() < 1e-12);
        // every triangle faces +Z like the polygon
        for t in &t {
            assert!((p[t[1]] - p[t[0]]).cross(p[t[2]] - p[t[0]]).z > 0.0);
        }
    }

    #[test]
    fn convex_keeps_the_fan() {
        let p = xy(&[(0., 0.), (1., 0.), (1., 1.), (0., 1.)]);
        assert_eq!(polygon(&p), vec![[0, 1, 2], [0, 2, 3]]);
    }

    #[test]
    fn tilted_doorway_wall() {
        // A 4x3 wall with a 1x2 doorway cut from the bottom edge, in the plane x = z.
        let p: Vec<DVec3> = [
            (0., 0.),
            (1.5, 0.),
            (1.5, 2.),
            (2.5, 2.),
            (2.5, 0.),
            (4., 0.),
            (4., 3.),
            (0., 3.),
        ]
        .iter()
        .map(|&(a, y)| DVec3::new(a / 2f64.sqrt(), y, a / 2f64.sqrt()))
        .collect();
        let t = polygon(&p);
        assert!((area(&p, &t) - 10.0).abs() < 1e-12, "{}", area(&p, &t));
    }
}
