//! Reading a mesh cache entry back ([`super::get_in`]): the header validated first, then the
//! payload's arrays read and checked part by part (see the format in [`super`]).
use super::{
    content_hash, stamp, Header, MeshMeta, Prepared, SlotRefs, TexMeta, WireMeta, FORMAT, MAGIC,
};
use crate::scene::clusters::Clusters;
use crate::scene::material::{Material, Texture, TextureOptions};
use crate::scene::{Mesh, Scene, Vertex, Wire};
use glam::DVec3;
use std::path::Path;
use std::sync::Arc;

/// Reads an entry: the header first, validated against the model's metadata before any of
/// the payload is read (a miss costs a few small reads), then each mesh's arrays read once,
/// straight into their final, aligned buffers, hashed as they arrive (no whole-file buffer,
/// no copy out of it).
pub(super) fn decode(
    mut file: std::fs::File,
    path: &Path,
    bytes: Option<&[u8]>,
    textures: TextureOptions,
) -> Option<Prepared> {
    let header = read_header(&mut file, path, bytes, textures)?;
    let mut payload = Payload {
        file,
        hasher: xxhash_rust::xxh3::Xxh3::new(),
        left: header.payload_len,
    };
    let meshes = read_meshes(&mut payload, &header.meshes)?;
    let wire = read_wire(&mut payload, &header.wire)?;
    let table = read_textures(&mut payload, &header.textures)?;
    let mut clusters = header.clusters;
    for c in clusters.iter_mut().flatten() {
        c.lod.indices = payload.read(c.lod.index_count)?;
    }
    if payload.left != 0 || payload.hasher.digest128() != header.payload_hash {
        return None;
    }
    let mut materials = header.materials;
    if header.slots.len() != materials.len() {
        return None;
    }
    attach_images(&mut materials, &header.slots, &table)?;
    let warnings = header.warnings;
    if meshes.iter().any(|m| m.material >= materials.len()) {
        return None;
    }
    if !clusters_fit(&meshes, &clusters) {
        return None;
    }
    let [lo, hi] = header.file_bounds;
    let scene = Scene {
        name: header.name,
        meshes,
        materials,
        bounds: header.bounds,
        origin: DVec3::from(header.origin),
        file_bounds: (DVec3::from(lo), DVec3::from(hi)),
        dependencies: header.dependencies.into_iter().map(|d| d.path).collect(),
        warnings,
        wire,
        maps: header.maps,
    };
    Some((scene, clusters))
}

/// The entry's header, if it is one for this model as it is now: magic, header length, cache
/// format and glview version, the model's and every dependency's stamp, the content hash when
/// `bytes` are given, the texture options, and the file's total length must all match. Leaves
/// `file` at the start of the payload.
fn read_header(
    file: &mut std::fs::File,
    path: &Path,
    bytes: Option<&[u8]>,
    textures: TextureOptions,
) -> Option<Header> {
    use std::io::Read;
    let file_len = file.metadata().ok()?.len();
    let mut head = [0u8; 12];
    file.read_exact(&mut head).ok()?;
    if &head[..4] != MAGIC {
        return None;
    }
    let json_len = u64::from_le_bytes(head[4..].try_into().ok()?);
    if json_len > file_len.saturating_sub(12) {
        return None;
    }
    let mut json = vec![0u8; usize::try_from(json_len).ok()?];
    file.read_exact(&mut json).ok()?;
    let header: Header = serde_json::from_slice(&json).ok()?;
    let canonical = path.canonicalize().ok()?;
    let valid = header.format == FORMAT
        && header.glview == env!("CARGO_PKG_VERSION")
        && stamp(&canonical).as_ref() == Some(&header.file)
        && bytes.is_none_or(|b| header.hash == Some(content_hash(b)))
        && header.allow_outside_paths == textures.allow_outside_paths
        && header.max_dimension == textures.max_dimension
        && header
            .dependencies
            .iter()
            .all(|d| stamp(&d.path).as_ref() == Some(d))
        && file_len == 12 + json_len + header.payload_len;
    valid.then_some(header)
}

/// Each mesh's arrays in header order; None if any is short or inconsistent (a partial
/// triangle, an index past the vertices, a per-vertex array of another length).
fn read_meshes(payload: &mut Payload, metas: &[MeshMeta]) -> Option<Vec<Mesh>> {
    let mut meshes = Vec::with_capacity(metas.len());
    for m in metas {
        if m.indices % 3 != 0 {
            return None;
        }
        let vertices: Vec<Vertex> = payload.read(m.vertices)?;
        let indices: Vec<u32> = payload.read(m.indices)?;
        let colors: Vec<[f32; 3]> = payload.read(m.colors)?;
        let color_alpha: Vec<f32> = payload.read(m.color_alpha)?;
        let uv1: Vec<[f32; 2]> = payload.read(m.uv1)?;
        let tangents: Vec<[f32; 4]> = payload.read(m.tangents)?;
        let per_vertex = |n: usize| n == 0 || n == vertices.len();
        if indices.iter().any(|&i| i as usize >= vertices.len())
            || !(per_vertex(colors.len())
                && per_vertex(color_alpha.len())
                && per_vertex(uv1.len())
                && per_vertex(tangents.len()))
        {
            return None;
        }
        meshes.push(Mesh {
            name: m.name.clone(),
            vertices,
            indices,
            material: m.material,
            has_uv: m.has_uv,
            generated_normals: m.generated_normals,
            colors,
            color_alpha,
            uv1,
            tangents,
        });
    }
    Some(meshes)
}

/// The lines and points; None if short or if an index is past the wire's positions.
fn read_wire(payload: &mut Payload, w: &WireMeta) -> Option<Wire> {
    let wire = Wire {
        positions: payload.read(w.positions)?,
        segments: payload.read(w.segments)?,
        points: payload.read(w.points)?,
        colors: payload.read(w.colors)?,
        normals: payload.read(w.normals)?,
    };
    let in_wire = |i: u32| (i as usize) < wire.positions.len();
    let per_position = |n: usize| n == 0 || n == wire.positions.len();
    if !(wire.segments.iter().flatten().all(|&i| in_wire(i))
        && wire.points.iter().all(|&i| in_wire(i))
        && per_position(wire.colors.len())
        && per_position(wire.normals.len()))
    {
        return None;
    }
    Some(wire)
}

/// Every distinct texture's RGBA8 pixels, in the table's order; None if short or if a stated
/// size overflows.
fn read_textures(payload: &mut Payload, metas: &[TexMeta]) -> Option<Vec<Arc<Texture>>> {
    let mut table = Vec::with_capacity(metas.len());
    for t in metas {
        let n = (t.width as usize)
            .checked_mul(t.height as usize)?
            .checked_mul(4)?;
        table.push(Arc::new(Texture {
            path: t.path.clone(),
            image: t.image,
            width: t.width,
            height: t.height,
            rgba: payload.read(n)?,
        }));
    }
    Some(table)
}

/// Gives each material's texture slots their images from `table`; None if a slot and its
/// image reference do not come together (one without the other is corrupt) or a reference is
/// past the table.
fn attach_images(
    materials: &mut [Material],
    slots: &[SlotRefs],
    table: &[Arc<Texture>],
) -> Option<()> {
    for (m, refs) in materials.iter_mut().zip(slots) {
        for (slot, r) in m.slots_mut().into_iter().zip(refs) {
            match (slot, r) {
                (Some(s), Some(i)) => s.image = table.get(*i)?.clone(),
                (None, None) => {}
                _ => return None,
            }
        }
    }
    Some(())
}

/// Whether there is one cluster list per mesh and every cluster lies within its mesh's
/// triangles.
fn clusters_fit(meshes: &[Mesh], clusters: &[Option<Clusters>]) -> bool {
    let fits = |m: &Mesh, c: &Option<Clusters>| {
        let triangles = m.indices.len() as u64 / 3;
        c.as_ref().is_none_or(|c| {
            c.list
                .iter()
                .all(|k| u64::from(k.first) + u64::from(k.count) <= triangles)
                && c.lod.fits(triangles, c.list.len())
                && c.lod
                    .indices
                    .iter()
                    .all(|&i| (i as usize) < m.vertices.len())
        })
    };
    clusters.len() == meshes.len() && meshes.iter().zip(clusters).all(|(m, c)| fits(m, c))
}

/// The entry's payload being read: what is left of its stated length, and its running hash.
struct Payload {
    file: std::fs::File,
    hasher: xxhash_rust::xxh3::Xxh3,
    left: u64,
}

impl Payload {
    /// The next `n` elements, read straight into their final, aligned buffer and hashed; None
    /// past the stated length or the file's end.
    fn read<T: bytemuck::Pod + Default>(&mut self, n: usize) -> Option<Vec<T>> {
        use std::io::Read;
        let bytes = u64::try_from(n.checked_mul(std::mem::size_of::<T>())?).ok()?;
        if bytes > self.left {
            return None;
        }
        self.left -= bytes;
        let mut v = vec![T::default(); n];
        let part = bytemuck::cast_slice_mut::<T, u8>(&mut v);
        self.file.read_exact(part).ok()?;
        self.hasher.update(part);
        Some(v)
    }
}
