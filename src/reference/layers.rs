//! The glTF PBR extensions in the reference renderer (the truth `pbr.frag`'s permutations
//! are measured against): the dielectric F0 of KHR_materials_ior and _specular, and the
//! sheen and clearcoat layers over the core model's radiance, from the same formulas
//! (docs/gltf/extensions.md), with the environment integrated by Monte Carlo: the coat's
//! GGX lobe by GGX-sampled half vectors, the sheen's Charlie lobe and its albedo E by
//! uniform hemisphere samples.
use super::material::{self, Corners};
use super::Context;
use crate::pbr::brdf::Surface;
use crate::pbr::sheen;
use crate::scene::model::texture_slot::Slot;
use crate::scene::Material;
use glam::DVec3;
use std::f64::consts::PI;

/// A slot's texel at the hit (None: no map or no UVs).
fn texel(m: &Material, slot: Slot, c: &Corners, srgb: bool) -> Option<glam::DVec4> {
    material::read(m, m.image(slot).map(|t| &**t), slot, c, srgb)
}

/// The dielectric (F0, F90) of KHR_materials_ior and _specular at a hit:
/// F0 = min(ior F0 · specularColor, 1) · weight, F90 = weight, weight = specularFactor.
pub(crate) fn dielectric(m: &Material, c: &Corners) -> (DVec3, f64) {
    let (f0, w) = m.khr.dielectric();
    let mut f0 = DVec3::from(f0.map(f64::from));
    let mut w = f64::from(w);
    if let Some(t) = texel(m, Slot::SpecularColor, c, true) {
        f0 *= t.truncate();
    }
    if let Some(t) = texel(m, Slot::Specular, c, false) {
        w *= t.w;
    }
    (f0.min(DVec3::ONE) * w, w)
}

/// KHR_materials_iridescence's film at a hit (None without it, or with the `--terms` layer
/// off): the factor times the texture's red (0 where the film is 0 nm thick), the thickness
/// from the minimum to the maximum by the thickness texture's green (the maximum without it).
pub(crate) fn film(m: &Material, c: &Corners, on: bool) -> Option<crate::pbr::brdf::Film> {
    let i = m.khr.iridescence.filter(|_| on)?;
    let mut factor = f64::from(i.factor);
    if let Some(t) = texel(m, Slot::Iridescence, c, false) {
        factor *= t.x;
    }
    let (lo, hi) = (f64::from(i.thickness_min), f64::from(i.thickness_max));
    let thickness =
        texel(m, Slot::IridescenceThickness, c, false).map_or(hi, |t| lo + (hi - lo) * t.y);
    // A film of no thickness is none (as the Sample Viewer: the formula would tint).
    if thickness <= 0.0 {
        factor = 0.0;
    }
    Some(crate::pbr::brdf::Film {
        factor,
        ior: f64::from(i.ior),
        thickness,
    })
}

/// KHR_materials_anisotropy's lobe at a hit (None without it, with the `--terms` layer off,
/// at strength 0, or without a tangent frame), as `pbrAnisotropy` finds it: the texture's
/// direction (red, green) or the tangent's, turned by the rotation, in the frame of the
/// interpolated tangent Gram-Schmidt against `ng` (the interpolated normal on the viewer's
/// side), bitangent ng × t · w, both flipped on back faces; b = ng × t; the strength is the
/// factor times the texture's blue.
pub(crate) fn anisotropy(
    m: &Material,
    c: &Corners,
    ng: DVec3,
    front: bool,
    on: bool,
) -> Option<crate::pbr::anisotropy::Aniso> {
    let a = m.khr.anisotropy.filter(|_| on)?;
    let tan = c.tangent()?;
    let mut strength = f64::from(a.strength);
    let mut dir = glam::DVec2::X;
    if let Some(t) = texel(m, Slot::Anisotropy, c, false) {
        dir = glam::DVec2::new(t.x, t.y) * 2.0 - glam::DVec2::ONE;
        strength *= t.z;
    }
    let (sin, cos) = f64::from(a.rotation).sin_cos();
    let dir = glam::DVec2::new(cos * dir.x - sin * dir.y, sin * dir.x + cos * dir.y);
    let dir = dir.try_normalize().unwrap_or(glam::DVec2::X);
    let side = if front { 1.0 } else { -1.0 };
    let tv = tan.truncate() * side;
    let t = (tv - ng * ng.dot(tv)).try_normalize()?;
    let b = ng.cross(t) * if tan.w < 0.0 { -side } else { side };
    let at = t * dir.x + b * dir.y;
    let strength = strength.clamp(0.0, 1.0);
    (strength > 0.0).then(|| crate::pbr::anisotropy::Aniso {
        strength,
        t: at,
        b: ng.cross(at),
    })
}

/// The layers over the core model at one hit.
#[derive(Default)]
pub(crate) struct Layers {
    /// Clearcoat factor, roughness and normal.
    clearcoat: Option<(f64, f64, DVec3)>,
    /// Sheen colour and roughness.
    sheen: Option<(DVec3, f64)>,
    /// The transmission at the hit ([`super::transmission`]).
    pub(crate) transmission: Option<super::transmission::Transmit>,
}

impl Layers {
    /// The material's layers at a hit at `p`; `n` is the interpolated normal turned to the
    /// viewer (the coat's normal where it has no map of its own), `mapped` the shading normal.
    pub(crate) fn new(
        ctx: &Context,
        m: &Material,
        c: &Corners,
        (p, n, mapped): (DVec3, DVec3, DVec3),
        front: bool,
    ) -> Layers {
        let terms = &ctx.settings.lighting.pbr_terms;
        let mut out = Layers::default();
        if super::transmission::transmissive(ctx, m) {
            out.transmission = Some(super::transmission::at_hit(ctx, m, c, p, mapped));
        }
        if let (Some(cc), true) = (m.khr.clearcoat, terms.clearcoat) {
            let mut factor = f64::from(cc.factor);
            if let Some(t) = texel(m, Slot::Clearcoat, c, false) {
                factor *= t.x;
            }
            let mut rough = f64::from(cc.roughness);
            if let Some(t) = texel(m, Slot::ClearcoatRoughness, c, false) {
                rough *= t.y;
            }
            let normal = if terms.normal_map {
                material::normal_map_slot(m, Slot::ClearcoatNormal, cc.normal_scale, c, n, front)
            } else {
                n
            };
            out.clearcoat = Some((factor, rough.clamp(0.0, 1.0), normal));
        }
        if let (Some(sh), true) = (m.khr.sheen, terms.sheen) {
            let mut color = DVec3::from(sh.color.map(f64::from));
            if let Some(t) = texel(m, Slot::SheenColor, c, true) {
                color *= t.truncate();
            }
            let mut rough = f64::from(sh.roughness);
            if let Some(t) = texel(m, Slot::SheenRoughness, c, false) {
                rough *= t.w;
            }
            out.sheen = Some((color, rough));
        }
        out
    }

    /// `base` (the core model's linear radiance at `p`, normal `n`) under the sheen, then
    /// the coat: base·(1 − max(sheen)·E) + sheen, then ·(1 − clearcoat·F_cc) + clearcoat·coat.
    pub(crate) fn over(
        &self,
        ctx: &Context,
        ao: f64,
        base: DVec3,
        p: DVec3,
        n: DVec3,
        vis: &[f64],
    ) -> DVec3 {
        let mut c = base;
        if self.sheen.is_none() && self.clearcoat.is_none() {
            return c;
        }
        let v = (ctx.view.eye - p).normalize_or_zero();
        let settings = ctx.settings;
        let terms = &settings.lighting.pbr_terms;
        let scale = f64::from(settings.lighting.pbr.ibl_intensity);
        let radiance = |d: DVec3| {
            ctx.env
                .as_ref()
                .map_or(DVec3::ZERO, |e| e.sample(d) * scale)
        };
        let samples = ctx.pbr_samples;
        // Each light's colour, direction and visibility (the direct-specular term).
        let lights: Vec<(DVec3, DVec3)> = settings
            .lights
            .iter()
            .enumerate()
            .filter(|_| terms.direct_specular)
            .map(|(i, light)| {
                let seen = if terms.shadows {
                    vis.get(i).copied().unwrap_or(1.0)
                } else {
                    1.0
                };
                (crate::shading::to_light(light, p), light.color_at(p) * seen)
            })
            .collect();
        let ibl = ctx.env.is_some() && terms.ibl_specular;
        if let Some((color, rough)) = self.sheen {
            let n_dot_v = n.dot(v).max(1e-4);
            let e = sheen::albedo(n_dot_v, rough, samples.max(256));
            let mut f = DVec3::ZERO;
            if ibl {
                // The environment's lobe scaled to an albedo of at most 1, as the table's.
                f += sheen::mc_radiance(n, v, rough, samples, &radiance) * ao / e.max(1.0);
            }
            let e = e.min(1.0);
            for (l, lc) in &lights {
                f += *lc * PI * sheen::brdf(n, v, *l, rough) * n.dot(*l).max(0.0);
            }
            c = c * (1.0 - color.max_element() * e) + f * color;
        }
        if let Some((factor, rough, cn)) = self.clearcoat {
            let coat = Surface {
                albedo: DVec3::ZERO,
                metallic: 0.0,
                roughness: rough,
                ao: 1.0,
                emissive: DVec3::ZERO,
                f0: DVec3::splat(crate::pbr::F0),
                f90: 1.0,
                transmission: 0.0,
                film: None,
                aniso: None,
            };
            let mut f = DVec3::ZERO;
            if ibl {
                f += coat.mc_specular(cn, v, samples, &radiance) * ao;
            }
            for (l, lc) in &lights {
                f += *lc * coat.direct(cn, v, *l);
            }
            let fresnel = crate::pbr::brdf::f_schlick(DVec3::splat(crate::pbr::F0), cn.dot(v));
            c = c * (DVec3::ONE - factor * fresnel) + factor * f;
        }
        c
    }
}
