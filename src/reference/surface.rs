//! Shading one ray hit the way `lit.frag` does: interpolated normal (flipped on back faces),
//! bilinear texture, exact shadow rays, then `shading::shade` (Phong) or per-vertex factors
//! interpolated across the triangle (Gouraud, as `lit.vert` computes them).
use super::bvh::Hit;
use super::material::{self, Corners};
use super::Context;
use crate::frame::Shading;
use crate::light::{Light, LightKind};
use crate::scene::model::texture_slot::Slot;
use crate::scene::Mesh;
use crate::shading::{reflect, shade, specular_factor, to_light, Tex};
use glam::DVec3;

/// What the renderer records about a shaded surface besides its colour.
pub(crate) struct Shaded {
    pub(crate) color: DVec3,
    /// Bit i set: light i's shadow ray was blocked.
    pub(crate) shadowed: u32,
}

pub(crate) fn shade_hit(ctx: &Context, hit: &Hit, dir: DVec3, vis: &mut Vec<f64>) -> Shaded {
    let mesh = &ctx.scene.meshes[hit.tri.mesh as usize];
    let material = &ctx.scene.materials[mesh.material];
    let corners = Corners::new(ctx, hit);
    let vtx = corners.idx.map(|i| &mesh.vertices[i]);
    let w = corners.w;
    let pos = vtx.map(|v| DVec3::from(v.position.map(f64::from)));
    // On the triangle itself rather than origin + t·dir, so its distance from the plane (which
    // the shadow-ray offset must exceed) does not grow with the camera's distance.
    let p = w[0] * pos[0] + w[1] * pos[1] + w[2] * pos[2];
    let ng = (pos[1] - pos[0]).cross(pos[2] - pos[0]).normalize_or_zero();
    let front = ng.dot(dir) < 0.0;
    let pbr_tier = ctx.settings.shading == Shading::Pbr;
    // The base colour texture: display values for the legacy tier, decoded per texel for
    // PBR (an sRGB texture format decodes before filtering).
    let base = material::read(
        material,
        material.image(Slot::BaseColor).map(|t| &**t),
        Slot::BaseColor,
        &corners,
        pbr_tier,
    )
    .map_or(DVec3::ONE, |t| t.truncate());
    // Vertex colours: interpolated like any attribute; they multiply what a texture
    // multiplies (Ka and Kd in the legacy tier, the base colour after sRGB decoding in PBR).
    let vc = vertex_colour(mesh, &w, &corners.idx);
    if material.unlit {
        // KHR_materials_unlit: the base colour is the colour, through the output step.
        let color = if pbr_tier {
            let mut s = super::pbr::surface(material, base, &corners, &ctx.settings.lighting);
            s.albedo *= vc.map(crate::pbr::srgb_decode);
            DVec3::from(ctx.settings.lighting.output.apply(s.albedo.to_array()))
        } else {
            let kd = DVec3::from(material.phong_terms().diffuse.map(f64::from));
            (kd * base * vc).clamp(DVec3::ZERO, DVec3::ONE)
        };
        return Shaded { color, shadowed: 0 };
    }

    // The interpolated normal, turned to the viewer's side of the facet like the GPU's.
    let ns = w[0] * normal_of(vtx[0].normal) + w[1] * normal_of(vtx[1].normal);
    let ns = safe_normalize(ns + w[2] * normal_of(vtx[2].normal), ctx.view.back);
    let ns = if front { ns } else { -ns };
    let lift = ctx.terminator_lift[hit.tri.mesh as usize];
    let lights = &ctx.settings.lights;
    vis.clear();
    let mut shadowed = 0;
    for (i, light) in lights.iter().enumerate() {
        // Only the first `shadow_casters` lights cast, as on the GPU.
        let casts = i < usize::from(ctx.settings.lighting.shadow_casters);
        let lit = !ctx.shadows || !casts || light_visible(ctx, p, ng, ns, lift, light);
        if !lit && i < 32 {
            shadowed |= 1 << i;
        }
        vis.push(if lit { 1.0 } else { 0.0 });
    }
    debug_assert!(p.is_finite() && base.is_finite(), "bad hit {hit:?}");
    // The normal map bends the per-fragment normal (not Gouraud's per-vertex factors).
    let mapped = |n: DVec3| {
        if ctx.settings.lighting.pbr_terms.normal_map {
            material::normal_map(material, &corners, n, front)
        } else {
            n
        }
    };

    let color = if pbr_tier {
        let mut s = super::pbr::surface(material, base, &corners, &ctx.settings.lighting);
        s.albedo *= vc.map(crate::pbr::srgb_decode);
        let n = mapped(ns);
        let on = ctx.settings.lighting.pbr_terms.anisotropy;
        s.aniso = super::layers::anisotropy(material, &corners, ns, front, on);
        let layers = super::layers::Layers::new(ctx, material, &corners, (p, ns, n), front);
        super::pbr::shade(ctx, &s, &layers, p, n, vis)
    } else {
        let emissive = material::read(
            material,
            material.image(Slot::Emissive).map(|t| &**t),
            Slot::Emissive,
            &corners,
            false,
        )
        .map_or(DVec3::ONE, |t| t.truncate());
        let tex = Tex {
            diffuse: base * vc,
            emissive,
        };
        if ctx.settings.shading == Shading::Gouraud {
            gouraud(
                ctx,
                material,
                &pos,
                &vtx.map(|v| v.normal),
                &w,
                front,
                tex,
                vis,
            )
        } else {
            debug_assert!(ns.is_normalized(), "normal {ns} at {hit:?}");
            let params = &ctx.settings.lighting;
            shade(
                material,
                tex,
                p,
                mapped(ns),
                ctx.view.eye,
                lights,
                vis,
                params,
            )
        }
    };
    Shaded { color, shadowed }
}

fn normal_of(n: [f32; 3]) -> DVec3 {
    DVec3::from(n.map(f64::from))
}

/// `safeNormalize` of lighting.glsl: a zero (or, here, non-finite) normal becomes eye-space +Z,
/// i.e. it faces the camera.
fn safe_normalize(n: DVec3, fallback: DVec3) -> DVec3 {
    let len = n.length();
    if len > 0.0 && len.is_finite() {
        n / len
    } else {
        fallback
    }
}

/// A shadow ray towards the light, blocked by opaque triangles only (translucent meshes are
/// not drawn into the GPU's shadow maps either). Its origin moves off the surface by a tiny
/// step along the geometric normal, to the side the light is on: the hit point lies on the
/// plane only up to rounding, and without the step the ray could re-hit its own triangle.
/// The step, 1e-7 of the scene's radius, is orders of magnitude above f64 rounding of scene
/// coordinates and orders below anything a pixel resolves. Stepping to the light's side
/// means a triangle never shadows itself; on a closed mesh a facet that faces away from the
/// light is still shadowed by the mesh's lit side, as in the limit of a shadow map.
///
/// The shadow terminator rule of `shadow.glsl`: where the shading normal `ns` faces the light
/// but the facet (`ng`, turned to `ns`'s side) faces away, the facet would be shadowed by its
/// own lit neighbours (dark triangles inside the lit side of coarse smooth meshes); there the
/// ray starts `lift` along `ns` instead, at about the smooth surface the normals describe.
pub(super) fn light_visible(
    ctx: &Context,
    p: DVec3,
    ng: DVec3,
    ns: DVec3,
    lift: f64,
    light: &Light,
) -> bool {
    let towards = match light.kind {
        LightKind::Point(q) => q.as_dvec3() - p,
        LightKind::Directional(d) => -d.as_dvec3(),
    };
    let ngs = if ng.dot(ns) < 0.0 { -ng } else { ng };
    let band = ns.dot(towards) > 0.0 && ngs.dot(towards) <= 0.0;
    let p = if band { p + ns * lift } else { p };
    let towards = match light.kind {
        LightKind::Point(q) => q.as_dvec3() - p,
        LightKind::Directional(d) => -d.as_dvec3(),
    };
    let step = if ng.dot(towards) >= 0.0 { ng } else { -ng } * ctx.epsilon;
    let o = p + step;
    // What the shadow pass draws: the light is its viewer, looking back along the ray.
    let drawn = |d: DVec3| move |hit: &Hit| material::drawn(ctx, hit, -d);
    match light.kind {
        LightKind::Point(q) => {
            let d = q.as_dvec3() - o;
            !ctx.opaque.occluded_where(o, d, 0.0, 1.0, drawn(d))
        }
        LightKind::Directional(_) => {
            !ctx.opaque
                .occluded_where(o, towards, 0.0, f64::INFINITY, drawn(towards))
        }
    }
}

/// The interpolated vertex colour at the hit (white where the mesh has none).
fn vertex_colour(mesh: &Mesh, w: &[f64; 3], idx: &[usize; 3]) -> DVec3 {
    if mesh.colors.len() != mesh.vertices.len() {
        return DVec3::ONE;
    }
    (0..3).fold(DVec3::ZERO, |a, k| {
        a + w[k] * DVec3::from(mesh.colors[idx[k]].map(f64::from))
    })
}

/// `lightFactors` of lighting.glsl: (diffuse, specular) for one light.
fn light_factors(l: DVec3, n: DVec3, v: DVec3, ns: f64, wrap: bool) -> (f64, f64) {
    let nl = n.dot(l);
    let d = if wrap { (1.0 + nl) * 0.5 } else { nl.max(0.0) };
    let s = if nl > 0.0 {
        specular_factor(reflect(-l, n).dot(v), ns)
    } else {
        0.0
    };
    (d, s)
}

/// Gouraud as the GPU does it: factors per vertex for the normal and its opposite, the
/// facing set interpolated (the ray's barycentrics are the perspective-correct ones), and
/// texture and shadow applied per pixel.
#[allow(clippy::too_many_arguments)]
fn gouraud(
    ctx: &Context,
    m: &crate::scene::Material,
    pos: &[DVec3; 3],
    normals: &[[f32; 3]; 3],
    w: &[f64; 3],
    front: bool,
    tex: Tex,
    vis: &[f64],
) -> DVec3 {
    let s = ctx.settings;
    let (terms, eye) = (s.lighting.terms, ctx.view.eye);
    let rgb = |c: [f32; 3]| DVec3::from(c.map(f64::from));
    let ph = m.phong_terms();
    let mut c = rgb(m.legacy_emissive()) * tex.emissive;
    let tex = tex.diffuse;
    if terms.ambient {
        c += rgb(ph.ambient) * tex * s.lighting.ambient;
    }
    for (i, light) in s.lights.iter().enumerate() {
        let (mut fd, mut fs) = (0.0, 0.0);
        for k in 0..3 {
            let n = safe_normalize(normal_of(normals[k]), ctx.view.back);
            let n = if front { n } else { -n };
            debug_assert!(n.is_normalized(), "normal {n}");
            let v = (eye - pos[k]).normalize_or_zero();
            let l = to_light(light, pos[k]);
            let (d, sp) = light_factors(l, n, v, f64::from(ph.shininess), s.lighting.wrap);
            // lit.vert's factors carry the falloff per vertex.
            let fall = light.falloff_at(pos[k]);
            fd += w[k] * d * fall;
            fs += w[k] * sp * fall;
        }
        let lc = light.color.as_dvec3();
        let mut lit = DVec3::ZERO;
        if terms.diffuse {
            lit += rgb(ph.diffuse) * tex * lc * fd;
        }
        if terms.specular {
            lit += rgb(ph.specular) * lc * fs;
        }
        c += vis.get(i).copied().unwrap_or(1.0) * lit;
    }
    c.clamp(DVec3::ZERO, DVec3::ONE)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::reference::material::sample;
    use crate::scene::model::texture_slot::Sampler;
    use crate::scene::Texture;

    fn checker() -> Texture {
        // 2×2: white, black / black, white (row 0 on top).
        let px = |c: u8| [c, c, c, 255];
        let rgba = [px(255), px(0), px(0), px(255)].concat();
        Texture {
            path: "checker".into(),
            image: None,
            width: 2,
            height: 2,
            rgba,
        }
    }

    #[test]
    fn default_sampler_hits_texel_centres_and_wraps() {
        let t = checker();
        let s = Sampler::default();
        let at = |u: f64, v: f64| sample(&t, &s, glam::DVec2::new(u, v), false).truncate();
        assert_eq!(at(0.25, 0.25), DVec3::ONE);
        assert_eq!(at(0.75, 0.25), DVec3::ZERO);
        assert_eq!(at(0.25, 0.75), DVec3::ZERO);
        // Halfway between texel centres, and across the REPEAT seam.
        assert!((at(0.5, 0.25) - DVec3::splat(0.5)).length() < 1e-12);
        assert!((at(0.0, 0.25) - DVec3::splat(0.5)).length() < 1e-12);
        assert_eq!(at(1.25, -0.75), DVec3::ONE);
        assert!((at(1e9 + 0.25, 0.25) - DVec3::ONE).length() < 1e-6);
        assert!(at(f64::NAN, 0.0).is_finite());
    }

    #[test]
    fn factors_match_the_formula_limits() {
        let (n, l) = (DVec3::Y, DVec3::Y);
        assert_eq!(light_factors(l, n, DVec3::Y, 0.0, false), (1.0, 1.0));
        assert_eq!(light_factors(-l, n, DVec3::Y, 0.0, false), (0.0, 0.0));
        assert_eq!(light_factors(-l, n, DVec3::Y, 8.0, true), (0.0, 0.0));
        assert_eq!(light_factors(DVec3::X, n, DVec3::Y, 8.0, true), (0.5, 0.0));
        assert_eq!(safe_normalize(DVec3::ZERO, DVec3::Z), DVec3::Z);
        assert_eq!(safe_normalize(DVec3::NAN, DVec3::Z), DVec3::Z);
    }
}
