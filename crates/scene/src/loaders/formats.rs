//! STL (`crate::loaders::stl`) and PLY (`crate::loaders::ply`), optionally gzipped (`flate2`, read as a
//! stream), into the same [`Scene`] as OBJ: re-centred in f64, polygons triangulated like
//! OBJ faces, normals generated with the same creases. Bad input is a one-line error naming
//! the file, as for OBJ.
use crate::error::{Error, Result};
use crate::load::options::LoadOptions;
use crate::model::scene::Parts;
use glam::DVec3;
use std::io::Read;
use std::path::Path;
use {
    crate::geometry::triangulate, crate::model::material::Material, crate::model::Bounds,
    crate::model::Mesh, crate::model::Scene, crate::model::Vertex, crate::model::Wire,
};

/// Largest decompressed size accepted from a gzipped OBJ (a gzip bomb stops here). STL and
/// PLY are read as streams and need no such bound: their element counts are.
const MAX_INFLATED: u64 = 1 << 30;

/// Largest inflated STL or PLY stream read (the rest is not looked at).
pub(crate) const MAX_STREAM: u64 = 2 << 30;

/// Model formats glview reads, from the file name.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    Obj,
    Stl,
    Ply,
    Gltf,
}

/// The format and whether the file is gzipped (`model.ply.gz`).
pub fn format_of(path: &Path) -> (Format, bool) {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().to_ascii_lowercase())
        .unwrap_or_default();
    let (stem, gz) = match name.strip_suffix(".gz") {
        Some(s) => (s.to_string(), true),
        None => (name, false),
    };
    let f = if stem.ends_with(".stl") {
        Format::Stl
    } else if stem.ends_with(".ply") {
        Format::Ply
    } else if stem.ends_with(".gltf") || stem.ends_with(".glb") {
        Format::Gltf
    } else {
        Format::Obj
    };
    (f, gz)
}

pub(crate) fn gunzip(path: &Path, bytes: &[u8]) -> Result<Vec<u8>> {
    let mut out = Vec::new();
    flate2::read::GzDecoder::new(bytes)
        .take(MAX_INFLATED + 1)
        .read_to_end(&mut out)
        .map_err(|e| Error::model(path, None, format!("not a valid gzip file: {e}")))?;
    if out.len() as u64 > MAX_INFLATED {
        return Err(Error::model(path, None, "decompresses to more than 1 GiB"));
    }
    Ok(out)
}

/// A stream error (gzip included) or a parse error, as one line naming the file.
fn fail(path: &Path, (line, m): (Option<usize>, String)) -> Error {
    Error::model(path, line, m.replace('\n', "; "))
}

/// What a mesh file gave: positions, polygons (flat corners and their counts), and optional
/// per-vertex normals and colours.
struct Raw {
    positions: Vec<DVec3>,
    corners: Vec<u32>,
    sizes: Vec<u32>,
    normals: Option<Vec<[f32; 3]>>,
    colors: Option<Vec<[f32; 3]>>,
}

/// "facet 7" or "facet 7 and 2 more": the dropped facets named in the error and the warning
/// alike (the error said "and 0 more" for a single facet).
fn facets(first: impl std::fmt::Display, dropped: usize) -> String {
    match dropped {
        0 | 1 => format!("facet {first}"),
        n => format!("facet {first} and {} more", n - 1),
    }
}

pub(crate) fn load_stl(
    path: &Path,
    r: impl std::io::BufRead,
    size: Option<u64>,
    opts: &LoadOptions,
) -> Result<Scene> {
    let raw = crate::loaders::stl::read(r, size).map_err(|e| fail(path, e))?;
    let (dropped, first) = raw.non_finite;
    let n = raw.corners.len() / 3;
    let mut scene = build(
        path,
        Raw {
            positions: raw.positions,
            corners: raw.corners,
            sizes: vec![3; n],
            normals: None,
            colors: None,
        },
        opts,
    )
    .map_err(|e| match e {
        Error::Model { message, .. } if dropped > 0 => Error::model(
            path,
            None,
            format!(
                "{message} ({}: non-finite vertices, dropped)",
                facets(first, dropped)
            ),
        ),
        e => e,
    })?;
    if dropped > 0 {
        scene.warnings.push(crate::model::Warning {
            file: path.to_path_buf(),
            line: None,
            message: format!(
                "{}: non-finite vertex coordinates; dropped",
                facets(first, dropped)
            ),
        });
    }
    Ok(scene)
}

pub(crate) fn load_ply(
    path: &Path,
    r: impl std::io::BufRead,
    size: Option<u64>,
    opts: &LoadOptions,
) -> Result<Scene> {
    let raw = crate::loaders::ply::read(r, size).map_err(|e| fail(path, e))?;
    build(
        path,
        Raw {
            positions: raw.positions,
            corners: raw.corners,
            sizes: raw.sizes,
            normals: raw.normals,
            colors: raw.colors,
        },
        opts,
    )
}

/// One mesh with the default material, re-centred and rotated like an OBJ.
fn build(path: &Path, raw: Raw, opts: &LoadOptions) -> Result<Scene> {
    if raw.sizes.is_empty() && !raw.positions.is_empty() {
        return Ok(cloud(path, raw.positions, raw.normals, raw.colors, opts));
    }
    let positions: Vec<DVec3> = raw.positions.iter().map(|&p| opts.up.rotate(p)).collect();
    let (lo, hi, origin) =
        crate::model::extent_and_origin(raw.corners.iter().map(|&i| positions[i as usize]));
    let mut indices = Vec::new();
    let mut dropped = 0;
    let mut at = 0;
    for &size in &raw.sizes {
        let f = &raw.corners[at..at + size as usize];
        at += size as usize;
        let mut d = f.to_vec();
        d.sort_unstable();
        d.dedup();
        if d.len() < 3 {
            dropped += 1;
            continue;
        }
        let p: Vec<DVec3> = f.iter().map(|&i| positions[i as usize]).collect();
        for t in triangulate::polygon(&p) {
            indices.extend(t.map(|c| f[c]));
        }
    }
    if indices.is_empty() {
        return Err(Error::model(path, None, "no triangles in the file"));
    }
    let normal_ok = raw
        .normals
        .as_ref()
        .is_some_and(|n| n.len() == positions.len());
    let vertices: Vec<Vertex> = positions
        .iter()
        .enumerate()
        .map(|(i, p)| Vertex {
            position: (*p - origin).as_vec3().into(),
            normal: match &raw.normals {
                Some(n) if normal_ok => {
                    let r = opts.up.rotate(glam::Vec3::from(n[i]).as_dvec3());
                    r.as_vec3().into()
                }
                _ => [0.0; 3],
            },
            uv: [0.0; 2],
        })
        .collect();
    // (A PLY with two vertex elements has more positions than colours: then none.)
    let colors = raw
        .colors
        .filter(|c| c.len() == positions.len())
        .unwrap_or_default();
    let mut mesh = Mesh {
        name: path
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default(),
        vertices,
        indices,
        material: 0,
        has_uv: false,
        generated_normals: 0,
        colors,
        ..Default::default()
    };
    // STL's per-facet normals are often wrong or zero: then generated from the geometry.
    mesh.finish_normals(normal_ok, None, opts.creases);
    let mut bounds = Bounds::empty();
    for v in &mesh.vertices {
        bounds.include(v.position.into());
    }
    let mut warnings = Vec::new();
    if dropped > 0 {
        warnings.push(crate::model::Warning {
            file: path.to_path_buf(),
            line: None,
            message: format!("dropped {dropped} face(s) with fewer than 3 distinct corners"),
        });
    }
    let mut material = Material::default();
    if let Some(t) = &opts.texture {
        warnings.push(crate::model::Warning {
            file: t.clone(),
            line: None,
            message: "--texture: this file has no texture coordinates; ignored".into(),
        });
    }
    material.name = "default".into();
    let name = mesh.name.clone();
    let parts = Parts {
        meshes: vec![mesh].into(),
        materials: vec![material],
        bounds,
        origin,
        file_bounds: (lo, hi),
        warnings,
        ..Parts::default()
    };
    Ok(Scene::new(name, parts))
}

/// A file of vertices and no faces (a scan, photogrammetry): every vertex a point, with its
/// normal and colour where the file gives them all. The material is white, so a colour is
/// drawn as given.
fn cloud(
    path: &Path,
    positions: Vec<DVec3>,
    normals: Option<Vec<[f32; 3]>>,
    colors: Option<Vec<[f32; 3]>>,
    opts: &LoadOptions,
) -> Scene {
    let mut positions = positions;
    for p in &mut positions {
        *p = opts.up.rotate(*p);
    }
    let (lo, hi, origin) = crate::model::extent_and_origin(positions.iter().copied());
    let mut bounds = Bounds::empty();
    let local: Vec<[f32; 3]> = positions
        .iter()
        .map(|p| {
            let l = (*p - origin).as_vec3();
            bounds.include(l);
            l.into()
        })
        .collect();
    drop(positions);
    let n = local.len();
    let normals = normals
        .filter(|v| v.len() == n)
        .map(|v| {
            v.iter()
                .map(|q| {
                    let r = opts.up.rotate(glam::Vec3::from(*q).as_dvec3());
                    r.normalize_or_zero().as_vec3().into()
                })
                .collect()
        })
        .unwrap_or_default();
    let wire = Wire {
        positions: local,
        segments: Vec::new(),
        points: (0..n as u32).collect(),
        colors: colors.filter(|c| c.len() == n).unwrap_or_default(),
        normals,
    };
    let material = Material {
        name: "point cloud".into(),
        ..Material::cloud()
    };
    let name = path
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    let parts = Parts {
        materials: vec![material],
        bounds,
        origin,
        file_bounds: (lo, hi),
        wire,
        ..Parts::default()
    };
    Scene::new(name, parts)
}
