//! The precomputed maps on disk, keyed by the environment's content and the settings, so a
//! second start with the same environment skips the precomputation. Stored in the mesh
//! cache's folder as `ibl-KEY.bin`: a JSON header line, then the texels as f32 LE. Anything
//! unreadable is a miss (and rewritten), never an error.
use crate::pbr::precompute::{Cube, IblData, IblSettings, Lut};
use crate::pbr::store::MapStore;
use crate::pbr::EnvSource;
use std::path::PathBuf;

const MAGIC: &[u8] = b"glview-ibl 1\n";
/// Bumped whenever the precomputation's algorithm changes what it writes: part of the key.
const ALGORITHM: &str = "precompute-5";

#[derive(serde::Serialize, serde::Deserialize)]
struct Header {
    settings: IblSettings,
    irradiance: u32,
    specular: Vec<u32>,
    lut: u32,
}

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
    let data = std::fs::read(path(key)?).ok()?;
    let rest = data.strip_prefix(MAGIC)?;
    let nl = rest.iter().position(|&b| b == b'\n')?;
    let h: Header = serde_json::from_slice(&rest[..nl]).ok()?;
    let body = &rest[nl + 1..];
    if body.len() % 4 != 0 {
        return None;
    }
    let floats: Vec<f32> = body
        .chunks_exact(4)
        .map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]]))
        .collect();
    let mut at = 0usize;
    let mut take = |n: usize| -> Option<&[f32]> {
        let s = floats.get(at..at + n)?;
        at += n;
        Some(s)
    };
    let mut cube = |size: u32| -> Option<Cube> {
        let n = (size * size) as usize;
        let mut faces = Vec::with_capacity(6);
        for _ in 0..6 {
            let f = take(n * 3)?;
            faces.push(f.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect());
        }
        Some(Cube { size, faces })
    };
    let irradiance = cube(h.irradiance)?;
    let mut specular = Vec::new();
    for &s in &h.specular {
        specular.push(cube(s)?);
    }
    let n = (h.lut * h.lut) as usize;
    let lut = take(n * 3)?
        .chunks_exact(3)
        .map(|c| [c[0], c[1], c[2]])
        .collect();
    if at != floats.len() {
        return None;
    }
    Some(IblData {
        settings: h.settings,
        irradiance,
        specular,
        lut: Lut {
            size: h.lut,
            texels: lut,
        },
        compute_ms: 0.0,
    })
}

fn put(key: u64, d: &IblData) {
    let Some(p) = path(key) else { return };
    let h = Header {
        settings: d.settings,
        irradiance: d.irradiance.size,
        specular: d.specular.iter().map(|c| c.size).collect(),
        lut: d.lut.size,
    };
    let mut out = MAGIC.to_vec();
    out.extend(serde_json::to_vec(&h).unwrap_or_default());
    out.push(b'\n');
    let mut push = |v: f32| out.extend_from_slice(&v.to_le_bytes());
    for c in std::iter::once(&d.irradiance).chain(&d.specular) {
        for f in &c.faces {
            for t in f {
                t.iter().for_each(|&v| push(v));
            }
        }
    }
    for t in &d.lut.texels {
        t.iter().for_each(|&v| push(v));
    }
    // Write then rename, so a concurrent reader never sees half a file.
    if let Some(dir) = p.parent() {
        let _ = std::fs::create_dir_all(dir);
    }
    let tmp = p.with_extension(format!("tmp{}", std::process::id()));
    if std::fs::write(&tmp, &out).is_ok() {
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
