//! Pass "lit" (legacy tier): every mesh with the Phong (or Gouraud) program matching its
//! features; opaque meshes first, then translucent ones back to front with blending (each
//! drawn back faces first, then front faces, so a glass shows its far wall behind its near
//! wall). The skeleton is the one both tiers share (`super::tier`); the helpers here (view
//! set-up, light and shadow uniforms, draw order) are shared with the PBR pass.
use super::frusta::ShadowProjection;
use super::tier::{MeshDraw, Prepared};
use super::{FrameCx, Outcome, Pass, Shading};
use crate::gpu::program::Program;
use crate::light::LightKind;
use crate::scene::clusters::ClusterView;
use crate::shader::cache::ProgramKey;
use crate::Result;
use glam::{Mat3, Mat4, Vec2, Vec3, Vec4};

/// Texture unit of shadow map i is SHADOW_UNIT + i; unit 0 is the diffuse map.
pub(crate) const SHADOW_UNIT: u32 = 1;
/// The legacy tier's normal and emissive maps, after the four shadow maps.
const NORMAL_UNIT: u32 = SHADOW_UNIT + 4;
const EMISSIVE_UNIT: u32 = NORMAL_UNIT + 1;

pub(crate) struct Lit;

/// The legacy tier's program: lights, shadow maps, PCF taps, which maps are six-face
/// atlases, texture, Gouraud.
pub fn program_key(
    lights: u8,
    shadows: u8,
    pcf: u8,
    cube_mask: u8,
    textured: bool,
    gouraud: bool,
    colored: bool,
) -> ProgramKey {
    shadow_flags(
        ProgramKey::new("lit", "lit.vert", "lit.frag"),
        lights,
        shadows,
        pcf,
        cube_mask,
    )
    .switch("HAS_TEXTURE", "tex", textured)
    .switch("GOURAUD", "gouraud", gouraud)
    .switch("HAS_COLOR", "vc", colored)
}

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
    pub view: Mat4,
    pub proj: Mat4,
    pub normal_matrix: Mat3,
    /// Light positions (w = 1) or directions towards the light (w = 0) in eye space.
    pub light_pos: Vec<Vec4>,
    pub shadow: ShadowUniforms,
    pub lights: u8,
    pub shadows: u8,
    pub cube_mask: u8,
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
    pub fn new(cx: &mut FrameCx) -> View {
        let s = cx.settings;
        let view = s.camera.view();
        let proj = s.camera.projection(&cx.scene.scene.bounds, cx.aspect());
        let (w, h) = (cx.viewport[2], cx.viewport[3]);
        cx.cull = Some(ClusterView::new(proj * view).with_lod(proj * view, w, h, cx.lod.error));
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
        }
    }

    /// Camera, light and shadow uniforms (once per program per frame: a program keeps them).
    pub fn set_uniforms(&self, p: &Program, cx: &FrameCx) {
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
    pub fn draw_order(&self, cx: &mut FrameCx) -> (Vec<usize>, usize) {
        let meshes = &cx.scene.meshes;
        let visible = cx.scene.visible(&(self.proj * self.view));
        cx.stats.culled = (meshes.len() - visible.len()) as u32;
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

impl Pass for Lit {
    fn name(&self) -> &'static str {
        "lit"
    }

    fn run(&self, cx: &mut FrameCx) -> Result<Outcome> {
        let s = cx.settings;
        if s.shading == Shading::Pbr {
            return Ok(Outcome::Skipped("PBR tier".into()));
        }
        if s.lighting.attribute_view != crate::frame::AttributeView::None {
            return Ok(Outcome::Skipped(
                "attribute view (drawn by the PBR program)".into(),
            ));
        }
        let tier = LegacyTier {
            gouraud: s.shading == Shading::Gouraud,
            bound_texture: None,
        };
        super::tier::run(cx, tier)?;
        Ok(Outcome::Ran("lit".into()))
    }
}

/// The legacy tier in the lit skeleton ([`super::tier`]): Phong or Gouraud programs.
#[derive(Clone)]
struct LegacyTier {
    gouraud: bool,
    /// The base colour texture bound to unit 0 by this draw call (not bound again).
    bound_texture: Option<usize>,
}

/// A mesh's legacy textures (indices into the frame's texture table).
struct LegacyMaps {
    texture: Option<usize>,
    normal: Option<usize>,
    emissive: Option<usize>,
}

impl super::tier::Tier for LegacyTier {
    type Maps = LegacyMaps;

    fn prepare(
        &mut self,
        cx: &mut FrameCx,
        v: &View,
        m: &MeshDraw,
    ) -> Result<Prepared<LegacyMaps>> {
        let s = cx.settings;
        let mat = &cx.scene.scene.materials[m.material];
        let texture = base_texture(cx, m.material, m.has_uv)?;
        // The legacy tier works in display values: every image is read as it is (not
        // sRGB-decoded), whatever its slot's colour space.
        // The normal map bends a per-fragment normal: Gouraud has none.
        let normal = match &mat.normal_texture {
            Some(t) if m.has_tangents && !self.gouraud && s.lighting.pbr_terms.normal_map => {
                Some(cx.res.textures.get(cx.gpu, &t.image, false, &t.sampler)?)
            }
            _ => None,
        };
        let emissive = match &mat.emissive_texture {
            Some(t) if m.has_uv => Some(cx.res.textures.get(cx.gpu, &t.image, false, &t.sampler)?),
            _ => None,
        };
        let key = program_key(
            v.lights,
            v.shadows,
            s.shadows.pcf,
            v.cube_mask,
            texture.is_some(),
            self.gouraud,
            m.has_colors,
        )
        .switch("HAS_NORMAL_MAP", "nrm", normal.is_some())
        .switch("HAS_EMISSIVE_MAP", "emi", emissive.is_some());
        // Single-sided opaque draws cull back faces (cull.rs): no fragment needs the flip.
        let front_only = !mat.double_sided && !m.translucent;
        Ok(Prepared {
            key: light_flags(key, s).switch("FRONT_ONLY", "front", front_only),
            textured: texture.is_some(),
            maps: LegacyMaps {
                texture,
                normal,
                emissive,
            },
        })
    }

    fn program_uniforms(&self, p: &Program, _: &FrameCx, _: &View) {
        p.set_i32("uNormalMap", NORMAL_UNIT as i32);
        p.set_i32("uEmissiveMap", EMISSIVE_UNIT as i32);
    }

    fn material(&mut self, p: &Program, cx: &mut FrameCx, m: &MeshDraw, maps: LegacyMaps) {
        let mat = &cx.scene.scene.materials[m.material];
        for (index, unit) in [(maps.normal, NORMAL_UNIT), (maps.emissive, EMISSIVE_UNIT)] {
            if let Some(t) = index {
                cx.res.textures.texture(t).bind(unit);
                cx.stats.textures_bound += 1;
            }
        }
        let phong = mat.phong_terms();
        set_material_terms(p, cx.settings, &phong);
        p.set_vec3("uKd", Vec3::from(phong.diffuse));
        p.set_vec3("uKe", Vec3::from(mat.legacy_emissive()));
        p.set_f32("uNs", phong.shininess);
        if let Some(t) = maps.texture {
            if self.bound_texture != Some(t) {
                cx.res.textures.texture(t).bind(0);
                self.bound_texture = Some(t);
                cx.stats.textures_bound += 1;
            }
            p.set_i32("uDiffuseMap", 0);
        }
    }
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

/// The legacy program's compile-time light flags: `POINT_LIGHTS` where some light has a
/// position (else every light's direction is a uniform, no per-fragment normalisation),
/// `WRAP` for wrap lighting.
fn light_flags(key: ProgramKey, s: &crate::frame::FrameSettings) -> ProgramKey {
    let point = s
        .lights
        .iter()
        .any(|l| matches!(l.kind, LightKind::Point(_)));
    key.switch("POINT_LIGHTS", "pt", point)
        .switch("WRAP", "wrap", s.lighting.wrap)
}

/// The material's colours times the ambient light and each light's colour, with the term
/// switches (`--terms`) applied: products of uniforms, formed here once per draw rather than
/// per fragment (lit.frag).
fn set_material_terms(
    p: &Program,
    s: &crate::frame::FrameSettings,
    mat: &crate::scene::material::PhongTerms,
) {
    let t = s.lighting.terms;
    let on = |b: bool| if b { 1.0 } else { 0.0 };
    let ambient = on(t.ambient) * Vec3::from(mat.ambient) * s.lighting.ambient.as_vec3();
    p.set_vec3("uAmbientTerm", ambient);
    for (i, l) in s.lights.iter().enumerate() {
        p.set_vec3(
            &format!("uLightDiffuse[{i}]"),
            on(t.diffuse) * Vec3::from(mat.diffuse) * l.color,
        );
        p.set_vec3(
            &format!("uLightSpecular[{i}]"),
            on(t.specular) * Vec3::from(mat.specular) * l.color,
        );
    }
}
