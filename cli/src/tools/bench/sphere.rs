//! The load benchmark's large model: a UV sphere OBJ with about a given number of triangles,
//! positions and unit normals (`f a//a b//b c//c`), written once into a cache folder.
use glview::{Error, Result};
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

/// Rings (latitude bands) and segments (longitude steps) for about `triangles` triangles:
/// two per quad between inner rings, one per segment in each polar cap, so
/// 2 · segments · (rings − 1) in all, with segments ≈ 2 · rings.
pub fn grid(triangles: u64) -> (u32, u32) {
    let rings = (((triangles.max(8) as f64) / 4.0).sqrt().round() as u32 + 1).max(3);
    let segments = (triangles.max(8) / (2 * u64::from(rings - 1))).max(3) as u32;
    (rings, segments)
}

pub fn triangle_count(rings: u32, segments: u32) -> u64 {
    2 * u64::from(segments) * u64::from(rings - 1)
}

/// The sphere's path in `dir`, written if missing (or left incomplete by an earlier run).
pub fn ensure(dir: &Path, triangles: u64) -> Result<PathBuf> {
    let (rings, segments) = grid(triangles);
    let n = triangle_count(rings, segments);
    let path = dir.join(format!("sphere_{n}.obj"));
    let done = dir.join(format!("sphere_{n}.obj.done"));
    if path.is_file() && done.is_file() {
        return Ok(path);
    }
    super::ensure_dir(dir)?;
    let file = std::fs::File::create(&path).map_err(|e| Error::io(&path, e))?;
    write(
        &mut BufWriter::with_capacity(1 << 20, file),
        rings,
        segments,
    )
    .and_then(|w| w.flush())
    .map_err(|e| Error::io(&path, e))?;
    super::write_file(&done, "")?;
    Ok(path)
}

fn write<W: Write>(w: &mut W, rings: u32, segments: u32) -> std::io::Result<&mut W> {
    writeln!(
        w,
        "# UV sphere, {rings} rings x {segments} segments, {} triangles (glview bench)",
        triangle_count(rings, segments)
    )?;
    // Vertex 1 is the north pole, then rings − 1 rings of `segments` vertices, then the
    // south pole.
    let vertex = |w: &mut W, p: [f64; 3]| -> std::io::Result<()> {
        writeln!(w, "v {:.6} {:.6} {:.6}", p[0], p[1], p[2])?;
        writeln!(w, "vn {:.6} {:.6} {:.6}", p[0], p[1], p[2])
    };
    vertex(w, [0.0, 1.0, 0.0])?;
    for j in 1..rings {
        let theta = std::f64::consts::PI * f64::from(j) / f64::from(rings);
        for i in 0..segments {
            let phi = std::f64::consts::TAU * f64::from(i) / f64::from(segments);
            vertex(
                w,
                [
                    theta.sin() * phi.cos(),
                    theta.cos(),
                    theta.sin() * phi.sin(),
                ],
            )?;
        }
    }
    vertex(w, [0.0, -1.0, 0.0])?;
    let ring = |j: u32, i: u32| 2 + (j - 1) * segments + (i % segments);
    let south = 2 + (rings - 1) * segments;
    let face = |w: &mut W, a: u32, b: u32, c: u32| writeln!(w, "f {a}//{a} {b}//{b} {c}//{c}");
    // Counter-clockwise seen from outside: north → east → south order on the surface.
    for i in 0..segments {
        face(w, 1, ring(1, i + 1), ring(1, i))?;
    }
    for j in 1..rings - 1 {
        for i in 0..segments {
            let (a, b) = (ring(j, i), ring(j, i + 1));
            let (c, d) = (ring(j + 1, i), ring(j + 1, i + 1));
            face(w, a, b, d)?;
            face(w, a, d, c)?;
        }
    }
    for i in 0..segments {
        face(w, ring(rings - 1, i), ring(rings - 1, i + 1), south)?;
    }
    Ok(w)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn about_a_million() {
        let (r, s) = grid(1_000_000);
        let n = triangle_count(r, s);
        assert!((n as i64 - 1_000_000).abs() < 5_000, "{r} x {s} = {n}");
    }

    #[test]
    fn small_sphere_loads_with_outward_faces() {
        let dir = std::env::temp_dir().join(format!("glview-sphere-{}", std::process::id()));
        let path = ensure(&dir, 200).unwrap();
        let scene = glview::scene::load(&path, &Default::default()).unwrap();
        let (r, s) = grid(200);
        assert_eq!(scene.triangle_count() as u64, triangle_count(r, s));
        for m in &scene.meshes {
            for t in m.indices.chunks_exact(3) {
                let p = |k: usize| glam::Vec3::from(m.vertices[t[k] as usize].position);
                let n = (p(1) - p(0)).cross(p(2) - p(0));
                let centre = (p(0) + p(1) + p(2)) / 3.0;
                assert!(n.dot(centre) > 0.0, "inward face {t:?}");
            }
        }
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
