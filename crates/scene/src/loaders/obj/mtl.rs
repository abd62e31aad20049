//! MTL → [`Material`]: every statement of a material read in one pass over tobj's material,
//! which [`read`] takes by value, so nothing can read it a second time. Colours and `Ns` go
//! to the Phong terms, `d`/`Tr` to the opacity, `map_Kd` to the base colour slot, and the
//! PBR extension (`Pr`, `Pm`, `map_Pr`, `map_Pm`, `map_ao`, `map_Ke`, `norm`, and
//! `map_Bump`/`bump` where the image is a normal map) to the PBR values and slots. What comes
//! back is a [`Read`]: the exporters' quirks ([`crate::loaders::obj::quirks`]) are handled on it, then
//! [`Read::map`] runs the MTL → PBR mapping ([`crate::loaders::obj::mtl_mapping`]) exactly once.
use crate::model::material::{
    translucency, AlphaMode, Material, PhongTerms, Texture, TextureOptions,
};
use crate::model::texture_slot::{ColorSpace, TextureSlot};
use crate::model::Warning;
use crate::textures::path::load_texture;
use std::path::Path;
use std::sync::Arc;

#[cfg(test)]
thread_local! {
    /// How many materials [`read`] read on this thread (the tests count reads per load).
    pub(crate) static READS: std::cell::Cell<usize> = const { std::cell::Cell::new(0) };
}

/// A material read from an MTL whose PBR values are not mapped yet: `Pm` and `Pr` as the
/// file gives them, kept until [`Read::map`] consumes them.
#[derive(Debug)]
pub(crate) struct Read {
    material: Material,
    pm: Option<f32>,
    pr: Option<f32>,
}

impl Read {
    /// The material before the mapping (the quirks change its opacity and `Ks`).
    pub(crate) fn material_mut(&mut self) -> &mut Material {
        &mut self.material
    }

    /// The mapping into the PBR values, once: it consumes the read material.
    pub(crate) fn map(self) -> Material {
        let Read {
            mut material,
            pm,
            pr,
        } = self;
        crate::loaders::obj::mtl_mapping::map(&mut material, pm, pr);
        material
    }
}

fn to_rgb(v: Option<[f64; 3]>, default: [f32; 3]) -> [f32; 3] {
    v.map(|c| c.map(|x| if x.is_finite() { x as f32 } else { 0.0 }))
        .unwrap_or(default)
}

/// Where a material's textures are and where warnings about them go.
pub(crate) struct Files<'a> {
    /// Texture paths are relative to this folder.
    pub(crate) dir: &'a Path,
    /// The material library warnings name.
    pub(crate) mtl_file: &'a Path,
    pub(crate) opts: TextureOptions,
}

/// Reads one tobj material: values, then maps, relative to `files.dir`.
pub(crate) fn read(m: tobj::Material, files: &Files, warnings: &mut Vec<Warning>) -> Read {
    #[cfg(test)]
    READS.with(|r| r.set(r.get() + 1));
    let mut out = values(&m);
    let (pm, pr) = (number(&m, "Pm"), number(&m, "Pr"));
    read_maps(&m, files, &mut out, warnings);
    Read {
        material: out,
        pm,
        pr,
    }
}

/// A statement's value by key. Keys match in any case, but tobj keeps them in a HashMap
/// whose order changes from one load to the next: with two spellings in one material
/// (`map_Pm` and `map_pm`), the first match made the same file load differently each time
/// (found by the fuzz target's differential check). The exact spelling wins, then the
/// smallest of the others.
fn param(m: &tobj::Material, k: &str) -> Option<String> {
    m.unknown_param
        .get(k)
        .or_else(|| {
            m.unknown_param
                .iter()
                .filter(|(key, _)| key.eq_ignore_ascii_case(k))
                .min_by(|a, b| a.0.cmp(b.0))
                .map(|(_, v)| v)
        })
        .map(|v| v.trim().to_string())
}

/// A statement's first number, if finite.
fn number(m: &tobj::Material, k: &str) -> Option<f32> {
    param(m, k)
        .and_then(|v| v.split_whitespace().next()?.parse::<f32>().ok())
        .filter(|x| x.is_finite())
}

/// The material's values (colours, shininess, illum, opacity, emissive), no maps.
fn values(m: &tobj::Material) -> Material {
    // `d`, else `1 - Tr` (that exact spelling), clamped to [0, 1].
    let opacity = m
        .dissolve
        .map(|x| x as f32)
        .or_else(|| {
            m.unknown_param
                .get("Tr")
                .and_then(|t| t.trim().parse::<f32>().ok())
                .map(|t| 1.0 - t)
        })
        .filter(|x| x.is_finite())
        .unwrap_or(1.0)
        .clamp(0.0, 1.0);
    let d = PhongTerms::default();
    let phong = PhongTerms {
        ambient: to_rgb(m.ambient, d.ambient),
        diffuse: to_rgb(m.diffuse, d.diffuse),
        specular: to_rgb(m.specular, d.specular),
        shininess: m
            .shininess
            .map(|x| x as f32)
            .filter(|x| x.is_finite())
            .unwrap_or(d.shininess),
        illum: m.illumination_model,
        mapped: true,
    };
    Material {
        name: m.name.clone(),
        emissive: to_rgb(m.emissive, [0.0; 3]),
        opacity: translucency(opacity, AlphaMode::Opaque),
        phong: Some(phong),
        ..Material::gltf_default()
    }
}

/// The material's maps: `map_Kd` as the base colour (its colours stay where it fails), and
/// metallic, roughness, occlusion, emissive and normal maps (`norm`, else a `map_Bump` that
/// looks like one). A failure is warned about and noted as it happens; the loaded maps are
/// noted for `--check` after all of them, in this order.
fn read_maps(m: &tobj::Material, files: &Files, out: &mut Material, warnings: &mut Vec<Warning>) {
    let param = |k: &str| param(m, k);
    let load = |spec: &str| load_texture(spec, files.dir, files.opts).map(Arc::new);
    let warn = |warnings: &mut Vec<Warning>, message: String| {
        warnings.push(Warning {
            file: files.mtl_file.to_path_buf(),
            line: None,
            message,
        })
    };
    let slot = |t: Arc<Texture>, cs| Some(TextureSlot::plain(t, cs));
    out.check.base_color = m.diffuse_texture.clone();
    if let Some(spec) = &m.diffuse_texture {
        match load(spec) {
            Ok(t) => out.base_color_texture = slot(t, ColorSpace::Srgb),
            Err(msg) => warn(
                warnings,
                format!(
                    "material {}: map_Kd {spec:?}: {msg}; using its colours",
                    m.name
                ),
            ),
        }
    }
    let mut loaded = Vec::new();
    let mut map = |key: &str, spec: Option<String>, warnings: &mut Vec<Warning>| {
        let spec = spec?;
        match load(&spec) {
            Ok(t) => Some((spec, t)),
            Err(msg) => {
                warn(
                    warnings,
                    format!("material {}: {key} {spec:?}: {msg}; ignored", m.name),
                );
                let note = format!("not loaded: {msg}");
                out.check.maps.push((key.into(), spec, note));
                None
            }
        }
    };
    let lin = ColorSpace::Linear;
    let metallic = map("map_Pm", param("map_Pm"), warnings).map(|(s, t)| {
        loaded.push(("map_Pm", s, "metallic (red channel)"));
        t
    });
    let roughness = map("map_Pr", param("map_Pr"), warnings).map(|(s, t)| {
        loaded.push(("map_Pr", s, "roughness (red channel)"));
        t
    });
    let ao = map(
        "map_ao",
        param("map_ao").or_else(|| param("map_AO")),
        warnings,
    )
    .map(|(s, t)| {
        loaded.push(("map_ao", s, "ambient occlusion (indirect light)"));
        t
    });
    let emissive = map("map_Ke", param("map_Ke"), warnings).map(|(s, t)| {
        loaded.push(("map_Ke", s, "emissive (sRGB)"));
        t
    });
    let normal = match map("norm", param("norm"), warnings) {
        Some((s, t)) => {
            loaded.push(("norm", s, "normal map (tangent space)"));
            Some(t)
        }
        None => match map("map_Bump", m.normal_texture.clone(), warnings) {
            Some((s, t)) if looks_like_normal_map(&t) => {
                loaded.push(("map_Bump", s, "normal map (tangent space)"));
                Some(t)
            }
            Some((s, _)) => {
                loaded.push(("map_Bump", s, "height map: not used"));
                None
            }
            None => None,
        },
    };
    out.metallic_texture = metallic.and_then(|t| slot(t, lin));
    out.roughness_texture = roughness.and_then(|t| slot(t, lin));
    out.occlusion_texture = ao.and_then(|t| slot(t, lin));
    out.emissive_texture = emissive.and_then(|t| slot(t, ColorSpace::Srgb));
    out.normal_texture = normal.and_then(|t| slot(t, lin));
    out.check.maps.extend(
        loaded
            .into_iter()
            .map(|(k, s, w)| (k.to_string(), s, w.to_string())),
    );
}

/// A normal map is mostly "up" in tangent space: blue high, red and green near one half. A
/// height (bump) map is grey. Decides which a `map_Bump` image is.
pub(crate) fn looks_like_normal_map(t: &Texture) -> bool {
    let n = (t.rgba.len() / 4).max(1) as f64;
    let mut sum = [0f64; 3];
    for p in t.rgba.chunks_exact(4) {
        for c in 0..3 {
            sum[c] += f64::from(p[c]) / 255.0;
        }
    }
    let [r, g, b] = sum.map(|s| s / n);
    b > 0.65 && (r - 0.5).abs() < 0.2 && (g - 0.5).abs() < 0.2
}

#[cfg(test)]
#[path = "mtl_tests.rs"]
mod tests;
