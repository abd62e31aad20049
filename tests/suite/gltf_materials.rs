//! The glTF material model (issue 19, loader side): every slot with its sampler, UV set and
//! texture transform, alpha mode, sidedness, unlit and emissive strength read exactly; the
//! metallic-roughness image kept as the file has it (blue metal, green rough); images of
//! one file distinct textures; COLOR_0 in integer encodings; winding kept front-facing under a
//! mirroring node.
use crate::common::*;
use glview::scene::model::material::AlphaMode;
use glview::scene::model::texture_slot::{ColorSpace, Filter, Slot, Wrap};
use glview::scene::{load, LoadOptions};
use std::path::PathBuf;

pub fn b64(data: &[u8]) -> String {
    const A: &[u8] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut s = String::new();
    for c in data.chunks(3) {
        let n = (u32::from(c[0]) << 16)
            | (u32::from(*c.get(1).unwrap_or(&0)) << 8)
            | u32::from(*c.get(2).unwrap_or(&0));
        for k in 0..4 {
            s.push(if k <= c.len() {
                A[(n >> (18 - 6 * k) & 63) as usize] as char
            } else {
                '='
            });
        }
    }
    s
}

/// A 2x1 PNG of two RGBA pixels, as a data: URI.
fn png(a: [u8; 4], b: [u8; 4]) -> String {
    let img = image::RgbaImage::from_raw(2, 1, [a, b].concat()).unwrap();
    let mut out = std::io::Cursor::new(Vec::new());
    img.write_to(&mut out, image::ImageFormat::Png).unwrap();
    format!("data:image/png;base64,{}", b64(&out.into_inner()))
}

/// A triangle with TEXCOORD_0/1 and COLOR_0 (normalized u8 RGBA), `extra` JSON fields merged
/// at the top level (materials, textures, samplers, images, node scale).
fn model(name: &str, scale_x: f32, materials: &str) -> PathBuf {
    let mut bin = Vec::new();
    for x in [0f32, 0., 0., 1., 0., 0., 0., 1., 0.] {
        bin.extend(x.to_le_bytes());
    }
    for x in [0f32, 0., 1., 0., 0., 1.] {
        bin.extend(x.to_le_bytes());
    }
    bin.extend([255u8, 0, 0, 255, 0, 255, 0, 255, 0, 0, 255, 128]);
    let json = format!(
        r#"{{"asset": {{"version": "2.0"}}, "scene": 0, "scenes": [{{"nodes": [0]}}],
      "extensionsUsed": ["KHR_texture_transform", "KHR_materials_unlit", "KHR_materials_emissive_strength"],
      "nodes": [{{"mesh": 0, "scale": [{scale_x}, 1, 1]}}],
      "meshes": [{{"primitives": [{{"attributes": {{"POSITION": 0, "TEXCOORD_0": 1, "TEXCOORD_1": 1, "COLOR_0": 2}}, "material": 0}}]}}],
      "buffers": [{{"uri": "data:application/octet-stream;base64,{}", "byteLength": {}}}],
      "bufferViews": [{{"buffer": 0, "byteLength": 36}}, {{"buffer": 0, "byteOffset": 36, "byteLength": 24}},
                      {{"buffer": 0, "byteOffset": 60, "byteLength": 12}}],
      "accessors": [{{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]}},
                    {{"bufferView": 1, "componentType": 5126, "count": 3, "type": "VEC2"}},
                    {{"bufferView": 2, "componentType": 5121, "normalized": true, "count": 3, "type": "VEC4"}}],
      {materials}}}"#,
        b64(&bin),
        bin.len()
    );
    let p = out_dir("gltf-materials").join(name);
    std::fs::write(&p, json).unwrap();
    p
}

const FULL: &str = r#""samplers": [{"wrapS": 33071, "wrapT": 33648, "magFilter": 9728, "minFilter": 9984}],
  "textures": [{"source": 0, "sampler": 0}, {"source": 1}, {"source": 2}],
  "materials": [{"name": "all",
    "pbrMetallicRoughness": {"baseColorFactor": [1, 1, 1, 0.5],
      "baseColorTexture": {"index": 0, "extensions": {"KHR_texture_transform": {"offset": [0.5, 0], "rotation": 0, "scale": [2, 2], "texCoord": 1}}},
      "metallicRoughnessTexture": {"index": 1}},
    "normalTexture": {"index": 2, "scale": 0.5},
    "occlusionTexture": {"index": 1, "texCoord": 1, "strength": 0.25},
    "emissiveTexture": {"index": 0},
    "emissiveFactor": [1, 0.5, 0.25],
    "alphaMode": "MASK", "alphaCutoff": 0.3, "doubleSided": true,
    "extensions": {"KHR_materials_unlit": {}, "KHR_materials_emissive_strength": {"emissiveStrength": 4}}}]"#;

fn images() -> String {
    format!(
        r#""images": [{{"uri": "{}"}}, {{"uri": "{}"}}, {{"uri": "{}"}}]"#,
        png([255, 0, 0, 255], [0, 0, 255, 255]),
        // metallic-roughness: occlusion in r, roughness in g, metal in b.
        png([10, 20, 30, 255], [40, 50, 60, 255]),
        png([128, 128, 255, 255], [128, 128, 255, 255]),
    )
}

#[test]
fn every_slot_sampler_and_mode_is_read() {
    let p = model("full.gltf", 1.0, &format!("{FULL}, {}", images()));
    let s = load(&p, &LoadOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    let m = &s.materials[s.meshes[0].material];
    let md = m;
    assert_eq!(md.alpha_mode, AlphaMode::Mask(0.3));
    assert!(md.double_sided && md.unlit);
    assert_eq!(
        (md.normal_scale, md.occlusion_strength, md.emissive_strength),
        (0.5, 0.25, 4.0)
    );
    assert_eq!(m.emissive, [4.0, 2.0, 1.0]);
    let base = md.slot(Slot::BaseColor).unwrap();
    assert_eq!(
        (base.sampler.wrap_s, base.sampler.wrap_t, base.sampler.mag),
        (Wrap::ClampToEdge, Wrap::MirroredRepeat, Filter::Nearest)
    );
    assert_eq!(base.sampler.min, Some(Filter::NearestMipmapNearest));
    assert_eq!(base.uv_set, 1, "texCoord override of KHR_texture_transform");
    let x = base.transform.unwrap();
    assert_eq!(
        (x.offset, x.rotation, x.scale),
        ([0.5, 0.0], 0.0, [2.0, 2.0])
    );
    assert_eq!(md.slot(Slot::Occlusion).unwrap().uv_set, 1);
    assert_eq!(
        md.slot(Slot::MetallicRoughness).unwrap().sampler.wrap_s,
        Wrap::Repeat
    );
    assert!(m.check.gltf_slots.iter().all(|l| !l.contains("not loaded")));
    assert_eq!(m.check.gltf_slots.len(), 5);
    // Colour slots are sRGB, data slots linear.
    let space = |s: Slot| md.slot(s).unwrap().color_space;
    assert_eq!(
        [
            Slot::BaseColor,
            Slot::MetallicRoughness,
            Slot::Normal,
            Slot::Occlusion,
            Slot::Emissive
        ]
        .map(space),
        [
            ColorSpace::Srgb,
            ColorSpace::Linear,
            ColorSpace::Linear,
            ColorSpace::Linear,
            ColorSpace::Srgb
        ]
    );
    // The metallic-roughness image is kept as the file has it (the shader reads metal from
    // blue and roughness from green); occlusion is read from red of its own image.
    let channel = |s: Slot, c: usize| {
        let t = md.image(s).unwrap();
        [t.rgba[c], t.rgba[4 + c]]
    };
    assert_eq!(channel(Slot::MetallicRoughness, 2), [30, 60]);
    assert_eq!(channel(Slot::MetallicRoughness, 1), [20, 50]);
    assert!(m.metallic_texture.is_none() && m.roughness_texture.is_none());
    assert_eq!(channel(Slot::Occlusion, 0), [10, 40]);
    assert_eq!(channel(Slot::Emissive, 0), [255, 0]);
    // TEXCOORD_1 is kept beside the vertices.
    assert_eq!(s.meshes[0].uv1.len(), s.meshes[0].vertices.len());
    assert!(m.normal_texture.is_some());
    // COLOR_0 as normalized u8 RGBA.
    assert!(s.meshes[0].colors.contains(&[1.0, 0.0, 0.0]));
    assert!(s.meshes[0].colors.contains(&[0.0, 0.0, 1.0]));
    // --check describes the material in glTF terms.
    let o = run(&["--check", p.to_str().unwrap()], &[]);
    let out = String::from_utf8_lossy(&o.stdout);
    for want in [
        "material all: alphaMode MASK (alphaCutoff 0.3), doubleSided true, KHR_materials_unlit",
        "emissiveStrength 4",
        "baseColorTexture image 0: TEXCOORD_1, wrap ClampToEdge/MirroredRepeat, mag Nearest, \
         min NearestMipmapNearest, KHR_texture_transform offset [0.5, 0.0] rotation 0 scale [2.0, 2.0]",
        "normalTexture image 2: TEXCOORD_0, wrap Repeat/Repeat, mag Linear, min default, scale 0.5",
        "occlusionTexture image 1: TEXCOORD_1",
    ] {
        assert!(out.contains(want), "{want:?} not in:\n{out}");
    }
    // Unlit and the texture transform are drawn now: no "ignored" or "not drawn" warning.
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!out.contains("KHR_") || !err.contains("ignores"), "{err}");
    assert!(!err.contains("not yet drawn") && !out.contains("not yet drawn"));
}

#[test]
fn images_of_one_file_are_distinct_textures() {
    let mats = r#""textures": [{"source": 0}, {"source": 1}],
      "materials": [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}},
                    {"pbrMetallicRoughness": {"baseColorTexture": {"index": 1}}}]"#;
    let p = model("two.gltf", 1.0, &format!("{mats}, {}", images()));
    let s = load(&p, &LoadOptions::default()).unwrap();
    let (a, b) = (
        s.materials[0].image(Slot::BaseColor).unwrap(),
        s.materials[1].image(Slot::BaseColor).unwrap(),
    );
    assert_eq!(a.path, b.path);
    assert_eq!((a.image, b.image), (Some(0), Some(1)));
    assert_ne!(
        **a, **b,
        "two images of one file must not be the same texture"
    );
    assert_ne!(a.rgba, b.rgba);
}

#[test]
fn a_mirroring_node_keeps_triangles_front_facing() {
    let mats = r#""materials": [{"doubleSided": false}]"#;
    for (name, sx) in [("plain.gltf", 1.0), ("mirror.gltf", -1.0)] {
        let s = load(&model(name, sx, mats), &LoadOptions::default()).unwrap();
        let m = &s.meshes[0];
        let p = |i: u32| glam::Vec3::from(m.vertices[i as usize].position);
        let t = &m.indices[..3];
        let face = (p(t[1]) - p(t[0])).cross(p(t[2]) - p(t[0]));
        let n = glam::Vec3::from(m.vertices[t[0] as usize].normal);
        assert!(face.dot(n) > 0.0, "{name}: winding against the normal");
        assert!(face.z > 0.0, "{name}: faces +z after the mirror");
        assert!(!s.materials[0].double_sided);
    }
}

#[test]
fn quantized_positions_and_colours_load_exactly() {
    // KHR_mesh_quantization: u16 positions (not normalized) scaled by the node; COLOR_0 as
    // normalized u16 RGB.
    let mut bin = Vec::new();
    for x in [0u16, 0, 0, 0, 4, 0, 0, 0, 0, 4, 0, 0] {
        bin.extend(x.to_le_bytes());
    }
    for x in [65535u16, 0, 0, 0, 0, 65535, 0, 0, 0, 0, 65535, 0] {
        bin.extend(x.to_le_bytes());
    }
    let json = format!(
        r#"{{"asset": {{"version": "2.0"}}, "scene": 0, "scenes": [{{"nodes": [0]}}],
      "extensionsUsed": ["KHR_mesh_quantization"], "extensionsRequired": ["KHR_mesh_quantization"],
      "nodes": [{{"mesh": 0, "scale": [0.25, 0.25, 0.25]}}],
      "meshes": [{{"primitives": [{{"attributes": {{"POSITION": 0, "COLOR_0": 1}}}}]}}],
      "buffers": [{{"uri": "data:application/octet-stream;base64,{}", "byteLength": 48}}],
      "bufferViews": [{{"buffer": 0, "byteLength": 24, "byteStride": 8}},
                      {{"buffer": 0, "byteOffset": 24, "byteLength": 24, "byteStride": 8}}],
      "accessors": [{{"bufferView": 0, "componentType": 5123, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [4, 4, 0]}},
                    {{"bufferView": 1, "componentType": 5123, "normalized": true, "count": 3, "type": "VEC3"}}]}}"#,
        b64(&bin)
    );
    let p = out_dir("gltf-materials").join("quantized.gltf");
    std::fs::write(&p, json).unwrap();
    let s = load(&p, &LoadOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    assert!(s.warnings.is_empty(), "{:?}", s.warnings);
    assert_eq!(
        s.file_bounds,
        (glam::DVec3::ZERO, glam::DVec3::new(1.0, 1.0, 0.0))
    );
    let c = &s.meshes[0].colors;
    for want in [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]] {
        assert!(c.contains(&want), "{c:?}");
    }
}

/// `--check` says how an OBJ/MTL, STL or PLY file maps into the material model, slot by slot
/// in the file's own terms.
#[test]
fn check_prints_the_mapping_of_other_formats() {
    let dir = out_dir("material-model-mapping");
    let tri = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\n";
    std::fs::write(
        dir.join("m.obj"),
        format!("mtllib m.mtl\n{tri}usemtl pbr\nf 1/1 2/2 3/3\nusemtl glass\nf 1/1 3/3 2/2\n"),
    )
    .unwrap();
    std::fs::copy(
        crate::common::repo().join("models/checker.png"),
        dir.join("c.png"),
    )
    .unwrap();
    std::fs::write(
        dir.join("m.mtl"),
        "newmtl pbr\nKd 0.5 0.25 1\nPm 0.7\nPr 0.3\nKe 0.1 0 0\nmap_Kd c.png\nmap_Ke c.png\n\
         newmtl glass\nKd 0.2 0.2 0.2\nKs 0.9 0.9 0.9\nNs 64\nd 0.4\n",
    )
    .unwrap();
    std::fs::write(
        dir.join("m.stl"),
        "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\n\
         endloop\nendfacet\nendsolid t\n",
    )
    .unwrap();
    std::fs::write(
        dir.join("m.ply"),
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n\
         property float z\nproperty uchar red\nproperty uchar green\nproperty uchar blue\n\
         element face 1\nproperty list uchar int vertex_indices\nend_header\n\
         0 0 0 255 0 0\n1 0 0 0 255 0\n0 1 0 0 0 255\n3 0 1 2\n",
    )
    .unwrap();
    let check = |file: &str| {
        let o = run(&["--check", dir.join(file).to_str().unwrap()], &[]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        String::from_utf8_lossy(&o.stdout).into_owned()
    };
    let obj = check("m.obj");
    for want in [
        "material model: material pbr: baseColor (0.500, 0.250, 1.000) (Kd, sRGB) x map_Kd ",
        "c.png (repeat, linear, mipmaps, UV set 0), metallic 0.70 (Pm), roughness 0.300 (Pr)",
        "emissive (0.100, 0.000, 0.000) (Ke) x map_Ke ",
        "OPAQUE (d 1), doubleSided",
        "material model: material glass: baseColor (0.200, 0.200, 0.200)",
        "metallic 0 (from Kd/Ks), roughness ",
        "(from Ns 64)",
        "BLEND (d 0.400)",
    ] {
        assert!(obj.contains(want), "{want:?} not in:\n{obj}");
    }
    let stl = check("m.stl");
    assert!(
        stl.contains(
            "baseColor (0.800, 0.800, 0.800), metallic 0, roughness 1, no textures, OPAQUE"
        ),
        "{stl}"
    );
    let ply = check("m.ply");
    assert!(
        ply.contains("(0.800, 0.800, 0.800) x vertex colours"),
        "{ply}"
    );
}
