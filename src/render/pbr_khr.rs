//! The glTF PBR extensions in the PBR tier (issue 32): which of them a material's program
//! computes (`KHR_CLEARCOAT`, `KHR_SHEEN`, `KHR_SPECULAR`: permutations, so a material
//! without an extension runs the core program unchanged), their textures' units and their
//! uniforms. The formulas are in `pbr.frag` and docs/gltf/extensions.md.
use super::textures::TextureTable;
use crate::gpu::program::Program;
use crate::gpu::GpuRef;
use crate::scene::material_khr::SLOTS;
use crate::scene::texture_slot::ColorSpace;
use crate::scene::Material;
use crate::shader::cache::ProgramKey;
use crate::Result;
use glam::{Vec2, Vec3};
use std::sync::atomic::{AtomicBool, Ordering};

/// The extension maps' program flags and sampler names, in [`SLOTS`] order.
const MAPS: [(&str, &str, &str); 7] = [
    ("HAS_CC_MAP", "ccm", "uClearcoatMap"),
    ("HAS_CC_ROUGH_MAP", "ccr", "uClearcoatRoughMap"),
    ("HAS_CC_NORMAL_MAP", "ccn", "uClearcoatNormalMap"),
    ("HAS_SHEEN_COLOR_MAP", "shc", "uSheenColorMap"),
    ("HAS_SHEEN_ROUGH_MAP", "shr", "uSheenRoughMap"),
    ("HAS_SPECULAR_MAP", "spm", "uSpecularMap"),
    ("HAS_SPECULAR_COLOR_MAP", "spc", "uSpecularColorMap"),
];

/// Which extensions and maps a program computes.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct KhrFlags {
    pub clearcoat: bool,
    pub sheen: bool,
    pub specular: bool,
    /// Per slot of [`SLOTS`]: the map is read.
    pub maps: [bool; 7],
}

impl KhrFlags {
    /// Every extension and map (for `--compile-shaders`).
    pub const ALL: KhrFlags = KhrFlags {
        clearcoat: true,
        sheen: true,
        specular: true,
        maps: [true; 7],
    };

    pub fn key(self, key: ProgramKey) -> ProgramKey {
        let mut key = key
            .switch("KHR_CLEARCOAT", "cc", self.clearcoat)
            .switch("KHR_SHEEN", "sheen", self.sheen)
            .switch("KHR_SPECULAR", "spec", self.specular)
            .switch("HAS_KHR_MAPS", "khrm", self.maps.iter().any(|m| *m));
        for (on, (define, short, _)) in self.maps.iter().zip(MAPS) {
            key = key.switch(define, short, *on);
        }
        key
    }
}

/// One material's extension textures (indices into the frame's [`TextureTable`]).
pub(crate) type KhrTextures = [Option<usize>; 7];

/// Uploads a material's extension textures (sRGB slots decoded by the format, as the core's).
pub(crate) fn textures(
    gpu: &GpuRef,
    table: &mut TextureTable,
    m: &Material,
) -> Result<KhrTextures> {
    let mut out = [None; 7];
    for (o, t) in out.iter_mut().zip(&m.khr.maps) {
        if let Some(t) = t {
            let srgb = t.color_space == ColorSpace::Srgb;
            *o = Some(table.get(gpu, &t.image, srgb, &t.sampler)?);
        }
    }
    Ok(out)
}

static UNITS_WARNED: AtomicBool = AtomicBool::new(false);

/// The program flags of material `m` drawn with `textures`: the extensions it uses, and the
/// maps that have UVs, tangents (the coat's normal map) and a texture unit (the units after
/// the specular levels, from `first_unit`; a map past the driver's last unit is left out,
/// said once).
pub(crate) fn flags(
    m: &Material,
    textures: &KhrTextures,
    has_uv: bool,
    has_tangents: bool,
    first_unit: u32,
    units: u32,
) -> KhrFlags {
    let k = &m.khr;
    let mut f = KhrFlags {
        clearcoat: k.clearcoat.is_some(),
        sheen: k.sheen.is_some(),
        specular: k.has_f0(),
        maps: [false; 7],
    };
    let used = [
        f.clearcoat,
        f.clearcoat,
        f.clearcoat && has_tangents,
        f.sheen,
        f.sheen,
        f.specular,
        f.specular,
    ];
    for (i, on) in f.maps.iter_mut().enumerate() {
        *on = has_uv && used[i] && textures[i].is_some();
        if *on && first_unit + i as u32 >= units {
            *on = false;
            if !UNITS_WARNED.swap(true, Ordering::Relaxed) {
                log::warn!(
                    "the driver has {units} texture units: glTF extension maps past unit {} \
                     are drawn with their factors alone",
                    units.saturating_sub(1)
                );
            }
        }
    }
    f
}

/// The sampler units of a program's extension maps (set once per program).
pub(crate) fn program_uniforms(p: &Program, first_unit: u32, terms: (bool, bool)) {
    for (i, (_, _, name)) in MAPS.iter().enumerate() {
        p.set_i32(name, (first_unit + i as u32) as i32);
    }
    let on = |b: bool| if b { 1.0 } else { 0.0 };
    p.set_vec2("uTermsC", Vec2::new(on(terms.0), on(terms.1)));
}

/// A material's extension uniforms, and its maps bound to their units; returns the number of
/// textures bound.
pub(crate) fn material(
    p: &Program,
    table: &TextureTable,
    m: &Material,
    f: KhrFlags,
    textures: &KhrTextures,
    first_unit: u32,
    has_uv1: bool,
) -> u32 {
    let k = &m.khr;
    if let Some(c) = k.clearcoat {
        p.set_f32("uClearcoat", c.factor);
        p.set_f32("uClearcoatRoughness", c.roughness);
        p.set_f32("uClearcoatNormalScale", c.normal_scale);
    }
    if let Some(s) = k.sheen {
        p.set_vec3("uSheenColor", Vec3::from(s.color));
        p.set_f32("uSheenRoughness", s.roughness);
    }
    if f.specular {
        let (f0, w) = k.dielectric();
        p.set_vec3("uF0", Vec3::from(f0));
        p.set_f32("uSpecularWeight", w);
    }
    let mut bound = 0;
    if f.maps.iter().any(|m| *m) {
        for (i, slot) in SLOTS.iter().enumerate() {
            p.set_mat3(
                &format!("uKhrXf[{i}]"),
                &super::slots::transform_matrix(m, *slot),
            );
            let set = m.slot(*slot).map_or(0, |t| t.uv_set);
            let set = if set == 1 && has_uv1 { 1.0 } else { 0.0 };
            p.set_f32(&format!("uKhrSet[{i}]"), set);
        }
        for (i, on) in f.maps.iter().enumerate() {
            if let (true, Some(t)) = (on, textures[i]) {
                table.texture(t).bind(first_unit + i as u32);
                bound += 1;
            }
        }
    }
    bound
}
