//! KHR_materials_pbrSpecularGlossiness (archived, but in many older exports) converted to the
//! one material model the Khronos Sample Viewer's way (`getSpecularGlossinessInfo`): the
//! diffuse colour is the base colour (factor and texture, alpha included), metallic 0, the
//! dielectric F0 is the specular colour (through KHR_materials_specular's slots: ior 1.5's
//! F0 0.04 times specularColor = specular / 0.04, the texture's rgb multiplying it, the
//! product clamped to 1), so the diffuse share is albedo·(1 − max(F0)); roughness is
//! 1 − glossiness, the texture's alpha converted once at load into a roughness image (green).
use crate::model::material::Texture;
use crate::model::material::{translucency, AlphaMode, Material};
use crate::model::material_khr::{Specular, CORE_IOR};
use crate::model::texture_slot::{ColorSpace, Slot, TextureSlot};
use crate::report::material::SlotFacts;
use std::sync::Arc;

pub(crate) const EXTENSION: &str = "KHR_materials_pbrSpecularGlossiness";

/// Converts `m`'s specular-glossiness values into `out`, if it has them; `load` decodes a
/// slot's image (and writes its `--check` line).
pub(crate) fn convert(
    doc: &gltf::Document,
    m: &gltf::Material,
    out: &mut Material,
    load: &mut dyn FnMut(SlotFacts, ColorSpace) -> Option<TextureSlot>,
) {
    use crate::loaders::gltf::slots::{floats, num, texture_info};
    let Some(e) = m.extension_value(EXTENSION) else {
        return;
    };
    let diffuse = floats(e, "diffuseFactor", [1.0; 4]);
    out.base_color = [diffuse[0], diffuse[1], diffuse[2]];
    out.base_alpha = diffuse[3];
    let blend_alpha = if out.alpha_mode == AlphaMode::Blend {
        diffuse[3]
    } else {
        1.0
    };
    out.opacity = translucency(blend_alpha, out.alpha_mode);
    out.metallic = 0.0;
    let gloss = num(e, "glossinessFactor", 1.0).clamp(0.0, 1.0);
    out.roughness = 1.0 - gloss;
    let f0 = CORE_IOR_F0;
    out.khr.specular = Some(Specular {
        factor: 1.0,
        color: floats(e, "specularFactor", [1.0; 3]).map(|c| c.max(0.0) / f0),
    });
    out.khr.converted_spec_gloss = true;
    if let Some(f) = e
        .get("diffuseTexture")
        .and_then(|i| texture_info(doc, Slot::BaseColor, i))
    {
        out.check.base_color = Some(format!("diffuseTexture image {}", f.image));
        out.base_color_texture = load(f, ColorSpace::Srgb);
    }
    if let Some(f) = e
        .get("specularGlossinessTexture")
        .and_then(|i| texture_info(doc, Slot::SpecularColor, i))
    {
        let facts = (f.sampler, f.uv_set, f.transform);
        let slot = load(f, ColorSpace::Srgb);
        if let Some(s) = &slot {
            // Roughness = 1 − glossiness·alpha, as an image whose green channel the
            // metallic-roughness slot reads (the factor 1 then leaves it as it is).
            out.roughness = 1.0;
            out.metallic_roughness_texture = Some(TextureSlot {
                image: Arc::new(roughness_image(&s.image, gloss)),
                sampler: facts.0,
                uv_set: facts.1,
                transform: facts.2,
                color_space: ColorSpace::Linear,
            });
        }
        *out.khr.slot_mut(Slot::SpecularColor) = slot;
    }
}

/// ((1.5 − 1)/(1.5 + 1))²: the F0 the specular colour is divided by.
const CORE_IOR_F0: f32 =
    ((CORE_IOR - 1.0) / (CORE_IOR + 1.0)) * ((CORE_IOR - 1.0) / (CORE_IOR + 1.0));

/// The roughness image of a specular-glossiness texture: green = 1 − gloss·alpha.
fn roughness_image(t: &Texture, gloss: f32) -> Texture {
    let rgba = t
        .rgba
        .chunks_exact(4)
        .flat_map(|p| {
            let r = 1.0 - gloss * f32::from(p[3]) / 255.0;
            [0, (r * 255.0).round() as u8, 0, 255]
        })
        .collect();
    Texture {
        // Its identity in the texture tables: no file has this name.
        path: format!("{} (roughness from glossiness {gloss})", t.path.display()).into(),
        image: t.image,
        width: t.width,
        height: t.height,
        rgba,
    }
}
