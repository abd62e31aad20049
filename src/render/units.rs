//! Every texture unit the scene passes bind, in one table, so two passes can never pick the
//! same unit for different things and no pass has to import another to find a free one.
//!
//! Why the numbers are what they are: a fragment shader can sample
//! `GL_MAX_TEXTURE_IMAGE_UNITS` units. GLSL ES 1.00 (GL ES 2.0) guarantees 8, GL 3.x and
//! ES 3.0 guarantee 16; GL 2.1 drivers give 8 or 16 (llvmpipe gives 32). So what every lit
//! frame needs comes first and fits in 8 (the legacy tier: 0-6) or 16 (the PBR tier's maps,
//! IBL and two specular levels: 0-12); what only some frames need comes after, each checked
//! against the driver's count where it is used:
//!
//! | unit      | bound by             | what                                                  |
//! |-----------|----------------------|-------------------------------------------------------|
//! | 0         | lit, pbr, shadow     | the base colour (diffuse / albedo) map                |
//! | 0         | background           | the skybox cube (no material map in that pass)        |
//! | 1-4       | lit, pbr             | the shadow pass's maps, one per shadowed light        |
//! | 5, 6      | lit                  | normal and emissive maps (legacy tier)                |
//! | 5-8       | pbr                  | normal, ORM, emissive, glTF occlusion maps            |
//! | 9, 10     | pbr                  | the IBL irradiance cube and the BRDF table            |
//! | 11-18     | pbr                  | the specular cubes, one per roughness level; levels   |
//! |           |                      | past the driver's count are dropped (`max_levels`)    |
//! | 19        | translucent, grid    | the RGBM frame's copy blended over in the shader      |
//! | 20-30     | pbr_khr              | the KHR extension maps (clearcoat, sheen, ...)        |
//! | 31        | pbr_khr              | the opaque frame's copy transmission reads            |
//!
//! Full-screen passes (post, aa, overlay, ibl_gpu, the shadow map view) draw one quad with
//! their own program and bind their inputs from unit 0 up; they share no program with the
//! scene passes, so they need no entry here.
use crate::scene::material_khr::COUNT as KHR_MAPS;

/// The base colour map of both lit tiers and of the shadow pass (alpha-tested texels).
pub(crate) const BASE_UNIT: u32 = 0;
/// The skybox cube of the background pass (its program samples nothing else).
pub(crate) const SKY_UNIT: u32 = 0;
/// Shadow map i is on `SHADOW_UNIT + i` (up to four shadowed lights).
pub(crate) const SHADOW_UNIT: u32 = 1;
/// Shadow maps the lit programs take (`uShadowMap0..3`).
const SHADOW_MAPS: u32 = 4;

/// The normal map of both tiers, after the shadow maps.
pub(crate) const NORMAL_UNIT: u32 = SHADOW_UNIT + SHADOW_MAPS;
/// The legacy tier's emissive map.
pub(crate) const LEGACY_EMISSIVE_UNIT: u32 = NORMAL_UNIT + 1;

/// The PBR tier's occlusion-roughness-metalness map.
pub(crate) const ORM_UNIT: u32 = NORMAL_UNIT + 1;
/// The PBR tier's emissive map.
pub(crate) const EMISSIVE_UNIT: u32 = ORM_UNIT + 1;
/// glTF's occlusion map (its own UV set and sampler; an MTL's is packed into the ORM map).
pub(crate) const AO_UNIT: u32 = EMISSIVE_UNIT + 1;
/// The IBL irradiance cube.
pub(crate) const IRRADIANCE_UNIT: u32 = AO_UNIT + 1;
/// The split-sum BRDF table.
pub(crate) const LUT_UNIT: u32 = IRRADIANCE_UNIT + 1;
/// Specular cube of roughness level l is on `SPECULAR_UNIT + l`.
pub(crate) const SPECULAR_UNIT: u32 = LUT_UNIT + 1;
/// Specular levels the shader can take (`uSpecular0..7`).
pub(crate) const MAX_LEVELS: u32 = 8;
/// The last texture unit the PBR tier's core maps can use.
const LAST_PBR_UNIT: u32 = SPECULAR_UNIT + MAX_LEVELS - 1;

/// The unit of the frame's copy translucent surfaces blend over on the RGBM path: past the
/// PBR tier's last specular level.
pub(crate) const BEHIND_UNIT: u32 = LAST_PBR_UNIT + 1;
/// The first unit of the extension maps: past the RGBM path's frame copy.
pub(crate) const KHR_FIRST_UNIT: u32 = BEHIND_UNIT + 1;
/// The opaque frame's copy transmission reads.
pub(crate) const FRAME_UNIT: u32 = KHR_FIRST_UNIT + KHR_MAPS as u32;

/// Roughness levels that fit the driver's texture units next to the other maps.
pub(crate) fn max_levels(units: u32) -> u32 {
    units.saturating_sub(SPECULAR_UNIT).min(MAX_LEVELS)
}

// The promises of the table above: the legacy tier runs on an 8-unit driver, the PBR tier
// with two roughness levels (the least `ibl` makes) on a 16-unit one.
const _: () = assert!(LEGACY_EMISSIVE_UNIT < 8);
const _: () = assert!(SPECULAR_UNIT + 2 <= 16);
