//! OBJ/MTL bytes → [`Scene`] (files reach it through [`crate::load::load()`]): tobj does the parsing (after `crate::loaders::obj::repair`); positions are read as
//! f64 and re-centred on the bounding-box centre before they are rounded to f32.

pub mod fast;
pub mod mtl;
pub mod mtl_mapping;
pub mod quirks;
pub mod repair;
use crate::error::{Error, Result};
use crate::geometry::normals::Creases;
use crate::load::options::LoadOptions;
use crate::load::read_regular_file;
use crate::loaders::obj::fast::Parser;
use crate::model::scene::Parts;
use glam::DVec3;
use std::cell::RefCell;
use std::path::Path;
use {
    crate::geometry::triangulate, crate::model::material::Material, crate::model::Bounds,
    crate::model::Mesh, crate::model::Scene, crate::model::UpAxis, crate::model::Vertex,
    crate::model::Warning, crate::model::Wire,
};

type MtlLineMap =
    RefCell<std::collections::HashMap<String, (std::path::PathBuf, repair::MtlLines)>>;

/// Where MTL bytes come from: files beside the OBJ, or memory for the built-in scene.
type MtlSource<'a> = &'a dyn Fn(&Path) -> Result<Vec<u8>>;

fn load_mtl(
    obj_dir: &Path,
    name: &Path,
    source: MtlSource,
    warnings: &RefCell<Vec<Warning>>,
    lines: &MtlLineMap,
) -> tobj::MTLLoadResult {
    let path = obj_dir.join(name.to_string_lossy().replace('\\', "/"));
    let warn = |msg: String| {
        warnings.borrow_mut().push(Warning {
            file: path.clone(),
            line: None,
            message: msg,
        })
    };
    let bytes = match source(&path) {
        Ok(b) => b,
        Err(e) => {
            warn(format!(
                "cannot read material library ({e}); using the default material"
            ));
            return Err(tobj::LoadError::OpenFileFailed);
        }
    };
    let text = match String::from_utf8(bytes) {
        Ok(t) => t,
        Err(e) => {
            warn("non-UTF-8 bytes replaced".into());
            String::from_utf8_lossy(e.as_bytes()).into_owned()
        }
    };
    let mut repairs = Vec::new();
    let text = repair::repair_mtl(&path, &text, &mut repairs);
    warnings.borrow_mut().extend(repairs);
    for (name, l) in repair::mtl_lines(&text) {
        lines
            .borrow_mut()
            .entry(name)
            .or_insert_with(|| (path.clone(), l));
    }
    tobj::load_mtl_buf(&mut text.as_bytes()).inspect_err(|e| {
        warn(format!("{e}; using the default material"));
    })
}

/// Loads OBJ bytes as if they were the file `path` (MTL and textures are looked up beside it).
pub(crate) fn load_bytes(path: &Path, bytes: &[u8], opts: &LoadOptions) -> Result<Scene> {
    load_bytes_with(path, bytes, opts, Parser::from_env())
}

/// As `load_bytes` with a chosen OBJ parser (the differential test compares the two).
pub fn load_bytes_with(
    path: &Path,
    bytes: &[u8],
    opts: &LoadOptions,
    parser: Parser,
) -> Result<Scene> {
    load_with(path, bytes, opts, &|p: &Path| read_regular_file(p), parser)
}

/// Loads an OBJ whose MTL library is in memory too (the built-in scene).
pub fn load_embedded(path: &Path, obj: &[u8], mtl: &[u8], opts: &LoadOptions) -> Result<Scene> {
    load_embedded_with(path, obj, mtl, opts, Parser::from_env())
}

/// As `load_embedded` with a chosen OBJ parser: every `mtllib` gets the same in-memory MTL
/// bytes whichever parser runs (the fuzz target compares the fast path with the old one).
pub fn load_embedded_with(
    path: &Path,
    obj: &[u8],
    mtl: &[u8],
    opts: &LoadOptions,
    parser: Parser,
) -> Result<Scene> {
    load_with(path, obj, opts, &|_: &Path| Ok(mtl.to_vec()), parser)
}

/// What the OBJ parse gave: tobj's models and materials, the pre-pass's findings (lines,
/// points, `usemtl` lines, smoothing groups), the warnings so far, each material's MTL lines
/// and the MTL files read.
struct Parsed {
    models: Vec<tobj::Model>,
    mats: Result<Vec<tobj::Material>, tobj::LoadError>,
    repaired: repair::Repaired,
    warnings: Vec<Warning>,
    mtl_lines: std::collections::HashMap<String, (std::path::PathBuf, repair::MtlLines)>,
    dependencies: Vec<std::path::PathBuf>,
}

/// Parses OBJ bytes: the fast parser where it can (it takes the MTL libraries as it meets
/// them), else the repair pre-pass and tobj.
fn parse(
    path: &Path,
    dir: &Path,
    bytes: &[u8],
    opts: &LoadOptions,
    mtl_source: MtlSource,
    parser: Parser,
) -> Result<Parsed> {
    let total = bytes.len() as u64;
    let report = |done: u64| {
        if let Some(p) = &opts.progress {
            p(done, total)
        }
    };
    let warnings = RefCell::new(Vec::new());
    let mtl_files = RefCell::new(Vec::new());
    let mtl_lines: MtlLineMap = RefCell::default();
    let mut mtl = |p: &Path| {
        mtl_files.borrow_mut().push(dir.join(p));
        load_mtl(dir, p, mtl_source, &warnings, &mtl_lines)
    };
    let fast = match parser {
        Parser::Auto => crate::loaders::obj::fast::parse(bytes, None, &report, &mut mtl),
        Parser::Chunked(n) => crate::loaders::obj::fast::parse(bytes, Some(n), &report, &mut mtl),
        Parser::Tobj => None,
    };
    // A file without faces (a point cloud) takes the old path, which keeps every position;
    // what the fast parse recorded on the way (its MTL reads) is read again there.
    let fast = match fast {
        Some(p) if p.models.iter().all(|m| m.mesh.indices.is_empty()) => {
            warnings.borrow_mut().clear();
            mtl_files.borrow_mut().clear();
            mtl_lines.borrow_mut().clear();
            None
        }
        other => other,
    };
    crate::profile::set_fast_path(fast.is_some());
    let (models, mats, repaired) = match fast {
        Some(p) => {
            let repaired = repair::Repaired {
                usemtl: p.usemtl,
                face_groups: p.face_groups,
                ..repair::Repaired::default()
            };
            (p.models, p.materials, repaired)
        }
        None => {
            let mut repaired = repair::repair_obj_with_progress(path, bytes, &report)?;
            crate::profile::mark(crate::profile::Stage::Repair);
            warnings.borrow_mut().append(&mut repaired.warnings);
            // Polygons come with their arity and are triangulated here (ear clipping where
            // concave); lines and points were taken out by the pre-pass.
            let load_opts = tobj::LoadOptions {
                triangulate: false,
                single_index: true,
                ignore_points: true,
                ignore_lines: true,
            };
            let (models, mats) =
                tobj::load_obj_buf(&mut repaired.text.as_bytes(), &load_opts, |p| mtl(p))
                    .map_err(|e| Error::model(path, None, e.to_string()))?;
            (models, mats, repaired)
        }
    };
    crate::profile::mark(crate::profile::Stage::Parse);
    Ok(Parsed {
        models,
        mats,
        repaired,
        warnings: warnings.into_inner(),
        mtl_lines: mtl_lines.into_inner(),
        dependencies: mtl_files.into_inner(),
    })
}

/// The OBJ's materials, each MTL material read once, its exporters' quirks handled and
/// mapped into the one material model once; `usemtl` of undefined names warned about (once
/// each); and last the default material (with `--texture`'s image where given), which meshes
/// without a material use. Also the `--check` lines of their maps; their textures become
/// dependencies.
#[allow(clippy::too_many_arguments)]
fn materials(
    path: &Path,
    dir: &Path,
    mats: Result<Vec<tobj::Material>, tobj::LoadError>,
    mtl_lines: &std::collections::HashMap<String, (std::path::PathBuf, repair::MtlLines)>,
    usemtl: &[(usize, String)],
    opts: &LoadOptions,
    warnings: &mut Vec<Warning>,
    dependencies: &mut Vec<std::path::PathBuf>,
) -> (Vec<Material>, Vec<String>) {
    let tobj_mats = mats.unwrap_or_default();
    // Texture warnings name the material library that was read (tobj does not say which of
    // several libraries a material came from; then the first one is named).
    let mtl_file = dependencies
        .first()
        .cloned()
        .unwrap_or_else(|| path.to_path_buf());
    // Each tobj material is read once (taken by value), its quirks handled, then mapped into
    // the PBR values once.
    let files = crate::loaders::obj::mtl::Files {
        dir,
        mtl_file: &mtl_file,
        opts: opts.textures,
    };
    let read: Vec<crate::loaders::obj::mtl::Read> = tobj_mats
        .into_iter()
        .map(|m| crate::loaders::obj::mtl::read(m, &files, warnings))
        .collect();
    let mut maps = Vec::new();
    let mut materials: Vec<Material> = Vec::with_capacity(read.len() + 1);
    for mut r in read {
        let m = r.material_mut();
        let origin = mtl_lines.get(&m.name).map(|(f, l)| (f.as_path(), l));
        quirks::fix_invisible(m, origin, opts.honor_transparency, warnings);
        quirks::fix_ns_zero(m, origin, warnings);
        maps.extend(quirks::map_report(m, origin));
        materials.push(r.map());
    }
    crate::profile::mark(crate::profile::Stage::Textures);
    let mut reported = std::collections::HashSet::new();
    for (line, name) in usemtl {
        if !materials.iter().any(|m| &m.name == name) && reported.insert(name.clone()) {
            warnings.push(Warning {
                file: path.to_path_buf(),
                line: Some(*line),
                message: format!("material {name:?} is not defined; using the default material"),
            });
        }
    }
    let mut default = Material::default();
    if let Some(t) = &opts.texture {
        match crate::textures::path::decode_texture(t.clone(), opts.textures) {
            Ok(tex) => {
                default.base_color_texture = Some(crate::model::texture_slot::TextureSlot::plain(
                    std::sync::Arc::new(tex),
                    crate::model::texture_slot::ColorSpace::Srgb,
                ));
                default.check.base_color = Some(t.display().to_string());
                maps.push(format!(
                    "map: --texture {}: base colour of meshes without a material",
                    t.display()
                ));
            }
            Err(e) => warnings.push(Warning {
                file: t.clone(),
                line: None,
                message: format!("--texture: {e}; using the default colour"),
            }),
        }
    }
    materials.push(default);
    dependencies.extend(
        materials
            .iter()
            .filter_map(|m| m.base_color_texture.as_ref().map(|t| t.image.path.clone())),
    );
    (materials, maps)
}

/// The file's lines and points (`l`, `p`) over the vertices they use (`used`, sorted),
/// placed as the meshes are; their extent is added to `bounds`.
fn wire_of(
    repaired: &repair::Repaired,
    used: &[u32],
    rotated: &dyn Fn(&[f64]) -> DVec3,
    origin: DVec3,
    bounds: &mut Bounds,
) -> Wire {
    let mut wire = Wire::default();
    if used.is_empty() {
        return wire;
    }
    let mut local = std::collections::HashMap::new();
    for &i in used {
        local.insert(i, wire.positions.len() as u32);
        let p = (rotated(&repaired.positions[i as usize]) - origin).as_vec3();
        bounds.include(p);
        wire.positions.push(p.into());
    }
    wire.segments = repaired
        .segments
        .iter()
        .map(|s| s.map(|i| local[&i]))
        .collect();
    wire.points = repaired.points.iter().map(|i| local[i]).collect();
    // A file without faces may give its vertices colours and (one `vn` each) normals.
    let all = repaired.positions.len();
    if repaired.colours.len() == all {
        wire.colors = used.iter().map(|&i| repaired.colours[i as usize]).collect();
    }
    if repaired.normals.len() == all {
        wire.normals = used
            .iter()
            .map(|&i| {
                let n = repaired.normals[i as usize].map(f64::from);
                // The up rotation is linear: it turns directions as it turns positions.
                rotated(&n).normalize_or_zero().as_vec3().to_array()
            })
            .collect();
    }
    wire
}

/// One tobj model as a mesh: polygons triangulated (ear clipping where concave) with their
/// smoothing groups (`groups`, per face in file order, counted by `face_no` across models),
/// vertices rotated upright and re-centred on `origin` in f64, UVs flipped to the textures'
/// top-first rows, normals finished. None when the model has no faces.
fn mesh_of(
    m: tobj::Model,
    up: UpAxis,
    origin: DVec3,
    groups: Option<&[u32]>,
    face_no: &mut usize,
    default_index: usize,
    creases: Creases,
) -> Option<Mesh> {
    let mesh = m.mesh;
    let n = mesh.positions.len() / 3;
    let rotated = |s: &[f64]| up.rotate(DVec3::new(s[0], s[1], s[2]));
    let pos = |i: u32| rotated(&mesh.positions[i as usize * 3..i as usize * 3 + 3]);
    let arities = if mesh.face_arities.is_empty() {
        vec![3; mesh.indices.len() / 3]
    } else {
        mesh.face_arities.clone()
    };
    let mut indices = Vec::with_capacity(mesh.indices.len());
    let mut tri_groups = Vec::new();
    let mut k = 0;
    for a in arities {
        let face = &mesh.indices[k..k + a as usize];
        k += a as usize;
        let g = groups.map_or(0, |g| g[*face_no]);
        *face_no += 1;
        if face.len() == 3 {
            indices.extend_from_slice(face);
            tri_groups.push(g);
        } else if face.len() > 3 {
            let p: Vec<DVec3> = face.iter().map(|&i| pos(i)).collect();
            for t in triangulate::polygon(&p) {
                indices.extend(t.map(|c| face[c]));
                tri_groups.push(g);
            }
        }
    }
    if indices.is_empty() {
        return None;
    }
    let has_normals = mesh.normals.len() == n * 3;
    let has_uv = mesh.texcoords.len() == n * 2;
    let has_colors = mesh.vertex_color.len() == n * 3;
    let vertices: Vec<Vertex> = (0..n)
        .map(|i| {
            let p = pos(i as u32) - origin;
            let normal = if has_normals {
                let s = up.rotate(DVec3::from_slice(&mesh.normals[i * 3..i * 3 + 3]));
                [s.x as f32, s.y as f32, s.z as f32]
            } else {
                [0.0; 3]
            };
            // OBJ's v = 0 is the image's bottom row; textures are uploaded top row first.
            // A non-finite coordinate would make the lookup undefined: 0 instead.
            let finite = |x: f64| if x.is_finite() { x as f32 } else { 0.0 };
            let uv = if has_uv {
                [
                    finite(mesh.texcoords[i * 2]),
                    1.0 - finite(mesh.texcoords[i * 2 + 1]),
                ]
            } else {
                [0.0; 2]
            };
            Vertex {
                position: p.as_vec3().into(),
                normal,
                uv,
            }
        })
        .collect();
    let colors: Vec<[f32; 3]> = if has_colors {
        mesh.vertex_color
            .chunks_exact(3)
            .map(|c| c.iter().map(|&x| x as f32).collect::<Vec<_>>())
            .map(|c| [c[0], c[1], c[2]].map(|x| if x.is_finite() { x } else { 1.0 }))
            .collect()
    } else {
        Vec::new()
    };
    let material = mesh
        .material_id
        .filter(|&i| i < default_index)
        .unwrap_or(default_index);
    let mut mesh = Mesh {
        name: m.name,
        vertices,
        indices,
        material,
        has_uv,
        generated_normals: 0,
        colors,
        ..Default::default()
    };
    mesh.finish_normals(has_normals, groups.map(|_| tri_groups.as_slice()), creases);
    Some(mesh)
}

fn load_with(
    path: &Path,
    bytes: &[u8],
    opts: &LoadOptions,
    mtl_source: MtlSource,
    parser: Parser,
) -> Result<Scene> {
    let dir = path.parent().unwrap_or(Path::new(".")).to_path_buf();
    let Parsed {
        models,
        mats,
        mut repaired,
        mut warnings,
        mtl_lines,
        mut dependencies,
    } = parse(path, &dir, bytes, opts, mtl_source, parser)?;
    let (materials, maps) = materials(
        path,
        &dir,
        mats,
        &mtl_lines,
        &repaired.usemtl,
        opts,
        &mut warnings,
        &mut dependencies,
    );
    let default_index = materials.len() - 1;

    let up = opts.up;
    let rotated = |s: &[f64]| up.rotate(DVec3::new(s[0], s[1], s[2]));
    // A file of `v` lines and no faces (not even dropped ones) is a point cloud: every
    // vertex a point.
    if repaired.segments.is_empty()
        && repaired.points.is_empty()
        && repaired.dropped_faces == 0
        && models.iter().all(|m| m.mesh.indices.is_empty())
    {
        repaired.points = (0..repaired.positions.len() as u32).collect();
    }
    let wire_used: Vec<u32> = {
        let mut u: Vec<u32> = repaired
            .segments
            .iter()
            .flatten()
            .chain(&repaired.points)
            .copied()
            .collect();
        u.sort_unstable();
        u.dedup();
        u
    };
    let (lo, hi, origin) = crate::model::extent_and_origin(
        models
            .iter()
            .flat_map(|m| m.mesh.positions.chunks_exact(3).map(rotated))
            .chain(
                wire_used
                    .iter()
                    .map(|&i| rotated(&repaired.positions[i as usize])),
            ),
    );

    // Smoothing groups are per face in file order; they apply only if tobj kept every face.
    let face_total: usize = models
        .iter()
        .map(|m| match m.mesh.face_arities.len() {
            0 => m.mesh.indices.len() / 3,
            n => n,
        })
        .sum();
    let groups = (!repaired.face_groups.is_empty() && repaired.face_groups.len() == face_total)
        .then_some(repaired.face_groups.as_slice());
    let mut face_no = 0usize;
    let mut meshes = Vec::with_capacity(models.len());
    let mut bounds = Bounds::empty();
    for m in models {
        let Some(mesh) = mesh_of(
            m,
            up,
            origin,
            groups,
            &mut face_no,
            default_index,
            opts.creases,
        ) else {
            continue;
        };
        for v in &mesh.vertices {
            bounds.include(v.position.into());
        }
        meshes.push(mesh);
    }
    let wire = wire_of(&repaired, &wire_used, &rotated, origin, &mut bounds);
    crate::profile::mark(crate::profile::Stage::Meshes);
    crate::load::finish::finish(path, &mut meshes, &materials, &mut warnings);
    if meshes.is_empty() && wire.is_empty() {
        return Err(Error::model(path, None, "no triangles in the file"));
    }
    let parts = Parts {
        meshes: meshes.into(),
        materials,
        bounds,
        origin,
        file_bounds: (lo, hi),
        dependencies,
        warnings,
        wire,
        maps,
        ..Parts::default()
    };
    Ok(Scene::new(Scene::name_of(path), parts))
}

#[cfg(test)]
mod tests {
    use super::*;

    const TRI: &[u8] = b"v 0 0 0\nv 2 0 0\nv 0 2 0\nf 1 2 3\n";

    #[test]
    fn recentres_on_bounds() {
        let s = load_bytes(Path::new("t.obj"), TRI, &LoadOptions::default()).unwrap();
        assert_eq!(s.origin, DVec3::new(1.0, 1.0, 0.0));
        assert_eq!(s.bounds.min.to_array(), [-1.0, -1.0, 0.0]);
        assert_eq!(s.meshes[0].vertices[0].normal, [0.0, 0.0, 1.0]);
        assert_eq!(s.meshes[0].material, 0);
        assert_eq!(s.materials[0], Material::default());
    }

    #[test]
    fn far_model_is_identical_locally() {
        let far = b"v 1000000 -2000000 3000000\nv 1000002 -2000000 3000000\nv 1000000 -1999998 3000000\nf 1 2 3\n";
        let a = load_bytes(Path::new("t.obj"), TRI, &LoadOptions::default()).unwrap();
        let b = load_bytes(Path::new("t.obj"), far, &LoadOptions::default()).unwrap();
        assert_eq!(a.meshes[0].vertices, b.meshes[0].vertices);
    }

    #[test]
    fn missing_mtl_is_a_warning() {
        let obj = b"mtllib nowhere.mtl\nv 0 0 0\nv 2 0 0\nv 0 2 0\nusemtl x\nf 1 2 3\n";
        let s = load_bytes(
            Path::new("/nonexistent/t.obj"),
            obj,
            &LoadOptions::default(),
        )
        .unwrap();
        assert!(
            s.warnings
                .iter()
                .any(|w| w.message.contains("material library")),
            "{:?}",
            s.warnings
        );
        assert_eq!(s.materials[s.meshes[0].material], Material::default());
    }

    /// The MTL is read once: its file is opened once and each material statement block is
    /// read once (`mtl::read` takes tobj's material by value; this counts the calls), on both
    /// OBJ parsers.
    #[test]
    fn mtl_is_read_once() {
        let obj = b"mtllib a.mtl\nv 0 0 0\nv 2 0 0\nv 0 2 0\nusemtl red\nf 1 2 3\n";
        let mtl = b"newmtl red\nKd 1 0 0\nnewmtl blue\nKd 0 0 1\nd 0.5\n";
        for parser in [Parser::Auto, Parser::Tobj] {
            let opened = std::cell::Cell::new(0);
            let source = |_: &Path| {
                opened.set(opened.get() + 1);
                Ok(mtl.to_vec())
            };
            crate::loaders::obj::mtl::READS.with(|r| r.set(0));
            let s = load_with(
                Path::new("t.obj"),
                obj,
                &LoadOptions::default(),
                &source,
                parser,
            )
            .unwrap();
            let reads = crate::loaders::obj::mtl::READS.with(|r| r.get());
            assert_eq!((opened.get(), reads), (1, 2), "{parser:?}");
            assert_eq!(s.materials.len(), 3);
            assert_eq!(s.materials[0].base_color, [1.0, 0.0, 0.0]);
            assert_eq!(s.materials[1].opacity, Some(0.5));
        }
    }

    #[test]
    fn no_triangles_is_an_error() {
        // Faces that were all dropped (two corners): not a cloud.
        let bytes = b"v 0 0 0\nv 1 0 0\nf 1 2\n";
        let e = load_bytes(Path::new("t.obj"), bytes, &LoadOptions::default()).unwrap_err();
        assert_eq!(e.to_string(), "t.obj: no triangles in the file");
        let e = load_bytes(Path::new("t.obj"), b"", &LoadOptions::default()).unwrap_err();
        assert_eq!(e.to_string(), "t.obj: no triangles in the file");
    }

    #[test]
    fn vertices_only_are_a_cloud() {
        let s = load_bytes(
            Path::new("t.obj"),
            b"v 0 0 0\nv 1 0 0\n",
            &LoadOptions::default(),
        )
        .unwrap();
        assert!(s.meshes.is_empty() && s.wire.is_cloud());
        assert_eq!(s.wire.points, [0, 1]);
    }
}
