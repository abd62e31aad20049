//! The glTF PBR extensions the `gltf` crate does not expose (KHR_materials_clearcoat,
//! _sheen, _specular, _ior), read from the material's raw extension JSON into
//! [`crate::model::material_khr::Khr`]. Texture infos are resolved like the core slots (sampler,
//! UV set, KHR_texture_transform); a malformed value is the extension's default, as a
//! missing one is, with a warning ([`problems`]).
use crate::loaders::gltf::slots::{floats, num, texture_info};
use crate::model::material_khr::{
    Anisotropy, Clearcoat, Iridescence, Khr, Sheen, Specular, Volume,
};
use crate::model::texture_slot::{ColorSpace, Slot};
use crate::report::material::SlotFacts;
use serde_json::Value;

/// The material extensions read from raw JSON (here and in `gltf_specgloss`).
const EXTENSIONS: [&str; 9] = [
    "KHR_materials_clearcoat",
    "KHR_materials_sheen",
    "KHR_materials_specular",
    "KHR_materials_ior",
    "KHR_materials_transmission",
    "KHR_materials_volume",
    "KHR_materials_pbrSpecularGlossiness",
    "KHR_materials_iridescence",
    "KHR_materials_anisotropy",
];

/// The images the extensions' texture infos of material `m` name (decoded with the core
/// slots' images).
pub(crate) fn used_images(doc: &gltf::Document, m: &gltf::Material) -> Vec<usize> {
    let mut out = Vec::new();
    for ext in EXTENSIONS {
        let Some(Value::Object(e)) = m.extension_value(ext) else {
            continue;
        };
        for (key, info) in e {
            if !key.ends_with("Texture") {
                continue;
            }
            let tex = info
                .get("index")
                .and_then(Value::as_u64)
                .and_then(|i| doc.textures().nth(i as usize));
            if let Some(t) = tex {
                out.push(t.source().index());
            }
        }
    }
    out
}

/// What the reader will not take in material `m`'s extensions, one line each: the reader
/// uses the default for a malformed value as for a missing one, and these lines say so.
/// By the extensions' naming: a `…Texture` is a texture info whose index names a texture,
/// a `…Factor`, `…Ior`, `…Minimum`, `…Maximum`, `…Strength`, `…Rotation`, `ior`,
/// `attenuationColor` and `attenuationDistance` are a finite number or an array of them (their lengths and ranges
/// are the reader's to keep).
pub(crate) fn problems(doc: &gltf::Document, m: &gltf::Material) -> Vec<String> {
    let finite = |v: &Value| v.as_f64().is_some_and(f64::is_finite);
    let textures = doc.textures().count();
    let mut out = Vec::new();
    for ext in EXTENSIONS {
        let Some(Value::Object(e)) = m.extension_value(ext) else {
            continue;
        };
        for (key, v) in e {
            let problem = if key.ends_with("Texture") {
                match v.get("index").and_then(Value::as_u64) {
                    Some(i) if (i as usize) < textures => None,
                    Some(i) => Some(format!("names texture {i}, which does not exist")),
                    None => Some("has no texture index".to_string()),
                }
            } else if [
                "Factor", "Ior", "Minimum", "Maximum", "Strength", "Rotation",
            ]
            .iter()
            .any(|s| key.ends_with(s))
                || ["ior", "attenuationColor", "attenuationDistance"].contains(&key.as_str())
            {
                let ok = finite(v) || v.as_array().is_some_and(|a| a.iter().all(finite));
                (!ok).then(|| format!("is {v}, not a finite number or numbers"))
            } else {
                None
            };
            if let Some(p) = problem {
                let name = m.name().unwrap_or("(unnamed)");
                out.push(format!(
                    "material {} '{name}': {ext}.{key} {p}; the extension's default is used",
                    m.index().map_or(String::from("default"), |i| i.to_string())
                ));
            }
        }
    }
    out
}

/// The extensions of material `m`; `load` turns a slot's facts into its slot (decoding the
/// image and writing the `--check` line).
pub(crate) fn read(
    doc: &gltf::Document,
    m: &gltf::Material,
    load: &mut dyn FnMut(SlotFacts, ColorSpace) -> Option<crate::model::texture_slot::TextureSlot>,
) -> Khr {
    let mut k = Khr::default();
    let mut tex = |ext: &Value, key: &str, slot: Slot, cs: ColorSpace, k: &mut Khr| {
        let f = ext.get(key).and_then(|i| texture_info(doc, slot, i));
        if let Some(f) = f {
            *k.slot_mut(slot) = load(f, cs);
        }
    };
    let (srgb, lin) = (ColorSpace::Srgb, ColorSpace::Linear);
    if let Some(e) = m.extension_value("KHR_materials_clearcoat") {
        let normal_scale = e
            .get("clearcoatNormalTexture")
            .map_or(1.0, |t| num(t, "scale", 1.0));
        k.clearcoat = Some(Clearcoat {
            factor: num(e, "clearcoatFactor", 0.0).clamp(0.0, 1.0),
            roughness: num(e, "clearcoatRoughnessFactor", 0.0).clamp(0.0, 1.0),
            normal_scale,
        });
        tex(e, "clearcoatTexture", Slot::Clearcoat, lin, &mut k);
        tex(
            e,
            "clearcoatRoughnessTexture",
            Slot::ClearcoatRoughness,
            lin,
            &mut k,
        );
        tex(
            e,
            "clearcoatNormalTexture",
            Slot::ClearcoatNormal,
            lin,
            &mut k,
        );
    }
    if let Some(e) = m.extension_value("KHR_materials_sheen") {
        k.sheen = Some(Sheen {
            color: floats(e, "sheenColorFactor", [0.0; 3]).map(|c| c.max(0.0)),
            roughness: num(e, "sheenRoughnessFactor", 0.0).clamp(0.0, 1.0),
        });
        tex(e, "sheenColorTexture", Slot::SheenColor, srgb, &mut k);
        tex(
            e,
            "sheenRoughnessTexture",
            Slot::SheenRoughness,
            lin,
            &mut k,
        );
    }
    if let Some(e) = m.extension_value("KHR_materials_specular") {
        k.specular = Some(Specular {
            factor: num(e, "specularFactor", 1.0).max(0.0),
            color: floats(e, "specularColorFactor", [1.0; 3]).map(|c| c.max(0.0)),
        });
        tex(e, "specularTexture", Slot::Specular, lin, &mut k);
        tex(e, "specularColorTexture", Slot::SpecularColor, srgb, &mut k);
    }
    if let Some(e) = m.extension_value("KHR_materials_transmission") {
        k.transmission = Some(num(e, "transmissionFactor", 0.0).clamp(0.0, 1.0));
        tex(e, "transmissionTexture", Slot::Transmission, lin, &mut k);
    }
    if let Some(e) = m.extension_value("KHR_materials_volume") {
        let d = num(e, "attenuationDistance", f32::INFINITY);
        k.volume = Some(Volume {
            thickness: num(e, "thicknessFactor", 0.0).max(0.0),
            attenuation_color: floats(e, "attenuationColor", [1.0; 3]).map(|c| c.clamp(0.0, 1.0)),
            attenuation_distance: (d > 0.0 && d.is_finite()).then_some(d),
        });
        tex(e, "thicknessTexture", Slot::Thickness, lin, &mut k);
    }
    if let Some(e) = m.extension_value("KHR_materials_iridescence") {
        k.iridescence = Some(iridescence(e));
        tex(e, "iridescenceTexture", Slot::Iridescence, lin, &mut k);
        tex(
            e,
            "iridescenceThicknessTexture",
            Slot::IridescenceThickness,
            lin,
            &mut k,
        );
    }
    if let Some(e) = m.extension_value("KHR_materials_anisotropy") {
        k.anisotropy = Some(Anisotropy {
            strength: num(e, "anisotropyStrength", 0.0).clamp(0.0, 1.0),
            rotation: num(e, "anisotropyRotation", 0.0),
        });
        tex(e, "anisotropyTexture", Slot::Anisotropy, lin, &mut k);
    }
    if let Some(e) = m.extension_value("KHR_materials_ior") {
        // At least 1, or exactly 0 (the specification's F0 = 1, for converted
        // specular-glossiness materials); anything else is the default.
        let ior = num(e, "ior", 1.5);
        k.ior = Some(if ior >= 1.0 || ior == 0.0 { ior } else { 1.5 });
    }
    k
}

/// KHR_materials_iridescence's factors. A film ior below 1 (no physical thin film) and
/// negative thicknesses are read as the defaults, as the specification's ranges say.
fn iridescence(e: &Value) -> Iridescence {
    let d = Iridescence::default();
    let ior = num(e, "iridescenceIor", d.ior);
    let nm = |key, default| Some(num(e, key, default)).filter(|t| *t >= 0.0);
    Iridescence {
        factor: num(e, "iridescenceFactor", d.factor).clamp(0.0, 1.0),
        ior: if ior >= 1.0 { ior } else { d.ior },
        thickness_min: nm("iridescenceThicknessMinimum", d.thickness_min)
            .unwrap_or(d.thickness_min),
        thickness_max: nm("iridescenceThicknessMaximum", d.thickness_max)
            .unwrap_or(d.thickness_max),
    }
}
