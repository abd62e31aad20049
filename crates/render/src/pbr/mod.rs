//! The PBR tier without GL: parameters, the BRDF in f64 (shared by the precomputation and the
//! CPU reference), environments, the split-sum precomputation and the hook its disk cache is given by.
//!
//! Lo = E_d(N)·k_d + E_s(R, r)·(k_s·BF(N·V, r).r + BF(N·V, r).g)
//! k_d = albedo·(1 − f0)·(1 − metallic), k_s = mix(f0, albedo, metallic), f0 = 0.04;
//! E_d: irradiance cube; E_s: one prefiltered cube per roughness level, linear between levels;
//! BF: the BRDF lookup table (GGX, α = r², Smith–Schlick G with k = r²/2).
pub mod anisotropy;
pub mod brdf;
pub mod env;
pub(crate) mod iridescence;
pub mod precompute;
pub mod sheen;
pub mod store;
pub mod views;

use glam::Vec3;
use serde::Serialize;
use std::path::PathBuf;

/// The dielectric reflectance at normal incidence.
pub const F0: f64 = 0.04;

crate::choice! {
    /// Tone mapping of the exposed linear colour before sRGB encoding.
    pub enum Tonemap {
        /// Narkowicz's ACES filmic fit (input scaled by 0.6).
        Aces = "aces",
        /// x / (1 + x)
        Reinhard = "reinhard",
        /// Khronos PBR Neutral: identity below 0.76, base colours kept.
        KhronosNeutral = "khronos-neutral",
        /// Clamp to [0, 1].
        None = "none",
    }
}

impl Tonemap {
    /// Shader switch value (`TONEMAP`).
    pub(crate) fn code(self) -> i32 {
        match self {
            Tonemap::None => 0,
            Tonemap::Aces => 1,
            Tonemap::Reinhard => 2,
            Tonemap::KhronosNeutral => 3,
        }
    }

    /// The curve per channel (Khronos Neutral needs all three), as in `output.glsl`.
    pub(crate) fn apply(self, c: [f64; 3]) -> [f64; 3] {
        match self {
            Tonemap::None => c.map(|x| x.clamp(0.0, 1.0)),
            Tonemap::Reinhard => c.map(|x| {
                let x = x.max(0.0);
                x / (1.0 + x)
            }),
            Tonemap::Aces => c.map(|x| {
                let x = x.max(0.0) * 0.6;
                ((x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14)).clamp(0.0, 1.0)
            }),
            Tonemap::KhronosNeutral => {
                let start = 0.8 - 0.04;
                let desat = 0.15;
                let x = c[0].min(c[1]).min(c[2]);
                let offset = if x < 0.08 { x - 6.25 * x * x } else { 0.04 };
                let c = c.map(|v| v - offset);
                let peak = c[0].max(c[1]).max(c[2]);
                if peak < start {
                    return c.map(|v| v.clamp(0.0, 1.0));
                }
                let d = 1.0 - start;
                let new_peak = 1.0 - d * d / (peak + d - start);
                let g = 1.0 - 1.0 / (desat * (peak - new_peak) + 1.0);
                c.map(|v| (v * new_peak / peak * (1.0 - g) + new_peak * g).clamp(0.0, 1.0))
            }
        }
    }
}

pub use glview_scene::model::colour::{srgb_decode, srgb_encode};

/// The PBR tier's output step: exposure, tone mapping, sRGB encoding.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct OutputParams {
    /// Exposure in EV: the linear colour is multiplied by 2^ev.
    pub exposure_ev: f32,
    pub tonemap: Tonemap,
}

impl OutputParams {
    /// Linear HDR colour → display value in [0, 1] (the CPU twin of `glviewOutput`).
    pub fn apply(&self, c: [f64; 3]) -> [f64; 3] {
        let e = 2f64.powf(f64::from(self.exposure_ev));
        self.tonemap.apply(c.map(|x| x * e)).map(srgb_encode)
    }
}

/// The PBR tier's per-frame knobs (material overrides and measured options).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct PbrParams {
    /// `--base-color`, `--metallic`, `--roughness`: override every material.
    pub base_color: Option<Vec3>,
    pub metallic: Option<f32>,
    pub roughness: Option<f32>,
    /// Sample E_s at normalize(mix(R, N, r²·…)) (Filament's dominant direction); off = the
    /// seed's formula.
    pub(crate) dominant_direction: bool,
    /// Multiple-scattering energy compensation (Fdez-Agüera / Filament); off = the seed's.
    pub(crate) multiscatter: bool,
    /// Draw the environment behind the model (else the background colour).
    pub skybox: bool,
    /// Roughness of the specular level the skybox shows (0 = sharp).
    pub(crate) skybox_blur: f32,
    /// Scale of the image-based light (1 = as the environment says).
    pub ibl_intensity: f32,
}

/// Where the environment comes from.
#[derive(Clone, Debug, PartialEq)]
pub enum EnvSource {
    /// The built-in procedural sky (sun, sky gradient, ground).
    Builtin,
    /// A uniform environment of this linear radiance.
    Uniform([f32; 3]),
    /// A Radiance HDR file, equirectangular.
    File(PathBuf),
}

crate::choice! {
    /// Texture encoding of the precomputed maps.
    #[derive(Hash)]
    pub enum Encoding {
        /// 16-bit float where the driver has it, else RGBM.
        Auto = "auto",
        Float = "float",
        /// 8-bit RGB·M (M in alpha, range 8), decoded in the shader.
        Rgbm = "rgbm",
    }
}

crate::choice! {
    /// Where the maps are computed.
    pub enum PrecomputeOn {
        /// The GPU where it can and is not a software rasterizer, else the CPU (the bench's
        /// measurement on llvmpipe: the CPU is faster there).
        Auto = "auto",
        Cpu = "cpu",
        Gpu = "gpu",
    }
}

/// What the PBR pass needs to make (or read from the cache) its maps.
#[derive(Clone, Debug, PartialEq)]
pub struct EnvRequest {
    pub source: EnvSource,
    pub settings: precompute::IblSettings,
    pub encoding: Encoding,
    /// Read and write the disk cache.
    pub cache: bool,
    pub precompute: PrecomputeOn,
}

impl Default for EnvRequest {
    fn default() -> Self {
        EnvRequest {
            source: EnvSource::Builtin,
            settings: precompute::IblSettings::default(),
            encoding: Encoding::Auto,
            cache: true,
            precompute: PrecomputeOn::Auto,
        }
    }
}
