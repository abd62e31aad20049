//! Redundant geometry dropped after loading: a face repeated (the same three vertex indices
//! in any rotation, so the same winding) is drawn once, and a face with zero area is not
//! drawn at all. A file with one triangle repeated 2,000,000 times otherwise costs the
//! rasteriser 2,000,000 times the overdraw of one. Opposite windings are different faces
//! (front and back), so they are both kept.
use glam::Vec3;
use std::collections::HashSet;
use std::path::Path;
use {crate::model::Mesh, crate::model::Warning};

/// foldhash: fast, well mixed (the byte-wise multiply-rotate hash used before clustered
/// sequential vertex numbers, and a 1M-triangle mesh took ~100 ms here) and randomly seeded.
type FaceSet = HashSet<[u32; 3], foldhash::fast::RandomState>;

/// What [`drop_redundant_faces`] removed.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct Dropped {
    pub(crate) duplicate: usize,
    pub(crate) degenerate: usize,
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

/// Hash shards for duplicate search: each is searched on its own (in parallel), and a face
/// can only duplicate a face of its own shard.
const SHARDS: usize = 16;

/// Drops duplicate and zero-area faces from one mesh; keeps the first of each duplicate.
/// Faces are classified in parallel, then searched for duplicates shard by shard (a shard's
/// faces in file order, so the first of each stays): the same result as one pass over a
/// single set, without its cache misses on one thread (110 ms on the 1M-triangle sphere).
pub(crate) fn dedup_mesh(mesh: &mut Mesh) -> Dropped {
    use rayon::prelude::*;
    use std::hash::BuildHasher;
    let pos = |i: u32| Vec3::from(mesh.vertices[i as usize].position);
    let hasher = foldhash::fast::RandomState::default();
    // Per face: None when degenerate, else its canonical corners and hash.
    let faces: Vec<Option<([u32; 3], u64)>> = mesh
        .indices
        .par_chunks_exact(3)
        .map(|f| {
            let f = [f[0], f[1], f[2]];
            let area2 = (pos(f[1]) - pos(f[0])).cross(pos(f[2]) - pos(f[0]));
            if f[0] == f[1] || f[1] == f[2] || f[0] == f[2] || area2 == Vec3::ZERO {
                None
            } else {
                let c = canonical(f);
                Some((c, hasher.hash_one(c)))
            }
        })
        .collect();
    // Faces grouped by shard, each group in file order. Each entry carries its key, so a
    // shard reads one contiguous slice (looking keys up by face number missed the cache on
    // every face).
    let (start, order) = crate::geometry::buckets::group(
        SHARDS,
        faces
            .iter()
            .enumerate()
            .filter_map(|(k, f)| f.map(|(c, h)| ((h >> 60) as usize % SHARDS, (c, k as u32)))),
    );
    let duplicates: Vec<Vec<u32>> = (0..SHARDS)
        .into_par_iter()
        .map(|shard| {
            let group = &order[start[shard]..start[shard + 1]];
            let mut seen = FaceSet::with_capacity_and_hasher(group.len(), Default::default());
            group
                .iter()
                .filter(|(c, _)| !seen.insert(*c))
                .map(|&(_, k)| k)
                .collect()
        })
        .collect();
    let mut drop = vec![false; faces.len()];
    for &k in duplicates.iter().flatten() {
        drop[k as usize] = true;
    }
    let d = Dropped {
        duplicate: duplicates.iter().map(Vec::len).sum(),
        degenerate: faces.iter().filter(|f| f.is_none()).count(),
    };
    if d != Dropped::default() {
        mesh.indices = mesh
            .indices
            .chunks_exact(3)
            .zip(faces.iter().zip(&drop))
            .filter(|(_, (f, &dropped))| f.is_some() && !dropped)
            .flat_map(|(t, _)| t.iter().copied())
            .collect();
    }
    d
}

/// Drops redundant faces from every mesh (and meshes left empty), adding one warning that
/// counts them.
pub(crate) fn drop_redundant_faces(
    path: &Path,
    meshes: &mut Vec<Mesh>,
    warnings: &mut Vec<Warning>,
) {
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
    use crate::model::Vertex;

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
