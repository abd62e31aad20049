//! The mesh cache: a second load of a large, unchanged OBJ skips parsing. Entries live in
//! `$GLVIEW_CACHE_DIR`, else `$XDG_CACHE_HOME/glview`, else `~/.cache/glview` (on Windows
//! `%LOCALAPPDATA%\glview`), one file per
//! model path. An entry is used only if the file's path, size, modification time and inode,
//! glview's version, and the size and modification time of every MTL library and texture it
//! used all match; anything else is a miss and the entry is rewritten. A hit reads only the
//! entry, never the model: hashing a 93 MB OBJ to validate it cost 137 ms of a 437 ms cached
//! load. The content hash (XXH3-128, stored when the model's bytes were at hand) is compared
//! only on request: `GLVIEW_CACHE_VERIFY=1` ([`set_verify`]), for files rewritten in place
//! within one timestamp tick with the same size. A
//! corrupt or truncated entry (bad header, wrong length, payload hash mismatch) is a miss too,
//! never a panic.
//!
//! The folder is bounded (`--cache-size`, default 1 GiB): a hit refreshes the entry's
//! modification time, and after each write the least recently used entries are deleted until
//! the total fits.
//!
//! Format: `GLVC`, a little-endian u64 header length, a JSON header (metadata, materials,
//! warnings, the texture table, clusters and level tables, each section's length and hash),
//! then two sections of raw little-endian arrays. The first is what a first view draws: per
//! mesh either its compact copy (a large mesh with whole-mesh levels of detail: the vertices
//! those levels use, with colours and second UVs, and the levels' remapped indices; see
//! [`crate::model::meshes`]) or its vertices, indices, colours, colour alphas, second UV set and
//! tangents; then the lines and points, every distinct texture's decoded RGBA8 pixels, and
//! the levels' indices of clustered meshes kept whole. The second holds, per compact mesh,
//! its full arrays and levels' indices. A hit reads the header and the first section (both
//! checked); the second is read, and checked against its own hash, when the scene's meshes
//! are first used (a draw needing more than a whole level, a CPU user); if it fails, the
//! model is read again. On the 2M-triangle sphere the first section is 7 MB of 92.
//! Everything a format can give is stored, so every format is cached, textures included: a
//! hit decodes no image either (a glTF's JPEGs and PNGs cost more than its meshes).
// Without the `native` feature (wasm32) only scene bytes are read ([`from_bytes`]): the disk
// entries' writer and its bounds go unused there.
#![cfg_attr(not(feature = "native"), allow(dead_code))]
use crate::lod::clusters::Clusters;
use crate::model::material::{Material, Texture, TextureOptions};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Arc;
use std::time::{SystemTime, UNIX_EPOCH};
use {crate::model::Bounds, crate::model::Scene, crate::model::Warning};

mod compact;
mod read;
use crate::model::meshes::Compact;
use compact::{compact_of, CompactMeta};

/// Files smaller than this parse in well under 100 ms: not worth a cache entry, unless their
/// images are large (see `worth_an_entry`).
pub const MIN_SIZE: u64 = 4 << 20;
/// Decoded texture pixels above which a model is cached whatever its file size: one 2048²
/// image costs tens of milliseconds to decode (a 3.4 MB GLB can hold five of them).
pub(crate) const MIN_TEXTURE_PIXELS: u64 = 1 << 22;

/// Whether a scene loaded from a file of `size` bytes earns an entry: a large file, or large
/// images (a few MB of JPEG inside a GLB decode far slower than they read back raw).
pub(crate) fn worth_an_entry(size: u64, scene: &Scene) -> bool {
    let pixels: u64 = image_table(scene)
        .0
        .iter()
        .map(|t| u64::from(t.width) * u64::from(t.height))
        .sum();
    size >= MIN_SIZE || pixels >= MIN_TEXTURE_PIXELS
}

/// The scene's distinct images in first-use order (one image in several slots or materials
/// is one entry), and per material its slots' indices into that list.
fn image_table(scene: &Scene) -> (Vec<&Arc<Texture>>, Vec<SlotRefs>) {
    let mut table: Vec<&Arc<Texture>> = Vec::new();
    let refs = scene
        .materials
        .iter()
        .map(|m| {
            m.slots().map(|t| {
                let t = &t.as_ref()?.image;
                Some(
                    match table.iter().position(|u| Arc::ptr_eq(u, t) || **u == *t) {
                        Some(i) => i,
                        None => {
                            table.push(t);
                            table.len() - 1
                        }
                    },
                )
            })
        })
        .collect();
    (table, refs)
}
const MAGIC: &[u8; 4] = b"GLVC";
/// 6: one flat material (issue 28): glTF-shaped values and slots, the MTL's Phong terms apart.
/// 7: the colour rule (issue 31): a material's `colour_rule`, glTF COLOR_0 stored encoded.
/// 8: COLOR_0's alpha per vertex (issue 32).
/// 9: point clouds (issue 31): the wire's per-point colours and normals.
/// 10: OBJ clouds' `v x y z r g b` colours and `vn` normals, glTF POINTS' COLOR_0 and NORMAL
/// (issue 31): entries of 9 hold such clouds without them.
/// 11: the glTF PBR extensions (issue 32): `Material::khr` and its nine texture slots.
/// 12: level of detail (issue 30): clusters' groups and levels, levels' indices at the end.
/// 13: two sections (issue 41): a first view's (large meshes' whole levels compact), then
/// the rest, each with its own hash.
/// 14: KHR_materials_iridescence (issue 37): `Khr::iridescence` and two more slots.
/// 15: KHR_materials_anisotropy (issue 37): `Khr::anisotropy` and one more slot.
/// 16: EXT_mesh_gpu_instancing drawn instanced (issue 37): the scene's `instancing`.
/// 17: glTF cameras, scenes and material variants (issue 37): the scene's `views`.
/// 18: KHR_lights_punctual (issue 37): the scene's `lights`.
/// 19: glTF skins, morph targets and animations (issue 39): scenes that move are not cached (no
///    entry holds a rig), and older entries of such files drew them unposed.
const FORMAT: u32 = 19;
/// The default bound on the cache folder's total size.
pub(crate) const DEFAULT_MAX_BYTES: u64 = 1 << 30;
static MAX_BYTES: AtomicU64 = AtomicU64::new(DEFAULT_MAX_BYTES);
static VERIFY: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

/// Makes hits also compare the model's content hash (reads the whole model again).
pub fn set_verify(on: bool) {
    VERIFY.store(on, Ordering::Relaxed);
}

pub(crate) fn verify() -> bool {
    VERIFY.load(Ordering::Relaxed)
}

/// Sets the bound on the folder's total size (`--cache-size`). A process-wide setting rather
/// than a `LoadOptions` field, so the loader's signature stays as it is.
pub fn set_max_bytes(bytes: u64) {
    MAX_BYTES.store(bytes, Ordering::Relaxed);
}

pub(crate) fn max_bytes() -> u64 {
    MAX_BYTES.load(Ordering::Relaxed)
}

#[derive(Serialize, Deserialize, PartialEq, Debug)]
struct Stamp {
    path: PathBuf,
    size: u64,
    mtime_ns: u128,
    /// A file replaced by another (rename over it, a copy tool keeping times) has a new inode.
    inode: u64,
}

fn stamp(path: &Path) -> Option<Stamp> {
    let m = std::fs::metadata(path).ok()?;
    let mtime_ns = m
        .modified()
        .ok()?
        .duration_since(UNIX_EPOCH)
        .ok()?
        .as_nanos();
    #[cfg(unix)]
    let inode = std::os::unix::fs::MetadataExt::ino(&m);
    #[cfg(not(unix))]
    let inode = 0;
    Some(Stamp {
        path: path.to_path_buf(),
        size: m.len(),
        mtime_ns,
        inode,
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
    colors: usize,
    color_alpha: usize,
    uv1: usize,
    tangents: usize,
}

/// One distinct decoded image (materials sharing an image share its entry).
#[derive(Serialize, Deserialize)]
struct TexMeta {
    path: PathBuf,
    image: Option<usize>,
    width: u32,
    height: u32,
}

/// Lengths of the scene's lines and points.
#[derive(Serialize, Deserialize)]
struct WireMeta {
    positions: usize,
    segments: usize,
    points: usize,
    colors: usize,
    normals: usize,
}

/// A material's texture slots as indices into the header's texture table, in the order of
/// [`Material::slots_mut`].
type SlotRefs = [Option<usize>; SLOTS];
const SLOTS: usize = 19;

#[derive(Serialize, Deserialize)]
struct Header {
    format: u32,
    glview: String,
    file: Stamp,
    /// The model's content hash, when its bytes were at hand at writing time.
    hash: Option<u128>,
    allow_outside_paths: bool,
    /// Textures were decoded under this size limit (`TextureOptions::max_dimension`).
    max_dimension: u32,
    dependencies: Vec<Stamp>,
    name: String,
    materials: Vec<Material>,
    textures: Vec<TexMeta>,
    /// Per material, its slots' entries in `textures`.
    slots: Vec<SlotRefs>,
    meshes: Vec<MeshMeta>,
    wire: WireMeta,
    /// `--check`'s texture statements.
    maps: Vec<String>,
    /// The instanced nodes, so a hit draws them instanced as a miss does.
    instancing: Vec<crate::loaders::gltf::instancing::Instancing>,
    /// The file's cameras, scenes and variants (`--camera` on a hit needs them).
    views: crate::model::views::Views,
    /// The file's lights (glTF KHR_lights_punctual).
    lights: Vec<crate::model::lights::FileLight>,
    bounds: Bounds,
    origin: [f64; 3],
    file_bounds: [[f64; 3]; 2],
    warnings: Vec<Warning>,
    /// Each mesh's clusters (None below `clusters::MIN_TRIANGLES`), built on the indices
    /// stored here (already reordered): a hit prepares nothing.
    clusters: Vec<Option<Clusters>>,
    /// Per mesh, its compact copy's lengths when the first section holds one instead of
    /// the mesh ([`compact_of`]).
    compact: Vec<Option<CompactMeta>>,
    /// Length and XXH3-128 of each section after the header (the first view's, then the
    /// rest): catches truncation and flipped bytes; the rest is checked when it is read.
    first_len: u64,
    first_hash: u128,
    rest_len: u64,
    rest_hash: u128,
}

/// A section's length and hash.
fn section(parts: &[&[u8]]) -> (u64, u128) {
    let mut hasher = xxhash_rust::xxh3::Xxh3::new();
    for p in parts {
        hasher.update(p);
    }
    (
        parts.iter().map(|p| p.len() as u64).sum(),
        hasher.digest128(),
    )
}

/// A folder set by the embedding program, before the environment: tests running many loads
/// in one process point the cache elsewhere without changing the process environment
/// (which other threads, and the GL driver, read concurrently).
static DIR_OVERRIDE: std::sync::Mutex<Option<PathBuf>> = std::sync::Mutex::new(None);

/// Makes every later load of this process use `dir` for its entries.
pub fn set_dir(dir: PathBuf) {
    *DIR_OVERRIDE.lock().unwrap_or_else(|e| e.into_inner()) = Some(dir);
}

/// The folder entries go in.
pub fn dir() -> Option<PathBuf> {
    if let Some(d) = DIR_OVERRIDE
        .lock()
        .unwrap_or_else(|e| e.into_inner())
        .clone()
    {
        return Some(d);
    }
    if let Some(d) = std::env::var_os("GLVIEW_CACHE_DIR") {
        return Some(PathBuf::from(d));
    }
    // Windows keeps per-user caches in %LOCALAPPDATA% (not roamed with the profile).
    #[cfg(windows)]
    let base = std::env::var_os("LOCALAPPDATA").map(PathBuf::from)?;
    #[cfg(not(windows))]
    let base = std::env::var_os("XDG_CACHE_HOME")
        .map(PathBuf::from)
        .or_else(|| std::env::var_os("HOME").map(|h| PathBuf::from(h).join(".cache")))?;
    Some(base.join("glview"))
}

/// XXH3-128: a strong non-cryptographic hash at memory speed (the FNV-1a it replaces was
/// weak and several times slower); deterministic across runs, versions and machines.
pub fn content_hash(bytes: &[u8]) -> u128 {
    xxhash_rust::xxh3::xxh3_128(bytes)
}

fn entry_path(dir: &Path, model: &Path) -> Option<PathBuf> {
    let canonical = model.canonicalize().ok()?;
    let key = xxhash_rust::xxh3::xxh3_64(canonical.as_os_str().as_encoded_bytes());
    Some(dir.join(format!("{key:016x}.glvc")))
}

/// A cached scene for `path`, if a valid entry exists: validated by the file's metadata only,
/// unless `verify` is on (then its content is read and hashed too).
pub fn lookup(path: &Path, textures: TextureOptions) -> Option<Prepared> {
    if verify() {
        let bytes = std::fs::read(path).ok()?;
        return get(path, &bytes, textures);
    }
    get_in(&dir()?, path, None, textures)
}

/// A cached scene for `path` whose bytes are `bytes` (content hash compared), if a valid
/// entry exists.
pub fn get(path: &Path, bytes: &[u8], textures: TextureOptions) -> Option<Prepared> {
    get_in(&dir()?, path, Some(bytes), textures)
}

/// As [`get`], with entries in `dir` and the content compared only when `bytes` are given; a
/// hit marks the entry as recently used.
pub fn get_in(
    dir: &Path,
    path: &Path,
    bytes: Option<&[u8]>,
    textures: TextureOptions,
) -> Option<Prepared> {
    wait_for_writes();
    let entry = entry_path(dir, path)?;
    let file = std::fs::File::open(&entry).ok()?;
    let scene = read::decode(file, path, bytes, textures);
    if scene.is_some() {
        touch(&entry);
    }
    scene
}

/// A scene with its meshes' clusters, as [`crate::lod::clusters::prepare`] makes them.
pub(crate) type Prepared = (Scene, Vec<Option<Clusters>>);

/// Marks an entry as used now (its modification time is the LRU clock).
fn touch(entry: &Path) {
    if let Ok(f) = std::fs::File::options().append(true).open(entry) {
        let _ = f.set_modified(SystemTime::now());
    }
}

/// Entries being written on other threads ([`put_later`]).
static PENDING: std::sync::Mutex<Vec<std::thread::JoinHandle<()>>> =
    std::sync::Mutex::new(Vec::new());

/// Runs `write` (which builds and puts an entry) on another thread; [`wait_for_writes`]
/// waits for it.
pub(crate) fn put_later(write: impl FnOnce() + Send + 'static) {
    let handle = std::thread::Builder::new()
        .name("glview-cache-write".into())
        .spawn(write);
    match handle {
        Ok(h) => PENDING.lock().unwrap_or_else(|e| e.into_inner()).push(h),
        Err(e) => log::debug!("mesh cache entry not written: no thread: {e}"),
    }
}

/// Waits until the entries `put_later` is writing are written: before a process exits
/// (the CLI calls it), and before a lookup, so a second load in one process finds the
/// first one's entry.
pub fn wait_for_writes() {
    let pending = std::mem::take(&mut *PENDING.lock().unwrap_or_else(|e| e.into_inner()));
    for h in pending {
        // A panic in a writer loses one cache entry, nothing else.
        let _ = h.join();
    }
}

/// Stores `scene` and its `clusters` for `path` (and the content hash of `bytes`, the file's,
/// when given); failures only cost the next load its speed-up.
pub(crate) fn put(
    path: &Path,
    bytes: Option<&[u8]>,
    textures: TextureOptions,
    (scene, clusters): (&Scene, &[Option<Clusters>]),
) {
    let Some(dir) = dir() else { return };
    if let Err(e) = put_in(&dir, max_bytes(), path, bytes, textures, (scene, clusters)) {
        log::debug!("mesh cache not written for {}: {e}", path.display());
    }
}

/// As `put`, with entries in `dir` bounded to `max_bytes` in total: least recently used
/// entries are deleted first; an entry larger than the whole bound is not written.
pub fn put_in(
    dir: &Path,
    max_bytes: u64,
    path: &Path,
    bytes: Option<&[u8]>,
    textures: TextureOptions,
    (scene, clusters): (&Scene, &[Option<Clusters>]),
) -> std::io::Result<()> {
    let entry = entry_path(dir, path).ok_or_else(|| std::io::Error::other("no canonical path"))?;
    let canonical = path.canonicalize()?;
    let origin = Origin {
        file: stamp(&canonical).ok_or_else(|| std::io::Error::other("no mtime"))?,
        hash: bytes.map(content_hash),
        textures,
        dependencies: scene.dependencies.iter().filter_map(|d| stamp(d)).collect(),
    };
    std::fs::create_dir_all(dir)?;
    // Written beside the entry and renamed: a reader never sees half a file.
    let tmp = entry.with_extension(format!("tmp{}", std::process::id()));
    {
        let mut w = std::io::BufWriter::new(std::fs::File::create(&tmp)?);
        let written = write_entry(&mut w, origin, max_bytes, (scene, clusters), &|j| j);
        if written.is_err() {
            drop(w);
            let _ = std::fs::remove_file(&tmp);
            return written;
        }
        std::io::Write::flush(&mut w)?;
    }
    std::fs::rename(&tmp, &entry)?;
    evict(dir, max_bytes, &entry)
}

/// Where an entry's scene came from: what a hit validates (none of it for scene bytes).
struct Origin {
    file: Stamp,
    hash: Option<u128>,
    textures: TextureOptions,
    dependencies: Vec<Stamp>,
}

/// The scene as bytes in the entry's format, for a reader with no disk (the browser build:
/// `glview export --live`, `glview serve`'s local mode), which [`from_bytes`] reads back:
/// parsed, normals made, levels of detail and clusters built, textures decoded. No file's
/// stamp is in it, and every path under a `renames` folder (the model's, as the writer's
/// disk has it) is written under its page folder instead (textures, warnings, notes): the
/// page is not told where the model sits.
pub fn to_bytes(
    (scene, clusters): (&Scene, &[Option<Clusters>]),
    renames: &[(&Path, &Path)],
) -> std::io::Result<Vec<u8>> {
    let origin = Origin {
        file: Stamp {
            path: PathBuf::new(),
            size: 0,
            mtime_ns: 0,
            inode: 0,
        },
        hash: None,
        textures: TextureOptions {
            allow_outside_paths: false,
            max_dimension: 0,
        },
        dependencies: Vec::new(),
    };
    let mut out = Vec::new();
    let rename = |json: Vec<u8>| -> Vec<u8> {
        let mut text = String::from_utf8_lossy(&json).into_owned();
        for (from, to) in renames {
            // As the JSON spells them (a Windows path's backslashes escaped).
            let spell = |p: &Path| serde_json::to_string(p).unwrap_or_default();
            let (from, to) = (spell(from), spell(to));
            let trim = |s: &str| s.trim_matches('"').to_string();
            if from.len() > 2 {
                text = text.replace(&trim(&from), &trim(&to));
            }
        }
        text.into_bytes()
    };
    write_entry(&mut out, origin, u64::MAX, (scene, clusters), &rename)?;
    Ok(out)
}

/// A scene [`to_bytes`] wrote; None for anything else (wrong magic, format or glview
/// version, a length or hash that does not match: nothing is trusted unchecked).
pub fn from_bytes(bytes: Vec<u8>) -> Option<Prepared> {
    read::decode_bytes(bytes)
}

/// Writes the entry of `scene`: magic, header (as `header` rewrites its JSON), both
/// sections; an error past `max_bytes`.
fn write_entry(
    out: &mut impl std::io::Write,
    origin: Origin,
    max_bytes: u64,
    (scene, clusters): (&Scene, &[Option<Clusters>]),
    header_json: &dyn Fn(Vec<u8>) -> Vec<u8>,
) -> std::io::Result<()> {
    let (table, slot_refs) = image_table(scene);
    let compacts: Vec<Option<Compact>> = scene
        .meshes
        .iter()
        .zip(clusters)
        .map(|(m, c)| {
            let tangents = scene
                .materials
                .get(m.material)
                .is_some_and(|t| t.needs_tangents());
            compact_of(m, c.as_ref()?, tangents)
        })
        .collect();
    let (first, rest) = sections(scene, clusters, &compacts, &table);
    let w = &scene.wire;
    let (first_len, first_hash) = section(&first);
    let (rest_len, rest_hash) = section(&rest);
    if first_len + rest_len > max_bytes {
        return Err(std::io::Error::other("entry larger than --cache-size"));
    }
    let header = Header {
        format: FORMAT,
        glview: env!("CARGO_PKG_VERSION").into(),
        file: origin.file,
        hash: origin.hash,
        allow_outside_paths: origin.textures.allow_outside_paths,
        max_dimension: origin.textures.max_dimension,
        dependencies: origin.dependencies,
        name: scene.name.clone(),
        materials: scene.materials.clone(),
        textures: table
            .iter()
            .map(|t| TexMeta {
                path: t.path.clone(),
                image: t.image,
                width: t.width,
                height: t.height,
            })
            .collect(),
        slots: slot_refs,
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
                colors: m.colors.len(),
                color_alpha: m.color_alpha.len(),
                uv1: m.uv1.len(),
                tangents: m.tangents.len(),
            })
            .collect(),
        wire: WireMeta {
            positions: w.positions.len(),
            segments: w.segments.len(),
            points: w.points.len(),
            colors: w.colors.len(),
            normals: w.normals.len(),
        },
        maps: scene.maps.clone(),
        instancing: scene.instancing.clone(),
        views: scene.views.clone(),
        lights: scene.lights.clone(),
        bounds: scene.bounds,
        origin: scene.origin.to_array(),
        file_bounds: [
            scene.file_bounds.0.to_array(),
            scene.file_bounds.1.to_array(),
        ],
        warnings: scene.warnings.clone(),
        clusters: clusters.to_vec(),
        compact: compacts
            .iter()
            .map(|k| k.as_ref().map(CompactMeta::of))
            .collect(),
        first_len,
        first_hash,
        rest_len,
        rest_hash,
    };
    let json = header_json(serde_json::to_vec(&header).map_err(std::io::Error::other)?);
    out.write_all(MAGIC)?;
    out.write_all(&(json.len() as u64).to_le_bytes())?;
    out.write_all(&json)?;
    for p in first.iter().chain(&rest) {
        out.write_all(p)?;
    }
    Ok(())
}

/// The payload's parts in file order, borrowed: hashed, then written, never copied into one
/// buffer (a textured entry is mostly its images: 84 MB for DamagedHelmet). The first
/// section is what a first view needs; the rest, what only later views or CPU users need
/// (the full arrays of the meshes kept compact in the first).
fn sections<'a>(
    scene: &'a Scene,
    clusters: &'a [Option<Clusters>],
    compacts: &'a [Option<Compact>],
    table: &[&'a Arc<Texture>],
) -> (Vec<&'a [u8]>, Vec<&'a [u8]>) {
    let w = &scene.wire;
    let (mut first, mut rest): (Vec<&[u8]>, Vec<&[u8]>) = (Vec::new(), Vec::new());
    for ((m, c), k) in scene.meshes.iter().zip(clusters).zip(compacts) {
        let full = [
            bytemuck::cast_slice(&m.vertices),
            bytemuck::cast_slice(&m.indices),
            bytemuck::cast_slice(&m.colors),
            bytemuck::cast_slice(&m.color_alpha),
            bytemuck::cast_slice(&m.uv1),
            bytemuck::cast_slice(&m.tangents),
        ];
        match k {
            Some(k) => {
                first.extend([
                    bytemuck::cast_slice(&k.vertices),
                    bytemuck::cast_slice(&k.indices),
                    bytemuck::cast_slice(&k.colors),
                    bytemuck::cast_slice(&k.color_alpha),
                    bytemuck::cast_slice(&k.uv1),
                ]);
                rest.extend(full);
                rest.extend(c.iter().map(|c| bytemuck::cast_slice(&c.lod.indices)));
            }
            None => first.extend(full),
        }
    }
    first.extend([
        bytemuck::cast_slice(&w.positions),
        bytemuck::cast_slice(&w.segments),
        bytemuck::cast_slice(&w.points),
        bytemuck::cast_slice(&w.colors),
        bytemuck::cast_slice(&w.normals),
    ]);
    first.extend(table.iter().map(|t| &t.rgba[..]));
    // The levels of the large meshes kept whole (the header has their tables).
    first.extend(
        clusters
            .iter()
            .zip(compacts)
            .filter(|(_, k)| k.is_none())
            .filter_map(|(c, _)| c.as_ref())
            .map(|c| bytemuck::cast_slice(&c.lod.indices)),
    );
    (first, rest)
}

/// Deletes the least recently used entries (oldest modification time first) until the
/// folder's entries total at most `max_bytes`; `keep` (the entry just written) goes last.
pub(crate) fn evict(dir: &Path, max_bytes: u64, keep: &Path) -> std::io::Result<()> {
    let mut entries: Vec<(SystemTime, u64, PathBuf)> = std::fs::read_dir(dir)?
        .flatten()
        .filter(|e| e.path().extension().is_some_and(|x| x == "glvc"))
        .filter_map(|e| {
            let m = e.metadata().ok()?;
            Some((m.modified().ok()?, m.len(), e.path()))
        })
        .collect();
    let mut total: u64 = entries.iter().map(|e| e.1).sum();
    entries.sort_by_key(|(t, _, p)| (p == keep, *t));
    for (_, len, p) in entries {
        if total <= max_bytes {
            break;
        }
        if std::fs::remove_file(&p).is_ok() {
            log::debug!("mesh cache: evicted {}", p.display());
            total -= len;
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests;
