//! glTF 2.0 (`.gltf` with its buffers, `.glb`) into the same [`Scene`]: the JSON is parsed by
//! the `gltf` crate, but buffers and images are resolved here under the folder rule every
//! format shares ([`super::uri`]), accessors are read with their sizes checked first
//! ([`super::gltf_accessor`]) and the node graph is walked without recursion, refusing cycles
//! ([`super::gltf_graph`]). Node transforms are applied in f64 and the scene re-centred like
//! OBJ; lines and points go to [`Scene::wire`]. A missing or broken image is a warning.
use super::gltf_accessor::{self as accessor, MAX_ELEMENTS};
use super::LoadOptions;
use super::{Bounds, Mesh, Scene, Texture, Vertex, Warning, Wire};
use crate::error::{Error, Result};
use glam::{DMat3, DVec3};
use gltf::accessor::Dimensions as D;
use gltf::mesh::{Mode, Semantic};
use std::path::Path;
use std::sync::Arc;

/// Extensions whose absence would make glview draw a required extension wrongly are refused;
/// these are the ones it implements.
pub const SUPPORTED_EXTENSIONS: &[&str] = &[
    "KHR_mesh_quantization",
    "KHR_materials_emissive_strength",
    "EXT_meshopt_compression",
    "KHR_materials_unlit",
    "KHR_texture_transform",
];

/// Decoded images stop here (bytes of RGBA8); later images are skipped with a warning.
const MAX_TEXTURE_BYTES: usize = 512 << 20;

struct Prim {
    positions: Vec<DVec3>,
    normals: Option<Vec<DVec3>>,
    uvs: Option<Vec<[f32; 2]>>,
    uv1: Option<Vec<[f32; 2]>>,
    tangents: Option<Vec<[f32; 4]>>,
    colors: Option<Vec<[f32; 3]>>,
    indices: Vec<u32>,
    material: Option<usize>,
    name: String,
}

pub fn load_gltf(path: &Path, opts: &LoadOptions) -> Result<Scene> {
    let bytes = super::load::read_regular_file(path)?;
    load_gltf_bytes(path, &bytes, opts)
}

/// Loads glTF or GLB bytes as if they were the file `path` (buffers and images are looked up
/// beside it).
pub fn load_gltf_bytes(path: &Path, bytes: &[u8], opts: &LoadOptions) -> Result<Scene> {
    // gltf's validation errors can span lines; the user gets one.
    let bad = |m: String| Error::model(path, None, m.replace('\n', "; "));
    // The crate subtracts the 12-byte header from the GLB's stated length unchecked
    // (overflow, found by the gltf fuzz target).
    if bytes.starts_with(b"glTF") {
        let len = bytes
            .get(8..12)
            .map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]));
        if len.is_none_or(|l| l < 12) {
            return Err(bad(
                "not a valid glTF file: GLB header shorter than 12 bytes".into(),
            ));
        }
    }
    let parsed = gltf::Gltf::from_slice_without_validation(bytes)
        .map_err(|e| bad(format!("not a valid glTF file: {e}")))?;
    let mut warnings = Vec::new();
    let warn = |warnings: &mut Vec<Warning>, message: String| {
        warnings.push(Warning {
            file: path.to_path_buf(),
            line: None,
            message,
        })
    };
    let mut json = parsed.document.into_json();
    for x in &json.extensions_required {
        if !SUPPORTED_EXTENSIONS.contains(&x.as_str()) {
            return Err(bad(format!(
                "requires glTF extension {x}, which glview does not support"
            )));
        }
    }
    for x in &json.extensions_used {
        if !SUPPORTED_EXTENSIONS.contains(&x.as_str()) {
            warn(
                &mut warnings,
                format!("uses glTF extension {x}, which glview ignores"),
            );
        }
    }
    // The crate's validator indexes the accessors with the POSITION index before it has
    // checked that index (a panic, found by the gltf fuzz target).
    for (mi, m) in json.meshes.iter().enumerate() {
        for (pi, p) in m.primitives.iter().enumerate() {
            if let Some(a) = p
                .attributes
                .values()
                .find(|a| a.value() >= json.accessors.len())
            {
                return Err(bad(format!(
                    "mesh {mi} primitive {pi}: accessor {} does not exist",
                    a.value()
                )));
            }
        }
    }
    // Checked above; the crate's validator refuses any it does not know itself.
    json.extensions_required.clear();
    let doc =
        gltf::Document::from_json(json).map_err(|e| bad(format!("not a valid glTF file: {e}")))?;
    let dir = path.parent().unwrap_or(Path::new("."));
    let buffers =
        super::gltf_buffers::buffers(&doc, parsed.blob, dir, opts.textures.allow_outside_paths)
            .map_err(bad)?;
    let views = super::gltf_buffers::decoded_views(&doc, &buffers).map_err(bad)?;
    let buffers = accessor::Buffers { buffers, views };
    let dependencies = super::gltf_buffers::external_files(&doc, dir, opts.textures);

    let images = decode_images(&doc, &buffers.buffers, path, opts, &mut warnings);
    let mut materials = Vec::new();
    for m in doc.materials() {
        let mut image = |i: usize| images.get(i).cloned().flatten();
        materials.push(super::gltf_material::material(&m, &mut image));
    }
    let default_index = materials.len();
    materials.push(super::Material::default());

    let scene = doc
        .default_scene()
        .or_else(|| doc.scenes().next())
        .ok_or_else(|| bad("no scene in the file".into()))?;
    let instances = super::gltf_graph::instances(&doc, &scene).map_err(bad)?;
    // Meshes can be instanced by many nodes: the total is bounded before anything is read.
    let mut total = 0usize;
    for (node, mesh, _) in &instances {
        for p in mesh.primitives() {
            let n = p.get(&Semantic::Positions).map_or(0, |a| a.count());
            let k = p.indices().map_or(0, |a| a.count());
            total = total.saturating_add(n.max(k / 3));
            if total > MAX_ELEMENTS {
                return Err(bad(format!(
                    "node {node}: the scene instances more than {MAX_ELEMENTS} vertices; \
                     refused before reading them"
                )));
            }
        }
    }

    let mut prims = Vec::new();
    let mut wire_pts: Vec<DVec3> = Vec::new();
    let mut wire = Wire::default();
    let up = opts.up;
    for (node, mesh, world) in &instances {
        let normal_m = DMat3::from_mat4(*world).inverse().transpose();
        // A singular transform (a zero scale) has no normal matrix: normals are generated.
        let normal_ok = normal_m.is_finite();
        let mirrored = world.determinant() < 0.0;
        for (pi, p) in mesh.primitives().enumerate() {
            let where_ = || format!("mesh {} primitive {pi}", mesh.index());
            let Some(pos_acc) = p.get(&Semantic::Positions) else {
                warn(&mut warnings, format!("{}: no POSITION: skipped", where_()));
                continue;
            };
            let (_, raw) = accessor::read_f32(&pos_acc, &buffers, &[D::Vec3]).map_err(bad)?;
            if let Some(k) = raw.iter().position(|x| !x.is_finite()) {
                return Err(bad(format!(
                    "accessor {} (POSITION of {}): element {} is not finite",
                    pos_acc.index(),
                    where_(),
                    k / 3
                )));
            }
            let positions: Vec<DVec3> = raw
                .chunks_exact(3)
                .map(|q| up.rotate(world.transform_point3(glam::Vec3::from_slice(q).as_dvec3())))
                .collect();
            // Beyond f32 they would become infinite when rounded after re-centring.
            if positions
                .iter()
                .any(|q| !q.is_finite() || q.abs().max_element() > f64::from(f32::MAX))
            {
                return Err(bad(format!(
                    "{}: node {node} transforms positions beyond 32-bit float range",
                    where_()
                )));
            }
            let n = positions.len() as u32;
            let corners: Vec<u32> = match p.indices() {
                Some(a) => accessor::read_indices(&a, &buffers).map_err(bad)?,
                None => (0..n).collect(),
            };
            if let Some(k) = corners.iter().position(|&k| k >= n) {
                return Err(bad(format!(
                    "{}: index {} (element {k}) out of range ({n} vertices)",
                    where_(),
                    corners[k]
                )));
            }
            let (indices, segments) = super::gltf_modes::split(p.mode(), &corners, mirrored);
            if matches!(p.mode(), Mode::Points) || !segments.is_empty() {
                let base = wire_pts.len() as u32;
                wire_pts.extend(&positions);
                if p.mode() == Mode::Points {
                    wire.points.extend(corners.iter().map(|i| base + i));
                }
                wire.segments
                    .extend(segments.iter().map(|s| [base + s[0], base + s[1]]));
                continue;
            }
            let normals = match p.get(&Semantic::Normals).filter(|_| normal_ok) {
                Some(a) => {
                    let (_, v) = accessor::read_f32(&a, &buffers, &[D::Vec3]).map_err(bad)?;
                    if let Some(k) = v.iter().position(|x| !x.is_finite()) {
                        warn(
                            &mut warnings,
                            format!(
                                "accessor {} (NORMAL of {}): element {} is not finite; \
                                 normals generated",
                                a.index(),
                                where_(),
                                k / 3
                            ),
                        );
                        None
                    } else {
                        Some(
                            v.chunks_exact(3)
                                .map(|q| up.rotate(normal_m * glam::Vec3::from_slice(q).as_dvec3()))
                                .collect(),
                        )
                    }
                }
                None => None,
            };
            let mut uv_set = |set: u32| -> Result<Option<Vec<[f32; 2]>>> {
                let Some(a) = p.get(&Semantic::TexCoords(set)) else {
                    return Ok(None);
                };
                let (_, v) = accessor::read_f32(&a, &buffers, &[D::Vec2]).map_err(bad)?;
                if v.iter().all(|x| x.is_finite()) {
                    Ok(Some(v.chunks_exact(2).map(|q| [q[0], q[1]]).collect()))
                } else {
                    warn(
                        &mut warnings,
                        format!(
                            "accessor {}: a TEXCOORD_{set} is not finite: unused",
                            a.index()
                        ),
                    );
                    Ok(None)
                }
            };
            let uvs = uv_set(0)?;
            let uv1 = uv_set(1)?;
            // Supplied tangents follow the node's linear part like any direction in the
            // surface; a mirroring transform reverses cross(N, T), so the bitangent sign flips
            // with it.
            let tangents = match p.get(&Semantic::Tangents).filter(|_| normal_ok) {
                Some(a) => {
                    let (_, v) = accessor::read_f32(&a, &buffers, &[D::Vec4]).map_err(bad)?;
                    if v.iter().all(|x| x.is_finite()) {
                        let m3 = DMat3::from_mat4(*world);
                        let flip = if mirrored { -1.0 } else { 1.0 };
                        Some(
                            v.chunks_exact(4)
                                .map(|q| {
                                    let t = up.rotate(m3 * glam::Vec3::from_slice(q).as_dvec3());
                                    let t = t.normalize_or_zero().as_vec3();
                                    let w = if q[3] < 0.0 { -flip } else { flip };
                                    [t.x, t.y, t.z, w as f32]
                                })
                                .collect(),
                        )
                    } else {
                        warn(
                            &mut warnings,
                            format!(
                                "accessor {} (TANGENT of {}): not finite; tangents generated",
                                a.index(),
                                where_()
                            ),
                        );
                        None
                    }
                }
                None => None,
            };
            let colors = match p.get(&Semantic::Colors(0)) {
                Some(a) => {
                    let (d, v) =
                        accessor::read_f32(&a, &buffers, &[D::Vec3, D::Vec4]).map_err(bad)?;
                    Some(v.chunks_exact(d).map(|q| [q[0], q[1], q[2]]).collect())
                }
                None => None,
            };
            prims.push(Prim {
                positions,
                normals,
                uvs,
                uv1,
                tangents,
                colors,
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
            indices: p.indices,
            material: p
                .material
                .filter(|&m| m < default_index)
                .unwrap_or(default_index),
            has_uv,
            generated_normals: 0,
            colors: p.colors.filter(|c| c.len() == count).unwrap_or_default(),
            uv1: p.uv1.filter(|c| c.len() == count).unwrap_or_default(),
            // Tangents go with the file's normals: generated normals get generated tangents.
            tangents: p
                .tangents
                .filter(|c| c.len() == count && has_n)
                .unwrap_or_default(),
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
        dependencies,
        warnings,
        wire,
        maps: Vec::new(),
    })
}

/// Every image a material uses, decoded in parallel (a few at a time, so the texture budget is
/// checked between batches and at most one batch overshoots it); a missing, broken or
/// over-budget image is a warning and None.
fn decode_images(
    doc: &gltf::Document,
    buffers: &[Vec<u8>],
    path: &Path,
    opts: &LoadOptions,
    warnings: &mut Vec<Warning>,
) -> Vec<Option<Arc<Texture>>> {
    use rayon::prelude::*;
    let mut used = vec![false; doc.images().len()];
    for m in doc.materials() {
        let pbr = m.pbr_metallic_roughness();
        let slots = [
            pbr.base_color_texture().map(|t| t.texture()),
            pbr.metallic_roughness_texture().map(|t| t.texture()),
            m.normal_texture().map(|t| t.texture()),
            m.occlusion_texture().map(|t| t.texture()),
            m.emissive_texture().map(|t| t.texture()),
        ];
        for t in slots.into_iter().flatten() {
            if let Some(u) = used.get_mut(t.source().index()) {
                *u = true;
            }
        }
    }
    let wanted: Vec<usize> = (0..used.len()).filter(|&i| used[i]).collect();
    let mut out: Vec<Option<Arc<Texture>>> = vec![None; used.len()];
    let mut texture_bytes = 0usize;
    for batch in wanted.chunks(rayon::current_num_threads().max(1)) {
        let decoded: Vec<(usize, std::result::Result<Texture, String>)> =
            if texture_bytes > MAX_TEXTURE_BYTES {
                batch
                    .iter()
                    .map(|&i| {
                        let e = format!("over the {} MiB texture budget", MAX_TEXTURE_BYTES >> 20);
                        (i, Err(e))
                    })
                    .collect()
            } else {
                batch
                    .par_iter()
                    .map(|&i| {
                        (
                            i,
                            super::gltf_buffers::image(doc, i, buffers, path, opts.textures),
                        )
                    })
                    .collect()
            };
        for (i, t) in decoded {
            let label = super::gltf_buffers::image_label(doc, i);
            match t {
                Ok(t) => {
                    texture_bytes += t.rgba.len();
                    out[i] = Some(Arc::new(t));
                }
                Err(e) => warnings.push(Warning {
                    file: path.to_path_buf(),
                    line: None,
                    message: format!("{label}: {e}; materials using it render without it"),
                }),
            }
        }
    }
    out
}
