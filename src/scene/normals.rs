//! Smooth, area-weighted vertex normals for meshes whose file has none (or broken ones).
use super::Vertex;
use glam::Vec3;
use std::collections::HashMap;

fn key(p: [f32; 3]) -> [u32; 3] {
    // +0.0 and -0.0 are the same point.
    p.map(|x| (x + 0.0).to_bits())
}

/// Face normals weighted by area (the un-normalised cross product), summed per position, so
/// vertices split by UV seams still share one normal. Returns the unit normal per position
/// key; a position touched only by zero-area faces gets +Y rather than NaN.
fn smooth_normals(vertices: &[Vertex], indices: &[u32]) -> HashMap<[u32; 3], Vec3> {
    let mut acc: HashMap<[u32; 3], glam::DVec3> = HashMap::new();
    for t in indices.chunks_exact(3) {
        let t = [t[0], t[1], t[2]];
        let p: [glam::DVec3; 3] =
            std::array::from_fn(|k| Vec3::from(vertices[t[k] as usize].position).as_dvec3());
        let n = (p[1] - p[0]).cross(p[2] - p[0]);
        for i in t {
            *acc.entry(key(vertices[i as usize].position)).or_default() += n;
        }
    }
    acc.into_iter()
        .map(|(k, n)| {
            let n = n.normalize_or_zero().as_vec3();
            (k, if n == Vec3::ZERO { Vec3::Y } else { n })
        })
        .collect()
}

/// In f64: a normal like (0, 0, 1e20) is finite in f32 but squares to infinity there.
fn usable(n: [f32; 3]) -> bool {
    let v = Vec3::from(n).as_dvec3();
    v.is_finite() && v.length_squared() > 1e-20
}

/// Fills in normals that are missing (`all`), zero or not finite; normalises the rest.
/// Returns how many normals were generated.
pub fn repair_normals(vertices: &mut [Vertex], indices: &[u32], all: bool) -> usize {
    let _timer = super::profile::nested(super::profile::Stage::Normals);
    let need = all || vertices.iter().any(|v| !usable(v.normal));
    let smooth = if need {
        smooth_normals(vertices, indices)
    } else {
        HashMap::new()
    };
    let mut generated = 0;
    for v in vertices.iter_mut() {
        if all || !usable(v.normal) {
            v.normal = smooth
                .get(&key(v.position))
                .copied()
                .unwrap_or(Vec3::Y)
                .into();
            generated += 1;
        } else {
            v.normal = Vec3::from(v.normal).as_dvec3().normalize().as_vec3().into();
        }
    }
    generated
}

#[cfg(test)]
mod tests {
    use super::*;

    fn vtx(p: [f32; 3], n: [f32; 3]) -> Vertex {
        Vertex {
            position: p,
            normal: n,
            uv: [0.0; 2],
        }
    }

    #[test]
    fn flat_quad_gets_plus_z() {
        let mut v = vec![
            vtx([0., 0., 0.], [0.; 3]),
            vtx([1., 0., 0.], [0.; 3]),
            vtx([1., 1., 0.], [0.; 3]),
            vtx([0., 1., 0.], [0.; 3]),
        ];
        assert_eq!(repair_normals(&mut v, &[0, 1, 2, 0, 2, 3], true), 4);
        for x in &v {
            assert_eq!(x.normal, [0., 0., 1.]);
        }
    }

    #[test]
    fn area_weighting() {
        // A big triangle facing +Z and a tiny one facing +X share vertex 0.
        let mut v = vec![
            vtx([0., 0., 0.], [0.; 3]),
            vtx([10., 0., 0.], [0.; 3]),
            vtx([0., 10., 0.], [0.; 3]),
            vtx([0., 0.1, 0.], [0.; 3]),
            vtx([0., 0., -0.1], [0.; 3]),
        ];
        repair_normals(&mut v, &[0, 1, 2, 0, 3, 4], true);
        let n = Vec3::from(v[0].normal);
        // The big face dominates; the tiny one (facing -X) only tilts it slightly.
        assert!(n.z > 0.99 && n.x < 0.0 && n.x > -0.01, "{n}");
    }

    #[test]
    fn only_broken_normals_replaced() {
        let mut v = vec![
            vtx([0., 0., 0.], [0., 0., 2.]),
            vtx([1., 0., 0.], [f32::NAN, 0., 0.]),
            vtx([0., 1., 0.], [0., 0., 0.]),
        ];
        assert_eq!(repair_normals(&mut v, &[0, 1, 2], false), 2);
        assert_eq!(v[0].normal, [0., 0., 1.]);
        assert_eq!(v[1].normal, [0., 0., 1.]);
    }

    #[test]
    fn huge_normals_normalise() {
        let mut v = vec![
            vtx([0., 0., 0.], [0., 0., 1e20]),
            vtx([1., 0., 0.], [0., 0., 1e20]),
            vtx([0., 1., 0.], [3e38, 0., 0.]),
        ];
        assert_eq!(repair_normals(&mut v, &[0, 1, 2], false), 0);
        assert_eq!(v[0].normal, [0., 0., 1.]);
        assert_eq!(v[2].normal, [1., 0., 0.]);
    }

    #[test]
    fn zero_area_gives_finite_normal() {
        let mut v = vec![
            vtx([0., 0., 0.], [0.; 3]),
            vtx([1., 0., 0.], [0.; 3]),
            vtx([2., 0., 0.], [0.; 3]),
        ];
        repair_normals(&mut v, &[0, 1, 2], true);
        assert!(v.iter().all(|x| Vec3::from(x.normal).is_finite()));
    }
}
