//! Where precomputed maps are kept between runs, given by the caller: the renderer has no
//! files. The native library keeps them in the mesh cache's folder (`ibl_cache.rs` there);
//! the browser build is given them as bytes ([`Given`], [`bytes`]) or computes them.
use super::precompute::{IblData, IblSettings};
use super::EnvSource;
use std::sync::{Arc, OnceLock};

/// A store of precomputed maps. Anything it cannot read is a miss, never an error.
pub trait MapStore: Send + Sync {
    /// The key of these maps, or `None` when they cannot be keyed (an unreadable file).
    fn key(&self, source: &EnvSource, settings: &IblSettings) -> Option<u64>;
    fn get(&self, key: u64) -> Option<IblData>;
    fn put(&self, key: u64, data: &IblData);
}

static STORE: OnceLock<Arc<dyn MapStore>> = OnceLock::new();

/// Gives the renderer its store, once (later calls change nothing).
pub fn set_store(s: Arc<dyn MapStore>) {
    let _ = STORE.set(s);
}

pub(crate) fn store() -> Option<&'static Arc<dyn MapStore>> {
    STORE.get()
}

/// Maps handed over ready (the browser's, from `glview export --live`'s page): a request
/// with the settings they were computed with gets them, whatever its source (a page has
/// the one environment its maps were made from); any other is computed as without a store.
pub struct Given(pub IblData);

impl MapStore for Given {
    fn key(&self, _: &EnvSource, settings: &IblSettings) -> Option<u64> {
        (*settings == self.0.settings).then_some(0)
    }
    fn get(&self, _: u64) -> Option<IblData> {
        Some(self.0.clone())
    }
    fn put(&self, _: u64, _: &IblData) {}
}

/// The maps as bytes: a magic line, a JSON header line (settings, the cubes' and table's
/// sizes), then every texel (irradiance, each specular level, the table) as f32 or f16,
/// little-endian. The disk store keeps f32, exactly what was computed. A page
/// (`glview export --live`) is given f16, half the bytes and no less exact where it
/// draws: the float upload makes RGBA16F textures, and the driver rounds f32 to f16 to
/// nearest-even as `half` does, so the textures hold the same values either way. (Only
/// the RGBM path, for contexts without half-float textures, would quantise the rounded
/// values; the browser's PBR tier is WebGL 2's, which always has them.)
pub mod bytes {
    use super::super::precompute::{Cube, IblData, IblSettings, Lut};

    const MAGIC: &[u8] = b"glview-ibl 1\n";
    const MAGIC_HALF: &[u8] = b"glview-ibl-f16 1\n";

    #[derive(serde::Serialize, serde::Deserialize)]
    struct Header {
        settings: IblSettings,
        irradiance: u32,
        specular: Vec<u32>,
        lut: u32,
    }

    /// Largest face or table side read back: a header can ask for no more memory than the
    /// bytes could fill anyway (the body's length is checked first), but this keeps the
    /// arithmetic in range.
    const MAX_SIDE: u32 = 4096;

    /// `data` as bytes, f32.
    pub fn encode(d: &IblData) -> Vec<u8> {
        encode_with(d, MAGIC, |out, v| out.extend_from_slice(&v.to_le_bytes()))
    }

    /// `data` as bytes, f16 (half the size; see the module's note).
    pub fn encode_half(d: &IblData) -> Vec<u8> {
        encode_with(d, MAGIC_HALF, |out, v| {
            out.extend_from_slice(&half::f16::from_f32(v).to_le_bytes())
        })
    }

    fn encode_with(d: &IblData, magic: &[u8], put: impl Fn(&mut Vec<u8>, f32)) -> Vec<u8> {
        let h = Header {
            settings: d.settings,
            irradiance: d.irradiance.size,
            specular: d.specular.iter().map(|c| c.size).collect(),
            lut: d.lut.size,
        };
        let mut out = magic.to_vec();
        out.extend(serde_json::to_vec(&h).unwrap_or_default());
        out.push(b'\n');
        let mut push = |v: f32| put(&mut out, v);
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
        out
    }

    /// The maps of [`encode`]'s or [`encode_half`]'s bytes; None for anything else (a
    /// short, long or foreign file).
    pub fn decode(data: &[u8]) -> Option<IblData> {
        let (rest, width) = match data.strip_prefix(MAGIC) {
            Some(rest) => (rest, 4),
            None => (data.strip_prefix(MAGIC_HALF)?, 2),
        };
        let nl = rest.iter().position(|&b| b == b'\n')?;
        let h: Header = serde_json::from_slice(&rest[..nl]).ok()?;
        let body = &rest[nl + 1..];
        let cubes = std::iter::once(h.irradiance).chain(h.specular.iter().copied());
        let mut texels: u64 = 0;
        for (s, faces) in cubes.map(|s| (s, 6)).chain(std::iter::once((h.lut, 1))) {
            if s == 0 || s > MAX_SIDE {
                return None;
            }
            texels += u64::from(s) * u64::from(s) * faces;
        }
        if body.len() as u64 != texels * 3 * width as u64 {
            return None;
        }
        let mut floats = body.chunks_exact(width).map(|c| match c {
            [a, b, c, d] => f32::from_le_bytes([*a, *b, *c, *d]),
            [a, b] => half::f16::from_le_bytes([*a, *b]).to_f32(),
            _ => 0.0,
        });
        let mut take = |n: usize| -> Vec<[f32; 3]> {
            (0..n)
                .map(|_| [0; 3].map(|_| floats.next().unwrap_or(0.0)))
                .collect()
        };
        let mut cube = |size: u32| Cube {
            size,
            faces: (0..6).map(|_| take((size * size) as usize)).collect(),
        };
        let irradiance = cube(h.irradiance);
        let specular = h.specular.iter().map(|&s| cube(s)).collect();
        let lut = Lut {
            size: h.lut,
            texels: take((h.lut * h.lut) as usize),
        };
        Some(IblData {
            settings: h.settings,
            irradiance,
            specular,
            lut,
            compute_ms: 0.0,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::bytes::{decode, encode, encode_half};
    use super::*;
    use crate::pbr::env::Environment;
    use crate::pbr::precompute::{compute, IblSettings};

    fn small() -> IblData {
        let s = IblSettings {
            irradiance_size: 4,
            specular_size: 8,
            levels: 3,
            samples: 8,
            lut_size: 8,
            lut_samples: 8,
        };
        compute(&Environment::builtin(), &s)
    }

    #[test]
    fn maps_read_back_exactly_and_nothing_else_is_taken() {
        let d = small();
        let b = encode(&d);
        let back = decode(&b).expect("decodes");
        assert_eq!(
            (back.irradiance, back.specular, back.lut),
            (d.irradiance.clone(), d.specular.clone(), d.lut.clone())
        );
        assert_eq!(back.settings, d.settings);
        assert!(decode(&b[..b.len() - 4]).is_none(), "short body");
        let mut long = b.clone();
        long.extend([0; 12]);
        assert!(decode(&long).is_none(), "long body");
        assert!(decode(b"glview-ibl 1\n{\"settings\":0}\n").is_none());
        assert!(decode(&[]).is_none());
    }

    #[test]
    fn half_maps_are_the_maps_rounded_to_f16_at_half_the_size() {
        let d = small();
        let (full, halfs) = (encode(&d), encode_half(&d));
        let back = decode(&halfs).expect("decodes");
        let round = |v: f32| half::f16::from_f32(v).to_f32();
        for (a, b) in d.specular.iter().zip(&back.specular) {
            for (fa, fb) in a.faces.iter().zip(&b.faces) {
                for (ta, tb) in fa.iter().zip(fb) {
                    assert_eq!(ta.map(round), *tb);
                }
            }
        }
        assert_eq!(back.lut.texels[5], d.lut.texels[5].map(round));
        assert!(
            halfs.len() < full.len() * 6 / 10,
            "{} vs {}",
            halfs.len(),
            full.len()
        );
        assert!(decode(&halfs[..halfs.len() - 2]).is_none());
    }

    #[test]
    fn given_maps_answer_their_own_settings_only() {
        let d = small();
        let g = Given(d.clone());
        assert_eq!(g.key(&EnvSource::Builtin, &d.settings), Some(0));
        let other = IblSettings {
            samples: 9,
            ..d.settings
        };
        assert_eq!(g.key(&EnvSource::Builtin, &other), None);
    }
}
