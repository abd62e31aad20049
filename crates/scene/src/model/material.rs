//! The one CPU material every format loads into: glTF 2.0's metallic-roughness model on the
//! outside (base colour and alpha mode, metallic, roughness, emissive, normal scale,
//! occlusion strength, sidedness, unlit, one [`TextureSlot`] per map), and the Phong terms an
//! MTL gives ([`PhongTerms`]) as an optional part, which the legacy tier draws with. An MTL is
//! mapped into the PBR values once, at load (`crate::loaders::obj::mtl_mapping`); a glTF material has
//! no Phong terms and the legacy tier derives them from the base colour
//! ([`Material::phong_terms`]). Decoded images (RGBA8) are here too; no GL.
use crate::model::texture_slot::{Slot, TextureSlot};
use serde::{Deserialize, Serialize};
use std::path::PathBuf;

/// A decoded texture, RGBA8, row 0 at the top (image order).
#[derive(Clone, Debug, Default)]
pub struct Texture {
    /// The image file, or the glTF file that holds the image.
    pub path: PathBuf,
    /// Which image of the container at `path` (a glTF image index); `None` for an image file.
    /// Part of the texture's identity: every image inside one `.glb` has the same `path`.
    pub image: Option<usize>,
    pub width: u32,
    pub height: u32,
    pub rgba: Vec<u8>,
}

impl PartialEq for Texture {
    fn eq(&self, other: &Self) -> bool {
        self.path == other.path && self.image == other.image
    }
}

/// Options that make texture loading safe; see `--allow-outside-paths`.
#[derive(Clone, Copy, Debug, Default)]
pub struct TextureOptions {
    pub allow_outside_paths: bool,
    /// Largest width/height accepted from a file header; larger images are refused before
    /// decoding (decompression bombs) and images above the driver limit are downscaled later.
    pub max_dimension: u32,
}

/// How the base colour's alpha (factor times texture) is used: glTF's `alphaMode`. An MTL's
/// materials are OPAQUE here (its `d` is [`Material::opacity`]; `map_Kd`'s alpha is not
/// used: MTL has `map_d` for that, which glview ignores).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub enum AlphaMode {
    #[default]
    Opaque,
    /// Discard below the cutoff.
    Mask(f32),
    /// The base colour texture's alpha multiplies the opacity.
    Blend,
}

/// The fixed-function (legacy tier) colours and exponent of an MTL material.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct PhongTerms {
    /// `Ka`
    pub ambient: [f32; 3],
    /// `Kd`: the base colour too, except for a classic metal, whose base colour is `Ks`.
    pub diffuse: [f32; 3],
    /// `Ks`
    pub specular: [f32; 3],
    /// `Ns`; Ns <= 0 means "specular factor 1 wherever N·L > 0" (the limit x^0 = 1 of the
    /// fixed-function formula), evaluated without calling pow.
    pub shininess: f32,
    pub illum: Option<u8>,
    /// The PBR values were mapped from these terms (the MTL gives no `Pr`/`Pm`); x-ray
    /// maps them again, as the mapping's glass rule reads the translucency.
    pub mapped: bool,
}

impl Default for PhongTerms {
    /// The fixed-function OpenGL material defaults.
    fn default() -> Self {
        PhongTerms {
            ambient: [0.2; 3],
            diffuse: [0.8; 3],
            specular: [0.0; 3],
            shininess: 0.0,
            illum: None,
            mapped: true,
        }
    }
}

/// The one colour rule: what a material's colour factors (base colour, emissive) and its
/// meshes' colours mean, decided by the loader. The legacy tier draws display values, so it
/// draws a linear colour as its sRGB encoding (the display value of the same colour), once,
/// where its uniforms are made ([`Material::phong_terms`], `Material::legacy_emissive`):
/// a factor, an sRGB texture and a vertex colour of one colour then look the same. The PBR
/// tier reads every factor as linear.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum ColourRule {
    /// Display values, drawn as written: MTL `Ka`/`Kd`/`Ks`/`Ke`, PLY and STL colours,
    /// glview's defaults.
    #[default]
    Display,
    /// Linear values (glTF's factors, emissive, KHR_materials_unlit), sRGB-encoded for the
    /// legacy tier.
    Linear,
}

impl ColourRule {
    /// `c` as the legacy tier draws it.
    pub(crate) fn legacy(self, c: [f32; 3]) -> [f32; 3] {
        match self {
            ColourRule::Display => c,
            ColourRule::Linear => c.map(srgb_encode_hdr),
        }
    }

    /// `--check`'s words for the rule.
    pub(crate) fn describe(self) -> &'static str {
        match self {
            ColourRule::Display => "display colours, drawn as written by the legacy tier",
            ColourRule::Linear => {
                "linear colours (factors, emissive, COLOR_0), drawn sRGB-encoded by the \
                 legacy tier, as its textures are read"
            }
        }
    }
}

/// sRGB encoding continued above 1 (an emissive strength makes linear values above 1: their
/// encoding stays above 1 and the legacy tier's output clamps it).
/// 0 and 1 are kept exactly (pure colours stay pure).
pub(crate) fn srgb_encode_hdr(x: f32) -> f32 {
    if x <= 0.003_130_8 {
        12.92 * x.max(0.0)
    } else if x <= 1.0 {
        crate::model::colour::srgb_encode(f64::from(x)).min(1.0) as f32
    } else {
        1.055 * x.powf(1.0 / 2.4) - 0.055
    }
}

/// What `--check` says about a material's textures beyond its slots: what the file named,
/// loaded or not (a slot exists only for a decoded image).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct CheckNotes {
    /// The base colour texture as the file names it (`map_Kd` as written, `--texture`'s
    /// path, glTF's "baseColorTexture image N").
    pub(crate) base_color: Option<String>,
    /// Every other MTL map statement as (key, file as written, what happened).
    pub maps: Vec<(String, String, String)>,
    /// A glTF material's texture slots in glTF terms, one line each, the failed ones too.
    pub gltf_slots: Vec<String>,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Material {
    pub name: String,
    /// Linear RGB factor (glTF `baseColorFactor` rgb; an MTL's mapped `Kd` or `Ks`).
    pub base_color: [f32; 3],
    /// glTF `baseColorFactor` alpha: what MASK's cutoff is compared with (times the texture).
    pub base_alpha: f32,
    pub alpha_mode: AlphaMode,
    /// The one field translucency is decided from: `Some(opacity)` is drawn blended with
    /// that opacity (an MTL's `d` or `1 - Tr` below 1, glTF's BLEND, x-ray), `None` opaque.
    pub opacity: Option<f32>,
    pub metallic: f32,
    pub roughness: f32,
    /// Linear RGB, `KHR_materials_emissive_strength` already multiplied in.
    pub emissive: [f32; 3],
    pub emissive_strength: f32,
    pub normal_scale: f32,
    pub occlusion_strength: f32,
    /// OBJ, STL and PLY say nothing about sides: double-sided.
    pub double_sided: bool,
    /// `KHR_materials_unlit`: the base colour is the colour.
    pub unlit: bool,
    /// What the colour factors mean (display or linear values), decided by the loader.
    #[serde(default)]
    pub colour_rule: ColourRule,
    pub base_color_texture: Option<TextureSlot>,
    /// glTF's packed image: roughness in green, metallic in blue.
    pub metallic_roughness_texture: Option<TextureSlot>,
    pub normal_texture: Option<TextureSlot>,
    /// Red channel.
    pub occlusion_texture: Option<TextureSlot>,
    pub emissive_texture: Option<TextureSlot>,
    /// An MTL's separate `map_Pm` (red channel), which glTF packs into
    /// `metallic_roughness_texture`.
    pub metallic_texture: Option<TextureSlot>,
    /// An MTL's separate `map_Pr` (red channel).
    pub roughness_texture: Option<TextureSlot>,
    /// The glTF PBR extensions (clearcoat, sheen, specular, ior) with their slots.
    #[serde(default)]
    pub khr: crate::model::material_khr::Khr,
    /// The MTL's terms (also the defaults of STL, PLY and OBJ without a material); None for
    /// glTF.
    pub phong: Option<PhongTerms>,
    #[serde(default)]
    pub check: CheckNotes,
}

impl Default for Material {
    /// The fixed-function OpenGL material defaults, mapped as an MTL without values is.
    fn default() -> Self {
        Material::with_phong(PhongTerms::default())
    }
}

impl Material {
    /// glTF's defaults where a PBR value is concerned, no textures, no Phong terms.
    pub fn gltf_default() -> Self {
        Material {
            name: "default".into(),
            base_color: [1.0; 3],
            base_alpha: 1.0,
            alpha_mode: AlphaMode::Opaque,
            opacity: None,
            metallic: 1.0,
            roughness: 1.0,
            emissive: [0.0; 3],
            emissive_strength: 1.0,
            normal_scale: 1.0,
            occlusion_strength: 1.0,
            double_sided: true,
            unlit: false,
            colour_rule: ColourRule::Display,
            base_color_texture: None,
            metallic_roughness_texture: None,
            normal_texture: None,
            occlusion_texture: None,
            emissive_texture: None,
            metallic_texture: None,
            roughness_texture: None,
            khr: Default::default(),
            phong: None,
            check: CheckNotes::default(),
        }
    }

    /// A point cloud's: white diffuse (so per-point colours are drawn as given), the
    /// fixed-function ambient, no specular.
    pub(crate) fn cloud() -> Self {
        Material::with_phong(PhongTerms {
            diffuse: [1.0; 3],
            ..PhongTerms::default()
        })
    }

    /// A material with these Phong terms (no `Pr`/`Pm`), its PBR values mapped from them.
    pub fn with_phong(phong: PhongTerms) -> Self {
        let mut m = Material {
            phong: Some(phong),
            ..Material::gltf_default()
        };
        crate::loaders::obj::mtl_mapping::map(&mut m, None, None);
        m
    }

    /// Drawn blended, in the translucent pass.
    pub fn is_translucent(&self) -> bool {
        self.opacity.is_some()
    }

    /// The opacity the material is drawn with (1 when opaque).
    pub fn draw_opacity(&self) -> f32 {
        self.opacity.unwrap_or(1.0)
    }

    /// Sets the opacity as x-ray does (the only change made to a loaded material that an
    /// input of the MTL mapping depends on): translucent below 1 or where the alpha mode is
    /// BLEND, and the classic mapping made again, whose glass rule reads the translucency.
    pub(crate) fn set_opacity(&mut self, opacity: f32) {
        self.opacity = translucency(opacity, self.alpha_mode);
        if self.phong.is_some_and(|p| p.mapped) {
            crate::loaders::obj::mtl_mapping::map(self, None, None);
        }
    }

    /// The legacy tier's terms: the MTL's, or, for glTF, the base colour (as the colour
    /// rule draws it) as ambient and diffuse colour and no specular highlight.
    pub fn phong_terms(&self) -> PhongTerms {
        let base = self.colour_rule.legacy(self.base_color);
        self.phong.unwrap_or(PhongTerms {
            ambient: base,
            diffuse: base,
            specular: [0.0; 3],
            shininess: 0.0,
            illum: None,
            mapped: false,
        })
    }

    /// The emissive colour the legacy tier draws (`Ke`), by the colour rule.
    pub fn legacy_emissive(&self) -> [f32; 3] {
        self.colour_rule.legacy(self.emissive)
    }

    /// The slot `s` (the glTF slots; an MTL's separate metallic and roughness maps are
    /// fields of their own).
    pub fn slot(&self, s: Slot) -> Option<&TextureSlot> {
        match s {
            Slot::BaseColor => self.base_color_texture.as_ref(),
            Slot::MetallicRoughness => self.metallic_roughness_texture.as_ref(),
            Slot::Normal => self.normal_texture.as_ref(),
            Slot::Occlusion => self.occlusion_texture.as_ref(),
            Slot::Emissive => self.emissive_texture.as_ref(),
            s => self.khr.slot(s),
        }
    }

    /// The decoded image of slot `s`.
    pub fn image(&self, s: Slot) -> Option<&std::sync::Arc<Texture>> {
        self.slot(s).map(|t| &t.image)
    }

    #[cfg_attr(not(feature = "native"), allow(dead_code))]
    /// Every texture slot in one fixed order (the mesh cache's slot table follows it).
    pub(crate) fn slots_mut(&mut self) -> [&mut Option<TextureSlot>; 19] {
        let [a, b, c, d, e, f, g, h, i, j, k, l] = &mut self.khr.maps;
        [
            &mut self.base_color_texture,
            &mut self.normal_texture,
            &mut self.metallic_texture,
            &mut self.roughness_texture,
            &mut self.metallic_roughness_texture,
            &mut self.occlusion_texture,
            &mut self.emissive_texture,
            a,
            b,
            c,
            d,
            e,
            f,
            g,
            h,
            i,
            j,
            k,
            l,
        ]
    }

    #[cfg_attr(not(feature = "native"), allow(dead_code))]
    /// As [`Material::slots_mut`], read only.
    pub fn slots(&self) -> [&Option<TextureSlot>; 19] {
        let [a, b, c, d, e, f, g, h, i, j, k, l] = &self.khr.maps;
        [
            &self.base_color_texture,
            &self.normal_texture,
            &self.metallic_texture,
            &self.roughness_texture,
            &self.metallic_roughness_texture,
            &self.occlusion_texture,
            &self.emissive_texture,
            a,
            b,
            c,
            d,
            e,
            f,
            g,
            h,
            i,
            j,
            k,
            l,
        ]
    }

    /// Whether a tangent frame is read: the normal map, the clearcoat's, or
    /// KHR_materials_anisotropy (its direction is given in tangent space).
    pub fn needs_tangents(&self) -> bool {
        self.normal_texture.is_some()
            || self.khr.slot(Slot::ClearcoatNormal).is_some()
            || self.khr.anisotropy.is_some()
    }

    /// Whether the occlusion, roughness and metallic maps are an MTL's single-channel images,
    /// which the GPU packs into one texture (glTF's are used as they are). MTL materials are
    /// the ones with Phong terms.
    pub fn packs_orm(&self) -> bool {
        self.phong.is_some()
    }
}

/// Translucency from an opacity and an alpha mode: below 1, or BLEND (whose texture alpha
/// may be below 1 where the factor is 1).
pub(crate) fn translucency(opacity: f32, mode: AlphaMode) -> Option<f32> {
    (opacity < 1.0 || mode == AlphaMode::Blend).then_some(opacity)
}

/// The factors of a glTF material that KHR_animation_pointer may animate, as the file gives
/// them; [`Factors::apply`] makes them the material's values, for the loader and for a pose
/// alike (so a moment's material is the one a file holding those factors loads as).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Factors {
    pub(crate) base_color: [f32; 4],
    pub(crate) metallic: f32,
    pub(crate) roughness: f32,
    pub(crate) emissive: [f32; 3],
    pub(crate) emissive_strength: f32,
}

impl Factors {
    /// Sets `out`'s colour, opacity, metallic, roughness and emissive values from these
    /// factors (`out.alpha_mode` decides the opacity).
    pub(crate) fn apply(&self, out: &mut Material) {
        let [r, g, b, a] = self.base_color;
        out.base_color = [r, g, b];
        out.base_alpha = a;
        // The factor's alpha is the opacity only in BLEND (MASK tests it, OPAQUE ignores it).
        let opacity = if out.alpha_mode == AlphaMode::Blend {
            a
        } else {
            1.0
        };
        out.opacity = translucency(opacity, out.alpha_mode);
        out.metallic = self.metallic.clamp(0.0, 1.0);
        out.roughness = self.roughness.clamp(0.0, 1.0);
        let strength = self.emissive_strength;
        out.emissive = self.emissive.map(|e| e * strength);
        out.emissive_strength = strength;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The colour rule: a linear glTF factor is drawn by the legacy tier as its sRGB
    /// encoding (TextureEncodingTest's 0.2462 is 136/255), display colours as written.
    #[test]
    fn linear_factors_are_encoded_for_the_legacy_tier() {
        let mut m = Material::gltf_default();
        m.base_color = [0.0, 0.246_201_33, 1.0];
        m.emissive = [2.0, 0.0, 0.0];
        assert_eq!(m.phong_terms().diffuse, m.base_color);
        m.colour_rule = ColourRule::Linear;
        let d = m.phong_terms().diffuse;
        assert_eq!((d[0], d[2]), (0.0, 1.0));
        assert!((d[1] * 255.0 - 136.0).abs() < 0.01, "{d:?}");
        assert!(m.legacy_emissive()[0] > 1.0);
        assert_eq!(Material::default().phong_terms().diffuse, [0.8; 3]);
    }

    #[test]
    fn defaults_are_fixed_function() {
        let m = Material::default().phong_terms();
        assert_eq!(
            (m.ambient, m.diffuse, m.specular, m.shininess),
            ([0.2; 3], [0.8; 3], [0.0; 3], 0.0)
        );
    }

    /// Translucency is one field: every way a material becomes translucent sets `opacity`,
    /// and `is_translucent` reads nothing else.
    #[test]
    fn translucency_is_decided_from_one_field() {
        assert_eq!(translucency(1.0, AlphaMode::Opaque), None);
        assert_eq!(translucency(0.5, AlphaMode::Opaque), Some(0.5));
        assert_eq!(translucency(1.0, AlphaMode::Blend), Some(1.0));
        assert_eq!(translucency(1.0, AlphaMode::Mask(0.5)), None);
        let mut m = Material::default();
        assert!(!m.is_translucent());
        // Nothing but `opacity` changes the answer: a BLEND alpha mode alone does not.
        m.alpha_mode = AlphaMode::Blend;
        assert!(!m.is_translucent());
        m.opacity = Some(1.0);
        assert!(m.is_translucent());
        m.set_opacity(1.0);
        assert_eq!(m.opacity, Some(1.0), "BLEND stays translucent at opacity 1");
        m.alpha_mode = AlphaMode::Opaque;
        m.set_opacity(1.0);
        assert!(!m.is_translucent());
        m.set_opacity(0.3);
        assert_eq!((m.is_translucent(), m.draw_opacity()), (true, 0.3));
    }
}
