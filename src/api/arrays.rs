//! A model from arrays (vertices, faces, optional normals, uvs, colours), checked like a
//! file and then loaded through the OBJ loader, so an array model and the same data in a
//! file give the same scene: the same generated normals, up axis, centring and warnings.
use crate::error::{Error, Result};
use std::fmt::Write;

/// Triangle arrays as a binding hands them over: flat, row-major.
#[derive(Clone, Copy, Debug, Default)]
pub struct Arrays<'a> {
    /// x, y, z per vertex, in f64 as the file coordinates a loader reads (a model from
    /// a file and the same file's numbers as arrays give the same scene).
    pub vertices: &'a [f64],
    /// Three vertex indices per triangle (0-based).
    pub faces: &'a [i64],
    /// x, y, z per vertex.
    pub normals: Option<&'a [f32]>,
    /// u, v per vertex.
    pub uvs: Option<&'a [f32]>,
    /// r, g, b in 0..1 per vertex.
    pub colors: Option<&'a [f32]>,
}

fn bad(message: String) -> Error {
    Error::Model {
        path: "<arrays>".into(),
        line: None,
        message,
    }
}

impl Arrays<'_> {
    /// The arrays as OBJ text, after checking their shapes, values and indices.
    pub(crate) fn to_obj(self) -> Result<String> {
        if !self.vertices.len().is_multiple_of(3) {
            return Err(bad(format!(
                "vertices has {} numbers: expected 3 per vertex",
                self.vertices.len()
            )));
        }
        let n = self.vertices.len() / 3;
        if !self.faces.len().is_multiple_of(3) {
            return Err(bad(format!(
                "faces has {} indices: expected 3 per triangle",
                self.faces.len()
            )));
        }
        if n == 0 || self.faces.is_empty() {
            return Err(bad("no vertices or no faces".into()));
        }
        for (name, data, per) in [
            ("normals", self.normals, 3),
            ("uvs", self.uvs, 2),
            ("colors", self.colors, 3),
        ] {
            if let Some(d) = data {
                if d.len() != n * per {
                    return Err(bad(format!(
                        "{name} has {} numbers: expected {per} for each of the {n} vertices",
                        d.len()
                    )));
                }
            }
        }
        let all = [self.normals, self.uvs, self.colors];
        let finite = self.vertices.iter().all(|x| x.is_finite())
            && all
                .iter()
                .flatten()
                .flat_map(|d| d.iter())
                .all(|x| x.is_finite());
        if !finite {
            return Err(bad("a value is not finite".into()));
        }
        if let Some((i, f)) = self
            .faces
            .iter()
            .enumerate()
            .find(|(_, &f)| f < 0 || f >= n as i64)
        {
            return Err(bad(format!(
                "face {} refers to vertex {f}, but there are {n} vertices",
                i / 3
            )));
        }
        let mut s = String::with_capacity(n * 40 + self.faces.len() * 8);
        for (i, v) in self.vertices.chunks_exact(3).enumerate() {
            let _ = write!(s, "v {} {} {}", v[0], v[1], v[2]);
            if let Some(c) = self.colors {
                let _ = write!(s, " {} {} {}", c[3 * i], c[3 * i + 1], c[3 * i + 2]);
            }
            s.push('\n');
        }
        for t in self.uvs.unwrap_or_default().chunks_exact(2) {
            let _ = writeln!(s, "vt {} {}", t[0], t[1]);
        }
        for v in self.normals.unwrap_or_default().chunks_exact(3) {
            let _ = writeln!(s, "vn {} {} {}", v[0], v[1], v[2]);
        }
        let (uv, normal) = (self.uvs.is_some(), self.normals.is_some());
        for f in self.faces.chunks_exact(3) {
            s.push('f');
            for &i in f {
                let i = i + 1;
                let _ = match (uv, normal) {
                    (false, false) => write!(s, " {i}"),
                    (true, false) => write!(s, " {i}/{i}"),
                    (false, true) => write!(s, " {i}//{i}"),
                    (true, true) => write!(s, " {i}/{i}/{i}"),
                };
            }
            s.push('\n');
        }
        Ok(s)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn obj_text_and_refusals() {
        let v = [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.5, 0.0];
        let a = Arrays {
            vertices: &v,
            faces: &[0, 1, 2],
            uvs: Some(&[0.0, 0.0, 1.0, 0.0, 0.0, 1.0]),
            ..Default::default()
        };
        assert_eq!(
            a.to_obj().unwrap(),
            "v 0 0 0\nv 1 0 0\nv 0 1.5 0\nvt 0 0\nvt 1 0\nvt 0 1\nf 1/1 2/2 3/3\n"
        );
        let e = Arrays {
            faces: &[0, 1, 3],
            ..a
        }
        .to_obj()
        .unwrap_err()
        .to_string();
        assert_eq!(
            e,
            "<arrays>: face 0 refers to vertex 3, but there are 3 vertices"
        );
        let e = Arrays {
            normals: Some(&[0.0; 3]),
            ..a
        }
        .to_obj()
        .unwrap_err();
        assert!(
            e.to_string()
                .contains("expected 3 for each of the 3 vertices"),
            "{e}"
        );
        let nan = [f64::NAN; 9];
        assert!(Arrays {
            vertices: &nan,
            ..a
        }
        .to_obj()
        .is_err());
    }
}
