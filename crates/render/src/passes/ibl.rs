//! The PBR tier's GPU resources: the environment maps (made on the CPU by `pbr::precompute`,
//! or read from the disk cache) uploaded as cube maps and a 2D table, in 16-bit float where
//! the driver has it, else RGBM / split 16-bit in RGBA8; and the materials' PBR textures.
use crate::gpu::texture::{Pixels, Sampling, Texture2d, TextureCube, TextureFormat};
use crate::gpu::GpuRef;
use crate::pbr::precompute::IblSettings;
use crate::pbr::precompute::{self, IblData};
use crate::pbr::{env::Environment, store::store, Encoding, EnvRequest, PrecomputeOn};
use crate::shader::cache::ProgramCache;
use crate::{Error, Result};
use std::cell::RefCell;
use std::rc::Rc;

/// RGBM range: values up to 16 are stored, brighter ones clipped (documented).
pub(crate) const RGBM_RANGE: f32 = 16.0;

pub(crate) struct IblGpu {
    pub(crate) irradiance: TextureCube,
    pub(crate) specular: Vec<TextureCube>,
    pub(crate) lut: Texture2d,
    pub(crate) rgbm: bool,
}

/// One environment's maps: the CPU copy, the uploaded textures and where they came from.
pub(crate) struct EnvMaps {
    data: IblData,
    gpu: IblGpu,
    /// What was done to get the maps, for `--stats` (e.g. `computed 412 ms`, `disk cache`).
    origin: String,
}

/// How many environments a context keeps (least recently used goes first): a server's
/// viewers switching between a few HDRs make each once.
const KEPT_ENVIRONMENTS: usize = 4;

/// The environment maps made on one context, keyed by their request and shared by every
/// renderer (scene) drawn on it: N scenes of one environment hold one copy of its maps.
#[derive(Default)]
pub struct Environments {
    /// Least recently used first.
    kept: Vec<(EnvRequest, Rc<EnvMaps>)>,
    made: u64,
}

impl Environments {
    /// A context's shared set, empty.
    pub fn shared() -> SharedEnvironments {
        Rc::new(RefCell::new(Environments::default()))
    }

    /// How many environments have been made (read from the disk cache or computed, and
    /// uploaded) since the set was made: `--stats` counts them per picture.
    pub fn made(&self) -> u64 {
        self.made
    }

    fn get(&mut self, r: &EnvRequest) -> Option<Rc<EnvMaps>> {
        let i = self.kept.iter().position(|(k, _)| k == r)?;
        let e = self.kept.remove(i);
        let maps = e.1.clone();
        self.kept.push(e);
        Some(maps)
    }

    fn put(&mut self, r: EnvRequest, maps: Rc<EnvMaps>) {
        if self.kept.len() >= KEPT_ENVIRONMENTS {
            self.kept.remove(0);
        }
        self.kept.push((r, maps));
    }
}

/// A context's [`Environments`], held by its session and every renderer on it.
pub type SharedEnvironments = Rc<RefCell<Environments>>;

#[derive(Default)]
pub(crate) struct IblState {
    request: Option<EnvRequest>,
    maps: Option<Rc<EnvMaps>>,
    /// The context's shared maps (a renderer of its own has none: it makes its own).
    shared: Option<SharedEnvironments>,
}

impl IblState {
    pub(crate) fn request(&mut self, r: EnvRequest) {
        if self.request.as_ref() != Some(&r) {
            self.request = Some(r);
            self.maps = None;
        }
    }

    pub(crate) fn share(&mut self, envs: SharedEnvironments) {
        self.shared = Some(envs);
    }

    pub(crate) fn data(&self) -> Option<&IblData> {
        self.maps.as_ref().map(|m| &m.data)
    }

    /// What was done to get the maps in use, for `--stats`.
    pub(crate) fn origin(&self) -> &str {
        self.maps.as_ref().map_or("", |m| &m.origin)
    }

    /// Makes the maps on first use: the context's shared ones, else from the disk cache,
    /// else computed (and cached).
    pub(crate) fn ensure(&mut self, gpu: &GpuRef, programs: &mut ProgramCache) -> Result<&IblGpu> {
        if self.maps.is_none() {
            let req = self.request.get_or_insert_with(EnvRequest::default).clone();
            let found = self.shared.as_ref().and_then(|s| s.borrow_mut().get(&req));
            let maps = match found {
                Some(m) => m,
                None => {
                    let m = Rc::new(make(gpu, programs, req.clone())?);
                    if let Some(s) = &self.shared {
                        let mut s = s.borrow_mut();
                        s.made += 1;
                        s.put(req, m.clone());
                    }
                    m
                }
            };
            self.maps = Some(maps);
        }
        Ok(&self.maps.as_ref().expect("set above").gpu)
    }
}

/// Reads or computes the maps of `req` (on the GPU where that is faster) and uploads them.
fn make(gpu: &GpuRef, programs: &mut ProgramCache, mut req: EnvRequest) -> Result<EnvMaps> {
    let fit = super::units::max_levels(gpu.caps.max_texture_units);
    if req.settings.levels > fit {
        log::warn!(
            "{} roughness levels need more texture units than {} has: using {fit}",
            req.settings.levels,
            gpu.caps.version
        );
        req.settings.levels = fit.max(2);
    }
    let on_gpu = match req.precompute {
        PrecomputeOn::Cpu => false,
        PrecomputeOn::Gpu => true,
        PrecomputeOn::Auto => {
            super::ibl_gpu::unsupported(gpu).is_none() && !super::ibl_gpu::software(gpu)
        }
    };
    let compute = |env: &Environment, s: &IblSettings| -> Result<IblData> {
        if on_gpu {
            super::ibl_gpu::compute(gpu, programs, env, s)
        } else {
            Ok(precompute::compute(env, s))
        }
    };
    let (data, origin) = load_or_compute_with(&req, compute, if on_gpu { "GPU" } else { "CPU" })?;
    let gpu = upload(gpu, &data, req.encoding)?;
    Ok(EnvMaps { data, gpu, origin })
}

/// Reads the maps from the disk cache or computes them on the CPU; says which.
pub fn load_or_compute(req: &EnvRequest) -> Result<(IblData, String)> {
    load_or_compute_with(req, |env, s| Ok(precompute::compute(env, s)), "CPU")
}

/// [`load_or_compute`] with the computation given (CPU or GPU, named by `on`).
pub(crate) fn load_or_compute_with(
    req: &EnvRequest,
    mut compute: impl FnMut(&Environment, &IblSettings) -> Result<IblData>,
    on: &str,
) -> Result<(IblData, String)> {
    let store = store().filter(|_| req.cache);
    let key = store.and_then(|s| s.key(&req.source, &req.settings));
    let start = crate::clock::Mark::now();
    if let Some(d) = store.zip(key).and_then(|(s, k)| s.get(k)) {
        let ms = start.ms();
        return Ok((d, format!("disk cache, read in {ms:.0} ms")));
    }
    let env = Environment::from_source(&req.source)?;
    let data = compute(&env, &req.settings)?;
    if let Some((s, k)) = store.zip(key) {
        s.put(k, &data);
    }
    let origin = format!("computed on the {on} in {:.0} ms", data.compute_ms);
    Ok((data, origin))
}

/// RGBM with M quantised upwards, so the stored rgb never exceeds 1.
pub(crate) fn rgbm(c: [f32; 3]) -> [u8; 4] {
    let max = c[0].max(c[1]).max(c[2]).max(1e-6) / RGBM_RANGE;
    let m = (max.clamp(1.0 / 255.0, 1.0) * 255.0).ceil() / 255.0;
    let q = |v: f32| ((v / (m * RGBM_RANGE)).clamp(0.0, 1.0) * 255.0).round() as u8;
    [q(c[0]), q(c[1]), q(c[2]), (m * 255.0).round() as u8]
}

fn upload_cube(gpu: &GpuRef, c: &precompute::Cube, rgbm_on: bool) -> Result<TextureCube> {
    let sampling = Sampling {
        linear: true,
        mipmaps: false,
        repeat: false,
    };
    if rgbm_on {
        let faces: Vec<Vec<u8>> = c
            .faces
            .iter()
            .map(|f| f.iter().flat_map(|&t| rgbm(t)).collect())
            .collect();
        let f = |i: usize| Pixels::U8(&faces[i]);
        TextureCube::new(
            gpu,
            TextureFormat::Rgba8,
            c.size,
            [f(0), f(1), f(2), f(3), f(4), f(5)],
            sampling,
        )
    } else {
        let faces: Vec<Vec<f32>> = c
            .faces
            .iter()
            .map(|f| f.iter().flat_map(|t| [t[0], t[1], t[2], 1.0]).collect())
            .collect();
        let f = |i: usize| Pixels::F32(&faces[i]);
        TextureCube::new(
            gpu,
            TextureFormat::Rgba16F,
            c.size,
            [f(0), f(1), f(2), f(3), f(4), f(5)],
            sampling,
        )
    }
}

fn upload(gpu: &GpuRef, d: &IblData, encoding: Encoding) -> Result<IblGpu> {
    let float = gpu.caps.half_float_textures;
    let rgbm_on = match encoding {
        Encoding::Auto => !float,
        Encoding::Rgbm => true,
        Encoding::Float if float => false,
        Encoding::Float => {
            return Err(Error::Unsupported(format!(
                "--ibl-encoding float: {} has no 16-bit float textures; use rgbm",
                gpu.caps.version
            )))
        }
    };
    let irradiance = upload_cube(gpu, &d.irradiance, rgbm_on)?;
    let specular = d
        .specular
        .iter()
        .map(|c| upload_cube(gpu, c, rgbm_on))
        .collect::<Result<Vec<_>>>()?;
    let n = d.lut.size;
    let lut = if rgbm_on {
        // A and B as 16-bit values, high byte then low byte; sampled nearest, filtered in
        // the shader (filtering split bytes in hardware would mix them). The sheen albedo E
        // sits in the right half (r, g), so the table stays one texture unit.
        let q = |v: f32| (v.clamp(0.0, 1.0) * 65535.0).round() as u16;
        let texel = |t: &[f32; 3]| {
            let (a, b) = (q(t[0]), q(t[1]));
            [(a >> 8) as u8, a as u8, (b >> 8) as u8, b as u8]
        };
        let sheen = |t: &[f32; 3]| {
            let e = q(t[2]);
            [(e >> 8) as u8, e as u8, 0, 255]
        };
        let n_us = n as usize;
        let data: Vec<u8> = d
            .lut
            .texels
            .chunks_exact(n_us)
            .flat_map(|row| {
                row.iter()
                    .flat_map(texel)
                    .chain(row.iter().flat_map(sheen))
                    .collect::<Vec<u8>>()
            })
            .collect();
        let s = Sampling::NEAREST;
        Texture2d::new(gpu, TextureFormat::Rgba8, 2 * n, n, Pixels::U8(&data), s)?
    } else {
        let s = Sampling {
            linear: true,
            mipmaps: false,
            repeat: false,
        };
        let data: Vec<f32> = d
            .lut
            .texels
            .iter()
            .flat_map(|t| [t[0], t[1], t[2], 1.0])
            .collect();
        Texture2d::new(gpu, TextureFormat::Rgba16F, n, n, Pixels::F32(&data), s)?
    };
    gpu.check_error("environment upload")?;
    Ok(IblGpu {
        irradiance,
        specular,
        lut,
        rgbm: rgbm_on,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rgbm_decode(p: [u8; 4]) -> [f32; 3] {
        let m = f32::from(p[3]) / 255.0 * RGBM_RANGE;
        [0, 1, 2].map(|i| f32::from(p[i]) / 255.0 * m)
    }

    #[test]
    fn rgbm_round_trip_error() {
        // Relative error of RGBM (range 16) for values from 0.05 to 16: at most one step of
        // the 8-bit rgb in units of M·16.
        for v in [0.05f32, 0.2, 0.9, 3.0, 15.0] {
            let d = rgbm_decode(rgbm([v, v * 0.5, v * 0.25]));
            let err = (d[0] - v).abs() / v;
            assert!(err < 0.04, "{v}: {d:?} ({err})");
        }
        assert_eq!(
            rgbm_decode(rgbm([100.0, 0.0, 0.0]))[0],
            16.0,
            "clipped at the range"
        );
    }
}
