//! The MTL → material mapping as the loader makes it today, statement by statement.
use super::*;
use crate::loaders::obj::mtl_mapping::roughness_from_ns;
use crate::model::material::AlphaMode;
use std::path::PathBuf;

/// A folder with a small normal map, a grey (height) map and a colour image.
fn folder() -> PathBuf {
    let dir = std::env::temp_dir().join(format!("glview-mtl-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for (name, px) in [
        ("n.png", [128, 128, 255, 255]),
        ("grey.png", [128, 128, 128, 255]),
        ("c.png", [200, 50, 25, 255]),
    ] {
        image::RgbaImage::from_pixel(2, 2, image::Rgba(px))
            .save(dir.join(name))
            .unwrap();
    }
    dir
}

/// The one material of `body`, read and mapped, with the warnings.
fn load(dir: &Path, body: &str) -> (Material, Vec<Warning>) {
    let text = format!("newmtl m\n{body}\n");
    let (mats, _) = tobj::load_mtl_buf(&mut text.as_bytes()).unwrap();
    let files = Files {
        dir,
        mtl_file: &dir.join("t.mtl"),
        opts: TextureOptions::default(),
    };
    let mut warnings = Vec::new();
    let m = read(mats.into_iter().next().unwrap(), &files, &mut warnings).map();
    (m, warnings)
}

type Check = fn(&Material) -> bool;

fn ph(m: &Material) -> PhongTerms {
    m.phong.unwrap()
}

#[test]
fn statements_map_as_documented() {
    let dir = folder();
    let cases: &[(&str, Check)] = &[
        ("", |m| {
            *m == Material {
                name: "m".into(),
                ..Material::default()
            }
        }),
        ("Kd 0.5 0.25 1", |m| {
            ph(m).diffuse == [0.5, 0.25, 1.0] && m.base_color == [0.5, 0.25, 1.0]
        }),
        ("Ka 0.1 0.2 0.3", |m| ph(m).ambient == [0.1, 0.2, 0.3]),
        // Dark diffuse, bright specular: a classic metal, base colour Ks.
        ("Kd 0.1 0.1 0.1\nKs 0.9 0.8 0.7", |m| {
            m.metallic == 1.0 && m.base_color == [0.9, 0.8, 0.7] && ph(m).specular[0] == 0.9
        }),
        ("Kd 0.8 0.8 0.8\nKs 0.6 0.6 0.6", |m| m.metallic == 0.0),
        ("Ns 64", |m| {
            ph(m).shininess == 64.0 && m.roughness == roughness_from_ns(64.0)
        }),
        ("Ns 0", |m| m.roughness == 1.0),
        ("d 0.5", |m| m.opacity == Some(0.5) && m.is_translucent()),
        ("d 1", |m| m.opacity.is_none()),
        ("Tr 0.25", |m| m.opacity == Some(0.75)),
        ("d 1.5", |m| m.opacity.is_none()),
        // Glass is a dielectric whatever its Ks: translucent, or illum 4, 6, 7.
        ("Kd 0.1 0.1 0.1\nKs 0.9 0.9 0.9\nd 0.5", |m| {
            m.metallic == 0.0
        }),
        ("Kd 0.1 0.1 0.1\nKs 0.9 0.9 0.9\nillum 4", |m| {
            m.metallic == 0.0 && ph(m).illum == Some(4)
        }),
        ("illum 2", |m| ph(m).illum == Some(2)),
        ("Ke 1 0.5 0", |m| m.emissive == [1.0, 0.5, 0.0]),
        // The PBR keys win over the classic mapping; Kd is the base colour.
        ("Kd 0.1 0.1 0.1\nKs 0.9 0.9 0.9\nPr 0.3", |m| {
            (m.roughness, m.metallic, m.base_color) == (0.3, 0.0, [0.1; 3]) && !ph(m).mapped
        }),
        ("Pm 1", |m| (m.metallic, m.roughness) == (1.0, 0.5)),
        ("Pm 2\nPr -1", |m| (m.metallic, m.roughness) == (1.0, 0.0)),
        ("map_Kd c.png", |m| {
            let t = m.base_color_texture.as_ref().unwrap();
            t.color_space == ColorSpace::Srgb
                && t.image.rgba[..4] == [200, 50, 25, 255]
                && m.check.base_color.as_deref() == Some("c.png")
        }),
        ("map_Kd -s 2 2 2 c.png", |m| m.base_color_texture.is_some()),
        ("map_Kd missing.png", |m| {
            m.base_color_texture.is_none() && m.check.base_color.as_deref() == Some("missing.png")
        }),
        ("map_Bump n.png", |m| {
            m.normal_texture.as_ref().unwrap().color_space == ColorSpace::Linear
        }),
        ("map_Bump grey.png", |m| {
            m.normal_texture.is_none() && m.check.maps[0].2 == "height map: not used"
        }),
        ("norm n.png", |m| m.normal_texture.is_some()),
        ("map_Pm grey.png", |m| m.metallic_texture.is_some()),
        ("map_Pr grey.png", |m| m.roughness_texture.is_some()),
        ("map_ao grey.png", |m| m.occlusion_texture.is_some()),
        ("map_Ke c.png", |m| {
            m.emissive_texture.as_ref().unwrap().color_space == ColorSpace::Srgb
        }),
        // A failed map is noted first, the loaded ones after, in statement order.
        ("map_Pr grey.png\nmap_Pm nowhere.png", |m| {
            let keys: Vec<_> = m
                .check
                .maps
                .iter()
                .map(|(k, _, w)| (k.as_str(), w.as_str()))
                .collect();
            m.metallic_texture.is_none()
                && keys[0].0 == "map_Pm"
                && keys[0].1.starts_with("not loaded")
                && keys[1] == ("map_Pr", "roughness (red channel)")
        }),
    ];
    for (body, check) in cases {
        let (m, _) = load(&dir, body);
        assert!(check(&m), "{body:?} gave {m:#?}");
        // MTL materials: opaque alpha mode, double-sided, lit, with Phong terms.
        assert_eq!(
            (m.alpha_mode, m.double_sided, m.unlit, m.packs_orm()),
            (AlphaMode::Opaque, true, false, true),
            "{body:?}"
        );
    }
    let (_, warnings) = load(&dir, "map_Kd missing.png");
    assert!(warnings[0].message.contains("map_Kd \"missing.png\""));
    std::fs::remove_dir_all(&dir).unwrap();
}
