//! The sheen lobe of KHR_materials_sheen in f64 (the twin of `brdf.glsl`'s): Charlie
//! distribution (Estevez & Kulla 2017) with the Neubelt–Pettineo visibility, and its
//! directional albedo E(N·V, sheen roughness), which the BRDF table's third channel holds:
//! the sheen's image-based light is E·sheenColor·(the environment prefiltered at the sheen
//! roughness), exact in a uniform environment, and the layers under the sheen are scaled by
//! 1 − max(sheenColor)·E, so the sum never reflects more than arrives. Neubelt's
//! visibility lets the lobe reflect more than arrives at grazing views of low roughness
//! (E = 2.7 at N·V 0.02, r 0.1; 0.9 at N·V 0.1): E is taken as at most 1 ([`table_albedo`])
//! and the environment's sheen lobe scaled to it, on the GPU and in the reference alike.
use super::brdf::hammersley;
use glam::DVec3;
use std::f64::consts::PI;

/// The lowest sheen roughness evaluated (0 is a limit the lobe only approaches).
pub(crate) const MIN_SHEEN_ROUGHNESS: f64 = 0.07;

/// Charlie D(h) with α = r²: (2 + 1/α)·sin(θ_h)^(1/α) / 2π.
pub(crate) fn d_charlie(n_dot_h: f64, r: f64) -> f64 {
    let a = r.max(MIN_SHEEN_ROUGHNESS).powi(2);
    let inv = 1.0 / a;
    let sin2 = (1.0 - n_dot_h * n_dot_h).max(0.0);
    (2.0 + inv) * sin2.powf(inv * 0.5) / (2.0 * PI)
}

/// Neubelt–Pettineo visibility 1 / (4·(N·L + N·V − N·L·N·V)).
pub(crate) fn v_neubelt(n_dot_v: f64, n_dot_l: f64) -> f64 {
    1.0 / (4.0 * (n_dot_l + n_dot_v - n_dot_l * n_dot_v)).max(1e-8)
}

/// The sheen BRDF (white colour) for unit vectors.
pub fn brdf(n: DVec3, v: DVec3, l: DVec3, r: f64) -> f64 {
    let (n_dot_l, n_dot_v) = (n.dot(l), n.dot(v).max(1e-4));
    if n_dot_l <= 0.0 {
        return 0.0;
    }
    let h = (l + v).normalize_or_zero();
    d_charlie(n.dot(h).max(0.0), r) * v_neubelt(n_dot_v, n_dot_l)
}

/// A uniformly distributed direction of the hemisphere around +Z.
fn uniform_hemisphere(u1: f64, u2: f64) -> DVec3 {
    let phi = 2.0 * PI * u1;
    let z = 1.0 - u2;
    let s = (1.0 - z * z).max(0.0).sqrt();
    DVec3::new(phi.cos() * s, phi.sin() * s, z)
}

/// E(N·V, r) = ∫ f_sheen·(N·L) dω, by uniform hemisphere sampling (the lobe lies near the
/// horizon at low roughness, where cosine sampling puts few points).
pub fn albedo(n_dot_v: f64, r: f64, samples: u32) -> f64 {
    let n_dot_v = n_dot_v.max(1e-4);
    let v = DVec3::new((1.0 - n_dot_v * n_dot_v).sqrt(), 0.0, n_dot_v);
    let mut e = 0.0;
    for i in 0..samples {
        let (u1, u2) = hammersley(i, samples);
        let l = uniform_hemisphere(u1, u2);
        e += brdf(DVec3::Z, v, l, r) * l.z;
    }
    e * 2.0 * PI / f64::from(samples.max(1))
}

/// The albedo the table holds and the layering uses: E, at most 1.
pub(crate) fn table_albedo(n_dot_v: f64, r: f64, samples: u32) -> f64 {
    albedo(n_dot_v, r, samples).min(1.0)
}

/// ∫ L·f_sheen·(N·L) dω by Monte Carlo (uniform hemisphere samples around `n`): the
/// reference's sheen image-based light (white colour).
pub fn mc_radiance(
    n: DVec3,
    v: DVec3,
    r: f64,
    samples: u32,
    radiance: &dyn Fn(DVec3) -> DVec3,
) -> DVec3 {
    let (t, b) = super::brdf::basis(n);
    let mut sum = DVec3::ZERO;
    for i in 0..samples {
        let (u1, u2) = hammersley(i, samples);
        let s = uniform_hemisphere(u1, u2);
        let l = t * s.x + b * s.y + n * s.z;
        let f = brdf(n, v, l, r) * s.z;
        if f > 0.0 {
            sum += radiance(l) * f;
        }
    }
    sum * 2.0 * PI / f64::from(samples.max(1))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn charlie_is_normalised() {
        // ∫ D(h)·(N·H) dω_h = 1, midpoint rule over the hemisphere.
        for r in [0.3, 0.6, 1.0] {
            let s = crate::pbr::brdf::projected_integral(|c| d_charlie(c, r), 4000);
            assert!((s - 1.0).abs() < 1e-2, "r {r}: {s}");
        }
    }

    #[test]
    fn albedo_is_below_one_but_at_grazing_low_roughness() {
        for r in [0.1, 0.5, 1.0] {
            for nv in [0.3, 0.5, 1.0] {
                let e = albedo(nv, r, 4096);
                assert!((0.0..1.0).contains(&e), "r {r} N·V {nv}: {e}");
            }
        }
        // Neubelt's visibility: more than arrives at a grazing view of a smooth sheen,
        // which the table clamps.
        assert!(albedo(0.02, 0.1, 4096) > 1.5);
        assert_eq!(table_albedo(0.02, 0.1, 4096), 1.0);
    }
}
