//! The BRDF of the PBR tier in f64: GGX distribution (α = r²), Smith–Schlick geometry with
//! k = r²/2 (the split sum of LearnOpenGL, used for image-based and direct light alike),
//! Schlick's Fresnel; low-discrepancy sampling; and the BRDF lookup table's integral.
use glam::DVec3;
use std::f64::consts::PI;

/// The lowest roughness the lobes are evaluated with: r = 0 is a mirror (a Dirac lobe), which
/// sampled and analytic forms only reach as a limit.
pub(crate) const MIN_ROUGHNESS: f64 = 0.02;

pub(crate) fn alpha(r: f64) -> f64 {
    let r = r.max(MIN_ROUGHNESS);
    r * r
}

/// GGX normal distribution D(h).
pub fn d_ggx(n_dot_h: f64, r: f64) -> f64 {
    let a2 = alpha(r) * alpha(r);
    let d = n_dot_h * n_dot_h * (a2 - 1.0) + 1.0;
    a2 / (PI * d * d)
}

/// Smith–Schlick geometry term G(l, v) with k = α/2 = r²/2.
pub fn g_smith(n_dot_v: f64, n_dot_l: f64, r: f64) -> f64 {
    let k = alpha(r) / 2.0;
    let g1 = |x: f64| x / (x * (1.0 - k) + k);
    g1(n_dot_v) * g1(n_dot_l)
}

/// Schlick's Fresnel.
pub fn f_schlick(f0: DVec3, v_dot_h: f64) -> DVec3 {
    f0 + (DVec3::ONE - f0) * (1.0 - v_dot_h).clamp(0.0, 1.0).powi(5)
}

/// Schlick's Fresnel with reflectance `f90` at grazing incidence.
pub fn f_schlick90(f0: DVec3, f90: f64, v_dot_h: f64) -> DVec3 {
    f0 + (DVec3::splat(f90) - f0) * (1.0 - v_dot_h).clamp(0.0, 1.0).powi(5)
}

/// The i-th of n points of the Hammersley set in [0, 1)².
pub(crate) fn hammersley(i: u32, n: u32) -> (f64, f64) {
    (
        (f64::from(i) + 0.5) / f64::from(n),
        f64::from(i.reverse_bits()) / 4294967296.0,
    )
}

/// An orthonormal basis (t, b) around unit `n` (Duff et al. 2017, no singularity).
pub(crate) fn basis(n: DVec3) -> (DVec3, DVec3) {
    let s = if n.z >= 0.0 { 1.0 } else { -1.0 };
    let a = -1.0 / (s + n.z);
    let b = n.x * n.y * a;
    (
        DVec3::new(1.0 + s * n.x * n.x * a, s * b, -s * n.x),
        DVec3::new(b, s + n.y * n.y * a, -n.y),
    )
}

/// A GGX-distributed half vector around `n` for the sample point (u1, u2).
pub(crate) fn sample_ggx(u1: f64, u2: f64, n: DVec3, r: f64) -> DVec3 {
    let a = alpha(r);
    let phi = 2.0 * PI * u1;
    let cos_t = ((1.0 - u2) / (1.0 + (a * a - 1.0) * u2)).sqrt();
    let sin_t = (1.0 - cos_t * cos_t).max(0.0).sqrt();
    let (t, b) = basis(n);
    (t * (phi.cos() * sin_t) + b * (phi.sin() * sin_t) + n * cos_t).normalize()
}

/// A cosine-distributed direction around `n`.
pub(crate) fn sample_cosine(u1: f64, u2: f64, n: DVec3) -> DVec3 {
    let phi = 2.0 * PI * u1;
    let r = u2.sqrt();
    let (t, b) = basis(n);
    (t * (phi.cos() * r) + b * (phi.sin() * r) + n * (1.0 - u2).max(0.0).sqrt()).normalize()
}

/// The split-sum BRDF integral (A, B) with ∫ f_spec·cos dω = F0·A + B, for N·V and
/// roughness, by importance-sampling GGX with `samples` Hammersley points.
pub fn integrate_brdf(n_dot_v: f64, r: f64, samples: u32) -> (f64, f64) {
    let n_dot_v = n_dot_v.max(1e-4);
    let v = DVec3::new((1.0 - n_dot_v * n_dot_v).sqrt(), 0.0, n_dot_v);
    let n = DVec3::Z;
    let (mut a, mut b) = (0.0, 0.0);
    for i in 0..samples {
        let (u1, u2) = hammersley(i, samples);
        let h = sample_ggx(u1, u2, n, r);
        let l = 2.0 * v.dot(h) * h - v;
        let (n_dot_l, n_dot_h, v_dot_h) = (l.z, h.z.max(0.0), v.dot(h).max(0.0));
        if n_dot_l > 0.0 {
            let g = g_smith(n_dot_v, n_dot_l, r);
            let g_vis = g * v_dot_h / (n_dot_h * n_dot_v);
            let fc = (1.0 - v_dot_h).powi(5);
            a += (1.0 - fc) * g_vis;
            b += fc * g_vis;
        }
    }
    (a / f64::from(samples), b / f64::from(samples))
}

/// A material as the PBR formula sees it (linear colours).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Surface {
    pub albedo: DVec3,
    pub metallic: f64,
    pub roughness: f64,
    pub ao: f64,
    pub emissive: DVec3,
    /// The dielectric's F0 (the core's 0.04; KHR_materials_ior and _specular: the ior's F0
    /// times the specular colour, clamped to 1, times the specular weight).
    pub f0: DVec3,
    /// The dielectric's reflectance at grazing incidence (the specular weight; 1 in the core).
    pub f90: f64,
    /// KHR_materials_transmission's share of the diffuse term that becomes transmission.
    pub transmission: f64,
    /// KHR_materials_iridescence's thin film (None: none, or the `--terms` layer off).
    pub film: Option<Film>,
    /// KHR_materials_anisotropy's stretched lobe (None: none, strength 0, or the `--terms`
    /// layer off: the isotropic lobe).
    pub aniso: Option<super::anisotropy::Aniso>,
}

/// A thin film over the base (KHR_materials_iridescence at one point).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Film {
    pub factor: f64,
    pub ior: f64,
    /// Nanometres.
    pub thickness: f64,
}

impl Surface {
    /// The core model's dielectric: F0 0.04, F90 1.
    pub const CORE_F0: (DVec3, f64) = (DVec3::splat(super::F0), 1.0);

    /// k_d = albedo·(1 − max(f0))·(1 − metallic)·(1 − transmission); under a film, f0 is
    /// mix(f0, film's reflectance at normal incidence, factor).
    pub fn kd(&self) -> DVec3 {
        let mut f0 = self.f0.max_element();
        if let Some(film) = self.film {
            let i = super::iridescence::fresnel(film.ior, 1.0, film.thickness, self.ks());
            f0 += (i.max_element() - f0) * film.factor;
        }
        self.albedo * (1.0 - f0) * (1.0 - self.metallic) * (1.0 - self.transmission)
    }
    /// k_s = mix(f0, albedo, metallic)
    pub fn ks(&self) -> DVec3 {
        self.f0.lerp(self.albedo, self.metallic)
    }
    /// F90 = mix(f90, 1, metallic)
    pub fn f90(&self) -> f64 {
        self.f90 + (1.0 - self.f90) * self.metallic
    }

    /// The reflection's Fresnel at V·H `v_dot_h`, viewed at N·V `n_dot_v`: Schlick's from k_s
    /// to F90; under a film, mixed with the film's (at N·V, the same for every half vector,
    /// as the Sample Viewer) by its factor.
    pub(crate) fn fresnel(&self, n_dot_v: f64, v_dot_h: f64) -> DVec3 {
        let f = f_schlick90(self.ks(), self.f90(), v_dot_h);
        match self.film {
            Some(film) => {
                let i = super::iridescence::fresnel(film.ior, n_dot_v, film.thickness, self.ks());
                f.lerp(i, film.factor)
            }
            None => f,
        }
    }

    /// Direct light of unit colour from direction `l`: (k_d + π·f_spec)·N·L. A light's colour
    /// is the radiance a white Lambert surface facing it reflects, as in the legacy tier.
    pub fn direct(&self, n: DVec3, v: DVec3, l: DVec3) -> DVec3 {
        let n_dot_l = n.dot(l);
        if n_dot_l <= 0.0 {
            return DVec3::ZERO;
        }
        let n_dot_v = n.dot(v).max(1e-4);
        let h = (l + v).normalize_or_zero();
        let lobe = match self.aniso {
            // The Sample Viewer's D·V, whose V holds the 1/(4·N·L·N·V).
            Some(a) => a.spec(n, n_dot_v, v, l, h, self.roughness),
            None => {
                d_ggx(n.dot(h).max(0.0), self.roughness) * g_smith(n_dot_v, n_dot_l, self.roughness)
                    / (4.0 * n_dot_v * n_dot_l)
            }
        };
        let spec = lobe * self.fresnel(n_dot_v, v.dot(h).max(0.0));
        (self.kd() + PI * spec) * n_dot_l
    }

    /// E_d by Monte Carlo: (1/π)∫ L·cos dω as the mean of cosine-distributed samples.
    pub fn mc_irradiance(n: DVec3, samples: u32, radiance: &dyn Fn(DVec3) -> DVec3) -> DVec3 {
        let mut sum = DVec3::ZERO;
        for i in 0..samples {
            let (u1, u2) = hammersley(i, samples);
            sum += radiance(sample_cosine(u1, u2, n));
        }
        sum / f64::from(samples.max(1))
    }

    /// The specular image-based light ∫ L·f_spec·cos dω by Monte Carlo with GGX-sampled half
    /// vectors (the truth the split sum approximates). Under anisotropy, the Sample Viewer's
    /// approximation that `pbr.frag` draws: the isotropic lobe turned from the mirror
    /// direction about `n` to the one about the bent normal (the environment is read through
    /// that rotation); docs/gltf/extensions.md measures it against the stretched lobe.
    pub fn mc_specular(
        &self,
        n: DVec3,
        v: DVec3,
        samples: u32,
        radiance: &dyn Fn(DVec3) -> DVec3,
    ) -> DVec3 {
        if let Some(a) = self.aniso {
            let r0 = (2.0 * n.dot(v) * n - v).normalize_or_zero();
            let bent = a.bent_normal(n, v, self.roughness);
            let r1 = (2.0 * bent.dot(v) * bent - v).normalize_or_zero();
            if r0 != DVec3::ZERO && r1 != DVec3::ZERO {
                let q = glam::DQuat::from_rotation_arc(r0, r1);
                let iso = Surface {
                    aniso: None,
                    ..*self
                };
                return iso.mc_specular(n, v, samples, &|d| radiance(q * d));
            }
        }
        let n_dot_v = n.dot(v).max(1e-4);
        let mut spec = DVec3::ZERO;
        for i in 0..samples {
            let (u1, u2) = hammersley(i, samples);
            let h = sample_ggx(u1, u2, n, self.roughness);
            let l = 2.0 * v.dot(h) * h - v;
            let n_dot_l = n.dot(l);
            if n_dot_l > 0.0 {
                let (n_dot_h, v_dot_h) = (n.dot(h).max(1e-8), v.dot(h).max(0.0));
                // f·cos/pdf with pdf = D·(N·H)/(4·V·H)
                let w = g_smith(n_dot_v, n_dot_l, self.roughness) * v_dot_h / (n_dot_h * n_dot_v);
                spec += radiance(l) * self.fresnel(n_dot_v, v_dot_h) * w;
            }
        }
        spec / f64::from(samples.max(1))
    }
}

/// ∫ D(h)·(N·H) dω_h over the hemisphere for `d` of N·H, by the midpoint rule in `n` steps
/// of the polar angle: 1 for a normalised microfacet distribution (GGX's and sheen's tests).
#[cfg(test)]
pub(crate) fn projected_integral(d: impl Fn(f64) -> f64, n: u32) -> f64 {
    let mut s = 0.0;
    for i in 0..n {
        let t = (f64::from(i) + 0.5) / f64::from(n) * PI / 2.0;
        s += d(t.cos()) * t.cos() * t.sin() * 2.0 * PI * (PI / 2.0 / f64::from(n));
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lut_matches_known_values() {
        // Smooth, head-on: almost all energy reflects, A + B ≈ 1.
        let (a, b) = integrate_brdf(1.0, 0.05, 1024);
        assert!((a + b - 1.0).abs() < 0.02, "{a} {b}");
        // Rough surfaces lose energy to single scattering: A + B < 1.
        let (a, b) = integrate_brdf(0.5, 1.0, 1024);
        assert!(a + b < 0.9 && a > 0.0 && b >= 0.0, "{a} {b}");
    }

    #[test]
    fn ggx_is_normalised() {
        // ∫ D(h)·(N·H) dω_h = 1, midpoint rule over the hemisphere.
        for r in [0.3, 0.6, 1.0] {
            let s = projected_integral(|c| d_ggx(c, r), 2000);
            assert!((s - 1.0).abs() < 1e-3, "r {r}: {s}");
        }
    }
}
