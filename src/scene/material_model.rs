//! The material model every format maps into (issue 19): glTF 2.0's, which is the richest.
//! Each texture slot has its own sampler, UV set and optional `KHR_texture_transform`; the
//! material has an alpha mode, sidedness and `unlit`. The decoded images live in
//! [`super::Material::diffuse_map`] and [`super::pbr_material::PbrInputs`]' maps; this
//! records how they are to be sampled and what the file said, so `--check` can describe a
//! glTF material in glTF terms.
//!
//! Mapping of the other formats: OBJ/MTL `Kd`/`map_Kd` → base colour (sRGB), `Pm`/`map_Pm` →
//! metallic, `Pr`/`map_Pr` → roughness, `norm`/`map_Bump` (normal maps) → normal, `map_ao` →
//! occlusion, `Ke`/`map_Ke` → emissive; `d`/`Tr` < 1 → BLEND, else OPAQUE; single-sided
//! culling is off (OBJ says nothing about sidedness: double-sided); samplers repeat with
//! linear filtering and mipmaps, UV set 0. STL and PLY: the default material (base colour
//! 0.8 grey, or the vertex colours), OPAQUE, double-sided.
use serde::{Deserialize, Serialize};

#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum Wrap {
    #[default]
    Repeat,
    ClampToEdge,
    MirroredRepeat,
}

#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum Filter {
    Nearest,
    #[default]
    Linear,
    NearestMipmapNearest,
    LinearMipmapNearest,
    NearestMipmapLinear,
    LinearMipmapLinear,
}

#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct Sampler {
    pub wrap_s: Wrap,
    pub wrap_t: Wrap,
    pub mag: Filter,
    /// Linear with mipmaps when the file does not say (the viewer's usual choice).
    pub min: Option<Filter>,
}

/// `KHR_texture_transform`: uv' = T(offset) · R(rotation) · S(scale) · uv.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct TexTransform {
    pub offset: [f32; 2],
    pub rotation: f32,
    pub scale: [f32; 2],
}

impl TexTransform {
    /// The transformed UV, by the extension's matrix.
    pub fn apply(&self, uv: [f32; 2]) -> [f32; 2] {
        let (s, c) = self.rotation.sin_cos();
        let (x, y) = (uv[0] * self.scale[0], uv[1] * self.scale[1]);
        [
            c * x + s * y + self.offset[0],
            -s * x + c * y + self.offset[1],
        ]
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum Slot {
    BaseColor,
    MetallicRoughness,
    Normal,
    Occlusion,
    Emissive,
}

impl Slot {
    pub fn gltf_name(self) -> &'static str {
        match self {
            Slot::BaseColor => "baseColorTexture",
            Slot::MetallicRoughness => "metallicRoughnessTexture",
            Slot::Normal => "normalTexture",
            Slot::Occlusion => "occlusionTexture",
            Slot::Emissive => "emissiveTexture",
        }
    }
}

/// One texture slot: which image, how it is sampled, which UV set, how UVs are transformed.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TextureSlot {
    pub slot: Slot,
    /// The image's index in its glTF file (its identity together with the file).
    pub image: usize,
    pub sampler: Sampler,
    /// TEXCOORD_n (the transform's texCoord override applied).
    pub uv_set: u32,
    pub transform: Option<TexTransform>,
    /// Whether the image was decoded (false: a warning said why).
    pub loaded: bool,
}

#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub enum AlphaMode {
    #[default]
    Opaque,
    /// Discard below the cutoff.
    Mask(f32),
    Blend,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Model {
    pub alpha_mode: AlphaMode,
    pub double_sided: bool,
    pub unlit: bool,
    pub normal_scale: f32,
    pub occlusion_strength: f32,
    /// `KHR_materials_emissive_strength` (already multiplied into the emissive colour).
    pub emissive_strength: f32,
    pub base_alpha: f32,
    pub textures: Vec<TextureSlot>,
}

impl Default for Model {
    fn default() -> Self {
        Model {
            alpha_mode: AlphaMode::Opaque,
            double_sided: true,
            unlit: false,
            normal_scale: 1.0,
            occlusion_strength: 1.0,
            emissive_strength: 1.0,
            base_alpha: 1.0,
            textures: Vec::new(),
        }
    }
}

impl Model {
    pub fn slot(&self, s: Slot) -> Option<&TextureSlot> {
        self.textures.iter().find(|t| t.slot == s)
    }

    /// One line per fact, in glTF terms (for `--check`).
    pub fn describe(&self) -> Vec<String> {
        let mut out = vec![format!(
            "alphaMode {}, doubleSided {}{}, baseColorFactor alpha {:.3}, emissiveStrength {}",
            match self.alpha_mode {
                AlphaMode::Opaque => "OPAQUE".to_string(),
                AlphaMode::Mask(c) => format!("MASK (alphaCutoff {c})"),
                AlphaMode::Blend => "BLEND".to_string(),
            },
            self.double_sided,
            if self.unlit {
                ", KHR_materials_unlit"
            } else {
                ""
            },
            self.base_alpha,
            self.emissive_strength
        )];
        for t in &self.textures {
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
                Slot::Normal => s += &format!(", scale {}", self.normal_scale),
                Slot::Occlusion => s += &format!(", strength {}", self.occlusion_strength),
                _ => {}
            }
            if let Some(x) = t.transform {
                s += &format!(
                    ", KHR_texture_transform offset {:?} rotation {} scale {:?}",
                    x.offset, x.rotation, x.scale
                );
            }
            out.push(s);
        }
        out
    }
}

/// How `m`, loaded from a file of `format` (not glTF), maps into the material model: one
/// line for `--check`, naming each slot's source in the file's own terms.
pub fn mapping(
    m: &super::Material,
    format: super::formats::Format,
    vertex_colours: bool,
) -> String {
    use super::formats::Format;
    let p = m.pbr();
    let i = &m.pbr_inputs;
    let rgb = |c: [f32; 3]| format!("({:.3}, {:.3}, {:.3})", c[0], c[1], c[2]);
    let map = |t: &Option<std::sync::Arc<super::Texture>>, key: &str| match t {
        Some(t) => format!(
            " x {key} {} (repeat, linear, mipmaps, UV set 0)",
            t.path.display()
        ),
        None => String::new(),
    };
    if matches!(format, Format::Stl | Format::Ply) {
        return format!(
            "baseColor {}{}, metallic 0, roughness 1, no textures, OPAQUE, doubleSided \
             (the format has no materials)",
            rgb(p.base_color),
            if vertex_colours {
                " x vertex colours"
            } else {
                ""
            }
        );
    }
    let (metal, rough) = if p.source == "classic" {
        (
            if p.metallic > 0.0 {
                "1 (Ks brighter than Kd: classic metal; baseColor from Ks)"
            } else {
                "0 (from Kd/Ks)"
            }
            .to_string(),
            format!("{:.3} (from Ns {})", p.roughness, m.shininess),
        )
    } else {
        (
            format!("{:.2} (Pm)", p.metallic),
            format!("{:.3} (Pr)", p.roughness),
        )
    };
    let alpha = if m.is_translucent() {
        format!("BLEND (d {:.3})", m.opacity)
    } else {
        "OPAQUE (d 1)".to_string()
    };
    format!(
        "baseColor {} (Kd, sRGB){}, metallic {metal}{}, roughness {rough}{}, normal{}, \
         occlusion{}, emissive {} (Ke){}, {alpha}, doubleSided (OBJ says nothing about sides)",
        rgb(p.base_color),
        map(&m.diffuse_map, "map_Kd"),
        map(&i.metallic_map, "map_Pm"),
        map(&i.roughness_map, "map_Pr"),
        match &i.normal_map {
            Some(t) => format!(
                " {} (norm/map_Bump, tangents by MikkTSpace)",
                t.path.display()
            ),
            None => " none".to_string(),
        },
        match &i.ao_map {
            Some(t) => format!(" {} (map_ao, red)", t.path.display()),
            None => " none".to_string(),
        },
        rgb(p.emissive),
        map(&i.emissive_map, "map_Ke"),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn transform_follows_the_extension_matrix() {
        let t = TexTransform {
            offset: [0.5, 0.0],
            rotation: std::f32::consts::FRAC_PI_2,
            scale: [2.0, 1.0],
        };
        // S: (2, 0) → R(90°): (cos·2 + sin·0, -sin·2 + cos·0) = (0, -2) → T: (0.5, -2).
        let [u, v] = t.apply([1.0, 0.0]);
        assert!((u - 0.5).abs() < 1e-6 && (v + 2.0).abs() < 1e-6, "{u} {v}");
    }
}
