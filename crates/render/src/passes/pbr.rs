//! Pass "pbr": the PBR tier. Every visible mesh with the PBR program matching its maps, lit
//! by the environment (irradiance cube, one specular cube per roughness level, BRDF table)
//! and by the `--light` lights with the shadow pass's maps; output through exposure, tone
//! mapping and sRGB encoding.
use super::ibl::IblGpu;
use super::pbr_khr::{KhrFlags, KhrTextures};
use super::textures::TextureTable;
use super::tier::{MeshDraw, Prepared};
use super::units::{
    max_levels, AO_UNIT, BASE_UNIT, EMISSIVE_UNIT, FRAME_UNIT, IRRADIANCE_UNIT, LUT_UNIT,
    NORMAL_UNIT, ORM_UNIT, SPECULAR_UNIT,
};
use super::view::{shadow_flags, View};
use super::{FrameCx, Outcome, Pass, Shading};
use crate::gpu::program::Program;
use crate::gpu::texture::TextureFormat;
use crate::gpu::GpuRef;
use crate::scene::model::texture_slot::{ColorSpace, TextureSlot};
use crate::scene::{Material, Scene, Texture};
use crate::shader::cache::ProgramKey;
use crate::{Error, Result};
use glam::{Mat3, Vec3, Vec4};

pub(crate) struct Pbr;

/// Which of a material's optional inputs a program reads.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct Maps {
    pub(crate) albedo: bool,
    pub(crate) normal: bool,
    pub(crate) orm: bool,
    pub(crate) ao: bool,
    pub(crate) emissive: bool,
    /// Per-vertex colours (they multiply the base colour like the albedo map).
    pub(crate) color: bool,
}

/// Per-program options of the tier (the extensions' flags are added by [`KhrFlags::key`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Options {
    pub(crate) levels: u32,
    pub(crate) rgbm: bool,
    pub(crate) srgb_in_shader: bool,
    pub(crate) tonemap: i32,
    pub(crate) dominant: bool,
    pub(crate) multiscatter: bool,
}

pub(crate) fn program_key(
    lights: u8,
    shadows: u8,
    pcf: u8,
    cube_mask: u8,
    maps: Maps,
    o: Options,
) -> ProgramKey {
    shadow_flags(
        ProgramKey::new("pbr", "pbr.vert", "pbr.frag"),
        lights,
        shadows,
        pcf,
        cube_mask,
    )
    .count("NUM_SPEC_LEVELS", "lv", o.levels as i32)
    .count("TONEMAP", "tm", o.tonemap)
    .switch("HAS_ALBEDO_MAP", "alb", maps.albedo)
    .switch("HAS_NORMAL_MAP", "nrm", maps.normal)
    .switch("HAS_ORM_MAP", "orm", maps.orm)
    .switch("HAS_AO_MAP", "ao", maps.ao)
    .switch("HAS_EMISSIVE_MAP", "emi", maps.emissive)
    .switch("HAS_COLOR", "vc", maps.color)
    .switch("IBL_RGBM", "rgbm", o.rgbm)
    .switch("SRGB_DECODE_IN_SHADER", "srgbsh", o.srgb_in_shader)
    .switch("DOMINANT_DIRECTION", "dom", o.dominant)
    .switch("MULTISCATTER", "ms", o.multiscatter)
}

/// The PBR keys `--compile-shaders` checks for one light/shadow variant: no maps with float
/// maps, and every map with RGBM, shader-side sRGB and both measured options.
pub(crate) fn all_keys(lights: u8, shadows: u8, pcf: u8, cube_mask: u8) -> Vec<ProgramKey> {
    let plain = Options {
        levels: 6,
        rgbm: false,
        srgb_in_shader: false,
        tonemap: 3,
        dominant: false,
        multiscatter: false,
    };
    let all = Maps {
        albedo: true,
        normal: true,
        orm: true,
        ao: true,
        emissive: true,
        color: true,
    };
    let every = Options {
        rgbm: true,
        srgb_in_shader: true,
        tonemap: 1,
        dominant: true,
        multiscatter: true,
        ..plain
    };
    vec![
        program_key(lights, shadows, pcf, cube_mask, Maps::default(), plain),
        KhrFlags::ALL
            .key(program_key(lights, shadows, pcf, cube_mask, all, every))
            .switch("FALLOFF", "fall", true),
    ]
}

/// One material's PBR textures (indices into the frame's [`TextureTable`]).
#[derive(Clone, Copy, Default)]
struct MaterialMaps {
    albedo: Option<usize>,
    normal: Option<usize>,
    orm: Option<usize>,
    /// The ORM map's red channel is occlusion (an MTL's packed maps), not glTF's unused red.
    orm_ao: bool,
    ao: Option<usize>,
    emissive: Option<usize>,
    khr: KhrTextures,
}

/// Which table textures each material uses in the PBR tier, decided on the first PBR frame
/// (a legacy-only session never uploads them).
pub(crate) struct MaterialTextures {
    materials: Vec<MaterialMaps>,
    srgb_in_shader: bool,
}

/// An MTL's occlusion, roughness and metallic maps packed into one texture (r, g, b), so the
/// tier needs one texture unit for three inputs. Sized like the largest input; the others are
/// sampled nearest into it. Missing inputs are 1 (the factor then acts alone). glTF's
/// metallic-roughness image is already packed and is used as it is.
fn orm_texture(index: usize, m: &Material) -> Option<Texture> {
    let maps = [
        &m.occlusion_texture,
        &m.roughness_texture,
        &m.metallic_texture,
    ]
    .map(|s| s.as_ref().map(|s| &*s.image));
    let (w, h) = maps
        .iter()
        .filter_map(|m| m.map(|t| (t.width, t.height)))
        .max_by_key(|(w, h)| w * h)?;
    let mut data = vec![255u8; (w * h * 4) as usize];
    for (c, map) in maps.iter().enumerate() {
        if let Some(t) = map {
            for y in 0..h {
                for x in 0..w {
                    let sx = (x * t.width / w).min(t.width - 1);
                    let sy = (y * t.height / h).min(t.height - 1);
                    data[((y * w + x) * 4) as usize + c] =
                        t.rgba[((sy * t.width + sx) * 4) as usize];
                }
            }
        }
    }
    Some(Texture {
        // Its identity in the texture table: no file has this name.
        path: format!("{} (packed ORM of material {index})", m.name).into(),
        image: None,
        width: w,
        height: h,
        rgba: data,
    })
}

impl MaterialTextures {
    fn new(gpu: &GpuRef, table: &mut TextureTable, scene: &Scene) -> Result<MaterialTextures> {
        let srgb_in_shader = !TextureFormat::Srgb8A8.supported(&gpu.caps);
        let mut materials = Vec::new();
        for (index, m) in scene.materials.iter().enumerate() {
            // Each slot's image as its colour space says (sRGB decoded by the texture format),
            // with its own sampler.
            let mut get = |t: &Option<TextureSlot>| {
                t.as_ref()
                    .map(|t| {
                        let srgb = t.color_space == ColorSpace::Srgb;
                        table.get(gpu, &t.image, srgb, &t.sampler)
                    })
                    .transpose()
            };
            let mut mm = MaterialMaps {
                albedo: get(&m.base_color_texture)?,
                normal: get(&m.normal_texture)?,
                emissive: get(&m.emissive_texture)?,
                ..Default::default()
            };
            if !m.packs_orm() {
                // glTF: metallic-roughness and occlusion each with their own UVs and sampler.
                mm.orm = get(&m.metallic_roughness_texture)?;
                mm.ao = get(&m.occlusion_texture)?;
            } else if let Some(t) = orm_texture(index, m) {
                mm.orm = Some(table.get(gpu, &t, false, &Default::default())?);
                mm.orm_ao = true;
            }
            mm.khr = super::pbr_khr::textures(gpu, table, m)?;
            materials.push(mm);
        }
        Ok(MaterialTextures {
            materials,
            srgb_in_shader,
        })
    }
}

fn bind_ibl(ibl: &IblGpu) {
    ibl.irradiance.bind(IRRADIANCE_UNIT);
    ibl.lut.bind(LUT_UNIT);
    for (i, c) in ibl.specular.iter().enumerate() {
        c.bind(SPECULAR_UNIT + i as u32);
    }
}

impl Pass for Pbr {
    fn name(&self) -> &'static str {
        "pbr"
    }

    fn run(&self, cx: &mut FrameCx) -> Result<Outcome> {
        let s = cx.settings;
        let attribute = s.lighting.attribute_view;
        if s.shading != Shading::Pbr && attribute == crate::frame::AttributeView::None {
            return Ok(Outcome::Skipped("legacy tier".into()));
        }
        let units = cx.gpu.caps.max_texture_units;
        if max_levels(units) < 2 {
            return Err(Error::Unsupported(format!(
                "--shading pbr needs {} texture units; {} has {units}",
                SPECULAR_UNIT + 2,
                cx.gpu.caps.version
            )));
        }
        if cx.res.pbr_textures.is_none() {
            let t = MaterialTextures::new(cx.gpu, &mut cx.res.textures, &cx.scene.scene)?;
            cx.res.pbr_textures = Some(t);
        }
        let gpu = cx.gpu.clone();
        let (rgbm, levels) = {
            let ibl = cx.res.ibl.ensure(&gpu, cx.programs)?;
            bind_ibl(ibl);
            (ibl.rgbm, ibl.specular.len() as u32)
        };
        cx.stats.textures_bound += 2 + levels;
        let srgb_in_shader = cx
            .res
            .pbr_textures
            .as_ref()
            .is_some_and(|m| m.srgb_in_shader);
        let opts = Options {
            levels,
            rgbm,
            srgb_in_shader,
            tonemap: s.lighting.output.tonemap.code(),
            dominant: s.lighting.pbr.dominant_direction,
            multiscatter: s.lighting.pbr.multiscatter,
        };
        super::tier::run(
            cx,
            PbrTier {
                opts,
                frame_levels: None,
            },
        )?;
        Ok(Outcome::Ran(format!(
            "pbr({levels} levels, {}, env {})",
            if rgbm { "rgbm" } else { "float" },
            cx.res.ibl.origin()
        )))
    }
}

/// The PBR tier in the lit skeleton ([`super::tier`]).
#[derive(Clone)]
struct PbrTier {
    opts: Options,
    /// The opaque frame's copy exists with these mip levels (transmissive meshes read it).
    frame_levels: Option<f32>,
}

impl super::tier::Tier for PbrTier {
    type Maps = (MaterialMaps, Maps, KhrFlags);

    fn prepare(
        &mut self,
        cx: &mut FrameCx,
        v: &View,
        m: &MeshDraw,
    ) -> Result<Prepared<(MaterialMaps, Maps, KhrFlags)>> {
        let s = cx.settings;
        let mm = cx.res.pbr_textures.as_ref().expect("made by run").materials[m.material];
        let has_uv = m.has_uv;
        let maps = Maps {
            albedo: has_uv && mm.albedo.is_some(),
            normal: m.has_tangents && mm.normal.is_some() && s.lighting.pbr_terms.normal_map,
            orm: has_uv && mm.orm.is_some(),
            ao: has_uv && mm.ao.is_some(),
            emissive: has_uv && mm.emissive.is_some(),
            color: m.has_colors,
        };
        let khr = super::pbr_khr::flags(
            &cx.scene.scene.materials[m.material],
            &mm.khr,
            has_uv,
            m.has_tangents,
            self.frame_levels.is_some(),
            cx.gpu.caps.max_texture_units,
        );
        let key = khr
            .key(program_key(
                v.lights,
                v.shadows,
                s.shadows.pcf,
                v.cube_mask,
                maps,
                self.opts,
            ))
            .mask("SHOW_ATTRIBUTE", "show", s.lighting.attribute_view.code())
            .switch("FALLOFF", "fall", v.falloff);
        Ok(Prepared {
            key,
            textured: maps.albedo,
            maps: (mm, maps, khr),
        })
    }

    fn program_uniforms(&self, program: &Program, cx: &FrameCx, v: &View) {
        let s = cx.settings;
        let (p, out, t) = (s.lighting.pbr, s.lighting.output, s.lighting.pbr_terms);
        let on = |b: bool| if b { 1.0 } else { 0.0 };
        program.set_mat3("uEnvFromEye", &Mat3::from_mat4(v.view).transpose());
        program.set_f32("uIblIntensity", p.ibl_intensity);
        program.set_f32("uExposure", 2f32.powf(out.exposure_ev));
        program.set_i32("uIrradiance", IRRADIANCE_UNIT as i32);
        program.set_i32("uBrdfLut", LUT_UNIT as i32);
        program.set_f32(
            "uLutSize",
            cx.res.ibl.data().map_or(1, |d| d.lut.size) as f32,
        );
        for l in 0..self.opts.levels {
            program.set_i32(&format!("uSpecular{l}"), (SPECULAR_UNIT + l) as i32);
        }
        program.set_i32("uAlbedoMap", BASE_UNIT as i32);
        program.set_i32("uNormalMap", NORMAL_UNIT as i32);
        program.set_i32("uOrmMap", ORM_UNIT as i32);
        program.set_i32("uEmissiveMap", EMISSIVE_UNIT as i32);
        program.set_i32("uAoMap", AO_UNIT as i32);
        program.set_vec4(
            "uTermsA",
            Vec4::new(
                on(t.direct_diffuse),
                on(t.direct_specular),
                on(t.ibl_diffuse),
                on(t.ibl_specular),
            ),
        );
        program.set_vec3(
            "uTermsB",
            Vec3::new(on(t.ao), on(t.shadows), on(t.emissive)),
        );
        super::pbr_khr::program_uniforms(
            program,
            [
                t.clearcoat,
                t.sheen,
                t.transmission,
                t.iridescence,
                t.anisotropy,
            ],
            self.frame_levels.unwrap_or(0.0),
        );
    }

    fn material(
        &mut self,
        program: &Program,
        cx: &mut FrameCx,
        m: &MeshDraw,
        (mm, maps, khr): (MaterialMaps, Maps, KhrFlags),
    ) {
        let p = cx.settings.lighting.pbr;
        let mat = &cx.scene.scene.materials[m.material];
        program.set_f32("uOcclusionStrength", mat.occlusion_strength);
        program.set_f32("uOrmAo", if mm.orm_ao { 1.0 } else { 0.0 });
        program.set_vec3(
            "uBaseColor",
            p.base_color.unwrap_or(Vec3::from(mat.base_color)),
        );
        program.set_f32("uMetallic", p.metallic.unwrap_or(mat.metallic));
        program.set_f32("uRoughness", p.roughness.unwrap_or(mat.roughness));
        program.set_vec3("uEmissive", Vec3::from(mat.emissive));
        for (index, on, unit) in [
            (mm.albedo, maps.albedo, BASE_UNIT),
            (mm.normal, maps.normal, NORMAL_UNIT),
            (mm.orm, maps.orm, ORM_UNIT),
            (mm.ao, maps.ao, AO_UNIT),
            (mm.emissive, maps.emissive, EMISSIVE_UNIT),
        ] {
            if let (Some(ti), true) = (index, on) {
                cx.res.textures.texture(ti).bind(unit);
                cx.stats.textures_bound += 1;
            }
        }
        cx.stats.textures_bound +=
            super::pbr_khr::material(program, &cx.res.textures, mat, khr, &mm.khr, m.has_uv1);
        if khr.transmission {
            if let Some(t) = &cx.res.transmission {
                t.bind(FRAME_UNIT);
            }
        }
    }

    fn transmissive(&self, cx: &FrameCx, material: usize) -> bool {
        cx.settings.lighting.pbr_terms.transmission
            && cx.settings.lighting.attribute_view == crate::frame::AttributeView::None
            && cx.scene.scene.materials[material]
                .khr
                .transmission
                .is_some_and(|t| t > 0.0)
    }

    fn frame_copied(&mut self, levels: f32) {
        self.frame_levels = Some(levels);
    }
}
