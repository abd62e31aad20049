//! KHR_materials_iridescence's thin film in f64 (the CPU reference's; `iridescence.glsl` is
//! the same formula in GLSL): the Fresnel of a film of index `film_ior` and thickness `d` nm
//! over a base of reflectance `base_f0`, seen at cos θ₁ from air (Belcour & Barla 2017,
//! "A Practical Extension to Microfacet Theory for the Modeling of Varying Iridescence", as the
//! Khronos Sample Viewer evaluates it: Schlick's Fresnel at both interfaces, the base's ior
//! from its F0, the spectral integral as the first two orders of the Airy sum against
//! Gaussian fits of the CIE XYZ sensitivities, converted to linear Rec. 709).
use super::brdf::f_schlick;
use glam::DVec3;
use std::f64::consts::PI;

/// ((n_t − n_i)/(n_t + n_i))²: the reflectance at normal incidence between two media.
fn ior_to_f0(n_t: DVec3, n_i: f64) -> DVec3 {
    let d = (n_t - DVec3::splat(n_i)) / (n_t + DVec3::splat(n_i));
    d * d
}

/// The index of refraction (from air) whose F0 is `f0` (f0 < 1).
fn f0_to_ior(f0: DVec3) -> DVec3 {
    let s = f0.clamp(DVec3::ZERO, DVec3::splat(0.9999)).powf(0.5);
    (DVec3::ONE + s) / (DVec3::ONE - s)
}

/// The film's spectral response to optical path difference `opd` (nm) with phase shift
/// `shift`, in linear Rec. 709: Gaussian fits of the XYZ sensitivities in Fourier space
/// (amplitudes normalised by the fits' integral of Y).
fn sensitivity(opd: f64, shift: DVec3) -> DVec3 {
    let phase = 2.0 * PI * opd * 1.0e-9;
    let amp = [0.846_590_002_3, 1.000_221_893_6, 1.001_122_485_7];
    let pos = [1.6810e6, 1.7953e6, 2.2084e6];
    let var = [4.3278e9, 9.3046e9, 6.6121e9];
    let lobe =
        |i: usize| amp[i] * (pos[i] * phase + shift[i]).cos() * (-phase * phase * var[i]).exp();
    // X has a second lobe (the CIE x̄'s blue bump).
    let x = lobe(0)
        + 0.153_868_306_5 * (2.2399e6 * phase + shift.x).cos() * (-4.5282e9 * phase * phase).exp();
    let (y, z) = (lobe(1), lobe(2));
    DVec3::new(
        3.240_454_2 * x - 1.537_138_5 * y - 0.498_531_4 * z,
        -0.969_266_0 * x + 1.876_010_8 * y + 0.041_556_0 * z,
        0.055_643_4 * x - 0.204_025_9 * y + 1.057_225_2 * z,
    )
}

/// The film's reflectance (linear RGB, ≥ 0) at cos θ₁ = `cos1` from air.
pub(crate) fn fresnel(film_ior: f64, cos1: f64, d: f64, base_f0: DVec3) -> DVec3 {
    // The film fades into air as it thins to nothing (no film, no colour).
    let t = (d / 0.03).clamp(0.0, 1.0);
    let n2 = 1.0 + (film_ior - 1.0) * t * t * (3.0 - 2.0 * t);
    let cos2_sq = 1.0 - (1.0 - cos1 * cos1) / (n2 * n2);
    if cos2_sq < 0.0 {
        return DVec3::ONE; // total internal reflection
    }
    let cos2 = cos2_sq.sqrt();
    // Air to film.
    let r12 = f_schlick(ior_to_f0(DVec3::splat(n2), 1.0), cos1).x;
    let t121 = 1.0 - r12;
    let phi12 = if n2 < 1.0 { PI } else { 0.0 };
    let phi21 = PI - phi12;
    // Film to base.
    let base_ior = f0_to_ior(base_f0);
    let r23 = f_schlick(ior_to_f0(base_ior, n2), cos2);
    let phi23 = DVec3::new(
        if base_ior.x < n2 { PI } else { 0.0 },
        if base_ior.y < n2 { PI } else { 0.0 },
        if base_ior.z < n2 { PI } else { 0.0 },
    );
    let opd = 2.0 * n2 * d * cos2;
    let phi = DVec3::splat(phi21) + phi23;
    let r123 = (r12 * r23).clamp(DVec3::splat(1e-5), DVec3::splat(0.9999));
    let rs = t121 * t121 * r23 / (DVec3::ONE - r123);
    let mut out = DVec3::splat(r12) + rs;
    let mut cm = rs - DVec3::splat(t121);
    for m in 1..=2 {
        cm *= r123.powf(0.5);
        let mf = f64::from(m);
        out += cm * 2.0 * sensitivity(mf * opd, mf * phi);
    }
    out.max(DVec3::ZERO)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn no_film_at_normal_incidence_is_the_base_f0() {
        // A film of no thickness is air: head-on, the base's own F0 (less the Airy sum's
        // clamped remainder, under 1 %). Off normal, Schlick's Fresnel of the air-to-air
        // interface is not 0, so the film's formula leaves a tint: a thickness of 0 is no
        // film at all, as in the Sample Viewer (`reference::layers::film`, `pbrFilm`).
        for f0 in [0.04, 0.5, 0.9] {
            let f = fresnel(1.3, 1.0, 0.0, DVec3::splat(f0));
            assert!(
                (f - DVec3::splat(f0)).abs().max_element() < 0.01,
                "{f0}: {f}"
            );
        }
    }

    #[test]
    fn a_film_colours_the_reflection_and_keeps_it_bounded() {
        // 400 nm of ior 1.3 over a dielectric: coloured (channels differ), within [0, 1].
        let f = fresnel(1.3, 1.0, 400.0, DVec3::splat(0.04));
        assert!(f.max_element() - f.min_element() > 0.02, "{f}");
        assert!(f.max_element() <= 1.0 && f.min_element() >= 0.0, "{f}");
    }
}
