//! A glTF material in the scene's material model ([`super::material_model`]): every texture
//! slot with its sampler, UV set and `KHR_texture_transform`; alpha mode, sidedness, unlit and
//! `KHR_materials_emissive_strength`. Images are kept as the file has them (the
//! metallic-roughness image's blue and green channels are read by the shader, no copies).
use super::material_model::{self as mm, AlphaMode, Slot, TextureSlot};
use super::{Material, Texture};
use gltf::texture::{MagFilter, MinFilter, WrappingMode};
use std::sync::Arc;

fn wrap(w: WrappingMode) -> mm::Wrap {
    match w {
        WrappingMode::ClampToEdge => mm::Wrap::ClampToEdge,
        WrappingMode::MirroredRepeat => mm::Wrap::MirroredRepeat,
        WrappingMode::Repeat => mm::Wrap::Repeat,
    }
}

fn min_filter(f: MinFilter) -> mm::Filter {
    match f {
        MinFilter::Nearest => mm::Filter::Nearest,
        MinFilter::Linear => mm::Filter::Linear,
        MinFilter::NearestMipmapNearest => mm::Filter::NearestMipmapNearest,
        MinFilter::LinearMipmapNearest => mm::Filter::LinearMipmapNearest,
        MinFilter::NearestMipmapLinear => mm::Filter::NearestMipmapLinear,
        MinFilter::LinearMipmapLinear => mm::Filter::LinearMipmapLinear,
    }
}

fn slot(
    s: Slot,
    tex: gltf::Texture,
    tex_coord: u32,
    transform: Option<gltf::texture::TextureTransform>,
    loaded: bool,
) -> TextureSlot {
    let smp = tex.sampler();
    TextureSlot {
        slot: s,
        image: tex.source().index(),
        sampler: mm::Sampler {
            wrap_s: wrap(smp.wrap_s()),
            wrap_t: wrap(smp.wrap_t()),
            mag: match smp.mag_filter() {
                Some(MagFilter::Nearest) => mm::Filter::Nearest,
                _ => mm::Filter::Linear,
            },
            min: smp.min_filter().map(min_filter),
        },
        uv_set: transform
            .as_ref()
            .and_then(|t| t.tex_coord())
            .unwrap_or(tex_coord),
        transform: transform.map(|t| mm::TexTransform {
            offset: t.offset(),
            rotation: t.rotation(),
            scale: t.scale(),
        }),
        loaded,
    }
}

/// `image(i)` decodes (once) or gives None after warning.
pub fn material(
    m: &gltf::Material,
    image: &mut dyn FnMut(usize) -> Option<Arc<Texture>>,
) -> Material {
    let pbr = m.pbr_metallic_roughness();
    let [r, g, b, a] = pbr.base_color_factor();
    let strength = m.emissive_strength().unwrap_or(1.0);
    let mut model = mm::Model {
        alpha_mode: match m.alpha_mode() {
            gltf::material::AlphaMode::Opaque => AlphaMode::Opaque,
            gltf::material::AlphaMode::Mask => AlphaMode::Mask(m.alpha_cutoff().unwrap_or(0.5)),
            gltf::material::AlphaMode::Blend => AlphaMode::Blend,
        },
        double_sided: m.double_sided(),
        unlit: m.unlit(),
        normal_scale: 1.0,
        occlusion_strength: 1.0,
        emissive_strength: strength,
        base_alpha: a,
        textures: Vec::new(),
    };
    let mut load = |s: Slot, t: gltf::Texture, uv: u32, x, model: &mut mm::Model| {
        let img = image(t.source().index());
        model.textures.push(slot(s, t, uv, x, img.is_some()));
        img
    };
    let base = pbr.base_color_texture().and_then(|i| {
        load(
            Slot::BaseColor,
            i.texture(),
            i.tex_coord(),
            i.texture_transform(),
            &mut model,
        )
    });
    let mr = pbr.metallic_roughness_texture().and_then(|i| {
        load(
            Slot::MetallicRoughness,
            i.texture(),
            i.tex_coord(),
            i.texture_transform(),
            &mut model,
        )
    });
    let normal = m.normal_texture().and_then(|n| {
        model.normal_scale = n.scale();
        load(Slot::Normal, n.texture(), n.tex_coord(), None, &mut model)
    });
    let occlusion = m.occlusion_texture().and_then(|o| {
        model.occlusion_strength = o.strength();
        load(
            Slot::Occlusion,
            o.texture(),
            o.tex_coord(),
            None,
            &mut model,
        )
    });
    let emissive = m.emissive_texture().and_then(|i| {
        load(
            Slot::Emissive,
            i.texture(),
            i.tex_coord(),
            i.texture_transform(),
            &mut model,
        )
    });
    let spec = pbr
        .base_color_texture()
        .map(|t| format!("baseColorTexture image {}", t.texture().source().index()));
    Material {
        name: m.name().unwrap_or("gltf").to_string(),
        ambient: [r, g, b],
        diffuse: [r, g, b],
        specular: [0.0; 3],
        emissive: m.emissive_factor().map(|e| e * strength),
        shininess: 0.0,
        opacity: if m.alpha_mode() == gltf::material::AlphaMode::Blend {
            a
        } else {
            1.0
        },
        illum: None,
        diffuse_map: base,
        diffuse_map_spec: spec,
        // The PBR tier reads these as it reads an MTL's Pm and Pr and their maps.
        pbr_inputs: super::pbr_material::PbrInputs {
            metallic: Some(pbr.metallic_factor()),
            roughness: Some(pbr.roughness_factor()),
            metallic_roughness_map: mr,
            normal_map: normal,
            ao_map: occlusion,
            emissive_map: emissive,
            model,
            ..Default::default()
        },
    }
}
