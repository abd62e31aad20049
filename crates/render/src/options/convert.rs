//! The frame's settings that are option groups converted, each conversion written once:
//! [`crate::view::settings::frame_settings`] calls them, and the frame types' `Default`s are the
//! same conversions of the declared defaults, so a default value is written only in
//! `declare_options!`. What no option sets stays a named constant beside its type (the
//! shadow's slope bias and normal offset, the bloom knee, the lookup table's samples) or is
//! the type's own (the library's sorted translucency: the command line's is `nearest`).
use super::{Diffuse, Light, Options, Pbr, Post, Shadow};
use crate::frame::{Bloom, ShadowSettings, BLOOM_KNEE, SHADOW_NORMAL_OFFSET, SHADOW_SLOPE_BIAS};
use crate::frame::{LightingParams, MIN_POINT_PX};
use crate::pbr::precompute::{IblSettings, LUT_SAMPLES};
use crate::pbr::{OutputParams, PbrParams};
use glam::{DVec3, Vec3};

impl From<&Shadow> for ShadowSettings {
    fn from(o: &Shadow) -> Self {
        ShadowSettings {
            enabled: o.enabled,
            size: o.size,
            pcf: o.pcf,
            bias: o.bias,
            slope_bias: SHADOW_SLOPE_BIAS,
            normal_offset: SHADOW_NORMAL_OFFSET,
        }
    }
}

impl Default for ShadowSettings {
    /// `--shadow-size`, `--pcf` and `--shadow-bias` at their declared defaults.
    fn default() -> Self {
        (&Shadow::default()).into()
    }
}

impl From<&Post> for Bloom {
    fn from(o: &Post) -> Self {
        Bloom {
            strength: if o.no_bloom { 0.0 } else { o.bloom.max(0.0) },
            threshold: o.bloom_threshold,
            knee: BLOOM_KNEE,
            sigma: o.bloom_sigma.clamp(0.5, 64.0),
            levels: o.bloom_levels,
        }
    }
}

impl Default for Bloom {
    /// The `--bloom*` options at their declared defaults (strength 0: off).
    fn default() -> Self {
        (&Post::default()).into()
    }
}

impl From<&Pbr> for OutputParams {
    fn from(o: &Pbr) -> Self {
        OutputParams {
            exposure_ev: o.exposure,
            tonemap: o.tonemap,
        }
    }
}

impl Default for OutputParams {
    /// `--exposure` and `--tonemap` at their declared defaults.
    fn default() -> Self {
        (&Pbr::default()).into()
    }
}

impl From<&Options> for PbrParams {
    fn from(o: &Options) -> Self {
        let p = &o.pbr;
        PbrParams {
            base_color: p.base_color.map(Vec3::from_array),
            metallic: p.metallic,
            roughness: p.roughness,
            dominant_direction: p.dominant_direction,
            multiscatter: p.multiscatter,
            // The environment is the background unless a colour is given.
            skybox: o.render.background.is_none(),
            skybox_blur: p.env_blur,
            ibl_intensity: p.ibl_intensity.max(0.0),
        }
    }
}

impl Default for PbrParams {
    fn default() -> Self {
        (&Options::default()).into()
    }
}

impl From<&Pbr> for IblSettings {
    fn from(o: &Pbr) -> Self {
        IblSettings {
            irradiance_size: o.irradiance_size,
            specular_size: o.ibl_size,
            levels: o.ibl_levels,
            samples: o.ibl_samples,
            lut_size: o.lut_size,
            lut_samples: LUT_SAMPLES,
        }
    }
}

impl Default for IblSettings {
    /// The `--ibl-*`, `--irradiance-size` and `--lut-size` options at their declared defaults.
    fn default() -> Self {
        (&Pbr::default()).into()
    }
}

/// `--ambient` as the lighting formula takes it (f64, from the option's f32).
pub(crate) fn ambient(o: &Light) -> DVec3 {
    Vec3::from_array(o.ambient).as_dvec3()
}

impl Default for LightingParams {
    /// The lighting options at their declared defaults; what no option sets as the frame
    /// types say: every light may cast a shadow, no headlight, sorted translucency.
    fn default() -> Self {
        let o = Options::default();
        LightingParams {
            ambient: ambient(&o.light),
            wrap: o.light.diffuse == Diffuse::Wrap,
            terms: o.render.legacy_terms,
            pbr: (&o).into(),
            pbr_terms: o.render.terms,
            output: (&o.pbr).into(),
            translucency: Default::default(),
            attribute_view: Default::default(),
            post: Default::default(),
            headlight: None,
            shadow_casters: crate::light::MAX_LIGHTS as u8,
            point_size: (MIN_POINT_PX, 0),
            edges: Default::default(),
            guides: Default::default(),
        }
    }
}
