//! A glTF material in the scene's material model.
use super::{Material, Texture};
use std::sync::Arc;

pub fn material(m: &gltf::Material, base_color: Option<Arc<Texture>>) -> Material {
    let pbr = m.pbr_metallic_roughness();
    let [r, g, b, a] = pbr.base_color_factor();
    let spec = pbr
        .base_color_texture()
        .map(|t| format!("baseColorTexture image {}", t.texture().source().index()));
    Material {
        name: m.name().unwrap_or("gltf").to_string(),
        ambient: [r, g, b],
        diffuse: [r, g, b],
        specular: [0.0; 3],
        emissive: m.emissive_factor(),
        shininess: 0.0,
        opacity: if m.alpha_mode() == gltf::material::AlphaMode::Blend {
            a
        } else {
            1.0
        },
        illum: None,
        diffuse_map: base_color,
        diffuse_map_spec: spec,
        // The PBR tier reads these as it reads an MTL's Pm and Pr.
        pbr_inputs: super::pbr_material::PbrInputs {
            metallic: Some(pbr.metallic_factor()),
            roughness: Some(pbr.roughness_factor()),
            ..Default::default()
        },
    }
}
