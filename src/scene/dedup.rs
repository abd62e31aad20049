//! Redundant geometry dropped after loading: a face repeated (the same three vertex indices
//! in any rotation, so the same winding) is drawn once, and a face with zero area is not
//! drawn at all. A file with one triangle repeated 2,000,000 times otherwise costs the
//! rasteriser 2,000,000 times the overdraw of one. Opposite windings are different faces
//! (front and back), so they are both kept.
use super::{Mesh, Warning};
use glam::Vec3;
use std::collections::HashSet;
use std::hash::{BuildHasherDefault, Hasher};
use std::path::Path;

/// A multiply-rotate hasher for three u32s (the Fx hash of rustc): std's SipHash made this
/// pass cost 150-250 ms on a 1M-triangle model; keys here are not attacker-chosen in a way
/// that matters (a collision flood only slows the pass, it cannot change its result).
#[derive(Default)]
struct FaceHasher(u64);

impl Hasher for FaceHasher {
    fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.write_u32(u32::from(b));
        }
    }
    fn write_u32(&mut self, x: u32) {
        self.0 = (self.0.rotate_left(5) ^ u64::from(x)).wrapping_mul(0x51_7c_c1_b7_27_22_0a_95);
    }
    fn write_usize(&mut self, x: usize) {
        self.write_u32(x as u32);
    }
    fn finish(&self) -> u64 {
        self.0
    }
}

type FaceSet = HashSet<[u32; 3], BuildHasherDefault<FaceHasher>>;

/// What [`drop_redundant_faces`] removed.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Dropped {
    pub duplicate: usize,
    pub degenerate: usize,
}

/// Rotates a face so its smallest index comes first, keeping the winding.
fn canonical([a, b, c]: [u32; 3]) -> [u32; 3] {
    if a <= b && a <= c {
        [a, b, c]
    } else if b <= a && b <= c {
        [b, c, a]
    } else {
        [c, a, b]
    }
}

/// Drops duplicate and zero-area faces from one mesh; keeps the first of each duplicate.
pub fn dedup_mesh(mesh: &mut Mesh) -> Dropped {
    let mut seen = FaceSet::with_capacity_and_hasher(mesh.indices.len() / 3, Default::default());
    let mut out = Vec::with_capacity(mesh.indices.len());
    let mut d = Dropped::default();
    let pos = |i: u32| Vec3::from(mesh.vertices[i as usize].position);
    for f in mesh.indices.chunks_exact(3) {
        let f = [f[0], f[1], f[2]];
        let area2 = (pos(f[1]) - pos(f[0])).cross(pos(f[2]) - pos(f[0]));
        if f[0] == f[1] || f[1] == f[2] || f[0] == f[2] || area2 == Vec3::ZERO {
            d.degenerate += 1;
        } else if !seen.insert(canonical(f)) {
            d.duplicate += 1;
        } else {
            out.extend_from_slice(&f);
        }
    }
    mesh.indices = out;
    d
}

/// Drops redundant faces from every mesh (and meshes left empty), adding one warning that
/// counts them.
pub fn drop_redundant_faces(path: &Path, meshes: &mut Vec<Mesh>, warnings: &mut Vec<Warning>) {
    let mut total = Dropped::default();
    for m in meshes.iter_mut() {
        let d = dedup_mesh(m);
        total.duplicate += d.duplicate;
        total.degenerate += d.degenerate;
    }
    meshes.retain(|m| !m.indices.is_empty());
    if total != Dropped::default() {
        warnings.push(Warning {
            file: path.to_path_buf(),
            line: None,
            message: format!(
                "dropped {} duplicate and {} degenerate (zero-area) face(s)",
                total.duplicate, total.degenerate
            ),
        });
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Vertex;

    fn mesh(indices: Vec<u32>) -> Mesh {
        let v = |x: f32, y: f32| Vertex {
            position: [x, y, 0.0],
            ..Default::default()
        };
        Mesh {
            vertices: vec![v(0.0, 0.0), v(1.0, 0.0), v(0.0, 1.0), v(2.0, 0.0)],
            indices,
            ..Default::default()
        }
    }

    #[test]
    fn rotations_are_duplicates_and_reversals_are_not() {
        let mut m = mesh(vec![0, 1, 2, 1, 2, 0, 2, 0, 1, 0, 2, 1, 0, 1, 2]);
        assert_eq!(
            dedup_mesh(&mut m),
            Dropped {
                duplicate: 3,
                degenerate: 0
            }
        );
        assert_eq!(m.indices, vec![0, 1, 2, 0, 2, 1]);
    }

    #[test]
    fn zero_area_faces_are_dropped() {
        // 0, 1, 3 are collinear; 0, 0, 1 repeats a corner.
        let mut m = mesh(vec![0, 1, 3, 0, 0, 1, 0, 1, 2]);
        assert_eq!(dedup_mesh(&mut m).degenerate, 2);
        assert_eq!(m.indices, vec![0, 1, 2]);
    }

    #[test]
    fn one_warning_counts_everything() {
        let mut meshes = vec![mesh(vec![0, 1, 3]), mesh(vec![0, 1, 2, 1, 2, 0])];
        let mut w = Vec::new();
        drop_redundant_faces(Path::new("m.obj"), &mut meshes, &mut w);
        assert_eq!(meshes.len(), 1);
        assert_eq!(w.len(), 1);
        assert_eq!(
            w[0].to_string(),
            "m.obj: dropped 1 duplicate and 1 degenerate (zero-area) face(s)"
        );
    }
}
