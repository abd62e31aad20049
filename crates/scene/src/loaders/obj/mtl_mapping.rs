//! The documented mapping of an MTL material into the PBR values, run once at load
//! ([`crate::loaders::obj::mtl::Read::map`]; x-ray runs it again, see [`Material::set_opacity`]):
//!
//! - With `Pr` or `Pm`: base colour `Kd`, metallic `Pm` (0 if absent), roughness `Pr` (0.5
//!   if absent), each clamped to [0, 1].
//! - A classic MTL (neither): roughness from `Ns` ([`roughness_from_ns`]); metallic 1 where
//!   the specular colour is brighter than 0.5 and than the diffuse colour (luminance; a
//!   classic file's way of writing metal: dark diffuse, bright specular) and the material is
//!   not glass (translucent, or `illum` 4, 6, 7), with `Ks` as the base colour; else a
//!   dielectric (metallic 0, base colour `Kd`).
//!
//! Emission is `Ke` either way; `--check` prints the outcome ([`crate::report::material`]).
use crate::model::material::Material;

fn luminance(c: [f32; 3]) -> f32 {
    0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]
}

/// Roughness from a Phong exponent: the Blinn-Phong lobe x^Ns matches a GGX lobe of
/// α² = 2 / (Ns + 2) (Walter et al. 2007), and roughness r = √α. Ns ≤ 0 (matte) gives 1.
pub(crate) fn roughness_from_ns(ns: f32) -> f32 {
    if ns.is_finite() && ns > 0.0 {
        (2.0 / (ns + 2.0)).sqrt().sqrt().clamp(0.0, 1.0)
    } else {
        1.0
    }
}

/// Sets `m`'s base colour, metallic and roughness from its Phong terms and the file's `Pm`
/// and `Pr`, as the module says. A material without Phong terms (glTF) is left as it is.
pub(crate) fn map(m: &mut Material, pm: Option<f32>, pr: Option<f32>) {
    let translucent = m.is_translucent();
    let Some(p) = &mut m.phong else {
        return;
    };
    p.mapped = pm.is_none() && pr.is_none();
    if !p.mapped {
        m.base_color = p.diffuse;
        m.metallic = pm.unwrap_or(0.0).clamp(0.0, 1.0);
        m.roughness = pr.unwrap_or(0.5).clamp(0.0, 1.0);
        return;
    }
    let (ks, kd) = (luminance(p.specular), luminance(p.diffuse));
    // Glass (translucent, or illum 4, 6, 7: refraction models) is a dielectric whatever
    // its Ks says.
    let glass = translucent || matches!(p.illum, Some(4 | 6 | 7));
    let metal = ks > 0.5 && ks > kd && !glass;
    m.base_color = if metal { p.specular } else { p.diffuse };
    m.metallic = if metal { 1.0 } else { 0.0 };
    m.roughness = roughness_from_ns(p.shininess);
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::material::PhongTerms;

    #[test]
    fn classic_mapping() {
        assert_eq!(roughness_from_ns(0.0), 1.0);
        assert!((roughness_from_ns(2.0) - 0.5f32.sqrt().sqrt()).abs() < 1e-6);
        // Ns 1000: α² = 2/1002, r ≈ 0.211
        assert!((roughness_from_ns(1000.0) - 0.2114).abs() < 1e-3);
        let metal = Material::with_phong(PhongTerms {
            diffuse: [0.1; 3],
            specular: [0.9, 0.8, 0.5],
            shininess: 64.0,
            ..Default::default()
        });
        assert_eq!((metal.metallic, metal.base_color), (1.0, [0.9, 0.8, 0.5]));
        let plastic = Material::with_phong(PhongTerms {
            diffuse: [0.8, 0.1, 0.1],
            specular: [0.5; 3],
            shininess: 32.0,
            ..Default::default()
        });
        assert_eq!(plastic.metallic, 0.0);
        assert_eq!(plastic.base_color, [0.8, 0.1, 0.1]);
    }

    #[test]
    fn pbr_keys_win() {
        let mut m = Material::default();
        map(&mut m, Some(1.0), Some(0.3));
        assert_eq!((m.roughness, m.metallic), (0.3, 1.0));
        assert!(!m.phong.unwrap().mapped);
    }

    /// x-ray changes the translucency, which the glass rule reads: an x-rayed classic metal is
    /// drawn as the glass a translucent MTL material is, and made opaque again it is metal.
    #[test]
    fn xray_maps_again() {
        let mut m = Material::with_phong(PhongTerms {
            diffuse: [0.45; 3],
            specular: [0.85; 3],
            shininess: 64.0,
            ..Default::default()
        });
        assert_eq!(m.metallic, 1.0);
        m.set_opacity(0.3);
        assert_eq!((m.metallic, m.base_color), (0.0, [0.45; 3]));
        m.set_opacity(1.0);
        assert_eq!((m.metallic, m.base_color), (1.0, [0.85; 3]));
    }
}
