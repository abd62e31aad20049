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
//! | 20        | pbr_khr              | the opaque frame's copy transmission reads            |
//! | 21-       | pbr_khr              | the KHR extension maps a material reads, packed       |
//! |           |                      | (`khr_units`)                                         |
//!
//! The extension maps (twelve slots) do not each own a unit: a program gets units from 21 up
//! for the maps its material reads, in [`KHR_PRIORITY`] order, so a material with a few maps
//! takes a few units. Where the driver's count ends first (11 units on a 32-unit driver;
//! none on a 16-unit one, where the specular levels end at 15) the maps last in that order
//! are left out, their layers drawn with their factors alone, said once.
//! Full-screen passes (post, aa, overlay, ibl_gpu, the shadow map view) draw one quad with
//! their own program and bind their inputs from unit 0 up; they share no program with the
//! scene passes, so they need no entry here.
use crate::scene::model::material_khr::{COUNT as KHR_MAPS, SLOTS as KHR_SLOTS};
use crate::scene::model::texture_slot::Slot;

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
/// The opaque frame's copy transmission reads: past the RGBM path's frame copy.
pub(crate) const FRAME_UNIT: u32 = BEHIND_UNIT + 1;
/// The first unit of the extension maps.
pub(crate) const KHR_FIRST_UNIT: u32 = FRAME_UNIT + 1;

/// The order in which the extension maps get units, most needed first: each layer's map of
/// where it is (its factor's texture) before the maps that refine it, and the coat's normal
/// map last (without it the coat follows the geometry, its default).
pub(crate) const KHR_PRIORITY: [Slot; KHR_MAPS] = [
    Slot::Transmission,
    Slot::Clearcoat,
    Slot::SheenColor,
    Slot::SpecularColor,
    Slot::Iridescence,
    Slot::Anisotropy,
    Slot::Thickness,
    Slot::ClearcoatRoughness,
    Slot::SheenRoughness,
    Slot::Specular,
    Slot::IridescenceThickness,
    Slot::ClearcoatNormal,
];

/// The units of the extension maps a program reads (`wanted`, in the order of the material's
/// slots, `material_khr::SLOTS`) on a driver with `units` units: from [`KHR_FIRST_UNIT`] up
/// in [`KHR_PRIORITY`] order; a map past the driver's last unit gets none.
pub(crate) fn khr_units(wanted: &[bool; KHR_MAPS], units: u32) -> [Option<u32>; KHR_MAPS] {
    let mut out = [None; KHR_MAPS];
    let mut next = KHR_FIRST_UNIT;
    for slot in KHR_PRIORITY {
        let Some(i) = KHR_SLOTS.iter().position(|s| *s == slot) else {
            continue;
        };
        if wanted[i] && next < units {
            out[i] = Some(next);
            next += 1;
        }
    }
    out
}

/// Roughness levels that fit the driver's texture units next to the other maps.
pub(crate) fn max_levels(units: u32) -> u32 {
    units.saturating_sub(SPECULAR_UNIT).min(MAX_LEVELS)
}

// The promises of the table above: the legacy tier runs on an 8-unit driver, the PBR tier
// with two roughness levels (the least `ibl` makes) on a 16-unit one.
const _: () = assert!(LEGACY_EMISSIVE_UNIT < 8);
const _: () = assert!(SPECULAR_UNIT + 2 <= 16);

#[cfg(test)]
mod tests {
    use super::*;

    /// Every slot is in the priority order once.
    #[test]
    fn priority_names_every_slot_once() {
        for s in KHR_SLOTS {
            assert_eq!(KHR_PRIORITY.iter().filter(|p| **p == s).count(), 1, "{s:?}");
        }
    }

    /// A material with every map: on llvmpipe's 32 units, 11 maps take 21-31 (each once)
    /// and the coat's normal map, last in priority, is left out; on a 16-unit driver no
    /// map gets a unit at or past 16, so the program samples no unit the driver lacks and
    /// draws with the factors; on 8 the same.
    #[test]
    fn every_map_fits_or_is_left_out_by_priority() {
        let all = [true; KHR_MAPS];
        let got = khr_units(&all, 32);
        let mut used: Vec<u32> = got.iter().flatten().copied().collect();
        used.sort_unstable();
        assert_eq!(used, (21..32).collect::<Vec<_>>());
        let cc_normal = KHR_SLOTS.iter().position(|s| *s == Slot::ClearcoatNormal);
        assert_eq!(got[cc_normal.unwrap()], None);
        for units in [8, 16, 21] {
            assert!(
                khr_units(&all, units).iter().all(Option::is_none),
                "{units}"
            );
        }
        // One unit past the frame's copy: the most needed map alone.
        let got = khr_units(&all, 22);
        let tr = KHR_SLOTS.iter().position(|s| *s == Slot::Transmission);
        assert_eq!(got[tr.unwrap()], Some(21));
        assert_eq!(got.iter().flatten().count(), 1);
    }

    /// A material takes the units of the maps it reads, packed from 21: an anisotropy map
    /// alone is on 21 whatever its slot's place.
    #[test]
    fn a_material_takes_units_for_its_own_maps() {
        let mut wanted = [false; KHR_MAPS];
        let an = KHR_SLOTS
            .iter()
            .position(|s| *s == Slot::Anisotropy)
            .unwrap();
        wanted[an] = true;
        let got = khr_units(&wanted, 32);
        assert_eq!(got[an], Some(KHR_FIRST_UNIT));
        assert_eq!(got.iter().flatten().count(), 1);
        let ir = KHR_SLOTS
            .iter()
            .position(|s| *s == Slot::IridescenceThickness)
            .unwrap();
        wanted[ir] = true;
        let got = khr_units(&wanted, 32);
        assert_eq!((got[an], got[ir]), (Some(21), Some(22)));
    }
}
