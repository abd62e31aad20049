//! Pass "lit" (legacy tier): every mesh with the Phong (or Gouraud) program matching its
//! features; opaque meshes first, then translucent ones back to front with blending (each
//! drawn back faces first, then front faces, so a glass shows its far wall behind its near
//! wall). The skeleton is the one both tiers share (`super::tier`); the helpers both tiers
//! use (view set-up, light and shadow uniforms, draw order) are in `super::view`.
use super::tier::{MeshDraw, Prepared};
use super::units::{BASE_UNIT, LEGACY_EMISSIVE_UNIT, NORMAL_UNIT};
use super::view::{base_texture, shadow_flags, View};
use super::{FrameCx, Outcome, Pass, Shading};
use crate::gpu::program::Program;
use crate::light::LightKind;
use crate::shader::cache::ProgramKey;
use crate::Result;
use glam::Vec3;

pub(crate) struct Lit;

/// The legacy tier's program: lights, shadow maps, PCF taps, which maps are six-face
/// atlases, texture, Gouraud.
pub(crate) fn program_key(
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
        .switch("HAS_EMISSIVE_MAP", "emi", emissive.is_some())
        .switch("FALLOFF", "fall", v.falloff);
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
        p.set_i32("uEmissiveMap", LEGACY_EMISSIVE_UNIT as i32);
    }

    fn material(&mut self, p: &Program, cx: &mut FrameCx, m: &MeshDraw, maps: LegacyMaps) {
        let mat = &cx.scene.scene.materials[m.material];
        for (index, unit) in [
            (maps.normal, NORMAL_UNIT),
            (maps.emissive, LEGACY_EMISSIVE_UNIT),
        ] {
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
                cx.res.textures.texture(t).bind(BASE_UNIT);
                self.bound_texture = Some(t);
                cx.stats.textures_bound += 1;
            }
            p.set_i32("uDiffuseMap", BASE_UNIT as i32);
        }
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
    mat: &crate::scene::model::material::PhongTerms,
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
