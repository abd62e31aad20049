//! The compact copies a mesh cache entry's first section holds of large meshes
//! ([`crate::model::meshes::Compact`]): a mesh's whole-mesh levels of detail over only the
//! vertices they use, so a cached first view reads and uploads a few MB, not the mesh.
use crate::lod::clusters::Clusters;
use crate::model::meshes::Compact;
use crate::model::Mesh;
use serde::{Deserialize, Serialize};

/// A compact copy's lengths in the first section, and what the renderer would compute
/// from the full arrays (as f32 bits: JSON's decimal text need not read back exact).
#[derive(Serialize, Deserialize, Clone, Debug)]
pub(super) struct CompactMeta {
    pub(super) vertices: usize,
    pub(super) indices: usize,
    pub(super) colors: usize,
    pub(super) color_alpha: usize,
    pub(super) uv1: usize,
    /// The first whole level's first triangle in the full index buffer (mesh, then levels).
    pub(super) first: u32,
    /// Bounding sphere centre and radius, and terminator lift, as `f32::to_bits`.
    pub(super) sphere: [u32; 4],
    pub(super) lift: u32,
}

impl CompactMeta {
    pub(super) fn of(c: &Compact) -> CompactMeta {
        CompactMeta {
            vertices: c.vertices.len(),
            indices: c.indices.len(),
            colors: c.colors.len(),
            color_alpha: c.color_alpha.len(),
            uv1: c.uv1.len(),
            first: c.first,
            sphere: [
                c.center[0].to_bits(),
                c.center[1].to_bits(),
                c.center[2].to_bits(),
                c.radius.to_bits(),
            ],
            lift: c.terminator_lift.to_bits(),
        }
    }
}

/// The compact copy of `m` (cut into `clusters`), when it has whole-mesh levels that end
/// its levels' indices and its material asks for no tangents (generated ones are computed
/// over the whole mesh at upload).
pub(super) fn compact_of(m: &Mesh, clusters: &Clusters, tangents: bool) -> Option<Compact> {
    let lod = &clusters.lod;
    let first = lod.whole.first()?.part.first;
    let base = u32::try_from(m.triangle_count()).ok()?;
    let end = base as usize + lod.indices.len() / 3;
    let contiguous = lod
        .whole
        .windows(2)
        .all(|w| w[0].part.first + w[0].part.count == w[1].part.first)
        && lod
            .whole
            .last()
            .is_some_and(|l| (l.part.first + l.part.count) as usize == end);
    if !contiguous || first < base || (m.has_uv && tangents) {
        return None;
    }
    let tail = &lod.indices[(first - base) as usize * 3..];
    // Vertices in order of first use; the triangles keep their order and corners.
    let mut remap = vec![u32::MAX; m.vertices.len()];
    let mut used = Vec::new();
    let indices = tail
        .iter()
        .map(|&i| {
            let r = &mut remap[i as usize];
            if *r == u32::MAX {
                *r = used.len() as u32;
                used.push(i as usize);
            }
            *r
        })
        .collect();
    let pick = |n: usize| n == m.vertices.len();
    let (center, radius) = crate::model::bounding_sphere(&m.vertices);
    Some(Compact {
        material: m.material,
        has_uv: m.has_uv,
        triangles: m.triangle_count(),
        vertex_count: m.vertices.len(),
        vertices: used.iter().map(|&i| m.vertices[i]).collect(),
        indices,
        first,
        colors: if pick(m.colors.len()) {
            used.iter().map(|&i| m.colors[i]).collect()
        } else {
            Vec::new()
        },
        color_alpha: if pick(m.color_alpha.len()) {
            used.iter().map(|&i| m.color_alpha[i]).collect()
        } else {
            Vec::new()
        },
        uv1: if pick(m.uv1.len()) {
            used.iter().map(|&i| m.uv1[i]).collect()
        } else {
            Vec::new()
        },
        center: center.to_array(),
        radius,
        terminator_lift: crate::model::terminator_lift(m) as f32,
    })
}
