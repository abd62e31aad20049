//! The glTF PBR extensions in the PBR tier (issue 32): which of them a material's program
//! computes (`KHR_CLEARCOAT`, `KHR_SHEEN`, `KHR_SPECULAR`, `KHR_TRANSMISSION`, `KHR_VOLUME`,
//! `KHR_IRIDESCENCE`, `KHR_ANISOTROPY`: permutations, so a material without an extension runs the core program unchanged), their
//! textures' units and their uniforms, and the copy of the opaque frame transmission reads
//! (`copy_frame`). The formulas are in `pbr.frag` and docs/gltf/extensions.md.
use super::textures::TextureTable;
use super::units::{khr_units, FRAME_UNIT};
use crate::gpu::program::Program;
use crate::gpu::GpuRef;
use crate::scene::model::material_khr::{COUNT, SLOTS};
use crate::scene::model::texture_slot::ColorSpace;
use crate::scene::Material;
use crate::shader::cache::ProgramKey;
use crate::Result;
use glam::Vec3;
use std::sync::atomic::{AtomicBool, Ordering};

/// The extension maps' program flags and sampler names, in [`SLOTS`] order.
const MAPS: [(&str, &str, &str); COUNT] = [
    ("HAS_CC_MAP", "ccm", "uClearcoatMap"),
    ("HAS_CC_ROUGH_MAP", "ccr", "uClearcoatRoughMap"),
    ("HAS_CC_NORMAL_MAP", "ccn", "uClearcoatNormalMap"),
    ("HAS_SHEEN_COLOR_MAP", "shc", "uSheenColorMap"),
    ("HAS_SHEEN_ROUGH_MAP", "shr", "uSheenRoughMap"),
    ("HAS_SPECULAR_MAP", "spm", "uSpecularMap"),
    ("HAS_SPECULAR_COLOR_MAP", "spc", "uSpecularColorMap"),
    ("HAS_TRANSMISSION_MAP", "trm", "uTransmissionMap"),
    ("HAS_THICKNESS_MAP", "thm", "uThicknessMap"),
    ("HAS_IRIDESCENCE_MAP", "irm", "uIridescenceMap"),
    (
        "HAS_IRIDESCENCE_THICKNESS_MAP",
        "irt",
        "uIridescenceThicknessMap",
    ),
    ("HAS_ANISOTROPY_MAP", "anm", "uAnisotropyMap"),
];

/// Which extensions and maps a program computes.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct KhrFlags {
    pub(crate) clearcoat: bool,
    pub(crate) sheen: bool,
    pub(crate) specular: bool,
    /// Thin-walled transmission through the opaque frame's copy (drawn after it).
    pub(crate) transmission: bool,
    /// Refraction through the volume and Beer–Lambert attenuation (with transmission).
    pub(crate) volume: bool,
    /// KHR_materials_iridescence's thin film over the base.
    pub(crate) iridescence: bool,
    /// KHR_materials_anisotropy's stretched lobe (needs a tangent frame).
    pub(crate) anisotropy: bool,
    /// Per slot of [`SLOTS`]: the map is read.
    pub(crate) maps: [bool; COUNT],
}

impl KhrFlags {
    /// Every extension and map (for `--compile-shaders`).
    pub(crate) const ALL: KhrFlags = KhrFlags {
        clearcoat: true,
        sheen: true,
        specular: true,
        transmission: true,
        volume: true,
        iridescence: true,
        anisotropy: true,
        maps: [true; COUNT],
    };

    pub(crate) fn key(self, key: ProgramKey) -> ProgramKey {
        let mut key = key
            .switch("KHR_CLEARCOAT", "cc", self.clearcoat)
            .switch("KHR_SHEEN", "sheen", self.sheen)
            .switch("KHR_SPECULAR", "spec", self.specular)
            .switch("KHR_TRANSMISSION", "trans", self.transmission)
            .switch("KHR_VOLUME", "vol", self.volume)
            .switch("KHR_IRIDESCENCE", "irid", self.iridescence)
            .switch("KHR_ANISOTROPY", "aniso", self.anisotropy)
            .switch("HAS_KHR_MAPS", "khrm", self.maps.iter().any(|m| *m));
        for (on, (define, short, _)) in self.maps.iter().zip(MAPS) {
            key = key.switch(define, short, *on);
        }
        key
    }
}

/// One material's extension textures (indices into the frame's [`TextureTable`]).
pub(crate) type KhrTextures = [Option<usize>; COUNT];

/// Uploads a material's extension textures (sRGB slots decoded by the format, as the core's).
pub(crate) fn textures(
    gpu: &GpuRef,
    table: &mut TextureTable,
    m: &Material,
) -> Result<KhrTextures> {
    let mut out = [None; COUNT];
    for (o, t) in out.iter_mut().zip(&m.khr.maps) {
        if let Some(t) = t {
            let srgb = t.color_space == ColorSpace::Srgb;
            *o = Some(table.get(gpu, &t.image, srgb, &t.sampler)?);
        }
    }
    Ok(out)
}

static UNITS_WARNED: AtomicBool = AtomicBool::new(false);
static NO_TANGENTS_WARNED: AtomicBool = AtomicBool::new(false);

/// The program flags of material `m` drawn with `textures`: the extensions it uses
/// (anisotropy where the mesh has a tangent frame, else isotropic, said once), and the maps
/// that have UVs, tangents (the coat's normal map) and a texture unit ([`khr_units`]; the
/// maps past the driver's last unit are left out, least needed first, said once).
/// `transmission`: the opaque frame's copy is there to read (the mesh is drawn after it).
pub(crate) fn flags(
    m: &Material,
    textures: &KhrTextures,
    has_uv: bool,
    has_tangents: bool,
    transmission: bool,
    units: u32,
) -> KhrFlags {
    let k = &m.khr;
    let transmission = transmission && k.transmission.is_some();
    let mut f = KhrFlags {
        clearcoat: k.clearcoat.is_some(),
        sheen: k.sheen.is_some(),
        specular: k.has_f0(),
        transmission,
        volume: transmission && k.volume.is_some(),
        iridescence: k.iridescence.is_some(),
        anisotropy: k.anisotropy.is_some() && has_tangents,
        maps: [false; COUNT],
    };
    if k.anisotropy.is_some() && !has_tangents && !NO_TANGENTS_WARNED.swap(true, Ordering::Relaxed)
    {
        log::warn!(
            "KHR_materials_anisotropy is drawn isotropic on a mesh without texture coordinates \
             (its direction is given in the tangent frame they define)"
        );
    }
    let used = [
        f.clearcoat,
        f.clearcoat,
        f.clearcoat && has_tangents,
        f.sheen,
        f.sheen,
        f.specular,
        f.specular,
        f.transmission,
        f.volume,
        f.iridescence,
        f.iridescence,
        f.anisotropy,
    ];
    let mut wanted = [false; COUNT];
    for (i, w) in wanted.iter_mut().enumerate() {
        *w = has_uv && used[i] && textures[i].is_some();
    }
    let got = khr_units(&wanted, units);
    for (i, on) in f.maps.iter_mut().enumerate() {
        *on = got[i].is_some();
        if wanted[i] && !*on && !UNITS_WARNED.swap(true, Ordering::Relaxed) {
            log::warn!(
                "the driver has {units} texture units: glTF extension maps that do not fit \
                 past unit {} are drawn with their factors alone (the first left out: {})",
                FRAME_UNIT,
                SLOTS[i].gltf_name()
            );
        }
    }
    f
}

/// The sampler unit of the frame's copy (set once per program); `levels`: the copy's mip
/// levels (0: none, read sharp). `terms`: the clearcoat, sheen, transmission, iridescence
/// and anisotropy layers.
pub(crate) fn program_uniforms(p: &Program, terms: [bool; 5], levels: f32) {
    p.set_i32("uTransmissionFrame", FRAME_UNIT as i32);
    p.set_f32("uFrameLevels", levels);
    let on = |b: bool| if b { 1.0 } else { 0.0 };
    p.set_vec3(
        "uTermsC",
        Vec3::new(on(terms[0]), on(terms[1]), on(terms[2])),
    );
    p.set_f32("uTermIridescence", on(terms[3]));
    p.set_f32("uTermAnisotropy", on(terms[4]));
}

/// A material's extension uniforms, and its maps bound to their units; returns the number of
/// textures bound.
pub(crate) fn material(
    p: &Program,
    table: &TextureTable,
    m: &Material,
    f: KhrFlags,
    textures: &KhrTextures,
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
    if f.transmission {
        p.set_f32("uTransmission", k.transmission.unwrap_or(0.0));
        p.set_f32(
            "uIor",
            k.ior
                .unwrap_or(crate::scene::model::material_khr::CORE_IOR)
                .max(1.0),
        );
    }
    if let (true, Some(v)) = (f.volume, k.volume) {
        p.set_f32("uThickness", v.thickness);
        p.set_vec3("uAttenuationColor", Vec3::from(v.attenuation_color));
        p.set_f32(
            "uAttenuationDistance",
            v.attenuation_distance.unwrap_or(0.0),
        );
    }
    if let (true, Some(i)) = (f.iridescence, k.iridescence) {
        p.set_f32("uIridescence", i.factor);
        p.set_f32("uIridescenceIor", i.ior);
        p.set_vec2(
            "uIridescenceThickness",
            glam::Vec2::new(i.thickness_min, i.thickness_max),
        );
    }
    if let (true, Some(a)) = (f.anisotropy, k.anisotropy) {
        let (sin, cos) = a.rotation.sin_cos();
        p.set_vec3("uAnisotropy", Vec3::new(cos, sin, a.strength));
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
        // The maps the flags kept all fit: their units are the packed ones `flags` found.
        let units = khr_units(&f.maps, u32::MAX);
        for (i, (_, _, name)) in MAPS.iter().enumerate() {
            if let (Some(unit), Some(t)) = (units[i], textures[i]) {
                p.set_i32(name, unit as i32);
                table.texture(t).bind(unit);
                bound += 1;
            }
        }
    }
    bound
}

static SHARP_WARNED: AtomicBool = AtomicBool::new(false);
static NO_COPY_WARNED: AtomicBool = AtomicBool::new(false);

/// Whether this frame can draw transmission: a single-sampled display-value frame (not the
/// linear or RGBM offscreen frame of bloom), without the stencil-masked background (drawn
/// last, it is not behind anything yet), and a unit for the copy. Said once when not.
pub(crate) fn frame_allows(cx: &super::FrameCx) -> bool {
    let why = if cx.linear || cx.rgbm {
        Some("with bloom's offscreen frame")
    } else if super::background::masked(cx) {
        Some("with --translucency nearest-masked")
    } else if FRAME_UNIT >= cx.gpu.caps.max_texture_units {
        Some("with fewer than 21 texture units")
    } else {
        None
    };
    if let Some(why) = why {
        if !NO_COPY_WARNED.swap(true, Ordering::Relaxed) {
            log::warn!("KHR_materials_transmission is drawn opaque {why}");
        }
        return false;
    }
    cx.bind_target();
    if cx.gpu.framebuffer_multisampled() {
        if !NO_COPY_WARNED.swap(true, Ordering::Relaxed) {
            log::warn!("KHR_materials_transmission is drawn opaque with multisampling");
        }
        return false;
    }
    true
}

/// Copies the frame drawn so far (the opaque meshes and the background) into
/// `res.transmission` on [`FRAME_UNIT`] and rebuilds its mip chain; returns the number of
/// levels the shader may blur across (log2 of the larger side), or 0 where the driver has
/// no `glGenerateMipmap` (GL 2.1 without framebuffer objects): rough transmission is then
/// read sharp, said once.
pub(crate) fn copy_frame(cx: &mut super::FrameCx) -> Result<f32> {
    use crate::gpu::texture::{Pixels, Sampling, Texture2d, TextureFormat};
    let [x, y, w, h] = cx.viewport;
    let stale = cx
        .res
        .transmission
        .as_ref()
        .is_none_or(|t| (t.width, t.height) != (w, h));
    if stale {
        let s = Sampling {
            linear: true,
            mipmaps: true,
            repeat: false,
        };
        cx.res.transmission = Some(Texture2d::new(
            cx.gpu,
            TextureFormat::Rgba8,
            w,
            h,
            Pixels::None,
            s,
        )?);
    }
    cx.bind_target();
    let t = cx.res.transmission.as_ref().expect("made above");
    t.copy_region_from_framebuffer(FRAME_UNIT, x, y);
    if cx.gpu.caps.generate_mipmap {
        t.generate_mipmaps(FRAME_UNIT);
        Ok((w.max(h) as f32).log2().floor())
    } else {
        if !SHARP_WARNED.swap(true, Ordering::Relaxed) {
            log::warn!(
                "{}: no glGenerateMipmap, so rough KHR_materials_transmission shows the scene \
                 behind it sharp (no mip chain of the opaque frame)",
                cx.gpu.caps.version
            );
        }
        Ok(0.0)
    }
}
