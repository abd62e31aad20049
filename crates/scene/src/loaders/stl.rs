//! STL, binary or ASCII, read as a stream (a gzipped file is never inflated whole). Binary
//! when the size matches the triangle count (even if the 80-byte header starts with "solid",
//! as many exporters write), or when the start is not ASCII STL; ASCII otherwise, CRLF or not.
//! Facet normals are ignored (often zero or wrong): normals are generated. A facet with a
//! non-finite vertex is dropped and reported with its number: the others do not depend on it.
use crate::loaders::gltf::accessor::MAX_ELEMENTS;
use crate::loaders::tokens::Tokens;
use glam::DVec3;
use std::collections::HashMap;
use std::io::{BufRead, Read};

/// Vertices welded by exact value, triangles as index triples; errors are `(line, message)`.
pub(crate) struct Raw {
    pub(crate) positions: Vec<DVec3>,
    pub(crate) corners: Vec<u32>,
    /// (facets dropped for non-finite vertices, the first one's 1-based number).
    pub(crate) non_finite: (usize, usize),
}

type Fail = (Option<usize>, String);

struct Weld {
    map: HashMap<[u32; 3], u32, foldhash::fast::RandomState>,
    out: Raw,
    facets: usize,
}

impl Weld {
    fn facet(&mut self, v: &[[f32; 3]]) -> Result<(), Fail> {
        self.facets += 1;
        if self.out.corners.len() > 3 * MAX_ELEMENTS {
            return Err((
                None,
                format!("facet {}: more than {MAX_ELEMENTS} triangles", self.facets),
            ));
        }
        if v.iter().flatten().any(|x| !x.is_finite()) {
            if self.out.non_finite.0 == 0 {
                self.out.non_finite.1 = self.facets;
            }
            self.out.non_finite.0 += 1;
            return Ok(());
        }
        // A polygon facet (ASCII allows more than three vertices) becomes a fan.
        let ids: Vec<u32> = v
            .iter()
            .map(|p| {
                // -0.0 and 0.0 are one point.
                let key = p.map(|x| (x + 0.0).to_bits());
                let next = self.out.positions.len() as u32;
                *self.map.entry(key).or_insert_with(|| {
                    self.out
                        .positions
                        .push(DVec3::new(p[0].into(), p[1].into(), p[2].into()));
                    next
                })
            })
            .collect();
        for k in 1..ids.len().saturating_sub(1) {
            self.out.corners.extend([ids[0], ids[k], ids[k + 1]]);
        }
        Ok(())
    }
}

/// Reads an STL stream of `size` bytes (when known).
pub(crate) fn read<R: BufRead>(mut r: R, size: Option<u64>) -> Result<Raw, Fail> {
    let mut head = Vec::with_capacity(84);
    r.by_ref()
        .take(84)
        .read_to_end(&mut head)
        .map_err(|e| (None, e.to_string()))?;
    let count =
        (head.len() == 84).then(|| u32::from_le_bytes([head[80], head[81], head[82], head[83]]));
    let size_matches = matches!((count, size), (Some(n), Some(s)) if 84 + 50 * u64::from(n) == s);
    let text = head.trim_ascii_start();
    let ascii_start = text.starts_with(b"solid")
        && head
            .iter()
            .all(|&b| b.is_ascii_graphic() || b.is_ascii_whitespace());
    let mut w = Weld {
        map: HashMap::default(),
        out: Raw {
            positions: Vec::new(),
            corners: Vec::new(),
            non_finite: (0, 0),
        },
        facets: 0,
    };
    if size_matches || (!ascii_start && count.is_some()) {
        let n = count.unwrap_or(0) as usize;
        if n > MAX_ELEMENTS {
            return Err((
                None,
                format!("header claims {n} facets, more than glview reads ({MAX_ELEMENTS})"),
            ));
        }
        if let Some(s) = size {
            if 84 + 50 * n as u64 > s {
                return Err((
                    None,
                    format!(
                        "not an STL file (binary header claims {n} facets, the file holds {})",
                        s.saturating_sub(84) / 50
                    ),
                ));
            }
        }
        let mut f = [0u8; 50];
        for i in 0..n {
            r.read_exact(&mut f)
                .map_err(|_| (None, format!("the file ends in facet {} of {n}", i + 1)))?;
            let c = |k: usize| f32::from_le_bytes([f[k], f[k + 1], f[k + 2], f[k + 3]]);
            let v = [12, 24, 36].map(|o| [c(o), c(o + 4), c(o + 8)]);
            w.facet(&v)?;
        }
        return Ok(w.out);
    }
    if !ascii_start {
        return Err((
            None,
            "not an STL file (no 'solid' header, and too short for a binary STL)".into(),
        ));
    }
    let mut toks = Tokens::new(std::io::Cursor::new(head).chain(r), 1);
    let mut verts: Vec<[f32; 3]> = Vec::new();
    let fail = |t: &Tokens<_>, m: String| (Some(t.line), m);
    while let Some(t) = toks.token().map_err(|m| (None, m))? {
        let t = t.to_vec();
        let t = t.as_slice();
        match t {
            b"solid" => toks.skip_line().map_err(|m| (None, m))?,
            b"vertex" => {
                let facet = w.facets + 1;
                let mut p = [0f32; 3];
                for c in &mut p {
                    *c = toks
                        .number(&format!("facet {facet}: vertex"))
                        .map_err(|m| fail(&toks, m))? as f32;
                }
                if verts.len() >= 1024 {
                    return Err(fail(
                        &toks,
                        format!("facet {facet} has more than 1024 vertices"),
                    ));
                }
                verts.push(p);
            }
            b"endfacet" => {
                if w.facets >= MAX_ELEMENTS {
                    return Err(fail(&toks, format!("more than {MAX_ELEMENTS} facets")));
                }
                w.facet(&verts).map_err(|(_, m)| fail(&toks, m))?;
                verts.clear();
            }
            _ => {}
        }
    }
    Ok(w.out)
}
