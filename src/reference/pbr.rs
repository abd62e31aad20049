//! The PBR tier in the reference renderer: the same BRDF as `pbr.frag`, but the environment is
//! integrated by Monte Carlo (cosine-sampled diffuse, GGX-sampled specular, `samples` points
//! of a Hammersley set each, f64) instead of the split sum, and direct lights get exact shadow
//! rays. This is the truth the tier's precomputed maps are measured against. Material maps
//! are read as `pbr.frag` reads them (`super::material`): glTF's metallic-roughness image
//! (B metal, G rough) and occlusion (R, strength) each through their own slot, an MTL's
//! separate maps directly (the GPU packs them into one texture, nearest-resampled to the
//! largest: where their sizes differ the two can differ), the emissive map sRGB-decoded.
use super::material::{self, Corners};
use super::Context;
use crate::frame::LightingParams;
use crate::pbr::brdf::Surface;
use crate::scene::model::texture_slot::{Slot, TextureSlot};
use crate::scene::Material;
use glam::DVec3;

/// Default Monte Carlo samples per lobe and pixel; the tests state the noise this leaves.
pub(crate) const DEFAULT_SAMPLES: u32 = crate::options::DEFAULT_REFERENCE_SAMPLES;

/// The material at a hit as the PBR formula sees it (`base` is the base colour texture's
/// linear colour, or white).
pub(crate) fn surface(m: &Material, base: DVec3, c: &Corners, l: &LightingParams) -> Surface {
    let p = &l.pbr;
    let factor = p
        .base_color
        .map(|c| c.as_dvec3())
        .unwrap_or(DVec3::from(m.base_color.map(f64::from)));
    let mut metallic = f64::from(p.metallic.unwrap_or(m.metallic));
    let mut roughness = f64::from(p.roughness.unwrap_or(m.roughness));
    let mut ao = 1.0;
    if !m.packs_orm() {
        if let Some(mr) = material::read(
            m,
            image(&m.metallic_roughness_texture),
            Slot::MetallicRoughness,
            c,
            false,
        ) {
            roughness *= mr.y;
            metallic *= mr.z;
        }
        let occlusion = material::read(m, image(&m.occlusion_texture), Slot::Occlusion, c, false);
        if let Some(r) = occlusion.map(|x| x.x) {
            ao *= 1.0 + f64::from(m.occlusion_strength) * (r - 1.0);
        }
    } else {
        // An MTL's maps: red channels, repeat and linear like the packed texture.
        let plain = |t: &Option<TextureSlot>| {
            image(t)
                .filter(|_| c.mesh.has_uv)
                .map(|t| material::sample(t, &Default::default(), c.uv(0), false).x)
        };
        ao = plain(&m.occlusion_texture).unwrap_or(1.0);
        roughness *= plain(&m.roughness_texture).unwrap_or(1.0);
        metallic *= plain(&m.metallic_texture).unwrap_or(1.0);
    }
    if !l.pbr_terms.ao {
        ao = 1.0;
    }
    let emissive = material::read(m, image(&m.emissive_texture), Slot::Emissive, c, true)
        .map_or(DVec3::ONE, |t| t.truncate());
    let (f0, f90) = if m.khr.has_f0() {
        super::layers::dielectric(m, c)
    } else {
        Surface::CORE_F0
    };
    Surface {
        albedo: factor * base,
        metallic,
        roughness,
        ao,
        emissive: DVec3::from(m.emissive.map(f64::from)) * emissive,
        f0,
        f90,
        transmission: 0.0,
        film: super::layers::film(m, c, l.pbr_terms.iridescence),
        // Set where the normal is known (`super::surface`).
        aniso: None,
    }
}

/// A slot's decoded image.
fn image(t: &Option<TextureSlot>) -> Option<&crate::scene::Texture> {
    t.as_ref().map(|t| &*t.image)
}

/// Linear radiance leaving point `p` towards the eye with the extensions' layers over it, then
/// the output step (display value).
pub(crate) fn shade(
    ctx: &Context,
    s: &Surface,
    layers: &super::layers::Layers,
    p: DVec3,
    n: DVec3,
    vis: &[f64],
) -> DVec3 {
    let mut s = *s;
    let transmitted = layers.transmission.map(|t| {
        s.transmission = t.factor;
        let v = (ctx.view.eye - p).normalize_or_zero();
        let n_dot_v = n.dot(v).max(1e-4);
        super::transmission::passed(&s, n_dot_v, t.factor, t.light, ctx.pbr_samples)
            + super::transmission::punctual(ctx, &s, &t, (p, n), v)
    });
    let c = shade_linear(ctx, &s, p, n, vis) + transmitted.unwrap_or(DVec3::ZERO);
    let c = layers.over(ctx, s.ao, c, p, n, vis);
    DVec3::from(ctx.settings.lighting.output.apply(c.to_array()))
}

/// The core model's linear radiance leaving point `p` towards the eye.
fn shade_linear(ctx: &Context, s: &Surface, p: DVec3, n: DVec3, vis: &[f64]) -> DVec3 {
    let settings = ctx.settings;
    let terms = &settings.lighting.pbr_terms;
    let params = &settings.lighting.pbr;
    let v = (ctx.view.eye - p).normalize_or_zero();
    let mut c = if terms.emissive {
        s.emissive
    } else {
        DVec3::ZERO
    };
    if let Some(env) = &ctx.env {
        let scale = f64::from(params.ibl_intensity);
        let radiance = |d: DVec3| env.sample(d) * scale;
        let n_samples = ctx.pbr_samples;
        if terms.ibl_diffuse {
            c += Surface::mc_irradiance(n, n_samples, &radiance) * s.kd() * s.ao;
        }
        if terms.ibl_specular {
            c += s.mc_specular(n, v, n_samples, &radiance) * s.ao;
        }
    }
    for (i, light) in settings.lights.iter().enumerate() {
        let l = crate::shading::to_light(light, p);
        let visible = if terms.shadows {
            vis.get(i).copied().unwrap_or(1.0)
        } else {
            1.0
        };
        let mut f = DVec3::ZERO;
        if terms.direct_diffuse {
            f += s.kd() * n.dot(l).max(0.0);
        }
        if terms.direct_specular {
            f += s.direct(n, v, l) - s.kd() * n.dot(l).max(0.0);
        }
        c += visible * light.color_at(p) * f;
    }
    c
}
