//! The PBR tier's material inputs: the MTL PBR extension (`Pr`, `Pm`, `map_Pr`, `map_Pm`,
//! `map_Ke`, `norm`, `map_ao`, and `map_Bump`/`bump` where the image is a normal map), and the
//! documented mapping from a classic MTL (Kd, Ks, Ns) where those keys are absent.
use super::material::{load_texture, Material, Texture, TextureOptions};
use super::Warning;
use std::path::Path;
use std::sync::Arc;

/// PBR values and maps read from the MTL. `None` where the file does not give them; the
/// mapping in [`Material::pbr`] fills the gaps.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct PbrInputs {
    /// `Pm`
    pub metallic: Option<f32>,
    /// `Pr`
    pub roughness: Option<f32>,
    /// Tangent-space normal map (`norm`, or `map_Bump`/`bump` holding a normal map), linear.
    #[serde(skip)]
    pub normal_map: Option<Arc<Texture>>,
    /// `map_Pm` (red channel), linear.
    #[serde(skip)]
    pub metallic_map: Option<Arc<Texture>>,
    /// `map_Pr` (red channel), linear.
    #[serde(skip)]
    pub roughness_map: Option<Arc<Texture>>,
    /// glTF's metallicRoughnessTexture as the file has it (blue metal, green roughness),
    /// linear; sampled directly with its own sampler and UV set.
    #[serde(skip)]
    pub metallic_roughness_map: Option<Arc<Texture>>,
    /// `map_ao` / `map_AO` (red channel), linear; multiplies indirect light only.
    #[serde(skip)]
    pub ao_map: Option<Arc<Texture>>,
    /// `map_Ke`, sRGB.
    #[serde(skip)]
    pub emissive_map: Option<Arc<Texture>>,
    /// Every map statement of the material as (key, file as written, what happened), for
    /// `--check`.
    pub maps: Vec<(String, String, String)>,
    /// Samplers, UV sets, alpha mode, sidedness: the one material model of every format.
    #[serde(default)]
    pub model: super::material_model::Model,
}

impl PbrInputs {
    pub fn has_maps(&self) -> bool {
        self.normal_map.is_some()
            || self.metallic_map.is_some()
            || self.roughness_map.is_some()
            || self.metallic_roughness_map.is_some()
            || self.ao_map.is_some()
            || self.emissive_map.is_some()
    }
}

/// The values the PBR shader gets for one material (before `--base-color`, `--metallic`,
/// `--roughness` overrides).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PbrValues {
    pub base_color: [f32; 3],
    pub metallic: f32,
    pub roughness: f32,
    pub emissive: [f32; 3],
    /// Where the values came from: `mtl-pbr` (Pr/Pm given) or `classic` (mapped).
    pub source: &'static str,
}

fn luminance(c: [f32; 3]) -> f32 {
    0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]
}

/// Roughness from a Phong exponent: the Blinn-Phong lobe x^Ns matches a GGX lobe of
/// α² = 2 / (Ns + 2) (Walter et al. 2007), and roughness r = √α. Ns ≤ 0 (matte) gives 1.
pub fn roughness_from_ns(ns: f32) -> f32 {
    if ns.is_finite() && ns > 0.0 {
        (2.0 / (ns + 2.0)).sqrt().sqrt().clamp(0.0, 1.0)
    } else {
        1.0
    }
}

impl Material {
    /// The PBR values of this material. With `Pr`/`Pm` in the MTL, Kd is the base colour.
    /// A classic MTL is mapped: roughness from Ns ([`roughness_from_ns`]); metallic 1 where
    /// the specular colour is brighter than 0.5 and than the diffuse colour (a classic file's
    /// way of writing metal: dark diffuse, bright specular) and the material is not glass
    /// (translucent, or illum 4, 6, 7), with Ks as the base colour; else a dielectric
    /// (metallic 0, base colour Kd).
    pub fn pbr(&self) -> PbrValues {
        let p = &self.pbr_inputs;
        if p.metallic.is_some() || p.roughness.is_some() {
            return PbrValues {
                base_color: self.diffuse,
                metallic: p.metallic.unwrap_or(0.0).clamp(0.0, 1.0),
                roughness: p.roughness.unwrap_or(0.5).clamp(0.0, 1.0),
                emissive: self.emissive,
                source: "mtl-pbr",
            };
        }
        let (ks, kd) = (luminance(self.specular), luminance(self.diffuse));
        // Glass (translucent, or illum 4, 6, 7: refraction models) is a dielectric whatever
        // its Ks says.
        let glass = self.is_translucent() || matches!(self.illum, Some(4 | 6 | 7));
        let metal = ks > 0.5 && ks > kd && !glass;
        PbrValues {
            base_color: if metal { self.specular } else { self.diffuse },
            metallic: if metal { 1.0 } else { 0.0 },
            roughness: roughness_from_ns(self.shininess),
            emissive: self.emissive,
            source: "classic",
        }
    }
}

/// A normal map is mostly "up" in tangent space: blue high, red and green near one half. A
/// height (bump) map is grey. Decides which a `map_Bump` image is.
pub fn looks_like_normal_map(t: &Texture) -> bool {
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

/// Reads the PBR keys of one tobj material (values and maps, relative to `dir`).
pub fn from_tobj(
    m: &tobj::Material,
    dir: &Path,
    mtl_file: &Path,
    opts: TextureOptions,
    warnings: &mut Vec<Warning>,
) -> PbrInputs {
    let mut out = PbrInputs::default();
    // Keys match in any case, but tobj keeps them in a HashMap whose order changes from one
    // load to the next: with two spellings in one material (`map_Pm` and `map_pm`), the first
    // match made the same file load differently each time (found by the fuzz target's
    // differential check). The exact spelling wins, then the smallest of the others.
    let param = |k: &str| {
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
    };
    let number = |k: &str| {
        param(k)
            .and_then(|v| v.split_whitespace().next()?.parse::<f32>().ok())
            .filter(|x| x.is_finite())
    };
    out.metallic = number("Pm");
    out.roughness = number("Pr");
    let mut load = |key: &str, spec: Option<String>, warnings: &mut Vec<Warning>| {
        let spec = spec?;
        match load_texture(&spec, dir, opts) {
            Ok(t) => Some((spec, Arc::new(t))),
            Err(msg) => {
                warnings.push(Warning {
                    file: mtl_file.to_path_buf(),
                    line: None,
                    message: format!("material {}: {key} {spec:?}: {msg}; ignored", m.name),
                });
                out.maps
                    .push((key.into(), spec, format!("not loaded: {msg}")));
                None
            }
        }
    };
    let mut maps = Vec::new();
    if let Some((s, t)) = load("map_Pm", param("map_Pm"), warnings) {
        maps.push(("map_Pm", s, "metallic (red channel)".to_string()));
        out.metallic_map = Some(t);
    }
    if let Some((s, t)) = load("map_Pr", param("map_Pr"), warnings) {
        maps.push(("map_Pr", s, "roughness (red channel)".to_string()));
        out.roughness_map = Some(t);
    }
    let ao = param("map_ao").or_else(|| param("map_AO"));
    if let Some((s, t)) = load("map_ao", ao, warnings) {
        maps.push((
            "map_ao",
            s,
            "ambient occlusion (indirect light)".to_string(),
        ));
        out.ao_map = Some(t);
    }
    if let Some((s, t)) = load("map_Ke", param("map_Ke"), warnings) {
        maps.push(("map_Ke", s, "emissive (sRGB)".to_string()));
        out.emissive_map = Some(t);
    }
    if let Some((s, t)) = load("norm", param("norm"), warnings) {
        maps.push(("norm", s, "normal map (tangent space)".to_string()));
        out.normal_map = Some(t);
    } else if let Some((s, t)) = load("map_Bump", m.normal_texture.clone(), warnings) {
        if looks_like_normal_map(&t) {
            maps.push(("map_Bump", s, "normal map (tangent space)".to_string()));
            out.normal_map = Some(t);
        } else {
            maps.push(("map_Bump", s, "height map: not used".to_string()));
        }
    }
    out.maps
        .extend(maps.into_iter().map(|(k, s, w)| (k.to_string(), s, w)));
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn classic_mapping() {
        assert_eq!(roughness_from_ns(0.0), 1.0);
        assert!((roughness_from_ns(2.0) - 0.5f32.sqrt().sqrt()).abs() < 1e-6);
        // Ns 1000: α² = 2/1002, r ≈ 0.211
        assert!((roughness_from_ns(1000.0) - 0.2114).abs() < 1e-3);
        let metal = Material {
            diffuse: [0.1; 3],
            specular: [0.9, 0.8, 0.5],
            shininess: 64.0,
            ..Default::default()
        };
        let v = metal.pbr();
        assert_eq!((v.metallic, v.base_color), (1.0, [0.9, 0.8, 0.5]));
        let plastic = Material {
            diffuse: [0.8, 0.1, 0.1],
            specular: [0.5; 3],
            shininess: 32.0,
            ..Default::default()
        };
        assert_eq!(plastic.pbr().metallic, 0.0);
        assert_eq!(plastic.pbr().base_color, [0.8, 0.1, 0.1]);
    }

    #[test]
    fn pbr_keys_win() {
        let mut m = Material::default();
        m.pbr_inputs.roughness = Some(0.3);
        m.pbr_inputs.metallic = Some(1.0);
        let v = m.pbr();
        assert_eq!((v.roughness, v.metallic, v.source), (0.3, 1.0, "mtl-pbr"));
    }
}
