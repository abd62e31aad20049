//! STL (ASCII and binary, `stl_io`) and PLY (ASCII and binary, `ply-rs`), optionally gzipped
//! (`flate2`), into the same [`Scene`] as OBJ: re-centred in f64, polygons triangulated like
//! OBJ faces, normals generated with the same creases. Bad input is a one-line error naming
//! the file, as for OBJ.
use super::obj::LoadOptions;
use super::{triangulate, Bounds, Material, Mesh, Scene, Vertex, Wire};
use crate::error::{Error, Result};
use glam::DVec3;
use ply_rs::ply::Property;
use std::io::Read;
use std::path::Path;

/// Largest decompressed size accepted from a `.gz` file (a gzip bomb stops here).
const MAX_INFLATED: u64 = 4 << 30;

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

pub fn gunzip(path: &Path, bytes: &[u8]) -> Result<Vec<u8>> {
    let mut out = Vec::new();
    flate2::read::GzDecoder::new(bytes)
        .take(MAX_INFLATED + 1)
        .read_to_end(&mut out)
        .map_err(|e| Error::model(path, None, format!("not a valid gzip file: {e}")))?;
    if out.len() as u64 > MAX_INFLATED {
        return Err(Error::model(path, None, "decompresses to more than 4 GiB"));
    }
    Ok(out)
}

/// What a mesh file gave: positions, polygons, and optional per-vertex normals and colours.
struct Raw {
    positions: Vec<DVec3>,
    faces: Vec<Vec<u32>>,
    normals: Option<Vec<[f32; 3]>>,
    colors: Option<Vec<[f32; 3]>>,
}

pub fn load_stl(path: &Path, bytes: &[u8], opts: &LoadOptions) -> Result<Scene> {
    let bad = |m: String| Error::model(path, None, m);
    // A binary STL states its triangle count: check it against the size before stl_io
    // allocates for it. ASCII files start with "solid" (binary ones may too, so the size
    // decides first).
    let binary_size_ok = bytes.len() >= 84 && {
        let n = u32::from_le_bytes([bytes[80], bytes[81], bytes[82], bytes[83]]) as u64;
        84 + 50 * n == bytes.len() as u64
    };
    if !binary_size_ok && !bytes.trim_ascii_start().starts_with(b"solid") {
        return Err(bad(
            "not an STL file (no 'solid' header, and the size does not match a binary STL's \
             triangle count)"
                .into(),
        ));
    }
    let mesh = stl_io::read_stl(&mut std::io::Cursor::new(bytes))
        .map_err(|e| bad(format!("not a valid STL file: {e}")))?;
    let positions = mesh
        .vertices
        .iter()
        .map(|v| DVec3::new(v.0[0].into(), v.0[1].into(), v.0[2].into()))
        .collect();
    let faces = mesh
        .faces
        .iter()
        .map(|f| f.vertices.iter().map(|&i| i as u32).collect())
        .collect();
    build(
        path,
        Raw {
            positions,
            faces,
            normals: None,
            colors: None,
        },
        opts,
    )
}

fn scalar(p: &Property) -> Option<f64> {
    Some(match *p {
        Property::Char(x) => x.into(),
        Property::UChar(x) => x.into(),
        Property::Short(x) => x.into(),
        Property::UShort(x) => x.into(),
        Property::Int(x) => x.into(),
        Property::UInt(x) => x.into(),
        Property::Float(x) => x.into(),
        Property::Double(x) => x,
        _ => return None,
    })
}

fn list(p: &Property) -> Option<Vec<i64>> {
    Some(match p {
        Property::ListChar(v) => v.iter().map(|&x| x.into()).collect(),
        Property::ListUChar(v) => v.iter().map(|&x| x.into()).collect(),
        Property::ListShort(v) => v.iter().map(|&x| x.into()).collect(),
        Property::ListUShort(v) => v.iter().map(|&x| x.into()).collect(),
        Property::ListInt(v) => v.iter().map(|&x| x.into()).collect(),
        Property::ListUInt(v) => v.iter().map(|&x| x.into()).collect(),
        _ => return None,
    })
}

pub fn load_ply(path: &Path, bytes: &[u8], opts: &LoadOptions) -> Result<Scene> {
    let bad = |m: String| Error::model(path, None, m);
    if !bytes.starts_with(b"ply") {
        return Err(bad("not a PLY file (no 'ply' magic)".into()));
    }
    // Element counts in the header are checked against the file size before ply-rs
    // allocates for them: every element takes at least one byte.
    let header_end = bytes
        .windows(10)
        .position(|w| w == b"end_header")
        .ok_or_else(|| bad("PLY header has no end_header".into()))?;
    for line in String::from_utf8_lossy(&bytes[..header_end]).lines() {
        let w: Vec<&str> = line.split_whitespace().collect();
        if w.first() == Some(&"element") {
            let n: u64 = w.get(2).and_then(|n| n.parse().ok()).unwrap_or(u64::MAX);
            if n > bytes.len() as u64 {
                return Err(bad(format!(
                    "header claims {n} {} elements, more than the file can hold",
                    w.get(1).unwrap_or(&"?")
                )));
            }
        }
    }
    let parser = ply_rs::parser::Parser::<ply_rs::ply::DefaultElement>::new();
    let ply = parser
        .read_ply(&mut std::io::Cursor::new(bytes))
        .map_err(|e| bad(format!("not a valid PLY file: {e}")))?;
    let empty = Vec::new();
    let verts = ply.payload.get("vertex").unwrap_or(&empty);
    let get = |e: &ply_rs::ply::DefaultElement, k: &str| e.get(k).and_then(scalar);
    let mut positions = Vec::with_capacity(verts.len());
    for (i, v) in verts.iter().enumerate() {
        let p = match (get(v, "x"), get(v, "y"), get(v, "z")) {
            (Some(x), Some(y), Some(z)) => DVec3::new(x, y, z),
            _ => return Err(bad(format!("vertex {i} has no x, y, z"))),
        };
        if !p.is_finite() || p.abs().max_element() > f64::from(f32::MAX) {
            return Err(bad(format!("vertex {i} position is not finite: {p}")));
        }
        positions.push(p);
    }
    let normals = verts
        .iter()
        .map(|v| {
            Some([
                get(v, "nx")? as f32,
                get(v, "ny")? as f32,
                get(v, "nz")? as f32,
            ])
        })
        .collect::<Option<Vec<_>>>()
        .filter(|n| !n.is_empty());
    // Colours: uchar 0..255 (the common case) or float 0..1.
    let colors = verts
        .iter()
        .map(|v| {
            let c = |k: &str| match v.get(k)? {
                Property::UChar(x) => Some(f32::from(*x) / 255.0),
                p => scalar(p).map(|x| x as f32),
            };
            Some([c("red")?, c("green")?, c("blue")?])
        })
        .collect::<Option<Vec<_>>>()
        .filter(|c| !c.is_empty());
    let n = positions.len() as i64;
    let mut faces = Vec::new();
    for (i, f) in ply.payload.get("face").unwrap_or(&empty).iter().enumerate() {
        let idx = f
            .get("vertex_indices")
            .or_else(|| f.get("vertex_index"))
            .and_then(list)
            .ok_or_else(|| bad(format!("face {i} has no vertex_indices list")))?;
        if let Some(&k) = idx.iter().find(|&&k| k < 0 || k >= n) {
            return Err(bad(format!(
                "face {i}: vertex index {k} out of range (file has {n} vertices)"
            )));
        }
        faces.push(idx.into_iter().map(|k| k as u32).collect());
    }
    build(
        path,
        Raw {
            positions,
            faces,
            normals,
            colors,
        },
        opts,
    )
}

/// One mesh with the default material, re-centred and rotated like an OBJ.
fn build(path: &Path, raw: Raw, opts: &LoadOptions) -> Result<Scene> {
    let positions: Vec<DVec3> = raw.positions.iter().map(|&p| opts.up.rotate(p)).collect();
    let (lo, hi, origin) =
        super::extent_and_origin(raw.faces.iter().flatten().map(|&i| positions[i as usize]));
    let mut indices = Vec::new();
    let mut dropped = 0;
    for f in &raw.faces {
        let mut d = f.clone();
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
    let colors = raw.colors.unwrap_or_default();
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
    };
    // STL's per-facet normals are often wrong or zero: then generated from the geometry.
    mesh.finish_normals(normal_ok, None, opts.creases);
    let mut bounds = Bounds::empty();
    for v in &mesh.vertices {
        bounds.include(v.position.into());
    }
    let mut warnings = Vec::new();
    if dropped > 0 {
        warnings.push(super::Warning {
            file: path.to_path_buf(),
            line: None,
            message: format!("dropped {dropped} face(s) with fewer than 3 distinct corners"),
        });
    }
    let mut material = Material::default();
    if let Some(t) = &opts.texture {
        warnings.push(super::Warning {
            file: t.clone(),
            line: None,
            message: "--texture: this file has no texture coordinates; ignored".into(),
        });
    }
    material.name = "default".into();
    Ok(Scene {
        name: mesh.name.clone(),
        meshes: vec![mesh],
        materials: vec![material],
        bounds,
        origin,
        file_bounds: (lo, hi),
        dependencies: Vec::new(),
        warnings,
        wire: Wire::default(),
        maps: Vec::new(),
    })
}
