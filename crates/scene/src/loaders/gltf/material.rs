//! A glTF material as the scene's [`Material`]: every texture slot with its sampler, UV set,
//! `KHR_texture_transform` and colour space; alpha mode, sidedness, unlit and
//! `KHR_materials_emissive_strength`. Images are kept as the file has them (the
//! metallic-roughness image's blue and green channels are read by the shader, no copies).
use crate::loaders::gltf::slots::facts;
use crate::model::material::{AlphaMode, ColourRule, Factors};
use crate::model::texture_slot::{ColorSpace, Slot, TextureSlot};
use crate::report::material::{slot_line, SlotFacts};
use std::sync::Arc;
use {crate::model::material::Material, crate::model::material::Texture};

/// One slot in colour space `cs`, when `image` decodes its image; its `--check` line, saying
/// whether the image loaded, goes to `lines` either way.
fn load_slot(
    image: &mut dyn FnMut(usize) -> Option<Arc<Texture>>,
    f: SlotFacts,
    cs: ColorSpace,
    lines: &mut Vec<String>,
) -> Option<TextureSlot> {
    let img = image(f.image);
    lines.push(slot_line(&SlotFacts {
        loaded: img.is_some(),
        ..f
    }));
    img.map(|image| TextureSlot {
        image,
        sampler: f.sampler,
        uv_set: f.uv_set,
        transform: f.transform,
        color_space: cs,
    })
}

/// The factors of glTF material `m` ([`Factors`]).
pub(crate) fn factors_of(m: &gltf::Material) -> Factors {
    let pbr = m.pbr_metallic_roughness();
    Factors {
        base_color: pbr.base_color_factor(),
        metallic: pbr.metallic_factor(),
        roughness: pbr.roughness_factor(),
        emissive: m.emissive_factor(),
        emissive_strength: m.emissive_strength().unwrap_or(1.0),
    }
}

/// `image(i)` decodes (once) or gives None after warning.
pub(crate) fn material(
    doc: &gltf::Document,
    m: &gltf::Material,
    image: &mut dyn FnMut(usize) -> Option<Arc<Texture>>,
) -> Material {
    let pbr = m.pbr_metallic_roughness();
    let alpha_mode = match m.alpha_mode() {
        gltf::material::AlphaMode::Opaque => AlphaMode::Opaque,
        gltf::material::AlphaMode::Mask => AlphaMode::Mask(m.alpha_cutoff().unwrap_or(0.5)),
        gltf::material::AlphaMode::Blend => AlphaMode::Blend,
    };
    let mut out = Material {
        name: m.name().unwrap_or("gltf").to_string(),
        alpha_mode,
        double_sided: m.double_sided(),
        unlit: m.unlit(),
        colour_rule: ColourRule::Linear,
        ..Material::gltf_default()
    };
    factors_of(m).apply(&mut out);
    out.check.base_color = pbr
        .base_color_texture()
        .map(|t| format!("baseColorTexture image {}", t.texture().source().index()));
    // Slots in glTF's order, so `--check` lists them so.
    let mut load = |f: SlotFacts, cs: ColorSpace, out: &mut Material| {
        load_slot(&mut *image, f, cs, &mut out.check.gltf_slots)
    };
    let (srgb, lin) = (ColorSpace::Srgb, ColorSpace::Linear);
    if let Some(i) = pbr.base_color_texture() {
        let f = facts(
            Slot::BaseColor,
            i.texture(),
            i.tex_coord(),
            i.texture_transform(),
            1.0,
        );
        out.base_color_texture = load(f, srgb, &mut out);
    }
    if let Some(i) = pbr.metallic_roughness_texture() {
        let f = facts(
            Slot::MetallicRoughness,
            i.texture(),
            i.tex_coord(),
            i.texture_transform(),
            1.0,
        );
        out.metallic_roughness_texture = load(f, lin, &mut out);
    }
    if let Some(n) = m.normal_texture() {
        out.normal_scale = n.scale();
        let f = facts(Slot::Normal, n.texture(), n.tex_coord(), None, n.scale());
        out.normal_texture = load(f, lin, &mut out);
    }
    if let Some(o) = m.occlusion_texture() {
        out.occlusion_strength = o.strength();
        let f = facts(
            Slot::Occlusion,
            o.texture(),
            o.tex_coord(),
            None,
            o.strength(),
        );
        out.occlusion_texture = load(f, lin, &mut out);
    }
    if let Some(i) = m.emissive_texture() {
        let f = facts(
            Slot::Emissive,
            i.texture(),
            i.tex_coord(),
            i.texture_transform(),
            1.0,
        );
        out.emissive_texture = load(f, srgb, &mut out);
    }
    let mut notes = Vec::new();
    // The extensions' slots (read while `out` is lent) are noted apart, listed after the core ones.
    let mut load_ext = |f: SlotFacts, cs: ColorSpace| load_slot(&mut *image, f, cs, &mut notes);
    out.khr = crate::loaders::gltf::khr::read(doc, m, &mut load_ext);
    crate::loaders::gltf::specgloss::convert(doc, m, &mut out, &mut load_ext);
    out.check.gltf_slots.extend(notes);
    out
}
