//! The legacy-tier lighting formula, evaluated on the CPU in f64. The GLSL in
//! `shaders_gl/include/phong.glsl` is the same formula; tests and the reference renderer use
//! this one as the truth.
//!
//! colour = Ke + Ka·ambient + Σ visibility·(Kd·Lc·max(N·L, 0) + Ks·Lc·spec), clamped to [0, 1],
//! spec = max(R·V, 0)^Ns where N·L > 0 (0 elsewhere); Ns <= 0 gives spec = 1 where N·L > 0
//! (the limit x^0 = 1), so pow never sees 0^0 or a negative base.
use crate::light::{Light, LightKind};
use crate::scene::Material;
use glam::DVec3;

/// Which terms of the formula are drawn (keys 1, 2, 3 in the window).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Terms {
    pub ambient: bool,
    pub diffuse: bool,
    pub specular: bool,
}

impl Default for Terms {
    fn default() -> Self {
        Terms {
            ambient: true,
            diffuse: true,
            specular: true,
        }
    }
}

/// Which terms of the PBR formula are drawn (`--terms`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PbrTerms {
    pub direct_diffuse: bool,
    pub direct_specular: bool,
    pub ibl_diffuse: bool,
    pub ibl_specular: bool,
    pub ao: bool,
    pub shadows: bool,
    pub emissive: bool,
    /// The material's normal map (both tiers); off: the interpolated normal.
    pub normal_map: bool,
    /// The glTF extensions' layers (KHR_materials_clearcoat, _sheen, _transmission): off,
    /// the material is drawn without the layer.
    pub clearcoat: bool,
    pub sheen: bool,
    pub transmission: bool,
}

impl Default for PbrTerms {
    fn default() -> Self {
        PbrTerms {
            direct_diffuse: true,
            direct_specular: true,
            ibl_diffuse: true,
            ibl_specular: true,
            ao: true,
            shadows: true,
            emissive: true,
            normal_map: true,
            clearcoat: true,
            sheen: true,
            transmission: true,
        }
    }
}

impl PbrTerms {
    /// No term drawn.
    pub const NONE: PbrTerms = PbrTerms {
        direct_diffuse: false,
        direct_specular: false,
        ibl_diffuse: false,
        ibl_specular: false,
        ao: false,
        shadows: false,
        emissive: false,
        normal_map: false,
        clearcoat: false,
        sheen: false,
        transmission: false,
    };

    /// Each term's `--terms` word and switch, in the order the words are written.
    fn named(&mut self) -> [(&'static str, &mut bool); 11] {
        [
            ("direct-diffuse", &mut self.direct_diffuse),
            ("direct-specular", &mut self.direct_specular),
            ("ibl-diffuse", &mut self.ibl_diffuse),
            ("ibl-specular", &mut self.ibl_specular),
            ("ao", &mut self.ao),
            ("shadows", &mut self.shadows),
            ("emissive", &mut self.emissive),
            ("normal-map", &mut self.normal_map),
            ("clearcoat", &mut self.clearcoat),
            ("sheen", &mut self.sheen),
            ("transmission", &mut self.transmission),
        ]
    }
}

/// `all`, `none` or terms comma-separated.
impl std::str::FromStr for PbrTerms {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s.trim() {
            "all" | "" => return Ok(PbrTerms::default()),
            "none" => return Ok(PbrTerms::NONE),
            _ => {}
        }
        let mut t = PbrTerms::NONE;
        for name in s.split(',').map(str::trim) {
            let mut named = t.named();
            let Some((_, on)) = named.iter_mut().find(|(n, _)| *n == name) else {
                // The words from the table itself, so a new term is listed with the rest.
                let words: Vec<&str> = named.iter().map(|(n, _)| *n).collect();
                return Err(format!(
                    "unknown term {name:?} ({}, all, none)",
                    words.join(", ")
                ));
            };
            **on = true;
        }
        Ok(t)
    }
}

impl std::fmt::Display for PbrTerms {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        if *self == PbrTerms::default() {
            return f.write_str("all");
        }
        if *self == PbrTerms::NONE {
            return f.write_str("none");
        }
        let mut t = *self;
        let on: Vec<&str> = t
            .named()
            .into_iter()
            .filter(|(_, b)| **b)
            .map(|(n, _)| n)
            .collect();
        f.write_str(&on.join(","))
    }
}

crate::word_value!(
    PbrTerms,
    "all, none or terms: direct-diffuse,ibl-specular,..."
);

/// What the formula and the frame's passes take besides lights and materials. Its `Default`
/// is the options' defaults converted (in `options::convert`, where the defaults live).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightingParams {
    pub ambient: DVec3,
    /// Half-Lambert: (1 + N·L)/2 instead of max(N·L, 0).
    pub wrap: bool,
    pub terms: Terms,
    /// The PBR tier's knobs (unused by the legacy formula).
    pub pbr: crate::pbr::PbrParams,
    pub pbr_terms: PbrTerms,
    /// The PBR tier's output step (the legacy tier's output is the fixed-function clamp).
    pub output: crate::pbr::OutputParams,
    /// How translucent surfaces are drawn (both tiers).
    pub translucency: crate::frame::Translucency,
    /// A per-pixel teaching view instead of the lit picture (`--show normals`, ...).
    pub attribute_view: crate::frame::AttributeView,
    /// Bloom, FXAA, transparent background.
    pub post: crate::frame::Post,
    /// A headlight of this colour: a directional light travelling along the view, resolved
    /// from the camera every frame (see `frame::resolve`).
    pub headlight: Option<glam::Vec3>,
    /// How many of the lights (the first ones) cast shadows.
    pub shadow_casters: u8,
    /// Diameter of points in pixels of a picture `point_size.1` pixels high (the frame
    /// scales it with its viewport: SSAA, a window resized).
    pub point_size: (f32, u32),
    /// Lines over the model (`--edges`, `--wireframe`).
    pub edges: crate::frame::Edges,
    /// The ground grid and the axes triad (`--grid`, `--axes`).
    pub guides: crate::frame::Guides,
}

/// The default point size's bounds in pixels: small enough that a dense scan stays a
/// surface of dots, large enough that a sparse one (or glTF POINTS) shows round dots.
pub const MIN_POINT_PX: f32 = 2.0;
pub const MAX_POINT_PX: f32 = 8.0;

/// The specular factor; see the module comment for Ns <= 0.
pub fn specular_factor(r_dot_v: f64, ns: f64) -> f64 {
    if ns <= 0.0 {
        1.0
    } else if r_dot_v <= 0.0 {
        0.0
    } else {
        r_dot_v.powf(ns)
    }
}

/// Unit vector from `p` towards the light.
pub fn to_light(light: &Light, p: DVec3) -> DVec3 {
    match light.kind {
        LightKind::Point(q) => (q.as_dvec3() - p).normalize_or_zero(),
        LightKind::Directional(d) => -d.as_dvec3().normalize(),
    }
}

/// What a material's textures give at one point (white where it has none).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Tex {
    /// Multiplies Ka and Kd (the diffuse map, times vertex colours).
    pub diffuse: DVec3,
    /// Multiplies Ke (the emissive map).
    pub emissive: DVec3,
}

impl Tex {
    pub const WHITE: Tex = Tex {
        diffuse: DVec3::ONE,
        emissive: DVec3::ONE,
    };

    pub fn diffuse(c: DVec3) -> Tex {
        Tex {
            diffuse: c,
            ..Tex::WHITE
        }
    }
}

/// Shades one point. `n` is the unit normal already flipped towards the viewer's side for
/// back faces; `tex` multiplies Ka and Kd, and Ke; `visibility[i]` is light i's shadow
/// factor (1 = lit).
#[allow(clippy::too_many_arguments)] // the formula's inputs, kept flat to mirror the GLSL
pub fn shade(
    m: &Material,
    tex: Tex,
    p: DVec3,
    n: DVec3,
    eye: DVec3,
    lights: &[Light],
    visibility: &[f64],
    params: &LightingParams,
) -> DVec3 {
    let ph = m.phong_terms();
    let ka = DVec3::from(ph.ambient.map(f64::from)) * tex.diffuse;
    let kd = DVec3::from(ph.diffuse.map(f64::from)) * tex.diffuse;
    let ks = DVec3::from(ph.specular.map(f64::from));
    let mut c = DVec3::from(m.legacy_emissive().map(f64::from)) * tex.emissive;
    if params.terms.ambient {
        c += ka * params.ambient;
    }
    let v = (eye - p).normalize_or_zero();
    for (i, light) in lights.iter().enumerate() {
        let l = to_light(light, p);
        let lc = light.color.as_dvec3();
        let n_dot_l = n.dot(l);
        let vis = visibility.get(i).copied().unwrap_or(1.0);
        let diffuse = if params.wrap {
            (1.0 + n_dot_l) * 0.5
        } else {
            n_dot_l.max(0.0)
        };
        let mut lit = DVec3::ZERO;
        if params.terms.diffuse {
            lit += kd * lc * diffuse;
        }
        if params.terms.specular && n_dot_l > 0.0 {
            let r = reflect(-l, n);
            lit += ks * lc * specular_factor(r.dot(v), f64::from(ph.shininess));
        }
        c += vis * lit;
    }
    c.clamp(DVec3::ZERO, DVec3::ONE)
}

pub fn reflect(i: DVec3, n: DVec3) -> DVec3 {
    i - 2.0 * n.dot(i) * n
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    fn white_light_above() -> Light {
        Light {
            kind: LightKind::Directional(Vec3::NEG_Y),
            color: Vec3::ONE,
        }
    }

    #[test]
    fn default_material_facing_light() {
        let m = Material::default();
        let c = shade(
            &m,
            Tex::WHITE,
            DVec3::ZERO,
            DVec3::Y,
            DVec3::Y * 5.0,
            &[white_light_above()],
            &[],
            &LightingParams::default(),
        );
        // 0.2 * 0.2 ambient + 0.8 diffuse.
        assert!((c - DVec3::splat(0.84)).length() < 1e-6);
    }

    #[test]
    fn ns_zero_and_grazing_are_finite() {
        assert_eq!(specular_factor(0.0, 0.0), 1.0);
        assert_eq!(specular_factor(-0.5, 10.0), 0.0);
        assert_eq!(specular_factor(0.5, 10_000.0), 0.0);
        assert!((specular_factor(0.5, 2.0) - 0.25).abs() < 1e-15);
    }

    #[test]
    fn shadowed_light_keeps_ambient_only() {
        let m = Material::default();
        let c = shade(
            &m,
            Tex::WHITE,
            DVec3::ZERO,
            DVec3::Y,
            DVec3::Y,
            &[white_light_above()],
            &[0.0],
            &LightingParams::default(),
        );
        assert!((c - DVec3::splat(0.04)).length() < 1e-6);
    }

    #[test]
    fn wrap_lights_the_back_half() {
        let m = Material::default();
        let p = LightingParams {
            wrap: true,
            ..Default::default()
        };
        let c = shade(
            &m,
            Tex::WHITE,
            DVec3::ZERO,
            DVec3::X,
            DVec3::X,
            &[white_light_above()],
            &[],
            &p,
        );
        assert!((c.x - (0.04 + 0.4)).abs() < 1e-6);
    }
}
