//! OBJ/MTL → [`Scene`]: tobj does the parsing (after [`super::repair`]); positions are read as
//! f64 and re-centred on the bounding-box centre before they are rounded to f32.
use super::material::{self, TextureOptions};
use super::{normals, repair, Bounds, Material, Mesh, Scene, Vertex, Warning};
use crate::error::{Error, Result};
use glam::DVec3;
use std::cell::RefCell;
use std::path::Path;

/// Called with (bytes scanned, total bytes) while a file is read.
pub type ProgressFn = std::sync::Arc<dyn Fn(u64, u64) + Send + Sync>;

#[derive(Clone, Default)]
pub struct LoadOptions {
    pub textures: TextureOptions,
    pub progress: Option<ProgressFn>,
    /// Use the mesh cache (`scene::cache`) for large files.
    pub cache: bool,
}

/// Reads a file, refusing what is not a regular file (directories, devices, FIFOs would hang).
pub fn read_regular_file(path: &Path) -> Result<Vec<u8>> {
    let meta = std::fs::metadata(path).map_err(|e| Error::io(path, e))?;
    if meta.is_dir() {
        return Err(Error::model(path, None, "is a directory, not an OBJ file"));
    }
    if !meta.is_file() {
        return Err(Error::model(path, None, "is not a regular file"));
    }
    std::fs::read(path).map_err(|e| Error::io(path, e))
}

/// Where MTL bytes come from: files beside the OBJ, or memory for the built-in scene.
type MtlSource<'a> = &'a dyn Fn(&Path) -> Result<Vec<u8>>;

fn load_mtl(
    obj_dir: &Path,
    name: &Path,
    source: MtlSource,
    warnings: &RefCell<Vec<Warning>>,
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
    tobj::load_mtl_buf(&mut text.as_bytes()).inspect_err(|e| {
        warn(format!("{e}; using the default material"));
    })
}

/// Loads an OBJ file (and its MTL libraries and diffuse textures).
pub fn load(path: &Path, opts: &LoadOptions) -> Result<Scene> {
    super::profile::begin(0);
    let bytes = read_regular_file(path)?;
    super::profile::set_bytes(bytes.len() as u64);
    super::profile::mark(super::profile::Stage::Read);
    let cached = opts.cache && bytes.len() as u64 >= super::cache::MIN_SIZE;
    if cached {
        if let Some(scene) = super::cache::get(path, &bytes, opts.textures) {
            log::debug!("{}: loaded from the mesh cache", path.display());
            super::profile::end(true);
            return Ok(scene);
        }
    }
    let scene = load_bytes(path, &bytes, opts)?;
    if cached {
        super::cache::put(path, &bytes, opts.textures, &scene);
    }
    Ok(scene)
}

/// Loads OBJ bytes as if they were the file `path` (MTL and textures are looked up beside it).
pub fn load_bytes(path: &Path, bytes: &[u8], opts: &LoadOptions) -> Result<Scene> {
    load_with(path, bytes, opts, &|p: &Path| read_regular_file(p))
}

/// Loads an OBJ whose MTL library is in memory too (the built-in scene).
pub fn load_embedded(path: &Path, obj: &[u8], mtl: &[u8], opts: &LoadOptions) -> Result<Scene> {
    let mtl = mtl.to_vec();
    load_with(path, obj, opts, &move |_: &Path| Ok(mtl.clone()))
}

fn load_with(
    path: &Path,
    bytes: &[u8],
    opts: &LoadOptions,
    mtl_source: MtlSource,
) -> Result<Scene> {
    let total = bytes.len() as u64;
    let report = |done: u64| {
        if let Some(p) = &opts.progress {
            p(done, total)
        }
    };
    let mut repaired = repair::repair_obj_with_progress(path, bytes, &report)?;
    super::profile::mark(super::profile::Stage::Repair);
    let dir = path.parent().unwrap_or(Path::new(".")).to_path_buf();
    let warnings = RefCell::new(std::mem::take(&mut repaired.warnings));
    let mtl_files = RefCell::new(Vec::new());
    let load_opts = tobj::LoadOptions {
        triangulate: true,
        single_index: true,
        ignore_points: true,
        ignore_lines: true,
    };
    let (models, mats) = tobj::load_obj_buf(&mut repaired.text.as_bytes(), &load_opts, |p| {
        mtl_files.borrow_mut().push(dir.join(p));
        load_mtl(&dir, p, mtl_source, &warnings)
    })
    .map_err(|e| Error::model(path, None, e.to_string()))?;
    super::profile::mark(super::profile::Stage::Parse);
    let mut warnings = warnings.into_inner();
    let mut dependencies = mtl_files.into_inner();
    let tobj_mats = mats.unwrap_or_default();
    // Texture warnings name the material library that was read (tobj does not say which of
    // several libraries a material came from; then the first one is named).
    let mtl_file = dependencies
        .first()
        .cloned()
        .unwrap_or_else(|| path.to_path_buf());
    let mut materials: Vec<Material> = tobj_mats
        .iter()
        .map(|m| material::from_tobj(m, &dir, &mtl_file, opts.textures, &mut warnings))
        .collect();
    super::profile::mark(super::profile::Stage::Textures);
    let mut reported = std::collections::HashSet::new();
    for (line, name) in &repaired.usemtl {
        if !materials.iter().any(|m| &m.name == name) && reported.insert(name.clone()) {
            warnings.push(Warning {
                file: path.to_path_buf(),
                line: Some(*line),
                message: format!("material {name:?} is not defined; using the default material"),
            });
        }
    }
    dependencies.extend(
        materials
            .iter()
            .filter_map(|m| m.diffuse_map.as_ref().map(|t| t.path.clone())),
    );
    let default_index = materials.len();
    materials.push(Material::default());

    let mut lo = DVec3::splat(f64::INFINITY);
    let mut hi = DVec3::splat(f64::NEG_INFINITY);
    for m in &models {
        for p in m.mesh.positions.chunks_exact(3) {
            let p = DVec3::new(p[0], p[1], p[2]);
            lo = lo.min(p);
            hi = hi.max(p);
        }
    }
    let origin = if lo.x <= hi.x {
        (lo + hi) * 0.5
    } else {
        DVec3::ZERO
    };

    let mut meshes = Vec::with_capacity(models.len());
    let mut bounds = Bounds::empty();
    for m in models {
        let mesh = m.mesh;
        if mesh.indices.is_empty() {
            continue;
        }
        let n = mesh.positions.len() / 3;
        let has_normals = mesh.normals.len() == n * 3;
        let has_uv = mesh.texcoords.len() == n * 2;
        let vertices: Vec<Vertex> = (0..n)
            .map(|i| {
                let p = DVec3::from_slice(&mesh.positions[i * 3..i * 3 + 3]) - origin;
                let normal = if has_normals {
                    let s = &mesh.normals[i * 3..i * 3 + 3];
                    [s[0] as f32, s[1] as f32, s[2] as f32]
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
        let material = mesh
            .material_id
            .filter(|&i| i < default_index)
            .unwrap_or(default_index);
        let mut mesh = Mesh {
            name: m.name,
            vertices,
            indices: mesh.indices,
            material,
            has_uv,
            generated_normals: 0,
        };
        mesh.generated_normals =
            normals::repair_normals(&mut mesh.vertices, &mesh.indices, !has_normals);
        for v in &mesh.vertices {
            bounds.include(v.position.into());
        }
        meshes.push(mesh);
    }
    super::profile::mark(super::profile::Stage::Meshes);
    super::finish::finish(path, &mut meshes, &materials, &mut warnings);
    if meshes.is_empty() {
        return Err(Error::model(path, None, "no triangles in the file"));
    }
    let name = path
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "model".into());
    Ok(Scene {
        name,
        meshes,
        materials,
        bounds,
        origin,
        file_bounds: (lo, hi),
        dependencies,
        warnings,
    })
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

    #[test]
    fn no_triangles_is_an_error() {
        let e = load_bytes(Path::new("t.obj"), b"v 0 0 0\n", &LoadOptions::default()).unwrap_err();
        assert_eq!(e.to_string(), "t.obj: no triangles in the file");
    }
}
