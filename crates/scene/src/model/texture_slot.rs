//! One texture slot of a material ([`TextureSlot`]) and the vocabulary it is described in:
//! glTF 2.0's, the richest of the formats (issue 19). Each slot has its own image, sampler,
//! UV set, optional `KHR_texture_transform` and colour space; an MTL's maps are slots with
//! the viewer's usual sampling (repeat, linear with mipmaps, UV set 0, no transform).
use crate::model::material::Texture;
use serde::{Deserialize, Serialize};
use std::sync::Arc;

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
    /// The extensions' slots (issue 32, [`crate::model::material_khr`]).
    Clearcoat,
    ClearcoatRoughness,
    ClearcoatNormal,
    SheenColor,
    SheenRoughness,
    Specular,
    SpecularColor,
    Transmission,
    Thickness,
    Iridescence,
    IridescenceThickness,
    Anisotropy,
}

impl Slot {
    pub fn gltf_name(self) -> &'static str {
        match self {
            Slot::BaseColor => "baseColorTexture",
            Slot::MetallicRoughness => "metallicRoughnessTexture",
            Slot::Normal => "normalTexture",
            Slot::Occlusion => "occlusionTexture",
            Slot::Emissive => "emissiveTexture",
            Slot::Clearcoat => "clearcoatTexture",
            Slot::ClearcoatRoughness => "clearcoatRoughnessTexture",
            Slot::ClearcoatNormal => "clearcoatNormalTexture",
            Slot::SheenColor => "sheenColorTexture",
            Slot::SheenRoughness => "sheenRoughnessTexture",
            Slot::Specular => "specularTexture",
            Slot::SpecularColor => "specularColorTexture",
            Slot::Transmission => "transmissionTexture",
            Slot::Thickness => "thicknessTexture",
            Slot::Iridescence => "iridescenceTexture",
            Slot::IridescenceThickness => "iridescenceThicknessTexture",
            Slot::Anisotropy => "anisotropyTexture",
        }
    }
}

/// How a slot's image is decoded: colours are sRGB-encoded, data (normals, metallic,
/// roughness, occlusion) is linear. The PBR tier decodes sRGB slots; the legacy tier works in
/// display values and reads every image as it is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum ColorSpace {
    Srgb,
    Linear,
}

/// One texture slot: the decoded image, how it is sampled, which UV set, how UVs are
/// transformed. A slot exists only where its image was decoded; `--check` describes the ones
/// that failed from [`crate::model::material::CheckNotes`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TextureSlot {
    /// The pixels are not serialised: the mesh cache stores each distinct image once and
    /// sets this from its table (`crate::cache`).
    #[serde(skip)]
    pub image: Arc<Texture>,
    pub sampler: Sampler,
    /// TEXCOORD_n (the transform's texCoord override applied).
    pub uv_set: u32,
    pub transform: Option<TexTransform>,
    pub color_space: ColorSpace,
}

impl TextureSlot {
    /// A slot with the viewer's usual sampling (repeat, trilinear, UV set 0, no transform):
    /// every MTL map and `--texture`.
    pub fn plain(image: Arc<Texture>, color_space: ColorSpace) -> Self {
        TextureSlot {
            image,
            sampler: Sampler::default(),
            uv_set: 0,
            transform: None,
            color_space,
        }
    }
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
