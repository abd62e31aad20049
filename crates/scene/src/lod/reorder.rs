//! The order of a large mesh's triangles ([`crate::lod::clusters`]): compact patches, each in
//! vertex-cache order. No GL here.
use crate::lod::clusters::{run_length, MIN_TRIANGLES};
use crate::model::Vertex;
use glam::Vec3;
use rayon::prelude::*;

/// Reorders `indices` (whole triangles) into compact patches: triangles sorted along a Morton
/// curve of their centroids, cut into blocks of `crate::lod::levels::GROUP` clusters, each block then put
/// in meshopt's FIFO vertex-cache order. A block is one compact patch (a run of 256 triangles
/// in FIFO order over the whole mesh was a long strip: its locked border stopped the
/// simplifier of the levels of detail at a fifth of the triangles, and its wide sphere
/// culled less), and any run inside it is a patch too. Same triangles, same winding; only
/// their order changes (which changes no pixel of an opaque depth-tested mesh except where
/// two triangles tie exactly in depth). Deterministic: ties in the curve keep file order.
pub fn reorder(vertices: &[Vertex], indices: &mut [u32]) {
    let triangles = indices.len() / 3;
    if triangles < MIN_TRIANGLES {
        return;
    }
    let block = run_length(triangles) * crate::lod::levels::GROUP;
    let (lo, hi) = vertices
        .par_iter()
        .fold(
            || (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)),
            |(lo, hi), v| {
                let p = Vec3::from(v.position);
                (lo.min(p), hi.max(p))
            },
        )
        .reduce(
            || (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)),
            |a, b| (a.0.min(b.0), a.1.max(b.1)),
        );
    // A counting sort by cell of a 64³ grid in Morton order: linear and stable (file order
    // within a cell), where a comparison sort of the full codes cost 60 ms more on the
    // 2M-triangle sphere; the FIFO pass orders each block's triangles anyway.
    let cells = (1usize << (3 * CELL_BITS)) as u32;
    let scale = Vec3::splat((1u32 << CELL_BITS) as f32) / (hi - lo).max(Vec3::splat(1e-30));
    let top = Vec3::splat(((1u32 << CELL_BITS) - 1) as f32);
    let keys: Vec<u32> = indices
        .par_chunks_exact(3)
        .map(|tri| {
            let c = tri
                .iter()
                .map(|&i| Vec3::from(vertices[i as usize].position))
                .sum::<Vec3>()
                / 3.0;
            let q = ((c - lo) * scale).clamp(Vec3::ZERO, top);
            morton(q.x as u64, q.y as u64, q.z as u64) as u32
        })
        .collect();
    let mut start = vec![0u32; cells as usize + 1];
    for &k in &keys {
        start[k as usize + 1] += 1;
    }
    for c in 0..cells as usize {
        start[c + 1] += start[c];
    }
    let mut sorted = vec![0u32; indices.len()];
    for (t, &k) in keys.iter().enumerate() {
        let at = start[k as usize] as usize * 3;
        start[k as usize] += 1;
        sorted[at..at + 3].copy_from_slice(&indices[t * 3..t * 3 + 3]);
    }
    drop(keys);
    indices.copy_from_slice(&sorted);
    drop(sorted);
    indices.par_chunks_mut(block * 3).for_each(fifo_local);
}

/// meshopt's FIFO vertex-cache order for one block, on vertex numbers counted from the
/// block's lowest (the optimiser's tables are as long as the vertex count: the mesh's would
/// cost a clear of megabytes per block), or renumbered when the block's span is wide.
fn fifo_local(block: &mut [u32]) {
    // No meshoptimizer in the browser build: blocks keep their Morton order there (a scene
    // there is reordered natively, in the mesh cache's entry, or drawn in file order).
    #[cfg(not(feature = "native"))]
    {
        let _ = block;
    }
    #[cfg(feature = "native")]
    fifo_native(block);
}

#[cfg(feature = "native")]
fn fifo_native(block: &mut [u32]) {
    let (lo, hi) = block
        .iter()
        .fold((u32::MAX, 0), |(lo, hi), &i| (lo.min(i), hi.max(i)));
    if ((hi - lo) as usize) < block.len() * 16 {
        block.iter_mut().for_each(|i| *i -= lo);
        meshopt::optimize_vertex_cache_fifo_in_place(block, (hi - lo) as usize + 1, 16);
        block.iter_mut().for_each(|i| *i += lo);
        return;
    }
    let mut local: Vec<u32> = block.to_vec();
    local.sort_unstable();
    local.dedup();
    for i in block.iter_mut() {
        *i = local.binary_search(i).expect("from the block") as u32;
    }
    meshopt::optimize_vertex_cache_fifo_in_place(block, local.len(), 16);
    for i in block.iter_mut() {
        *i = local[*i as usize];
    }
}

/// Bits per axis of the reordering's grid.
const CELL_BITS: u32 = 6;

/// The 63-bit Morton code of three 21-bit coordinates.
fn morton(x: u64, y: u64, z: u64) -> u64 {
    fn spread(mut v: u64) -> u64 {
        v &= 0x1f_ffff;
        v = (v | v << 32) & 0x1f_0000_0000_ffff;
        v = (v | v << 16) & 0x1f_0000_ff00_00ff;
        v = (v | v << 8) & 0x100f_00f0_0f00_f00f;
        v = (v | v << 4) & 0x10c3_0c30_c30c_30c3;
        (v | v << 2) & 0x1249_2492_4924_9249
    }
    spread(x) | spread(y) << 1 | spread(z) << 2
}
