//! What both lit tiers (lit.rs, pbr.rs, through tier.rs) and the shadow pass share and no tier
//! owns: the per-frame view (camera, lights, shadow maps bound to their units), the light and
//! shadow program flags, and the base colour texture of a material. It sits below the tiers so
//! they and tier.rs import it, never each other (the circle of issue #41).
use super::frusta::ShadowProjection;
use super::units::SHADOW_UNIT;
use super::FrameCx;
use crate::gpu::program::Program;
use crate::light::{Falloff, LightKind};
use crate::scene::lod::clusters::ClusterView;
use crate::shader::cache::ProgramKey;
use crate::Result;
use glam::{Mat3, Mat4, Vec2, Vec3, Vec4};

/// The light and shadow flags both lit tiers share (labels `l{n},s{n},pcf{n}[,cube{mask}]`).
pub(crate) fn shadow_flags(
    key: ProgramKey,
    lights: u8,
    shadows: u8,
    pcf: u8,
    cube_mask: u8,
) -> ProgramKey {
    let mut k = key
        .count("NUM_LIGHTS", "l", lights.into())
        .count("NUM_SHADOWS", "s", shadows.into())
        .count("PCF_TAPS", "pcf", pcf.into())
        .hidden("SHADOW_STRIDE", if cube_mask != 0 { 6 } else { 1 })
        .mask("SHADOW_CUBE_MASK", "cube", cube_mask.into());
    for (i, name) in [
        "SHADOW_CUBE0",
        "SHADOW_CUBE1",
        "SHADOW_CUBE2",
        "SHADOW_CUBE3",
    ]
    .into_iter()
    .enumerate()
    {
        k = k.hidden_float(name, i32::from(cube_mask & (1 << i) != 0));
    }
    k
}

/// Per-frame view and light data both lit tiers use.
pub(crate) struct View {
    pub(crate) view: Mat4,
    pub(crate) proj: Mat4,
    pub(crate) normal_matrix: Mat3,
    /// Light positions (w = 1) or directions towards the light (w = 0) in eye space.
    pub(crate) light_pos: Vec<Vec4>,
    pub(crate) shadow: ShadowUniforms,
    pub(crate) lights: u8,
    pub(crate) shadows: u8,
    pub(crate) cube_mask: u8,
    /// Some light weakens with distance or off a cone (a file's light): the lit programs
    /// have FALLOFF (falloff.glsl); frames of glview's own lights keep their programs.
    pub(crate) falloff: bool,
}

/// Shadow lookup parameters, per light; matrices as (uniform array index, matrix).
#[derive(Default)]
pub(crate) struct ShadowUniforms {
    matrices: Vec<(usize, Mat4)>,
    texels: Vec<Vec2>,
    normal_offsets: Vec<f32>,
    eye_to_world: Mat3,
}

impl View {
    /// Sets up camera and lights, and binds the shadow maps to their units.
    pub(crate) fn new(cx: &mut FrameCx) -> View {
        let s = cx.settings;
        let view = s.camera.view();
        let proj = s.camera.projection(&cx.scene.scene.bounds, cx.aspect());
        let (w, h) = (cx.viewport[2], cx.viewport[3]);
        let lod = lod_view_proj(&s.camera, &cx.scene.scene.bounds, cx.aspect());
        cx.cull = Some(ClusterView::new(proj * view).with_lod(lod, w, h, cx.lod.error));
        let maps = &cx.res.shadow.maps;
        let cube_mask = maps
            .iter()
            .enumerate()
            .filter(|(_, m)| m.projection == ShadowProjection::Cube)
            .fold(0u8, |acc, (i, _)| acc | 1 << i);
        let stride = if cube_mask != 0 { 6 } else { 1 };
        let light_pos = s
            .lights
            .iter()
            .map(|l| match l.kind {
                LightKind::Point(p) => view.transform_point3(p).extend(1.0),
                LightKind::Directional(d) => view.transform_vector3(-d).normalize().extend(0.0),
            })
            .collect();
        let mut shadow = ShadowUniforms::default();
        for (i, m) in maps.iter().enumerate() {
            m.texture.bind(SHADOW_UNIT + i as u32);
            cx.stats.textures_bound += 1;
            for (f, mat) in m.eye_to_texture(&view).into_iter().enumerate() {
                shadow.matrices.push((i * stride + f, mat));
            }
            shadow.texels.push(Vec2::new(
                1.0 / m.texture.width as f32,
                1.0 / m.texture.height as f32,
            ));
            // A map texel covers about 2r/face of the scene (frusta are fitted to the bounding
            // sphere), so the normal offset is given in texels and converted here.
            shadow
                .normal_offsets
                .push(s.shadows.normal_offset * 2.0 * m.radius / m.face as f32);
        }
        shadow.eye_to_world = Mat3::from_mat4(view).transpose();
        View {
            normal_matrix: Mat3::from_mat4(view),
            view,
            proj,
            light_pos,
            shadow,
            lights: s.lights.len() as u8,
            shadows: maps.len() as u8,
            cube_mask,
            falloff: s.lights.iter().any(|l| l.falloff != Falloff::NONE),
        }
    }

    /// Camera, light and shadow uniforms (once per program per frame: a program keeps them).
    pub(crate) fn set_uniforms(&self, p: &Program, cx: &FrameCx) {
        let s = cx.settings;
        if s.lighting.translucency.log_depth {
            let (_, far) = s.camera.near_far(&cx.scene.scene.bounds);
            p.set_f32("uLogDepthC", crate::frame::LOG_DEPTH_C);
            p.set_f32("uLogDepthFar", far);
        }
        p.set_mat4("uModelView", &self.view);
        p.set_mat4("uProjection", &self.proj);
        p.set_mat3("uNormalMatrix", &self.normal_matrix);
        for (i, (pos, l)) in self.light_pos.iter().zip(&s.lights).enumerate() {
            p.set_vec4(&format!("uLightPos[{i}]"), *pos);
            p.set_vec3(&format!("uLightColor[{i}]"), l.color);
            if self.falloff {
                let (f, spot) = falloff_uniforms(&l.falloff, &self.view);
                p.set_vec4(&format!("uLightFalloff[{i}]"), f);
                p.set_vec3(&format!("uLightSpotDir[{i}]"), spot);
            }
        }
        let sh = &self.shadow;
        for (i, m) in &sh.matrices {
            p.set_mat4(&format!("uShadowMatrix[{i}]"), m);
        }
        for (i, (texel, offset)) in sh.texels.iter().zip(&sh.normal_offsets).enumerate() {
            p.set_i32(&format!("uShadowMap{i}"), SHADOW_UNIT as i32 + i as i32);
            p.set_vec2(&format!("uShadowTexel[{i}]"), *texel);
            p.set_f32(&format!("uShadowNormalOffset[{i}]"), *offset);
        }
        p.set_mat3("uEyeToWorld", &sh.eye_to_world);
        p.set_f32("uShadowBias", s.shadows.bias);
    }

    /// Visible meshes in draw order: opaque ones, then translucent ones back to front (by
    /// mesh centre); and the index in that order where the translucent ones start.
    pub(crate) fn draw_order(&self, cx: &mut FrameCx) -> (Vec<usize>, usize) {
        let meshes = &cx.scene.meshes;
        let visible = cx.scene.visible(&(self.proj * self.view));
        cx.stats.culled = (cx.scene.drawn_count() - visible.len()) as u32;
        let mut order: Vec<usize> = visible
            .iter()
            .copied()
            .filter(|&i| !meshes[i].translucent)
            .collect();
        let mut translucent: Vec<(f32, usize)> = visible
            .iter()
            .copied()
            .filter(|&i| meshes[i].translucent)
            .map(|i| (self.view.transform_point3(meshes[i].center).z, i))
            .collect();
        // Most negative eye-space z is farthest: draw those first.
        translucent.sort_by(|a, b| a.0.total_cmp(&b.0));
        let first = order.len();
        order.extend(translucent.iter().map(|&(_, i)| i));
        (order, first)
    }
}

/// falloff.glsl's uniforms of one light: (1/range², inverse square, spot scale, spot offset)
/// and the spot's eye-space direction; (0, 0, 0, 1) and 0 leave a light as it is.
fn falloff_uniforms(f: &Falloff, view: &Mat4) -> (Vec4, Vec3) {
    let (scale, offset, dir) = match f.spot {
        Some(s) => (
            s.scale,
            s.offset,
            view.transform_vector3(s.dir).normalize_or_zero(),
        ),
        None => (0.0, 1.0, Vec3::ZERO),
    };
    let inv = if f.inverse_square { 1.0 } else { 0.0 };
    (Vec4::new(f.inv_range2, inv, scale, offset), dir)
}

/// The legacy tier's base colour texture of `material` (display values, not sRGB-decoded),
/// with its slot's sampler; None without UVs or an image.
pub(crate) fn base_texture(
    cx: &mut FrameCx,
    material: usize,
    has_uv: bool,
) -> Result<Option<usize>> {
    let mat = &cx.scene.scene.materials[material];
    match (&mat.base_color_texture, has_uv) {
        (Some(t), true) => cx
            .res
            .textures
            .get(cx.gpu, &t.image, false, &t.sampler)
            .map(Some),
        _ => Ok(None),
    }
}

/// The view-projection the level of detail is chosen with: the mono camera's (a stereo
/// eye's without its offset and lens shift), so both eyes draw the same levels.
pub(crate) fn lod_view_proj(
    camera: &crate::camera::OrbitCamera,
    bounds: &crate::scene::Bounds,
    aspect: f32,
) -> glam::Mat4 {
    let c = camera.centre();
    c.projection(bounds, aspect) * c.view()
}
