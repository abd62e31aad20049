//! Reading a mesh cache entry back ([`crate::cache::get_in`]): the header validated first, then the
//! payload's arrays read and checked part by part (see the format in [`super`]).
use crate::lod::clusters::Clusters;
use crate::model::material::{Material, Texture, TextureOptions};
use crate::model::meshes::{Compact, First, Full, Meshes, Rest};
use crate::model::scene::Parts;
use glam::DVec3;
use std::path::Path;
use std::sync::Arc;
use {
    crate::cache::content_hash, crate::cache::stamp, crate::cache::CompactMeta,
    crate::cache::Header, crate::cache::MeshMeta, crate::cache::Prepared, crate::cache::SlotRefs,
    crate::cache::TexMeta, crate::cache::WireMeta, crate::cache::FORMAT, crate::cache::MAGIC,
};
use {crate::model::Mesh, crate::model::Scene, crate::model::Vertex, crate::model::Wire};

/// Reads an entry: the header first, validated against the model's metadata before any of
/// the payload is read (a miss costs a few small reads), then the first section's arrays
/// read once, straight into their final, aligned buffers, hashed as they arrive (no
/// whole-file buffer, no copy out of it). The second section (the full arrays of meshes the
/// first holds compact) is left in the file until the scene's meshes are first used.
pub(super) fn decode(
    mut file: std::fs::File,
    path: &Path,
    bytes: Option<&[u8]>,
    textures: TextureOptions,
) -> Option<Prepared> {
    let header = read_header(&mut file, path, bytes, textures)?;
    decode_payload(Box::new(file), header, Some((path.to_path_buf(), textures)))
}

/// Reads scene bytes ([`super::to_bytes`]): the header checked for its magic, format, glview
/// version and lengths (there is no file to stamp), then the payload as an entry's.
pub(super) fn decode_bytes(bytes: Vec<u8>) -> Option<Prepared> {
    let len = bytes.len() as u64;
    let mut r = std::io::Cursor::new(bytes);
    let (header, json_len) = read_json(&mut r, len)?;
    if !this_glviews(&header, json_len, len) {
        return None;
    }
    // The second section is checked now, not when the meshes are first used: there is no
    // model to read again, and a lazy failure would have nothing to stand in for it.
    let rest_at = usize::try_from(12 + json_len + header.first_len).ok()?;
    if content_hash(&r.get_ref()[rest_at..]) != header.rest_hash {
        return None;
    }
    decode_payload(Box::new(r), header, None)
}

/// The payload after a validated header; `model` is what is read again if the second
/// section fails its hash (None for scene bytes: then that is an error).
fn decode_payload(
    source: Box<dyn Source>,
    header: Header,
    model: Option<(std::path::PathBuf, TextureOptions)>,
) -> Option<Prepared> {
    let mut payload = Payload {
        file: source,
        hasher: xxhash_rust::xxh3::Xxh3::new(),
        left: header.first_len,
    };
    if header.compact.len() != header.meshes.len() || header.clusters.len() != header.meshes.len() {
        return None;
    }
    let firsts = read_first_meshes(&mut payload, &header.meshes, &header.compact)?;
    let wire = read_wire(&mut payload, &header.wire)?;
    let table = read_textures(&mut payload, &header.textures)?;
    let mut clusters = header.clusters;
    for (c, k) in clusters.iter_mut().zip(&header.compact) {
        if let (Some(c), None) = (c, k) {
            c.lod.indices = payload.read(c.lod.index_count)?;
        }
    }
    if payload.left != 0 || payload.hasher.digest128() != header.first_hash {
        return None;
    }
    crate::profile::set_entry_bytes(header.first_len);
    let mut materials = header.materials;
    if header.slots.len() != materials.len() {
        return None;
    }
    attach_images(&mut materials, &header.slots, &table)?;
    if !firsts.iter().all(|f| first_fits(f, materials.len())) || !clusters_fit(&firsts, &clusters) {
        return None;
    }
    let meshes = if header.compact.iter().all(Option::is_none) {
        let whole = firsts.into_iter().filter_map(|f| match f {
            First::Whole(m) => Some(m),
            First::Compact(_) => None,
        });
        Meshes::from(whole.collect::<Vec<_>>())
    } else {
        let rest = RestOfEntry {
            payload: Payload {
                file: payload.file,
                hasher: xxhash_rust::xxh3::Xxh3::new(),
                left: header.rest_len,
            },
            hash: header.rest_hash,
            metas: header.meshes,
            levels: clusters
                .iter()
                .map(|c| c.as_ref().map(|c| c.lod.index_count))
                .collect(),
            model,
        };
        Meshes::deferred(firsts, Box::new(rest))
    };
    let [lo, hi] = header.file_bounds;
    let parts = Parts {
        meshes,
        materials,
        bounds: header.bounds,
        origin: DVec3::from(header.origin),
        file_bounds: (DVec3::from(lo), DVec3::from(hi)),
        dependencies: header.dependencies.into_iter().map(|d| d.path).collect(),
        warnings: header.warnings,
        wire,
        maps: header.maps,
        instancing: header.instancing,
        views: header.views,
        lights: header.lights,
        motion: None,
    };
    let scene = Scene::new(header.name, parts);
    Some((scene, clusters))
}

/// Whether a first-view mesh's material exists.
fn first_fits(f: &First, materials: usize) -> bool {
    match f {
        First::Whole(m) => m.material < materials,
        First::Compact(c) => c.material < materials,
    }
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
    let file_len = file.metadata().ok()?.len();
    let (header, json_len) = read_json(file, file_len)?;
    let canonical = path.canonicalize().ok()?;
    let valid = this_glviews(&header, json_len, file_len)
        && stamp(&canonical).as_ref() == Some(&header.file)
        && bytes.is_none_or(|b| header.hash == Some(content_hash(b)))
        && header.allow_outside_paths == textures.allow_outside_paths
        && header.max_dimension == textures.max_dimension
        && header
            .dependencies
            .iter()
            .all(|d| stamp(&d.path).as_ref() == Some(d));
    valid.then_some(header)
}

/// Whether `header` is this glview's, of this cache format, and its sections' lengths add up
/// to the `total` bytes there are (after the 12-byte head and `json_len` of header).
fn this_glviews(header: &Header, json_len: u64, total: u64) -> bool {
    header.format == FORMAT
        && header.glview == env!("CARGO_PKG_VERSION")
        && Some(total)
            == (12 + json_len)
                .checked_add(header.first_len)
                .and_then(|n| n.checked_add(header.rest_len))
}

/// The magic, the header's length and the header, from a source of `total` bytes.
fn read_json(r: &mut impl std::io::Read, total: u64) -> Option<(Header, u64)> {
    let mut head = [0u8; 12];
    r.read_exact(&mut head).ok()?;
    if &head[..4] != MAGIC {
        return None;
    }
    let json_len = u64::from_le_bytes(head[4..].try_into().ok()?);
    if json_len > total.saturating_sub(12) {
        return None;
    }
    let mut json = vec![0u8; usize::try_from(json_len).ok()?];
    r.read_exact(&mut json).ok()?;
    Some((serde_json::from_slice(&json).ok()?, json_len))
}

/// What an entry's payload is read from: its file, or scene bytes in memory.
trait Source: std::io::Read + std::io::Seek + Send {}
impl<T: std::io::Read + std::io::Seek + Send> Source for T {}

/// Each mesh's first-view part in header order: its compact copy where the header has one,
/// else its arrays. None if any is short or inconsistent.
fn read_first_meshes(
    payload: &mut Payload,
    metas: &[MeshMeta],
    compact: &[Option<CompactMeta>],
) -> Option<Vec<First>> {
    metas
        .iter()
        .zip(compact)
        .map(|(m, k)| match k {
            Some(k) => read_compact(payload, m, k).map(First::Compact),
            None => read_mesh(payload, m).map(First::Whole),
        })
        .collect()
}

/// A mesh's arrays; None if any is short or inconsistent (a partial triangle, an index past
/// the vertices, a per-vertex array of another length).
fn read_mesh(payload: &mut Payload, m: &MeshMeta) -> Option<Mesh> {
    if !m.indices.is_multiple_of(3) {
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
    Some(Mesh {
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
    })
}

/// A mesh's compact copy; None if short or inconsistent, as [`read_mesh`].
fn read_compact(payload: &mut Payload, m: &MeshMeta, k: &CompactMeta) -> Option<Compact> {
    if !k.indices.is_multiple_of(3) || !m.indices.is_multiple_of(3) || k.vertices > m.vertices {
        return None;
    }
    let vertices: Vec<Vertex> = payload.read(k.vertices)?;
    let indices: Vec<u32> = payload.read(k.indices)?;
    let colors: Vec<[f32; 3]> = payload.read(k.colors)?;
    let color_alpha: Vec<f32> = payload.read(k.color_alpha)?;
    let uv1: Vec<[f32; 2]> = payload.read(k.uv1)?;
    let per_vertex = |n: usize| n == 0 || n == vertices.len();
    if indices.iter().any(|&i| i as usize >= vertices.len())
        || !(per_vertex(colors.len()) && per_vertex(color_alpha.len()) && per_vertex(uv1.len()))
    {
        return None;
    }
    let f = f32::from_bits;
    Some(Compact {
        material: m.material,
        has_uv: m.has_uv,
        triangles: m.indices / 3,
        vertex_count: m.vertices,
        vertices,
        indices,
        first: k.first,
        colors,
        color_alpha,
        uv1,
        center: [f(k.sphere[0]), f(k.sphere[1]), f(k.sphere[2])],
        radius: f(k.sphere[3]),
        terminator_lift: f(k.lift),
    })
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
/// triangles; a compact copy's triangles are its mesh's last levels, all of them.
fn clusters_fit(meshes: &[First], clusters: &[Option<Clusters>]) -> bool {
    let fits = |m: &First, c: &Option<Clusters>| {
        let (triangles, compact) = match m {
            First::Whole(m) => (m.indices.len() as u64 / 3, None),
            First::Compact(k) => (k.triangles as u64, Some(k)),
        };
        let Some(c) = c else {
            return compact.is_none();
        };
        let runs = c
            .list
            .iter()
            .all(|k| u64::from(k.first) + u64::from(k.count) <= triangles);
        let levels = match (m, compact) {
            (First::Whole(m), _) => {
                c.lod.fits(triangles, c.list.len())
                    && c.lod
                        .indices
                        .iter()
                        .all(|&i| (i as usize) < m.vertices.len())
            }
            (_, Some(k)) => {
                c.lod.tables_fit(triangles, c.list.len())
                    && u64::from(k.first) >= triangles
                    && u64::from(k.first) + k.indices.len() as u64 / 3
                        == triangles + c.lod.index_count as u64 / 3
            }
            _ => false,
        };
        runs && levels
    };
    clusters.len() == meshes.len() && meshes.iter().zip(clusters).all(|(m, c)| fits(m, c))
}

/// The entry's second section, read when the scene's meshes are first used: the full
/// arrays and levels' indices of the meshes the first section held compact.
struct RestOfEntry {
    payload: Payload,
    hash: u128,
    metas: Vec<MeshMeta>,
    /// Per mesh, its levels' index count when it has clusters.
    levels: Vec<Option<usize>>,
    /// Read again, whole, if the section fails its hash: the same scene (loading is
    /// deterministic), at a cold load's cost; None for scene bytes (nothing to read again).
    model: Option<(std::path::PathBuf, TextureOptions)>,
}

impl Rest for RestOfEntry {
    fn read(self: Box<Self>, first: Vec<Option<Mesh>>) -> Result<Full, String> {
        let (model, count) = (self.model.clone(), self.metas.len());
        let t = web_time::Instant::now();
        if let Some(full) = self.read_section(first) {
            log::debug!(
                "the meshes' full arrays read from the mesh cache in {:.0} ms",
                t.elapsed().as_secs_f64() * 1e3
            );
            return Ok(full);
        }
        let Some((model, textures)) = model else {
            return Err("the scene's bytes are corrupt past their first section".into());
        };
        log::warn!(
            "{}: the mesh cache entry is corrupt past its first section: the model is read again",
            model.display()
        );
        reload(&model, textures, count)
    }
}

impl RestOfEntry {
    fn read_section(mut self, mut first: Vec<Option<Mesh>>) -> Option<Full> {
        use std::io::Seek;
        let start = self.payload.file.stream_position().ok()?;
        let mut levels = vec![None; first.len()];
        for (i, slot) in first.iter_mut().enumerate() {
            if slot.is_some() {
                continue;
            }
            let m = read_mesh(&mut self.payload, self.metas.get(i)?)?;
            let count = (*self.levels.get(i)?)?;
            let l: Vec<u32> = self.payload.read(count)?;
            if l.iter().any(|&k| k as usize >= m.vertices.len()) {
                return None;
            }
            levels[i] = Some(l);
            *slot = Some(m);
        }
        if self.payload.left != 0 || self.payload.hasher.digest128() != self.hash {
            return None;
        }
        let bytes = self.payload.file.stream_position().ok()? - start;
        Some(Full {
            meshes: first.into_iter().collect::<Option<Vec<_>>>()?,
            levels,
            bytes,
        })
    }
}

/// The model read again without the cache, prepared as the entry's writer prepared it; an
/// error if it no longer has the entry's `count` meshes.
fn reload(model: &Path, textures: TextureOptions, count: usize) -> Result<Full, String> {
    let opts = crate::load::options::LoadOptions {
        textures,
        ..Default::default()
    };
    let mut scene = crate::load::load(model, &opts).map_err(|e| e.to_string())?;
    let clusters = crate::lod::clusters::prepare(&mut scene);
    let levels = clusters
        .into_iter()
        .map(|c| c.map(|c| c.lod.indices))
        .collect();
    let meshes = std::mem::take(&mut *scene.meshes);
    if meshes.len() != count {
        return Err(format!(
            "{}: read again for a corrupt mesh cache entry, it has {} meshes, not {count}",
            model.display(),
            meshes.len()
        ));
    }
    Ok(Full {
        meshes,
        levels,
        bytes: 0,
    })
}

/// The entry's payload being read: what is left of its stated length, and its running hash.
struct Payload {
    file: Box<dyn Source>,
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
