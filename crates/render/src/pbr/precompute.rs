//! The split-sum maps, computed on the CPU with rayon: the irradiance cube (E_d), one
//! prefiltered specular cube per roughness level (E_s) and the BRDF lookup table (BF).
use super::brdf::{self, hammersley, sample_ggx};
use super::env::{cube_direction, direction, sample_level, Environment};
use glam::DVec3;
use rayon::prelude::*;
use std::f64::consts::PI;

/// The quality knobs of the precomputation (each measured by `glview bench --pbr`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
pub struct IblSettings {
    /// Face size of the irradiance cube.
    pub irradiance_size: u32,
    /// Face size of the sharpest specular level; rougher levels halve it down to 16.
    /// Defaults from `glview bench --pbr` (README, PBR tier).
    pub specular_size: u32,
    /// Number of roughness levels, evenly spaced from 0 to 1 (at least 2).
    pub levels: u32,
    /// GGX samples per specular texel.
    pub samples: u32,
    /// BRDF lookup table size (square).
    pub lut_size: u32,
    /// GGX samples per lookup-table texel.
    pub lut_samples: u32,
}

/// GGX samples per lookup-table texel (no option sets it; `IblSettings::default`, the
/// options' defaults, is in `options::convert`).
pub(crate) const LUT_SAMPLES: u32 = 512;

impl IblSettings {
    pub(crate) fn level_roughness(&self, i: u32) -> f32 {
        i as f32 / (self.levels.max(2) - 1) as f32
    }
    pub(crate) fn level_size(&self, i: u32) -> u32 {
        (self.specular_size >> i)
            .max(16)
            .min(self.specular_size.max(1))
    }
}

/// Six faces of RGB texels in GL order, rows from t = 0.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Cube {
    pub size: u32,
    pub faces: Vec<Vec<[f32; 3]>>,
}

impl Cube {
    fn build(size: u32, f: impl Fn(DVec3) -> DVec3 + Sync) -> Cube {
        let n = size as usize;
        let faces = (0..6)
            .map(|face| {
                (0..n * n)
                    .into_par_iter()
                    .map(|i| {
                        let c = f(cube_direction(face, (i % n) as f64, (i / n) as f64, n));
                        [c.x as f32, c.y as f32, c.z as f32]
                    })
                    .collect()
            })
            .collect();
        Cube { size, faces }
    }

    /// Nearest-texel lookup (for tests and the teaching views).
    #[cfg(test)] // only the unit tests call it
    pub(crate) fn lookup(&self, d: DVec3) -> DVec3 {
        let a = d.abs();
        let (face, sc, tc, ma) = if a.x >= a.y && a.x >= a.z {
            if d.x > 0.0 {
                (0, -d.z, -d.y, a.x)
            } else {
                (1, d.z, -d.y, a.x)
            }
        } else if a.y >= a.z {
            if d.y > 0.0 {
                (2, d.x, d.z, a.y)
            } else {
                (3, d.x, -d.z, a.y)
            }
        } else if d.z > 0.0 {
            (4, d.x, -d.y, a.z)
        } else {
            (5, -d.x, -d.y, a.z)
        };
        let n = self.size as f64;
        let x = (((sc / ma + 1.0) / 2.0 * n) as usize).min(self.size as usize - 1);
        let y = (((tc / ma + 1.0) / 2.0 * n) as usize).min(self.size as usize - 1);
        let p = self.faces[face][y * self.size as usize + x];
        DVec3::new(p[0].into(), p[1].into(), p[2].into())
    }
}

/// The BRDF table: (A, B) at x = N·V (texel centres from 0 to 1), y = roughness, and the
/// sheen lobe's directional albedo E at y = sheen roughness ([`super::sheen::albedo`]).
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Lut {
    pub size: u32,
    pub texels: Vec<[f32; 3]>,
}

#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct IblData {
    pub settings: IblSettings,
    pub irradiance: Cube,
    pub specular: Vec<Cube>,
    pub lut: Lut,
    /// Milliseconds the computation took (0 when read from the cache).
    pub compute_ms: f64,
}

/// E_d: (1/π)∫ L(ω)·max(N·ω, 0) dω — the radiance a white Lambert surface reflects; summed
/// over every texel of a box-filtered copy of the environment at most 256 wide (each texel
/// with its solid angle), so a uniform environment is reproduced to rounding. Coarser copies
/// fail on small, very bright lights near a normal's horizon: a 64×32 copy put the studio
/// HDR's key light on the wrong side of the horizon for +Z and gave a third of the true value.
pub(crate) fn irradiance(env: &Environment, size: u32) -> Cube {
    let mips = env.mips();
    let (t, w, h) = mips
        .iter()
        .find(|(_, w, _)| *w <= 256)
        .cloned()
        .unwrap_or_else(|| mips.last().cloned().expect("level 0 exists"));
    let omegas: Vec<f64> = (0..w * h)
        .map(|i| {
            let theta = ((i / w) as f64 + 0.5) / h as f64 * PI;
            (2.0 * PI / w as f64) * (PI / h as f64) * theta.sin()
        })
        .collect();
    let texels: Vec<(DVec3, DVec3)> = (0..w * h)
        .map(|i| {
            let (x, y) = ((i % w) as f64 + 0.5, (i / w) as f64 + 0.5);
            let d = direction(x, y, w, h);
            let theta = y / h as f64 * PI;
            let d_omega = (2.0 * PI / w as f64) * (PI / h as f64) * theta.sin();
            let p = t[i];
            (
                d,
                DVec3::new(p[0].into(), p[1].into(), p[2].into()) * d_omega,
            )
        })
        .collect();
    Cube::build(size, |n| {
        // Normalising by the discrete sum of the cosine weights (π for the exact integral)
        // keeps a uniform environment exact despite the quadrature.
        let (mut s, mut wsum) = (DVec3::ZERO, 0.0);
        for ((d, l), omega) in texels.iter().zip(&omegas) {
            let c = n.dot(*d);
            if c > 0.0 {
                s += *l * c;
                wsum += c * omega;
            }
        }
        s / wsum.max(1e-12)
    })
}

/// Mip bias of the filtered lookups: Křivánek–Colbert suggest +1, which blurs (studio HDR,
/// metal r 0.5: mean error 0.090 at +1, 0.075 at 0, 0.080 at −0.5 where noise returns).
const LOD_BIAS: f64 = 0.0;

/// E_s for roughness r: Σ L(l)·(N·L) / Σ (N·L) over GGX samples around N = V = R, each read
/// from the mip level whose texel matches the sample's solid angle (filtered importance
/// sampling, Křivánek & Colbert 2008), which removes the noise a fixed count would leave.
pub(crate) fn specular(env: &Environment, r: f64, size: u32, samples: u32) -> Cube {
    let mips = env.mips();
    let texel_omega = 2.0 * PI * PI / (env.width * env.height) as f64;
    let lookup = |d: DVec3, lod: f64| {
        let lod = lod.clamp(0.0, (mips.len() - 1) as f64);
        let (l0, f) = (lod.floor() as usize, lod.fract());
        let (t, w, h) = &mips[l0];
        let a = sample_level(t, *w, *h, d);
        if f > 0.0 && l0 + 1 < mips.len() {
            let (t, w, h) = &mips[l0 + 1];
            a.lerp(sample_level(t, *w, *h, d), f)
        } else {
            a
        }
    };
    if r <= 0.0 {
        // A mirror: the environment itself, read at the level matching a cube texel.
        let cube_omega = 4.0 * PI / (6.0 * f64::from(size * size));
        let lod = 0.5 * (cube_omega / texel_omega).log2();
        return Cube::build(size, |d| lookup(d, lod));
    }
    // The sample set and its weights do not depend on N: compute them once in tangent space.
    let set: Vec<(DVec3, f64, f64)> = (0..samples)
        .filter_map(|i| {
            let (u1, u2) = hammersley(i, samples);
            let h = sample_ggx(u1, u2, DVec3::Z, r);
            let l = 2.0 * h.z * h - DVec3::Z;
            (l.z > 0.0).then(|| {
                // pdf of l with N = V: D·(N·H)/(4·V·H) = D/4
                let pdf = brdf::d_ggx(h.z, r) / 4.0;
                let omega_s = 1.0 / (f64::from(samples) * pdf);
                let lod = 0.5 * (omega_s / texel_omega).log2() + LOD_BIAS;
                (l, l.z, lod)
            })
        })
        .collect();
    Cube::build(size, |n| {
        let (t, b) = brdf::basis(n);
        let (mut c, mut wsum) = (DVec3::ZERO, 0.0);
        for (l, w, lod) in &set {
            let d = t * l.x + b * l.y + n * l.z;
            c += lookup(d, *lod) * *w;
            wsum += *w;
        }
        c / wsum.max(1e-12)
    })
}

pub(crate) fn lut(size: u32, samples: u32) -> Lut {
    let n = size as usize;
    let texels = (0..n * n)
        .into_par_iter()
        .map(|i| {
            let n_dot_v = ((i % n) as f64 + 0.5) / n as f64;
            let r = ((i / n) as f64 + 0.5) / n as f64;
            let (a, b) = brdf::integrate_brdf(n_dot_v, r, samples);
            let e = super::sheen::table_albedo(n_dot_v, r, samples);
            [a as f32, b as f32, e as f32]
        })
        .collect();
    Lut { size, texels }
}

pub fn compute(env: &Environment, s: &IblSettings) -> IblData {
    let start = crate::clock::Mark::now();
    let levels = s.levels.max(2);
    let specular = (0..levels)
        .map(|i| {
            specular(
                env,
                f64::from(s.level_roughness(i)),
                s.level_size(i),
                s.samples,
            )
        })
        .collect();
    IblData {
        settings: *s,
        irradiance: irradiance(env, s.irradiance_size),
        specular,
        lut: lut(s.lut_size, s.lut_samples),
        compute_ms: start.ms(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn uniform_environment_is_reproduced() {
        let env = Environment::uniform([0.5, 1.0, 2.0]);
        let irr = irradiance(&env, 4);
        for f in &irr.faces {
            for t in f {
                assert!(
                    (t[0] - 0.5).abs() < 2e-3 && (t[2] - 2.0).abs() < 8e-3,
                    "{t:?}"
                );
            }
        }
        let spec = specular(&env, 0.5, 4, 64);
        for f in &spec.faces {
            for t in f {
                assert!((t[1] - 1.0).abs() < 1e-4, "{t:?}");
            }
        }
    }
}

#[cfg(test)]
mod orientation {
    use super::*;

    /// The mirror level read through GL's face-selection rule ([`Cube::lookup`]) returns the
    /// environment in the same direction: cube faces and equirect agree on orientation.
    #[test]
    fn mirror_level_round_trips() {
        let mut env = Environment::uniform([0.0; 3]);
        env.width = 64;
        env.height = 32;
        env.texels = (0..64 * 32)
            .map(|i| {
                let d = direction((i % 64) as f64 + 0.5, (i / 64) as f64 + 0.5, 64, 32);
                [d.x as f32 + 1.0, d.y as f32 + 1.0, d.z as f32 + 1.0]
            })
            .collect();
        let c = specular(&env, 0.0, 32, 1);
        for d in [
            DVec3::X,
            DVec3::Y,
            DVec3::Z,
            DVec3::new(0.3, -0.5, 0.8).normalize(),
        ] {
            let got = c.lookup(d) - DVec3::ONE;
            assert!((got - d).length() < 0.15, "{d} -> {got}");
        }
    }
}
