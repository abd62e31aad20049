//! `--check`'s account of a material in glTF's terms: a glTF material as the file has it
//! ([`describe`], [`slot_line`]), and how a material of another format maps into the model
//! ([`mapping`]).
use crate::model::material::{AlphaMode, Material};
use crate::model::texture_slot::{Sampler, Slot, TexTransform};

/// A glTF material, one line per fact: alpha mode, sidedness, unlit, factor alpha, emissive
/// strength, then each texture slot (written at load by [`slot_line`]).
pub(crate) fn describe(m: &Material) -> Vec<String> {
    let mut out = vec![format!(
        "alphaMode {}, doubleSided {}{}, baseColorFactor alpha {:.3}, emissiveStrength {}",
        match m.alpha_mode {
            AlphaMode::Opaque => "OPAQUE".to_string(),
            AlphaMode::Mask(c) => format!("MASK (alphaCutoff {c})"),
            AlphaMode::Blend => "BLEND".to_string(),
        },
        m.double_sided,
        if m.unlit { ", KHR_materials_unlit" } else { "" },
        m.base_alpha,
        m.emissive_strength
    )];
    out.extend(khr_lines(&m.khr));
    out.extend(m.check.gltf_slots.iter().cloned());
    out
}

/// One line per glTF PBR extension the material uses, with its factors.
fn khr_lines(k: &crate::model::material_khr::Khr) -> Vec<String> {
    let mut out = Vec::new();
    if k.converted_spec_gloss {
        out.push(
            "KHR_materials_pbrSpecularGlossiness: converted (diffuse → base colour, metallic 0, \
             specular → dielectric F0 through KHR_materials_specular, 1 − glossiness → roughness)"
                .to_string(),
        );
    }
    if let Some(c) = k.clearcoat {
        out.push(format!(
            "KHR_materials_clearcoat: clearcoatFactor {}, clearcoatRoughnessFactor {}",
            c.factor, c.roughness
        ));
    }
    if let Some(s) = k.sheen {
        out.push(format!(
            "KHR_materials_sheen: sheenColorFactor {:?}, sheenRoughnessFactor {}",
            s.color, s.roughness
        ));
    }
    if let Some(s) = k.specular {
        out.push(format!(
            "KHR_materials_specular: specularFactor {}, specularColorFactor {:?}",
            s.factor, s.color
        ));
    }
    if let Some(t) = k.transmission {
        out.push(format!(
            "KHR_materials_transmission: transmissionFactor {t}"
        ));
    }
    if let Some(v) = k.volume {
        out.push(format!(
            "KHR_materials_volume: thicknessFactor {}, attenuationColor {:?}, attenuationDistance {}",
            v.thickness,
            v.attenuation_color,
            v.attenuation_distance
                .map_or("infinite".to_string(), |d| d.to_string())
        ));
    }
    if let Some(i) = k.iridescence {
        out.push(format!(
            "KHR_materials_iridescence: iridescenceFactor {}, iridescenceIor {}, \
             iridescenceThicknessMinimum {} nm, iridescenceThicknessMaximum {} nm",
            i.factor, i.ior, i.thickness_min, i.thickness_max
        ));
    }
    if let Some(a) = k.anisotropy {
        out.push(format!(
            "KHR_materials_anisotropy: anisotropyStrength {}, anisotropyRotation {} rad",
            a.strength, a.rotation
        ));
    }
    if let Some(i) = k.ior {
        out.push(format!(
            "KHR_materials_ior: ior {i} (dielectric F0 {:.4})",
            k.ior_f0()
        ));
    }
    out
}

/// What a glTF texture slot says, whether or not its image could be decoded.
pub(crate) struct SlotFacts {
    pub(crate) slot: Slot,
    /// The image's index in its glTF file.
    pub(crate) image: usize,
    pub(crate) loaded: bool,
    pub(crate) sampler: Sampler,
    pub(crate) uv_set: u32,
    pub(crate) transform: Option<TexTransform>,
    /// The normal texture's scale or the occlusion texture's strength.
    pub(crate) scale: f32,
}

/// One `--check` line for a glTF texture slot (made at load: a slot whose image failed to
/// decode has no [`crate::model::texture_slot::TextureSlot`]).
pub(crate) fn slot_line(t: &SlotFacts) -> String {
    let mut s = format!(
        "{} image {}{}: TEXCOORD_{}, wrap {:?}/{:?}, mag {:?}, min {}",
        t.slot.gltf_name(),
        t.image,
        if t.loaded { "" } else { " (not loaded)" },
        t.uv_set,
        t.sampler.wrap_s,
        t.sampler.wrap_t,
        t.sampler.mag,
        t.sampler
            .min
            .map_or("default".to_string(), |f| format!("{f:?}")),
    );
    match t.slot {
        Slot::Normal | Slot::ClearcoatNormal => s += &format!(", scale {}", t.scale),
        Slot::Occlusion => s += &format!(", strength {}", t.scale),
        _ => {}
    }
    if let Some(x) = t.transform {
        s += &format!(
            ", KHR_texture_transform offset {:?} rotation {} scale {:?}",
            x.offset, x.rotation, x.scale
        );
    }
    s
}

/// How `m`, loaded from a file of `format` (not glTF), maps into the material model: one
/// line for `--check`, naming each slot's source in the file's own terms.
pub(crate) fn mapping(
    m: &Material,
    format: crate::loaders::formats::Format,
    vertex_colours: bool,
) -> String {
    use crate::loaders::formats::Format;
    use crate::model::texture_slot::TextureSlot;
    let rgb = |c: [f32; 3]| format!("({:.3}, {:.3}, {:.3})", c[0], c[1], c[2]);
    let map = |t: &Option<TextureSlot>, key: &str| match t {
        Some(t) => format!(
            " x {key} {} (repeat, linear, mipmaps, UV set 0)",
            t.image.path.display()
        ),
        None => String::new(),
    };
    if matches!(format, Format::Stl | Format::Ply) {
        return format!(
            "baseColor {}{}, metallic 0, roughness 1, no textures, OPAQUE, doubleSided \
             (the format has no materials)",
            rgb(m.base_color),
            if vertex_colours {
                " x vertex colours"
            } else {
                ""
            }
        );
    }
    let (metal, rough) = if m.phong.is_some_and(|p| p.mapped) {
        (
            if m.metallic > 0.0 {
                "1 (Ks brighter than Kd: classic metal; baseColor from Ks)"
            } else {
                "0 (from Kd/Ks)"
            }
            .to_string(),
            format!("{:.3} (from Ns {})", m.roughness, m.phong_terms().shininess),
        )
    } else {
        (
            format!("{:.2} (Pm)", m.metallic),
            format!("{:.3} (Pr)", m.roughness),
        )
    };
    let alpha = match m.opacity {
        Some(d) => format!("BLEND (d {d:.3})"),
        None => "OPAQUE (d 1)".to_string(),
    };
    format!(
        "baseColor {} (Kd, sRGB){}, metallic {metal}{}, roughness {rough}{}, normal{}, \
         occlusion{}, emissive {} (Ke){}, {alpha}, doubleSided (OBJ says nothing about sides)",
        rgb(m.base_color),
        map(&m.base_color_texture, "map_Kd"),
        map(&m.metallic_texture, "map_Pm"),
        map(&m.roughness_texture, "map_Pr"),
        match &m.normal_texture {
            Some(t) => format!(
                " {} (norm/map_Bump, tangents by MikkTSpace)",
                t.image.path.display()
            ),
            None => " none".to_string(),
        },
        match &m.occlusion_texture {
            Some(t) => format!(" {} (map_ao, red)", t.image.path.display()),
            None => " none".to_string(),
        },
        rgb(m.emissive),
        map(&m.emissive_texture, "map_Ke"),
    )
}
