//! The material model on the GPU, for both tiers and the shadow pass: each texture slot's
//! sampler (wrap S/T, filters), UV set and `KHR_texture_transform` as uniforms
//! (`uSlotXf[i]`, `uSlotSet[i]`, read by `material.glsl`), and the alpha mode and `unlit` as
//! program flags. Slot indices: 0 base colour, 1 metallic-roughness, 2 normal, 3 occlusion,
//! 4 emissive.
use crate::gpu::program::Program;
use crate::gpu::texture::Texture2d;
use crate::scene::model::material::{AlphaMode, Material};
use crate::scene::model::texture_slot::{Filter, Sampler, Slot, Wrap};
use crate::shader::cache::ProgramKey;
use glam::Mat3;

const SLOTS: [Slot; 5] = [
    Slot::BaseColor,
    Slot::MetallicRoughness,
    Slot::Normal,
    Slot::Occlusion,
    Slot::Emissive,
];

fn wrap(w: Wrap) -> u32 {
    match w {
        Wrap::Repeat => glow::REPEAT,
        Wrap::ClampToEdge => glow::CLAMP_TO_EDGE,
        Wrap::MirroredRepeat => glow::MIRRORED_REPEAT,
    }
}

fn filter(f: Filter) -> u32 {
    match f {
        Filter::Nearest => glow::NEAREST,
        Filter::Linear => glow::LINEAR,
        Filter::NearestMipmapNearest => glow::NEAREST_MIPMAP_NEAREST,
        Filter::LinearMipmapNearest => glow::LINEAR_MIPMAP_NEAREST,
        Filter::NearestMipmapLinear => glow::NEAREST_MIPMAP_LINEAR,
        Filter::LinearMipmapLinear => glow::LINEAR_MIPMAP_LINEAR,
    }
}

/// Applies the slot's sampler to a texture uploaded with its mip chain. A file that names no
/// min filter gets trilinear filtering, the viewer's usual choice.
pub(crate) fn apply_sampler(t: &Texture2d, s: &Sampler) {
    t.set_sampler(
        [wrap(s.wrap_s), wrap(s.wrap_t)],
        filter(s.min.unwrap_or(Filter::LinearMipmapLinear)),
        filter(s.mag),
    );
}

/// `KHR_texture_transform` as the 3×3 matrix uv' = T · R · S · uv (column-major).
pub(crate) fn transform_matrix(model: &Material, slot: Slot) -> Mat3 {
    let Some(x) = model.slot(slot).and_then(|t| t.transform) else {
        return Mat3::IDENTITY;
    };
    let (s, c) = x.rotation.sin_cos();
    Mat3::from_cols_array(&[
        c * x.scale[0],
        -s * x.scale[0],
        0.0,
        s * x.scale[1],
        c * x.scale[1],
        0.0,
        x.offset[0],
        x.offset[1],
        1.0,
    ])
}

/// Program flags of a material: alpha mode (`ALPHA_MASK`, `ALPHA_BLEND`; neither is opaque),
/// a second UV set on the mesh (`HAS_UV1`) and `UNLIT`.
pub(crate) fn flags(
    key: ProgramKey,
    model: &Material,
    has_uv1: bool,
    textured: bool,
    colored: bool,
) -> ProgramKey {
    let mask = matches!(model.alpha_mode, AlphaMode::Mask(_));
    // Without a texture or vertex colours (COLOR_0's alpha) the factor's alpha is the
    // material's opacity already.
    let blend = model.alpha_mode == AlphaMode::Blend && (textured || colored);
    key.switch("ALPHA_MASK", "mask", mask)
        .switch("ALPHA_BLEND", "blend", blend)
        .switch("HAS_UV1", "uv1", has_uv1)
        .switch("UNLIT", "unlit", model.unlit)
}

/// Per-material uniforms: each slot's UV set and transform, the alpha cutoff and the base
/// colour factor's alpha.
pub(crate) fn set_uniforms(p: &Program, model: &Material, has_uv1: bool) {
    for (i, slot) in SLOTS.into_iter().enumerate() {
        p.set_mat3(&format!("uSlotXf[{i}]"), &transform_matrix(model, slot));
        let set = model.slot(slot).map_or(0, |t| t.uv_set);
        // A slot naming a UV set the mesh lacks reads set 0 (the file is invalid there).
        let set = if set == 1 && has_uv1 { 1.0 } else { 0.0 };
        p.set_f32(&format!("uSlotSet[{i}]"), set);
    }
    if let AlphaMode::Mask(c) = model.alpha_mode {
        p.set_f32("uAlphaCutoff", c);
    }
    p.set_f32("uBaseAlpha", model.base_alpha);
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::model::texture_slot::{ColorSpace, TexTransform, TextureSlot};

    #[test]
    fn matrix_equals_the_extensions_formula() {
        let x = TexTransform {
            offset: [0.25, -0.5],
            rotation: 0.7,
            scale: [2.0, 3.0],
        };
        let model = Material {
            emissive_texture: Some(TextureSlot {
                transform: Some(x),
                ..TextureSlot::plain(Default::default(), ColorSpace::Srgb)
            }),
            ..Material::gltf_default()
        };
        let m = transform_matrix(&model, Slot::Emissive);
        for uv in [[0.0, 0.0], [1.0, 0.0], [0.3, 0.9], [-2.0, 5.0]] {
            let a = m * glam::Vec3::new(uv[0], uv[1], 1.0);
            let b = x.apply(uv);
            assert!((a.x - b[0]).abs() < 1e-5 && (a.y - b[1]).abs() < 1e-5);
        }
        assert_eq!(transform_matrix(&model, Slot::BaseColor), Mat3::IDENTITY);
    }
}
