//! The glTF PBR extensions' layers on the one material (issue 32): KHR_materials_clearcoat,
//! _sheen, _specular and _ior, each with its factors and texture slots (sampler, UV set,
//! transform, as every slot). `None` is "the material does not use the extension", which
//! the PBR tier turns into a program without it (a permutation, not a branch).
//!
//! The formulas are the Khronos Sample Viewer's (docs/gltf/extensions.md): the dielectric
//! F0 is ((ior − 1)/(ior + 1))² · specularColor, clamped to 1, and the specular factor
//! weights the dielectric Fresnel (f0 and f90 alike); the clearcoat is a GGX lobe of F0 0.04
//! over the base, which it attenuates by 1 − clearcoat·F_cc; the sheen is a Charlie lobe over
//! the base, which it attenuates by 1 − max(sheenColor)·E_sheen. KHR_materials_iridescence
//! replaces the base's Fresnel by a thin film's (Belcour & Barla 2017) weighted by its factor.
//! KHR_materials_anisotropy stretches the base's GGX lobe along a direction in tangent space.
use crate::model::texture_slot::{Slot, TextureSlot};
use serde::{Deserialize, Serialize};

/// KHR_materials_clearcoat (its textures: [`Slot::Clearcoat`], [`Slot::ClearcoatRoughness`],
/// [`Slot::ClearcoatNormal`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Clearcoat {
    pub factor: f32,
    pub roughness: f32,
    pub normal_scale: f32,
}

/// KHR_materials_sheen (textures [`Slot::SheenColor`], [`Slot::SheenRoughness`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Sheen {
    /// Linear RGB.
    pub color: [f32; 3],
    pub roughness: f32,
}

/// KHR_materials_specular (textures [`Slot::Specular`], [`Slot::SpecularColor`]).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Specular {
    pub factor: f32,
    /// Linear RGB.
    pub color: [f32; 3],
}

impl Default for Specular {
    fn default() -> Self {
        Specular {
            factor: 1.0,
            color: [1.0; 3],
        }
    }
}

/// KHR_materials_volume (texture [`Slot::Thickness`], green channel).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Volume {
    /// In the mesh's units (glview bakes node transforms into the vertices: scene units).
    pub thickness: f32,
    /// Linear RGB: the colour white light has after `attenuation_distance` in the medium.
    pub attenuation_color: [f32; 3],
    /// None: infinite (no attenuation).
    pub attenuation_distance: Option<f32>,
}

/// KHR_materials_iridescence (textures [`Slot::Iridescence`], red channel: the factor;
/// [`Slot::IridescenceThickness`], green: the thickness from `thickness_min` to
/// `thickness_max`; without it the thickness is `thickness_max`).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Iridescence {
    pub factor: f32,
    /// The film's index of refraction.
    pub ior: f32,
    /// In nanometres.
    pub thickness_min: f32,
    pub thickness_max: f32,
}

impl Default for Iridescence {
    fn default() -> Self {
        Iridescence {
            factor: 0.0,
            ior: 1.3,
            thickness_min: 100.0,
            thickness_max: 400.0,
        }
    }
}

/// KHR_materials_anisotropy (texture [`Slot::Anisotropy`]: red and green the direction in
/// tangent space, mapped from [0, 1] to [-1, 1]; blue multiplies the strength; without it
/// the direction is the tangent's).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Anisotropy {
    /// In [0, 1]: how much rougher the lobe is along the direction than across it.
    pub strength: f32,
    /// Radians, counter-clockwise from the tangent towards the bitangent.
    pub rotation: f32,
}

/// The number of extension slots.
pub const COUNT: usize = 12;

/// The extension slots in the order of [`Khr::maps`] (and of the mesh cache's table).
pub const SLOTS: [Slot; COUNT] = [
    Slot::Clearcoat,
    Slot::ClearcoatRoughness,
    Slot::ClearcoatNormal,
    Slot::SheenColor,
    Slot::SheenRoughness,
    Slot::Specular,
    Slot::SpecularColor,
    Slot::Transmission,
    Slot::Thickness,
    Slot::Iridescence,
    Slot::IridescenceThickness,
    Slot::Anisotropy,
];

/// The extensions of one material. Serialised in the mesh cache with the material.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Khr {
    pub clearcoat: Option<Clearcoat>,
    pub sheen: Option<Sheen>,
    pub specular: Option<Specular>,
    /// KHR_materials_ior (None: the core's 1.5).
    pub ior: Option<f32>,
    /// KHR_materials_transmission's factor (texture [`Slot::Transmission`], red channel).
    #[serde(default)]
    pub transmission: Option<f32>,
    #[serde(default)]
    pub volume: Option<Volume>,
    #[serde(default)]
    pub iridescence: Option<Iridescence>,
    #[serde(default)]
    pub anisotropy: Option<Anisotropy>,
    /// The extensions' texture slots, in the order of [`SLOTS`].
    pub maps: [Option<TextureSlot>; COUNT],
    /// Converted from KHR_materials_pbrSpecularGlossiness (`crate::loaders::gltf::specgloss`).
    #[serde(default)]
    pub converted_spec_gloss: bool,
}

/// The core model's index of refraction (F0 0.04).
pub const CORE_IOR: f32 = 1.5;

impl Khr {
    /// Whether the dielectric F0 differs from the core's path: KHR_materials_specular or
    /// KHR_materials_ior is present.
    pub fn has_f0(&self) -> bool {
        self.specular.is_some() || self.ior.is_some()
    }

    /// ((ior − 1)/(ior + 1))²: the dielectric F0 before the specular colour.
    pub(crate) fn ior_f0(&self) -> f32 {
        let ior = self.ior.unwrap_or(CORE_IOR);
        ((ior - 1.0) / (ior + 1.0)).powi(2)
    }

    /// The dielectric F0 factor (ior times specular colour; textures multiply it and the
    /// shader clamps the product to 1) and the specular weight (specular factor).
    pub fn dielectric(&self) -> ([f32; 3], f32) {
        let f0 = self.ior_f0();
        match &self.specular {
            Some(s) => (s.color.map(|c| f0 * c), s.factor),
            None => ([f0; 3], 1.0),
        }
    }

    /// Slot `s` of the extensions (None for a core slot).
    pub(crate) fn slot(&self, s: Slot) -> Option<&TextureSlot> {
        let i = SLOTS.iter().position(|x| *x == s)?;
        self.maps[i].as_ref()
    }

    /// Extension slot `s`'s place in `maps` (for the loaders; `s` is one of [`SLOTS`]).
    pub(crate) fn slot_mut(&mut self, s: Slot) -> &mut Option<TextureSlot> {
        let i = SLOTS.iter().position(|x| *x == s);
        &mut self.maps[i.expect("an extension slot")]
    }
}
