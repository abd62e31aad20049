//! The legacy-tier lighting formula, evaluated on the CPU in f64. The GLSL in
//! `shaders_gl/include/phong.glsl` is the same formula; tests and the reference renderer use
//! this one as the truth.
//!
//! colour = Ke + Ka·ambient + Σ visibility·(Kd·Lc·max(N·L, 0) + Ks·Lc·spec), clamped to [0, 1],
//! spec = max(R·V, 0)^Ns where N·L > 0 (0 elsewhere); Ns <= 0 gives spec = 1 where N·L > 0
//! (the limit x^0 = 1), so pow never sees 0^0 or a negative base.
use crate::frame::LightingParams;
use crate::light::{Light, LightKind};
use crate::scene::Material;
use glam::DVec3;

/// The specular factor; see the module comment for Ns <= 0.
pub fn specular_factor(r_dot_v: f64, ns: f64) -> f64 {
    if ns <= 0.0 {
        1.0
    } else if r_dot_v <= 0.0 {
        0.0
    } else {
        r_dot_v.powf(ns)
    }
}

/// Unit vector from `p` towards the light.
pub fn to_light(light: &Light, p: DVec3) -> DVec3 {
    match light.kind {
        LightKind::Point(q) => (q.as_dvec3() - p).normalize_or_zero(),
        LightKind::Directional(d) => -d.as_dvec3().normalize(),
    }
}

/// What a material's textures give at one point (white where it has none).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Tex {
    /// Multiplies Ka and Kd (the diffuse map, times vertex colours).
    pub diffuse: DVec3,
    /// Multiplies Ke (the emissive map).
    pub emissive: DVec3,
}

impl Tex {
    pub const WHITE: Tex = Tex {
        diffuse: DVec3::ONE,
        emissive: DVec3::ONE,
    };

    pub fn diffuse(c: DVec3) -> Tex {
        Tex {
            diffuse: c,
            ..Tex::WHITE
        }
    }
}

/// Shades one point. `n` is the unit normal already flipped towards the viewer's side for
/// back faces; `tex` multiplies Ka and Kd, and Ke; `visibility[i]` is light i's shadow
/// factor (1 = lit).
#[allow(clippy::too_many_arguments)] // the formula's inputs, kept flat to mirror the GLSL
pub fn shade(
    m: &Material,
    tex: Tex,
    p: DVec3,
    n: DVec3,
    eye: DVec3,
    lights: &[Light],
    visibility: &[f64],
    params: &LightingParams,
) -> DVec3 {
    let ph = m.phong_terms();
    let ka = DVec3::from(ph.ambient.map(f64::from)) * tex.diffuse;
    let kd = DVec3::from(ph.diffuse.map(f64::from)) * tex.diffuse;
    let ks = DVec3::from(ph.specular.map(f64::from));
    let mut c = DVec3::from(m.legacy_emissive().map(f64::from)) * tex.emissive;
    if params.terms.ambient {
        c += ka * params.ambient;
    }
    let v = (eye - p).normalize_or_zero();
    for (i, light) in lights.iter().enumerate() {
        let l = to_light(light, p);
        let lc = light.color_at(p);
        let n_dot_l = n.dot(l);
        let vis = visibility.get(i).copied().unwrap_or(1.0);
        let diffuse = if params.wrap {
            (1.0 + n_dot_l) * 0.5
        } else {
            n_dot_l.max(0.0)
        };
        let mut lit = DVec3::ZERO;
        if params.terms.diffuse {
            lit += kd * lc * diffuse;
        }
        if params.terms.specular && n_dot_l > 0.0 {
            let r = reflect(-l, n);
            lit += ks * lc * specular_factor(r.dot(v), f64::from(ph.shininess));
        }
        c += vis * lit;
    }
    c.clamp(DVec3::ZERO, DVec3::ONE)
}

pub fn reflect(i: DVec3, n: DVec3) -> DVec3 {
    i - 2.0 * n.dot(i) * n
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    fn white_light_above() -> Light {
        Light::new(LightKind::Directional(Vec3::NEG_Y), Vec3::ONE)
    }

    #[test]
    fn default_material_facing_light() {
        let m = Material::default();
        let c = shade(
            &m,
            Tex::WHITE,
            DVec3::ZERO,
            DVec3::Y,
            DVec3::Y * 5.0,
            &[white_light_above()],
            &[],
            &LightingParams::default(),
        );
        // 0.2 * 0.2 ambient + 0.8 diffuse.
        assert!((c - DVec3::splat(0.84)).length() < 1e-6);
    }

    #[test]
    fn ns_zero_and_grazing_are_finite() {
        assert_eq!(specular_factor(0.0, 0.0), 1.0);
        assert_eq!(specular_factor(-0.5, 10.0), 0.0);
        assert_eq!(specular_factor(0.5, 10_000.0), 0.0);
        assert!((specular_factor(0.5, 2.0) - 0.25).abs() < 1e-15);
    }

    #[test]
    fn shadowed_light_keeps_ambient_only() {
        let m = Material::default();
        let c = shade(
            &m,
            Tex::WHITE,
            DVec3::ZERO,
            DVec3::Y,
            DVec3::Y,
            &[white_light_above()],
            &[0.0],
            &LightingParams::default(),
        );
        assert!((c - DVec3::splat(0.04)).length() < 1e-6);
    }

    #[test]
    fn wrap_lights_the_back_half() {
        let m = Material::default();
        let p = LightingParams {
            wrap: true,
            ..Default::default()
        };
        let c = shade(
            &m,
            Tex::WHITE,
            DVec3::ZERO,
            DVec3::X,
            DVec3::X,
            &[white_light_above()],
            &[],
            &p,
        );
        assert!((c.x - (0.04 + 0.4)).abs() < 1e-6);
    }
}
