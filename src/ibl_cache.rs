//! The precomputed maps on disk, keyed by the environment's content and the settings, so a
//! second start with the same environment skips the precomputation. Stored in the mesh
//! cache's folder as `ibl-KEY.bin` (`pbr::store::bytes`: a JSON header line, then the texels
//! as f32 LE). Anything
//! unreadable is a miss (and rewritten), never an error.
use crate::pbr::precompute::{IblData, IblSettings};
use crate::pbr::store::{bytes, MapStore};
use crate::pbr::EnvSource;
use std::path::PathBuf;

/// Bumped whenever the precomputation's algorithm changes what it writes: part of the key.
const ALGORITHM: &str = "precompute-5";

/// The cache key: the environment's bytes (or its description) and the settings.
fn key(source: &EnvSource, settings: &IblSettings) -> Option<u64> {
    let mut bytes = match source {
        EnvSource::Builtin => b"builtin-sky-1".to_vec(),
        EnvSource::Uniform(c) => format!("uniform {c:?}").into_bytes(),
        EnvSource::File(p) => std::fs::read(p).ok()?,
    };
    bytes.extend_from_slice(serde_json::to_string(settings).ok()?.as_bytes());
    bytes.extend_from_slice(env!("CARGO_PKG_VERSION").as_bytes());
    bytes.extend_from_slice(ALGORITHM.as_bytes());
    // The low 64 bits of the mesh cache's XXH3-128 are plenty to key a handful of files.
    Some(crate::scene::cache::content_hash(&bytes) as u64)
}

fn path(key: u64) -> Option<PathBuf> {
    Some(crate::scene::cache::dir()?.join(format!("ibl-{key:016x}.bin")))
}

fn get(key: u64) -> Option<IblData> {
    bytes::decode(&std::fs::read(path(key)?).ok()?)
}

fn put(key: u64, d: &IblData) {
    let Some(p) = path(key) else { return };
    // Write then rename, so a concurrent reader never sees half a file.
    if let Some(dir) = p.parent() {
        let _ = std::fs::create_dir_all(dir);
    }
    let tmp = p.with_extension(format!("tmp{}", std::process::id()));
    if std::fs::write(&tmp, bytes::encode(d)).is_ok() {
        let _ = std::fs::rename(&tmp, &p);
    }
}

/// The renderer's store of precomputed maps: this folder.
pub(crate) struct DiskMaps;

impl MapStore for DiskMaps {
    fn key(&self, source: &EnvSource, settings: &IblSettings) -> Option<u64> {
        key(source, settings)
    }
    fn get(&self, key: u64) -> Option<IblData> {
        get(key)
    }
    fn put(&self, key: u64, data: &IblData) {
        put(key, data)
    }
}
