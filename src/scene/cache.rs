//! The mesh cache: a second load of a large, unchanged OBJ skips parsing. Entries live in
//! `$GLVIEW_CACHE_DIR`, else `$XDG_CACHE_HOME/glview`, else `~/.cache/glview`, one file per
//! model path. An entry is used only if the file's path, size, modification time and content
//! hash, glview's version, and the size and modification time of every MTL library and
//! texture it used all match; anything else is a miss and the entry is rewritten.
//!
//! Format: `GLVC`, a little-endian u64 header length, a JSON header (metadata, materials,
//! warnings), then each mesh's vertices and indices as raw little-endian arrays.
use super::material::{self, Material, TextureOptions};
use super::{Bounds, Mesh, Scene, Vertex, Warning};
use glam::DVec3;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};
use std::time::UNIX_EPOCH;

/// Files smaller than this parse in well under 100 ms: not worth a cache entry.
pub const MIN_SIZE: u64 = 4 << 20;
const MAGIC: &[u8; 4] = b"GLVC";
const FORMAT: u32 = 1;

#[derive(Serialize, Deserialize, PartialEq, Debug)]
struct Stamp {
    path: PathBuf,
    size: u64,
    mtime_ns: u128,
}

fn stamp(path: &Path) -> Option<Stamp> {
    let m = std::fs::metadata(path).ok()?;
    let mtime_ns = m
        .modified()
        .ok()?
        .duration_since(UNIX_EPOCH)
        .ok()?
        .as_nanos();
    Some(Stamp {
        path: path.to_path_buf(),
        size: m.len(),
        mtime_ns,
    })
}

#[derive(Serialize, Deserialize)]
struct MeshMeta {
    name: String,
    material: usize,
    has_uv: bool,
    generated_normals: usize,
    vertices: usize,
    indices: usize,
}

#[derive(Serialize, Deserialize)]
struct Header {
    format: u32,
    glview: String,
    file: Stamp,
    hash: u64,
    allow_outside_paths: bool,
    dependencies: Vec<Stamp>,
    name: String,
    materials: Vec<Material>,
    textures: Vec<Option<PathBuf>>,
    meshes: Vec<MeshMeta>,
    bounds: Bounds,
    origin: [f64; 3],
    file_bounds: [[f64; 3]; 2],
    warnings: Vec<Warning>,
}

/// The folder entries go in.
pub fn dir() -> Option<PathBuf> {
    if let Some(d) = std::env::var_os("GLVIEW_CACHE_DIR") {
        return Some(PathBuf::from(d));
    }
    let base = std::env::var_os("XDG_CACHE_HOME")
        .map(PathBuf::from)
        .or_else(|| std::env::var_os("HOME").map(|h| PathBuf::from(h).join(".cache")))?;
    Some(base.join("glview"))
}

/// FNV-1a over 8-byte words: fast enough to hash hundreds of MB per second, deterministic
/// across runs and Rust versions (unlike std's hasher).
pub fn content_hash(bytes: &[u8]) -> u64 {
    let mut h = 0xcbf2_9ce4_8422_2325u64;
    let mut chunks = bytes.chunks_exact(8);
    for c in &mut chunks {
        h ^= u64::from_le_bytes([c[0], c[1], c[2], c[3], c[4], c[5], c[6], c[7]]);
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    for &b in chunks.remainder() {
        h ^= u64::from(b);
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    h ^ bytes.len() as u64
}

fn entry_path(model: &Path) -> Option<PathBuf> {
    let canonical = model.canonicalize().ok()?;
    let key = content_hash(canonical.as_os_str().as_encoded_bytes());
    Some(dir()?.join(format!("{key:016x}.glvc")))
}

/// A cached scene for `path` whose bytes are `bytes`, if a valid entry exists.
pub fn get(path: &Path, bytes: &[u8], textures: TextureOptions) -> Option<Scene> {
    let data = std::fs::read(entry_path(path)?).ok()?;
    let (header, mut rest) = parse_header(&data)?;
    let canonical = path.canonicalize().ok()?;
    let valid = header.format == FORMAT
        && header.glview == env!("CARGO_PKG_VERSION")
        && stamp(&canonical).as_ref() == Some(&header.file)
        && header.hash == content_hash(bytes)
        && header.allow_outside_paths == textures.allow_outside_paths
        && header
            .dependencies
            .iter()
            .all(|d| stamp(&d.path).as_ref() == Some(d));
    if !valid {
        return None;
    }
    let mut meshes = Vec::with_capacity(header.meshes.len());
    for m in &header.meshes {
        let vbytes = m.vertices * std::mem::size_of::<Vertex>();
        let ibytes = m.indices * 4;
        if rest.len() < vbytes + ibytes {
            return None;
        }
        // Copies (not casts) because the file's bytes carry no alignment guarantee.
        let vertices: Vec<Vertex> = bytemuck::pod_collect_to_vec(&rest[..vbytes]);
        let indices: Vec<u32> = bytemuck::pod_collect_to_vec(&rest[vbytes..vbytes + ibytes]);
        rest = &rest[vbytes + ibytes..];
        if indices.iter().any(|&i| i as usize >= vertices.len()) {
            return None;
        }
        meshes.push(Mesh {
            name: m.name.clone(),
            vertices,
            indices,
            material: m.material,
            has_uv: m.has_uv,
            generated_normals: m.generated_normals,
            colors: Vec::new(),
        });
    }
    let mut materials = header.materials;
    let mut warnings = header.warnings;
    for (m, t) in materials.iter_mut().zip(&header.textures) {
        if let Some(p) = t {
            match material::decode_texture(p.clone(), textures) {
                Ok(tex) => m.diffuse_map = Some(std::sync::Arc::new(tex)),
                Err(e) => warnings.push(Warning {
                    file: p.clone(),
                    line: None,
                    message: format!("material {}: {e}; using its colours", m.name),
                }),
            }
        }
    }
    if meshes.iter().any(|m| m.material >= materials.len()) {
        return None;
    }
    let [lo, hi] = header.file_bounds;
    Some(Scene {
        name: header.name,
        meshes,
        materials,
        bounds: header.bounds,
        origin: DVec3::from(header.origin),
        file_bounds: (DVec3::from(lo), DVec3::from(hi)),
        dependencies: header.dependencies.into_iter().map(|d| d.path).collect(),
        warnings,
        wire: Default::default(),
        maps: Vec::new(),
    })
}

fn parse_header(data: &[u8]) -> Option<(Header, &[u8])> {
    let rest = data.strip_prefix(MAGIC)?;
    let len = u64::from_le_bytes(rest.get(..8)?.try_into().ok()?) as usize;
    let json = rest.get(8..8 + len)?;
    Some((serde_json::from_slice(json).ok()?, &rest[8 + len..]))
}

/// Stores `scene` for `path`; failures only cost the next load its speed-up.
pub fn put(path: &Path, bytes: &[u8], textures: TextureOptions, scene: &Scene) {
    if let Err(e) = try_put(path, bytes, textures, scene) {
        log::debug!("mesh cache not written for {}: {e}", path.display());
    }
}

fn try_put(
    path: &Path,
    bytes: &[u8],
    textures: TextureOptions,
    scene: &Scene,
) -> std::io::Result<()> {
    let entry = entry_path(path).ok_or_else(|| std::io::Error::other("no cache folder"))?;
    let canonical = path.canonicalize()?;
    let header = Header {
        format: FORMAT,
        glview: env!("CARGO_PKG_VERSION").into(),
        file: stamp(&canonical).ok_or_else(|| std::io::Error::other("no mtime"))?,
        hash: content_hash(bytes),
        allow_outside_paths: textures.allow_outside_paths,
        dependencies: scene.dependencies.iter().filter_map(|d| stamp(d)).collect(),
        name: scene.name.clone(),
        materials: scene.materials.clone(),
        textures: scene
            .materials
            .iter()
            .map(|m| m.diffuse_map.as_ref().map(|t| t.path.clone()))
            .collect(),
        meshes: scene
            .meshes
            .iter()
            .map(|m| MeshMeta {
                name: m.name.clone(),
                material: m.material,
                has_uv: m.has_uv,
                generated_normals: m.generated_normals,
                vertices: m.vertices.len(),
                indices: m.indices.len(),
            })
            .collect(),
        bounds: scene.bounds,
        origin: scene.origin.to_array(),
        file_bounds: [
            scene.file_bounds.0.to_array(),
            scene.file_bounds.1.to_array(),
        ],
        warnings: scene.warnings.clone(),
    };
    let json = serde_json::to_vec(&header).map_err(std::io::Error::other)?;
    let dir = entry.parent().unwrap_or(Path::new("."));
    std::fs::create_dir_all(dir)?;
    // Written beside the entry and renamed: a reader never sees half a file.
    let tmp = entry.with_extension(format!("tmp{}", std::process::id()));
    {
        use std::io::Write;
        let mut w = std::io::BufWriter::new(std::fs::File::create(&tmp)?);
        w.write_all(MAGIC)?;
        w.write_all(&(json.len() as u64).to_le_bytes())?;
        w.write_all(&json)?;
        for m in &scene.meshes {
            w.write_all(bytemuck::cast_slice(&m.vertices))?;
            w.write_all(bytemuck::cast_slice(&m.indices))?;
        }
        w.flush()?;
    }
    std::fs::rename(&tmp, &entry)
}
