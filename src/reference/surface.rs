//! Shading one ray hit the way `lit.frag` does: interpolated normal (flipped on back faces),
//! bilinear texture, exact shadow rays, then `shading::shade` (Phong) or per-vertex factors
//! interpolated across the triangle (Gouraud, as `lit.vert` computes them).
use super::bvh::Hit;
use super::Context;
use crate::frame::Shading;
use crate::light::{Light, LightKind};
use crate::scene::{Mesh, Texture};
use crate::shading::{reflect, shade, specular_factor, to_light};
use glam::DVec3;

/// What the renderer records about a shaded surface besides its colour.
pub struct Shaded {
    pub color: DVec3,
    /// Bit i set: light i's shadow ray was blocked.
    pub shadowed: u32,
}

pub fn shade_hit(ctx: &Context, hit: &Hit, dir: DVec3, vis: &mut Vec<f64>) -> Shaded {
    let mesh = &ctx.scene.meshes[hit.tri.mesh as usize];
    let material = &ctx.scene.materials[mesh.material];
    let base = 3 * hit.tri.tri as usize;
    let corner = |k: usize| &mesh.vertices[mesh.indices[base + k] as usize];
    let vtx = [corner(0), corner(1), corner(2)];
    let w = [1.0 - hit.u - hit.v, hit.u, hit.v];
    let pos = vtx.map(|v| DVec3::from(v.position.map(f64::from)));
    // On the triangle itself rather than origin + t·dir, so its distance from the plane (which
    // the shadow-ray offset must exceed) does not grow with the camera's distance.
    let p = w[0] * pos[0] + w[1] * pos[1] + w[2] * pos[2];
    let ng = (pos[1] - pos[0]).cross(pos[2] - pos[0]).normalize_or_zero();
    let front = ng.dot(dir) < 0.0;
    let tex = texture_colour(ctx, mesh, hit, &w);
    // Vertex colours: interpolated like any attribute; they multiply what a texture
    // multiplies (Ka and Kd in the legacy tier, the base colour after sRGB decoding in PBR).
    let vc = vertex_colour(mesh, hit, &w);

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
    debug_assert!(p.is_finite() && tex.is_finite(), "bad hit {hit:?}");

    let color = if ctx.settings.shading == Shading::Pbr {
        let n = w[0] * normal_of(vtx[0].normal) + w[1] * normal_of(vtx[1].normal);
        let n = safe_normalize(n + w[2] * normal_of(vtx[2].normal), ctx.view.back);
        let n = if front { n } else { -n };
        let mut s = super::pbr::surface(material, tex, &ctx.settings.lighting.pbr);
        s.albedo *= vc.map(crate::pbr::srgb_decode);
        super::pbr::shade(ctx, &s, p, n, vis)
    } else if ctx.settings.shading == Shading::Gouraud {
        gouraud(
            ctx,
            material,
            &pos,
            &vtx.map(|v| v.normal),
            &w,
            front,
            tex * vc,
            vis,
        )
    } else {
        let n = w[0] * normal_of(vtx[0].normal) + w[1] * normal_of(vtx[1].normal);
        let n = safe_normalize(n + w[2] * normal_of(vtx[2].normal), ctx.view.back);
        let n = if front { n } else { -n };
        debug_assert!(n.is_normalized(), "normal {n} at {hit:?}");
        let params = &ctx.settings.lighting;
        shade(material, tex * vc, p, n, ctx.view.eye, lights, vis, params)
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
fn light_visible(ctx: &Context, p: DVec3, ng: DVec3, ns: DVec3, lift: f64, light: &Light) -> bool {
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
    match light.kind {
        LightKind::Point(q) => !ctx.opaque.occluded(o, q.as_dvec3() - o, 0.0, 1.0),
        LightKind::Directional(_) => !ctx.opaque.occluded(o, towards, 0.0, f64::INFINITY),
    }
}

/// The interpolated vertex colour at the hit (white where the mesh has none).
fn vertex_colour(mesh: &Mesh, hit: &Hit, w: &[f64; 3]) -> DVec3 {
    if mesh.colors.len() != mesh.vertices.len() {
        return DVec3::ONE;
    }
    let base = 3 * hit.tri.tri as usize;
    (0..3).fold(DVec3::ZERO, |a, k| {
        let c = mesh.colors[mesh.indices[base + k] as usize];
        a + w[k] * DVec3::from(c.map(f64::from))
    })
}

/// The diffuse map's colour at the hit (white without one), sampled like GL_LINEAR at level 0
/// with GL_REPEAT: texel centres at (i + 0.5) / size, row 0 at v = 0.
fn texture_colour(ctx: &Context, mesh: &Mesh, hit: &Hit, w: &[f64; 3]) -> DVec3 {
    let material = &ctx.scene.materials[mesh.material];
    let Some(t) = material.diffuse_map.as_deref().filter(|_| mesh.has_uv) else {
        return DVec3::ONE;
    };
    let base = 3 * hit.tri.tri as usize;
    let uv = (0..3).fold(glam::DVec2::ZERO, |a, k| {
        let v = &mesh.vertices[mesh.indices[base + k] as usize];
        a + w[k] * glam::DVec2::from(v.uv.map(f64::from))
    });
    bilinear(t, uv.x, uv.y)
}

pub fn bilinear(t: &Texture, u: f64, v: f64) -> DVec3 {
    if t.width == 0 || t.height == 0 || !(u.is_finite() && v.is_finite()) {
        return DVec3::ONE;
    }
    let (w, h) = (i64::from(t.width), i64::from(t.height));
    let (x, y) = (u * w as f64 - 0.5, v * h as f64 - 0.5);
    let (x0, y0) = (x.floor(), y.floor());
    let (fx, fy) = (x - x0, y - y0);
    let texel = |i: i64, j: i64| {
        let k = 4 * (j.rem_euclid(h) * w + i.rem_euclid(w)) as usize;
        DVec3::new(
            f64::from(t.rgba[k]),
            f64::from(t.rgba[k + 1]),
            f64::from(t.rgba[k + 2]),
        ) / 255.0
    };
    // Wrap the integer part first: huge u would lose the fraction after a float modulo.
    let (i, j) = ((x0 % w as f64) as i64, (y0 % h as f64) as i64);
    let top = texel(i, j) * (1.0 - fx) + texel(i + 1, j) * fx;
    let bottom = texel(i, j + 1) * (1.0 - fx) + texel(i + 1, j + 1) * fx;
    top * (1.0 - fy) + bottom * fy
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
    tex: DVec3,
    vis: &[f64],
) -> DVec3 {
    let s = ctx.settings;
    let (terms, eye) = (s.lighting.terms, ctx.view.eye);
    let rgb = |c: [f32; 3]| DVec3::from(c.map(f64::from));
    let mut c = rgb(m.emissive);
    if terms.ambient {
        c += rgb(m.ambient) * tex * s.lighting.ambient;
    }
    for (i, light) in s.lights.iter().enumerate() {
        let (mut fd, mut fs) = (0.0, 0.0);
        for k in 0..3 {
            let n = safe_normalize(normal_of(normals[k]), ctx.view.back);
            let n = if front { n } else { -n };
            debug_assert!(n.is_normalized(), "normal {n}");
            let v = (eye - pos[k]).normalize_or_zero();
            let l = to_light(light, pos[k]);
            let (d, sp) = light_factors(l, n, v, f64::from(m.shininess), s.lighting.wrap);
            fd += w[k] * d;
            fs += w[k] * sp;
        }
        let lc = light.color.as_dvec3();
        let mut lit = DVec3::ZERO;
        if terms.diffuse {
            lit += rgb(m.diffuse) * tex * lc * fd;
        }
        if terms.specular {
            lit += rgb(m.specular) * lc * fs;
        }
        c += vis.get(i).copied().unwrap_or(1.0) * lit;
    }
    c.clamp(DVec3::ZERO, DVec3::ONE)
}

#[cfg(test)]
mod tests {
    use super::*;

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
    fn bilinear_hits_texel_centres_and_wraps() {
        let t = checker();
        assert_eq!(bilinear(&t, 0.25, 0.25), DVec3::ONE);
        assert_eq!(bilinear(&t, 0.75, 0.25), DVec3::ZERO);
        assert_eq!(bilinear(&t, 0.25, 0.75), DVec3::ZERO);
        // Halfway between texel centres, and across the REPEAT seam.
        assert!((bilinear(&t, 0.5, 0.25) - DVec3::splat(0.5)).length() < 1e-12);
        assert!((bilinear(&t, 0.0, 0.25) - DVec3::splat(0.5)).length() < 1e-12);
        assert_eq!(bilinear(&t, 1.25, -0.75), DVec3::ONE);
        assert!((bilinear(&t, 1e9 + 0.25, 0.25) - DVec3::ONE).length() < 1e-6);
        assert!(bilinear(&t, f64::NAN, 0.0).is_finite());
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
