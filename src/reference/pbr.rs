//! The PBR tier in the reference renderer: the same BRDF as `pbr.frag`, but the environment is
//! integrated by Monte Carlo (cosine-sampled diffuse, GGX-sampled specular, `samples` points
//! of a Hammersley set each, f64) instead of the split sum, and direct lights get exact shadow
//! rays. This is the truth the tier's precomputed maps are measured against. Texture maps are
//! read like the GPU reads them except normal maps, which the reference ignores (documented).
use super::Context;
use crate::pbr::brdf::Surface;
use crate::pbr::{srgb_decode, PbrParams};
use crate::scene::Material;
use glam::DVec3;

/// Default Monte Carlo samples per lobe and pixel; the tests state the noise this leaves.
pub const DEFAULT_SAMPLES: u32 = 2048;

/// The material at a hit as the PBR formula sees it (`tex` is the diffuse map's sRGB colour,
/// or white).
pub fn surface(m: &Material, tex: DVec3, p: &PbrParams) -> Surface {
    let v = m.pbr();
    let base = p
        .base_color
        .map(|c| c.as_dvec3())
        .unwrap_or(DVec3::from(v.base_color.map(f64::from)));
    let tex = DVec3::new(srgb_decode(tex.x), srgb_decode(tex.y), srgb_decode(tex.z));
    Surface {
        albedo: base * tex,
        metallic: f64::from(p.metallic.unwrap_or(v.metallic)),
        roughness: f64::from(p.roughness.unwrap_or(v.roughness)),
        ao: 1.0,
        emissive: DVec3::from(v.emissive.map(f64::from)),
    }
}

/// Linear radiance leaving point `p` towards the eye, then the output step (display value).
pub fn shade(ctx: &Context, s: &Surface, p: DVec3, n: DVec3, vis: &[f64]) -> DVec3 {
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
        c += visible * light.color.as_dvec3() * f;
    }
    DVec3::from(settings.lighting.output.apply(c.to_array()))
}
