//! Points in the reference: each a disk of the frame's point size (`--point-size`, scaled to
//! the picture's height as the GPU scales it), centred on the point's projection, covering
//! the pixels whose centres lie within half the size of it — the GPU's sprite less the
//! fragments its shader discards outside the disk. A sprite has one depth (its centre's):
//! it is drawn where that is nearer than the surface at the pixel and than the points drawn
//! before (GL's LESS, in index order). The colour is the point's, shaded once per point as
//! the shaders do (their inputs do not vary across a sprite): unlit where the points have no
//! normals, else the tier's formula with the point's normal — the legacy `shade`, or the
//! PBR tier's `pbr::shade` (with material 0's factors and layers; no maps, as points have
//! no UVs). Points receive the meshes' shadows as on the GPU (which looks them up in the
//! surfaces' shadow maps): an exact shadow ray from the point towards each casting light.
//! They cast none, on the GPU (its depth pass draws triangles only) as here (the shadow rays
//! meet triangles only).
use super::material::Corners;
use super::Context;
use crate::frame::Shading;
use crate::scene::{Material, Mesh};
use crate::shading::{shade, Tex};
use glam::{DVec3, DVec4};

/// The diameter the frame draws points at, in pixels of a picture `height` high.
pub(crate) fn diameter(lighting: &crate::frame::LightingParams, height: u32) -> f64 {
    let (px, at) = lighting.point_size;
    let scale = if at == 0 {
        1.0
    } else {
        f64::from(height) / f64::from(at)
    };
    (f64::from(px) * scale).max(1.0)
}

/// Draws the scene's points over `data` (RGBA rows, top first), whose opaque surfaces lie at
/// window depths `depth` (1 where there is none).
pub(crate) fn draw(ctx: &Context, data: &mut [u8], depth: &mut [f64]) {
    let w = &ctx.scene.wire;
    let Some(material) = ctx.scene.materials.first() else {
        return;
    };
    let lit = w.normals.len() == w.positions.len();
    let pbr = ctx.settings.shading == Shading::Pbr;
    let (width, height) = ctx.size;
    let r = diameter(&ctx.settings.lighting, height) * 0.5;
    let l = &ctx.settings.lighting;
    for &i in &w.points {
        let i = i as usize;
        let p = DVec3::from(w.positions[i].map(f64::from));
        let clip = ctx.view.forward * DVec4::from((p, 1.0));
        if clip.w <= 0.0 {
            continue;
        }
        let ndc = clip.truncate() / clip.w;
        if !(-1.0..=1.0).contains(&ndc.z) {
            continue;
        }
        let z = ndc.z * 0.5 + 0.5;
        let cx = (ndc.x + 1.0) * 0.5 * f64::from(width);
        let cy = (1.0 - ndc.y) * 0.5 * f64::from(height);
        let vc = w
            .colors
            .get(i)
            .map_or(DVec3::ONE, |c| DVec3::from(c.map(f64::from)));
        let color = if !lit {
            if pbr {
                let base = l
                    .pbr
                    .base_color
                    .map_or(DVec3::from(material.base_color.map(f64::from)), |c| {
                        c.as_dvec3()
                    });
                let c = base * vc.map(crate::pbr::srgb_decode);
                DVec3::from(l.output.apply(c.to_array()))
            } else {
                let kd = DVec3::from(material.phong_terms().diffuse.map(f64::from));
                (kd * vc).clamp(DVec3::ZERO, DVec3::ONE)
            }
        } else {
            let n = DVec3::from(w.normals[i].map(f64::from)).normalize_or(ctx.view.back);
            lit_colour(ctx, material, p, n, vc)
        };
        let rgb = super::to_unorm8(color);
        let x0 = (cx - r - 1.0).floor().max(0.0) as u32;
        let y0 = (cy - r - 1.0).floor().max(0.0) as u32;
        let x1 = ((cx + r + 1.0).ceil().max(0.0) as u32).min(width);
        let y1 = ((cy + r + 1.0).ceil().max(0.0) as u32).min(height);
        for y in y0..y1 {
            for x in x0..x1 {
                let (dx, dy) = (f64::from(x) + 0.5 - cx, f64::from(y) + 0.5 - cy);
                let k = (y * width + x) as usize;
                if dx * dx + dy * dy > r * r || z >= depth[k] {
                    continue;
                }
                depth[k] = z;
                data[4 * k..4 * k + 3].copy_from_slice(&rgb);
            }
        }
    }
}

/// A lit point's colour: the tier's formula at `p` with normal `n` (facing whichever way the
/// file says: a sprite is always front-facing) and vertex colour `vc`, each casting light
/// seen or not along an exact shadow ray.
fn lit_colour(ctx: &Context, material: &Material, p: DVec3, n: DVec3, vc: DVec3) -> DVec3 {
    let casters = usize::from(ctx.settings.lighting.shadow_casters);
    let vis: Vec<f64> = (ctx.settings.lights.iter().enumerate())
        .map(|(i, light)| {
            let seen = !ctx.shadows
                || i >= casters
                || super::surface::light_visible(ctx, p, n, n, 0.0, light);
            if seen {
                1.0
            } else {
                0.0
            }
        })
        .collect();
    let l = &ctx.settings.lighting;
    if ctx.settings.shading != Shading::Pbr {
        return shade(
            material,
            Tex::diffuse(vc),
            p,
            n,
            ctx.view.eye,
            &ctx.settings.lights,
            &vis,
            l,
        );
    }
    // One vertex without UVs: the material's factors, as the GPU's point program reads them.
    let mesh = Mesh {
        vertices: vec![Default::default()],
        ..Default::default()
    };
    let corners = Corners::at_point(&mesh);
    let mut s = super::pbr::surface(material, DVec3::ONE, &corners, l);
    s.albedo *= vc.map(crate::pbr::srgb_decode);
    let layers = super::layers::Layers::new(ctx, material, &corners, (p, n, n), true);
    super::pbr::shade(ctx, &s, &layers, p, n, &vis)
}
