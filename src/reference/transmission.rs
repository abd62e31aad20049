//! KHR_materials_transmission and _volume in the reference renderer, from the tier's formula
//! (`pbr.frag`, docs/gltf/extensions.md): the light from behind is the opaque frame without
//! the transmissive meshes (what the GPU copies) where the ray leaves — straight on when
//! thin-walled, refracted through the thickness with a volume — with its output step undone,
//! attenuated by Beer–Lambert; the surface passes (1 − its specular albedo) of it, tinted by
//! the base colour, for the dielectric share. Read sharp: the GPU blurs rough transmission
//! across its copy's mip chain, which this does not reproduce.
use super::bvh::Hit;
use super::material::{self, Corners};
use super::Context;
use crate::pbr::brdf::{integrate_brdf, Surface};
use crate::pbr::Tonemap;
use crate::scene::model::texture_slot::Slot;
use crate::scene::Material;
use glam::{DVec3, DVec4};

/// Whether the rasterizer draws `m` after the opaque frame's copy (the GPU's rule).
pub(crate) fn transmissive(ctx: &Context, m: &Material) -> bool {
    let s = ctx.settings;
    s.shading == crate::frame::Shading::Pbr
        && s.lighting.pbr_terms.transmission
        && s.lighting.translucency.mode != crate::frame::TranslucencyMode::NearestMasked
        && m.khr.transmission.is_some_and(|t| t > 0.0)
}

/// The transmission at a hit.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Transmit {
    pub(crate) factor: f64,
    /// The linear light from behind (attenuated).
    pub(crate) light: DVec3,
    /// Where the ray leaves (the hit itself when thin-walled).
    pub(crate) exit: DVec3,
    /// Beer–Lambert's factor over the thickness (1 without a volume).
    pub(crate) attenuation: DVec3,
    pub(crate) ior: f64,
}

/// The transmission at a hit.
pub(crate) fn at_hit(ctx: &Context, m: &Material, c: &Corners, p: DVec3, n: DVec3) -> Transmit {
    let mut factor = f64::from(m.khr.transmission.unwrap_or(0.0));
    if let Some(t) = material::read(
        m,
        m.image(Slot::Transmission).map(|t| &**t),
        Slot::Transmission,
        c,
        false,
    ) {
        factor *= t.x;
    }
    let v = (ctx.view.eye - p).normalize_or_zero();
    let mut exit = p;
    let mut travel = 0.0;
    if let Some(vol) = m.khr.volume {
        let mut thick = f64::from(vol.thickness);
        if let Some(t) = material::read(
            m,
            m.image(Slot::Thickness).map(|t| &**t),
            Slot::Thickness,
            c,
            false,
        ) {
            thick *= t.y;
        }
        let ior = f64::from(m.khr.ior.unwrap_or(1.5).max(1.0));
        exit += refract(-v, n, 1.0 / ior).normalize_or_zero() * thick;
        travel = thick;
    }
    let clip = ctx.view.forward * DVec4::new(exit.x, exit.y, exit.z, 1.0);
    let (nx, ny) = (clip.x / clip.w, clip.y / clip.w);
    let (o, d) = ctx.view.ray_ndc(nx, ny);
    let behind = ctx.opaque.closest_where(o, d, 0.0, 1.0, |h| {
        material::drawn(ctx, h, d) && !transmissive(ctx, material_of(ctx, h))
    });
    let shown = match &behind {
        Some(h) => {
            let mut vis = Vec::new();
            super::surface::shade_hit(ctx, h, d, &mut vis).color
        }
        None => super::background(ctx, d),
    };
    let mut attenuation = DVec3::ONE;
    if let Some(vol) = m.khr.volume {
        if let Some(dist) = vol.attenuation_distance {
            let c = DVec3::from(vol.attenuation_color.map(f64::from)).max(DVec3::splat(1e-6));
            attenuation = c.powf(travel / f64::from(dist));
        }
    }
    Transmit {
        factor,
        light: inverse_output(ctx, shown) * attenuation,
        exit,
        attenuation,
        ior: f64::from(m.khr.ior.unwrap_or(1.5).max(1.0)),
    }
}

/// The lights through the surface (`pbr.frag`'s punctual BTDF, the Sample Viewer's): each
/// light's direction from the exit point mirrored to the viewer's side, a GGX lobe of the
/// roughness scaled by the ior, (1 − F)·albedo, no cosine, no shadow.
/// A file light's falloff is taken at `p`, where the light arrives, as the GPU does.
pub(crate) fn punctual(
    ctx: &Context,
    s: &Surface,
    t: &Transmit,
    (p, n): (DVec3, DVec3),
    v: DVec3,
) -> DVec3 {
    use crate::pbr::brdf::{d_ggx, f_schlick90, g_smith};
    if !ctx.settings.lighting.pbr_terms.direct_diffuse {
        return DVec3::ZERO;
    }
    let n_dot_v = n.dot(v).max(1e-4);
    let rough = s.roughness * (2.0 * t.ior - 2.0).clamp(0.0, 1.0);
    let mut sum = DVec3::ZERO;
    for light in &ctx.settings.lights {
        let l = crate::shading::to_light(light, t.exit);
        let lm = (l - 2.0 * n * l.dot(n)).normalize_or_zero();
        let h = (lm + v).normalize_or_zero();
        let n_dot_l = n.dot(lm).max(1e-4);
        let f = f_schlick90(s.ks(), s.f90(), v.dot(h).max(0.0));
        let bt = (DVec3::ONE - f)
            * s.albedo
            * d_ggx(n.dot(h).max(0.0), rough)
            * g_smith(n_dot_v, n_dot_l, rough)
            / (4.0 * n_dot_v * n_dot_l);
        sum += light.color_at(p) * std::f64::consts::PI * bt * t.attenuation;
    }
    t.factor * (1.0 - s.metallic) * sum
}

fn material_of<'a>(ctx: &'a Context, h: &Hit) -> &'a Material {
    &ctx.scene.materials[ctx.scene.meshes[h.tri.mesh as usize].material]
}

/// GLSL's refract (zero on total internal reflection).
fn refract(i: DVec3, n: DVec3, eta: f64) -> DVec3 {
    let k = 1.0 - eta * eta * (1.0 - n.dot(i).powi(2));
    if k < 0.0 {
        DVec3::ZERO
    } else {
        eta * i - (eta * n.dot(i) + k.sqrt()) * n
    }
}

/// What the surface passes of the light behind: trans·(1 − metallic)·(1 − (k_s·A + F90·B))
/// ·albedo·light, (A, B) integrated here.
pub(crate) fn passed(s: &Surface, n_dot_v: f64, factor: f64, light: DVec3, samples: u32) -> DVec3 {
    let (a, b) = integrate_brdf(n_dot_v, s.roughness, samples.max(256));
    let spec = s.ks() * a + DVec3::splat(s.f90() * b);
    factor * (1.0 - s.metallic) * (DVec3::ONE - spec) * s.albedo * light
}

/// The output step undone (`glviewInverseOutput`): sRGB decoded, the tone curve inverted,
/// the exposure divided out; at most 4 before the exposure.
pub(crate) fn inverse_output(ctx: &Context, shown: DVec3) -> DVec3 {
    let out = ctx.settings.lighting.output;
    let y = shown.map(|s| crate::pbr::srgb_decode(s.clamp(0.0, 1.0)));
    let y = match out.tonemap {
        Tonemap::None => y,
        Tonemap::Reinhard => y.min(DVec3::splat(0.999)).map(|y| y / (1.0 - y)),
        Tonemap::Aces => y.min(DVec3::splat(0.999)).map(|y| {
            let (a, b, c) = (2.43 * y - 2.51, 0.59 * y - 0.03, 0.14 * y);
            ((-b - (b * b - 4.0 * a * c).max(0.0).sqrt()) / (2.0 * a)).max(0.0) / 0.6
        }),
        Tonemap::KhronosNeutral => {
            let start = 0.8 - 0.04;
            let d = 1.0 - start;
            let mut y = y;
            let peak = y.max_element();
            if peak >= start {
                let p = peak.min(0.999);
                y *= (d * d / (1.0 - p) - d + start) / peak.max(1e-6);
            }
            let m = y.min_element();
            let x = if m < 0.04 {
                (m.max(0.0) / 6.25).sqrt()
            } else {
                m + 0.04
            };
            y + DVec3::splat(if x < 0.08 { x - 6.25 * x * x } else { 0.04 })
        }
    };
    y.min(DVec3::splat(4.0)) / 2f64.powf(f64::from(out.exposure_ev))
}
