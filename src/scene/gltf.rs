//! glTF 2.0 (`.gltf` with its buffers, `.glb`) through the `gltf` crate, into the same
//! [`Scene`]: node transforms applied in f64, re-centred like OBJ; base colour, metallic and
//! roughness factors and the base-colour texture kept in the material; lines and points go
//! to [`Scene::wire`].
use super::obj::LoadOptions;
use super::{Bounds, Material, Mesh, Scene, Texture, Vertex, Warning, Wire};
use crate::error::{Error, Result};
use glam::{DMat3, DMat4, DVec3, Mat4};
use std::path::Path;
use std::sync::Arc;

struct Prim {
    positions: Vec<DVec3>,
    normals: Option<Vec<DVec3>>,
    uvs: Option<Vec<[f32; 2]>>,
    colors: Option<Vec<[f32; 3]>>,
    indices: Vec<u32>,
    material: Option<usize>,
    name: String,
}

fn rgba(img: &gltf::image::Data) -> Option<Vec<u8>> {
    use gltf::image::Format as F;
    let px = &img.pixels;
    Some(match img.format {
        F::R8G8B8A8 => px.clone(),
        F::R8G8B8 => px
            .chunks_exact(3)
            .flat_map(|p| [p[0], p[1], p[2], 255])
            .collect(),
        F::R8G8 => px
            .chunks_exact(2)
            .flat_map(|p| [p[0], p[1], 0, 255])
            .collect(),
        F::R8 => px.iter().flat_map(|&r| [r, r, r, 255]).collect(),
        _ => return None,
    })
}

pub fn load_gltf(path: &Path, opts: &LoadOptions) -> Result<Scene> {
    // gltf's validation errors can span lines; the user gets one.
    let bad = |m: String| Error::model(path, None, m.replace('\n', "; "));
    let (doc, buffers, images) =
        gltf::import(path).map_err(|e| bad(format!("not a valid glTF file: {e}")))?;
    let mut warnings = Vec::new();
    let mut materials: Vec<Material> = doc
        .materials()
        .map(|m| {
            let pbr = m.pbr_metallic_roughness();
            let [r, g, b, a] = pbr.base_color_factor();
            let tex = pbr.base_color_texture().and_then(|info| {
                let i = info.texture().source().index();
                let img = images.get(i)?;
                match rgba(img) {
                    Some(px) => Some(Arc::new(Texture {
                        path: path.to_path_buf(),
                        width: img.width,
                        height: img.height,
                        rgba: px,
                    })),
                    None => {
                        warnings.push(Warning {
                            file: path.to_path_buf(),
                            line: None,
                            message: format!(
                                "material {:?}: base colour image {i} has 16-bit or float \
                                 pixels: not used",
                                m.name().unwrap_or("")
                            ),
                        });
                        None
                    }
                }
            });
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
                diffuse_map: tex,
                diffuse_map_spec: spec,
                // The PBR tier reads these as it reads an MTL's Pm and Pr.
                pbr_inputs: crate::scene::pbr_material::PbrInputs {
                    metallic: Some(pbr.metallic_factor()),
                    roughness: Some(pbr.roughness_factor()),
                    ..Default::default()
                },
            }
        })
        .collect();
    let default_index = materials.len();
    materials.push(Material::default());

    let mut prims = Vec::new();
    let mut wire_pts: Vec<DVec3> = Vec::new();
    let mut wire = Wire::default();
    let scene = doc
        .default_scene()
        .or_else(|| doc.scenes().next())
        .ok_or_else(|| bad("no scene in the file".into()))?;
    let mut stack: Vec<(gltf::Node, DMat4)> = scene.nodes().map(|n| (n, DMat4::IDENTITY)).collect();
    let up = opts.up;
    while let Some((node, parent)) = stack.pop() {
        let local = Mat4::from_cols_array_2d(&node.transform().matrix()).as_dmat4();
        let world = parent * local;
        stack.extend(node.children().map(|c| (c, world)));
        let Some(mesh) = node.mesh() else { continue };
        let normal_m = DMat3::from_mat4(world).inverse().transpose();
        for p in mesh.primitives() {
            let reader = p.reader(|b| buffers.get(b.index()).map(|d| &d.0[..]));
            let Some(pos) = reader.read_positions() else {
                continue;
            };
            let positions: Vec<DVec3> = pos
                .map(|q| up.rotate(world.transform_point3(glam::Vec3::from(q).as_dvec3())))
                .collect();
            if positions.iter().any(|q| !q.is_finite()) {
                return Err(bad("a position is not finite".into()));
            }
            let n = positions.len() as u32;
            let indices: Vec<u32> = match reader.read_indices() {
                Some(i) => i.into_u32().collect(),
                None => (0..n).collect(),
            };
            if let Some(&k) = indices.iter().find(|&&k| k >= n) {
                return Err(bad(format!(
                    "index {k} out of range (primitive has {n} vertices)"
                )));
            }
            use gltf::mesh::Mode;
            match p.mode() {
                Mode::Triangles => {}
                Mode::Lines | Mode::Points => {
                    let base = wire_pts.len() as u32;
                    wire_pts.extend(&positions);
                    if p.mode() == Mode::Lines {
                        wire.segments
                            .extend(indices.chunks_exact(2).map(|s| [base + s[0], base + s[1]]));
                    } else {
                        wire.points.extend(indices.iter().map(|i| base + i));
                    }
                    continue;
                }
                m => {
                    warnings.push(Warning {
                        file: path.to_path_buf(),
                        line: None,
                        message: format!("primitive mode {m:?} not supported: skipped"),
                    });
                    continue;
                }
            }
            prims.push(Prim {
                normals: reader.read_normals().map(|it| {
                    it.map(|q| up.rotate(normal_m * glam::Vec3::from(q).as_dvec3()))
                        .collect()
                }),
                uvs: reader.read_tex_coords(0).map(|t| t.into_f32().collect()),
                colors: reader.read_colors(0).map(|c| c.into_rgb_f32().collect()),
                positions,
                indices,
                material: p.material().index(),
                name: mesh.name().unwrap_or("mesh").to_string(),
            });
        }
    }
    let (lo, hi, origin) = super::extent_and_origin(
        prims
            .iter()
            .flat_map(|p| &p.positions)
            .chain(&wire_pts)
            .copied(),
    );
    let mut bounds = Bounds::empty();
    let mut meshes = Vec::new();
    for p in prims {
        if p.indices.len() < 3 {
            continue;
        }
        let count = p.positions.len();
        let has_n = p.normals.as_ref().is_some_and(|v| v.len() == count);
        let has_uv = p.uvs.as_ref().is_some_and(|v| v.len() == count);
        let vertices: Vec<Vertex> = (0..count)
            .map(|i| Vertex {
                position: (p.positions[i] - origin).as_vec3().into(),
                normal: match &p.normals {
                    Some(v) if has_n => v[i].as_vec3().into(),
                    _ => [0.0; 3],
                },
                // glTF's UV origin is the image's top-left, as textures are uploaded.
                uv: match &p.uvs {
                    Some(v) if has_uv => v[i],
                    _ => [0.0; 2],
                },
            })
            .collect();
        let mut mesh = Mesh {
            name: p.name,
            vertices,
            indices: p.indices[..p.indices.len() / 3 * 3].to_vec(),
            material: p
                .material
                .filter(|&m| m < default_index)
                .unwrap_or(default_index),
            has_uv,
            generated_normals: 0,
            colors: p.colors.filter(|c| c.len() == count).unwrap_or_default(),
        };
        mesh.finish_normals(has_n, None, opts.creases);
        for v in &mesh.vertices {
            bounds.include(v.position.into());
        }
        meshes.push(mesh);
    }
    for q in &wire_pts {
        let l = (*q - origin).as_vec3();
        bounds.include(l);
        wire.positions.push(l.into());
    }
    if meshes.is_empty() && wire.is_empty() {
        return Err(bad("no triangles in the file".into()));
    }
    Ok(Scene {
        name: path
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_else(|| "model".into()),
        meshes,
        materials,
        bounds,
        origin,
        file_bounds: (lo, hi),
        dependencies: Vec::new(),
        warnings,
        wire,
        maps: Vec::new(),
    })
}
