//! KHR_materials_anisotropy's lobe in f64, the twin of `shaders_gl/include/anisotropy.glsl`:
//! the Khronos Sample Viewer's anisotropic GGX distribution (Burley 2012) and
//! height-correlated Smith visibility (Heitz 2014), α_t = mix(α, 1, strength²) along the
//! anisotropy direction t and α_b = α (at least 0.001) along b = N_geom × t; and the Sample
//! Viewer's bent normal, which aims the environment's isotropic lobe.
use glam::DVec3;
use std::f64::consts::PI;

/// The stretched lobe at one point (directions in the reference's world space).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aniso {
    /// In (0, 1].
    pub strength: f64,
    /// The direction the lobe stretches along.
    pub t: DVec3,
    /// N_geom × t.
    pub b: DVec3,
}

fn d(n_dot_h: f64, t_dot_h: f64, b_dot_h: f64, at: f64, ab: f64) -> f64 {
    let a2 = at * ab;
    let f = DVec3::new(ab * t_dot_h, at * b_dot_h, a2 * n_dot_h);
    let w2 = a2 / f.length_squared();
    a2 * w2 * w2 / PI
}

#[allow(clippy::too_many_arguments)]
fn v(nl: f64, nv: f64, bv: f64, tv: f64, tl: f64, bl: f64, at: f64, ab: f64) -> f64 {
    let gv = nl * DVec3::new(at * tv, ab * bv, nv).length();
    let gl = nv * DVec3::new(at * tl, ab * bl, nl).length();
    (0.5 / (gv + gl)).clamp(0.0, 1.0)
}

impl Aniso {
    /// D·V (the specular BRDF without its Fresnel) for light `l`, half vector `h`, normal `n`
    /// seen at N·V `n_dot_v`, roughness `r`.
    pub(crate) fn spec(
        &self,
        n: DVec3,
        n_dot_v: f64,
        view: DVec3,
        l: DVec3,
        h: DVec3,
        r: f64,
    ) -> f64 {
        let alpha = super::brdf::alpha(r);
        let at = alpha + (1.0 - alpha) * self.strength * self.strength;
        let ab = alpha.clamp(0.001, 1.0);
        let nl = n.dot(l).clamp(0.0, 1.0);
        let nh = n.dot(h).clamp(0.001, 1.0);
        let (t, b) = (self.t, self.b);
        let vis = v(
            nl,
            n_dot_v,
            b.dot(view),
            t.dot(view),
            t.dot(l),
            b.dot(l),
            at,
            ab,
        );
        vis * d(nh, t.dot(h), b.dot(h), at, ab)
    }

    /// The Sample Viewer's bent normal: the normal of the plane holding b and facing `view`,
    /// mixed back to `n` by (1 − strength·(1 − r))⁴.
    pub(crate) fn bent_normal(&self, n: DVec3, view: DVec3, r: f64) -> DVec3 {
        let an = self.b.cross(view).cross(self.b);
        let bend = (1.0 - self.strength * (1.0 - r)).powi(4);
        let bent = an + (n - an) * bend;
        let len = bent.length();
        if len > 0.0 {
            bent / len
        } else {
            n
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The directional albedo ∫ D·V·F·(N·L) dω of the stretched lobe for a view at N·V
    /// `n_dot_v` in the plane of t (`along`) or of b, by Monte Carlo with half vectors
    /// sampled from D·(N·H) (the isotropic GGX of α = 1 in slope space, stretched to
    /// (α_t, α_b)), F = Schlick of `f0`.
    fn albedo(f0: f64, r: f64, strength: f64, n_dot_v: f64, along: bool) -> f64 {
        let a = Aniso {
            strength,
            t: DVec3::X,
            b: DVec3::Y,
        };
        let alpha = crate::pbr::brdf::alpha(r);
        let at = alpha + (1.0 - alpha) * strength * strength;
        let ab = alpha.clamp(0.001, 1.0);
        let s = (1.0 - n_dot_v * n_dot_v).sqrt();
        let v = if along {
            DVec3::new(s, 0.0, n_dot_v)
        } else {
            DVec3::new(0.0, s, n_dot_v)
        };
        let n = 64 * 1024;
        let mut sum = 0.0;
        for i in 0..n {
            let (u1, u2) = crate::pbr::brdf::hammersley(i, n);
            let tan = (u1 / (1.0 - u1)).sqrt();
            let phi = 2.0 * PI * u2;
            let h = DVec3::new(-at * tan * phi.cos(), -ab * tan * phi.sin(), 1.0).normalize();
            let l = 2.0 * v.dot(h) * h - v;
            if l.z <= 0.0 || v.dot(h) <= 0.0 {
                continue;
            }
            let f = f0 + (1.0 - f0) * (1.0 - v.dot(h)).powi(5);
            // f·cos / pdf(l), pdf(l) = D·(N·H) / (4·V·H); spec() is D·V.
            let dv = a.spec(DVec3::Z, n_dot_v, v, l, h, r);
            let dd = d(h.z, h.x, h.y, at, ab);
            sum += f * dv / dd * l.z * 4.0 * v.dot(h) / h.z;
        }
        sum / f64::from(n)
    }

    /// The stretched lobe conserves energy (its albedo is at most 1 for a white mirror F),
    /// and how far the Sample Viewer's environment approximation (the isotropic lobe's albedo
    /// A + B at the material's roughness, `brdf::integrate_brdf`) is from it for the tests'
    /// metal (roughness 0.35, strength 0.8): printed, and quoted in docs/gltf/extensions.md.
    #[test]
    fn the_stretched_lobe_conserves_energy() {
        for (r, s) in [(0.35, 0.8), (0.1, 1.0), (0.6, 0.5), (0.35, 0.0)] {
            for nv in [1.0, 0.7, 0.3] {
                for along in [true, false] {
                    let e = albedo(1.0, r, s, nv, along);
                    let (ia, ib) = crate::pbr::brdf::integrate_brdf(nv, r, 4096);
                    eprintln!(
                        "r {r} strength {s} N.V {nv} along {along}: stretched {e:.4}, \
                         isotropic split sum {:.4}",
                        ia + ib
                    );
                    assert!(e > 0.0 && e <= 1.0 + 1e-3, "r {r} s {s} nv {nv}: {e}");
                }
            }
        }
    }

    /// The distribution is normalised (∫ D·(N·H) dω_h = 1) for every strength: a midpoint
    /// sum over the hemisphere in polar and azimuthal steps.
    #[test]
    fn anisotropic_ggx_is_normalised() {
        let (n, t, b) = (DVec3::Z, DVec3::X, DVec3::Y);
        for (r, s) in [(0.5, 0.0), (0.5, 0.8), (0.8, 0.5), (1.0, 1.0)] {
            let alpha = crate::pbr::brdf::alpha(r);
            let at = alpha + (1.0 - alpha) * s * s;
            let ab = f64::max(alpha, 0.001);
            let (nt, np) = (400, 400);
            let mut sum = 0.0;
            for i in 0..nt {
                let th = (f64::from(i) + 0.5) / f64::from(nt) * PI / 2.0;
                for j in 0..np {
                    let ph = (f64::from(j) + 0.5) / f64::from(np) * 2.0 * PI;
                    let h = t * (th.sin() * ph.cos()) + b * (th.sin() * ph.sin()) + n * th.cos();
                    let dw = th.sin() * (PI / 2.0 / f64::from(nt)) * (2.0 * PI / f64::from(np));
                    sum += d(h.z, h.x, h.y, at, ab) * h.z * dw;
                }
            }
            assert!((sum - 1.0).abs() < 2e-3, "r {r} strength {s}: {sum}");
        }
    }

    /// At strength 0 the lobe is GGX's: D equals `brdf::d_ggx`.
    #[test]
    fn strength_zero_is_isotropic_ggx() {
        let a = Aniso {
            strength: 0.0,
            t: DVec3::X,
            b: DVec3::Y,
        };
        let h = DVec3::new(0.3, 0.2, 0.9).normalize();
        let alpha = crate::pbr::brdf::alpha(0.5);
        let got = d(h.z, h.x, h.y, alpha, alpha);
        let want = crate::pbr::brdf::d_ggx(h.z, 0.5);
        assert!((got - want).abs() < 1e-9 * want, "{got} {want}");
        // The bent normal is the normal itself when there is nothing to bend.
        let v = DVec3::new(0.2, 0.1, 1.0).normalize();
        assert!((a.bent_normal(DVec3::Z, v, 0.5) - DVec3::Z).length() < 1e-12);
    }
}
