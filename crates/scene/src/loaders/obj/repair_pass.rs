//! The OBJ repair pass itself ([`crate::loaders::obj::repair::repair_obj_with_progress`]): one method per kind of
//! statement, sharing the text being written for tobj and the counts the final warnings
//! report.
use crate::error::Error;
use crate::model::Warning;
use std::borrow::Cow;
use std::path::Path;
use {
    crate::loaders::obj::repair::is_name_statement, crate::loaders::obj::repair::keyword,
    crate::loaders::obj::repair::resolve, crate::loaders::obj::repair::Counts,
    crate::loaders::obj::repair::Repaired,
};

/// One repair pass over an OBJ file's logical lines: what has been written for tobj and
/// gathered so far (`out`), where the pass is in the file, and the counts the warnings at the
/// end report.
pub(super) struct Pass<'p> {
    path: &'p Path,
    out: Repaired,
    /// Elements in the whole file: indices are checked against these.
    total: Counts,
    /// Elements before the current line: negative indices count back from these.
    seen: Counts,
    /// Only some `v` lines have a colour (the others are written out white).
    mixed_colours: bool,
    /// A file without faces: `v` colours and `vn` normals are kept for its points.
    keep_colours: bool,
    keep_normals: bool,
    lossy_lines: usize,
    missing_refs: usize,
    unknown: usize,
    /// The smoothing group of the faces that follow, and whether the file has any `s`.
    group: u32,
    has_groups: bool,
    /// Scratch space for faces, reused across lines.
    corners: Vec<usize>,
    distinct: Vec<usize>,
}

impl<'p> Pass<'p> {
    pub(super) fn new(path: &'p Path, len: usize, total: Counts) -> Self {
        Pass {
            path,
            out: Repaired {
                text: String::with_capacity(len),
                positions: Vec::with_capacity(total.v),
                ..Repaired::default()
            },
            mixed_colours: total.coloured > 0 && total.coloured < total.v,
            keep_colours: total.f == 0 && total.coloured > 0,
            keep_normals: total.f == 0 && total.v > 0 && total.vn == total.v,
            total,
            seen: Counts::default(),
            lossy_lines: 0,
            missing_refs: 0,
            unknown: 0,
            group: 0,
            has_groups: false,
            corners: Vec::new(),
            distinct: Vec::new(),
        }
    }

    pub(super) fn warn(&mut self, line: Option<usize>, message: String) {
        self.out.warnings.push(Warning {
            file: self.path.to_path_buf(),
            line,
            message,
        });
    }

    /// Checks one logical line, gathers what it holds and writes it to the text for tobj:
    /// as it is, repaired, or not at all (statements tobj need not see, or would reject).
    pub(super) fn statement(&mut self, lineno: usize, raw: &[u8]) -> Result<(), Error> {
        let path = self.path;
        let err = |msg: String| Error::model(path, Some(lineno), msg);
        let kw = keyword(raw);
        let line: Cow<str> = match std::str::from_utf8(raw) {
            Ok(s) => s.into(),
            Err(_) if is_name_statement(kw) => {
                self.lossy_lines += 1;
                String::from_utf8_lossy(raw).into_owned().into()
            }
            Err(_) => return Err(err("non-UTF-8 bytes where a number should be".into())),
        };
        let mut words = line.split_whitespace();
        let first = words.next().unwrap_or("");
        match first {
            "v" => return self.vertex(lineno, &line, words),
            "s" => {
                self.has_groups = true;
                let arg = words.next().unwrap_or("0");
                self.group = if arg.eq_ignore_ascii_case("off") {
                    0
                } else {
                    arg.parse::<u32>().unwrap_or(0)
                };
                return Ok(());
            }
            "l" | "p" => return self.line_or_points(lineno, first, words),
            "vt" => self.seen.vt += 1,
            "vn" => {
                self.seen.vn += 1;
                if self.keep_normals {
                    self.cloud_normal(words);
                }
            }
            "f" => return self.face(lineno, words),
            "usemtl" if line.trim() == "usemtl" => {
                self.warn(Some(lineno), "empty usemtl ignored".into());
                return Ok(());
            }
            "usemtl" => self
                .out
                .usemtl
                .push((lineno, line.trim()[6..].trim().to_string())),
            "" | "vp" | "o" | "g" | "mtllib" => {}
            w if w.starts_with('#') => {}
            _ => {
                self.unknown += 1;
                return Ok(());
            }
        }
        self.out.text.push_str(&line);
        self.out.text.push('\n');
        Ok(())
    }

    /// A `v` line (`words` after the keyword): its position checked (finite, within f32) and
    /// kept for lines and points, and the line written, with a white colour added if others
    /// have one.
    fn vertex<'a>(
        &mut self,
        lineno: usize,
        line: &str,
        words: impl Iterator<Item = &'a str>,
    ) -> Result<(), Error> {
        let err = |msg: String| Error::model(self.path, Some(lineno), msg);
        self.seen.v += 1;
        let nums: Vec<&str> = words.collect();
        if nums.len() < 3 {
            return Err(err(format!("vertex needs 3 coordinates: {}", line.trim())));
        }
        let mut p = [0.0f64; 3];
        for (k, w) in nums.iter().take(3).enumerate() {
            let x: f64 = w.parse().map_err(|_| err(format!("not a number: {w:?}")))?;
            p[k] = x;
            if !x.is_finite() {
                return Err(err(format!("vertex position is not finite: {w}")));
            }
            // Positions become f32 on the GPU: beyond its range they would be ±inf.
            if x.abs() > f64::from(f32::MAX) {
                return Err(err(format!(
                    "vertex position out of range (beyond 32-bit float): {w}"
                )));
            }
        }
        // tobj reads `v x y z w` as homogeneous; keep the same meaning here.
        if nums.len() == 4 {
            if let Ok(w) = nums[3].parse::<f64>() {
                if w != 0.0 && w.is_finite() {
                    p = p.map(|x| x / w);
                }
            }
        }
        self.out.positions.push(p);
        if self.keep_colours {
            // Colours written 0–255 (some exporters) are read as such where one exceeds 1.
            let c: Vec<f32> = nums
                .get(3..6)
                .filter(|_| nums.len() == 6)
                .map_or(Vec::new(), |c| {
                    c.iter().filter_map(|w| w.parse().ok()).collect()
                });
            let c = if c.len() == 3 && c.iter().all(|x: &f32| x.is_finite()) {
                let scale = if c.iter().any(|&x| x > 1.0) {
                    255.0
                } else {
                    1.0
                };
                [c[0], c[1], c[2]].map(|x| (x / scale).clamp(0.0, 1.0))
            } else {
                [1.0; 3]
            };
            self.out.colours.push(c);
        }
        // tobj fails without a line number when only some vertices have a colour:
        // the others get white, as written out for tobj.
        if self.mixed_colours && nums.len() != 6 {
            self.out.uncoloured += 1;
            let text = &mut self.out.text;
            text.push_str(&format!("v {} {} {} 1 1 1\n", p[0], p[1], p[2]));
            return Ok(());
        }
        self.out.text.push_str(line);
        self.out.text.push('\n');
        Ok(())
    }

    /// A `vn` line of a file without faces: kept as the next vertex's normal; a malformed one
    /// drops them all (the points are then drawn unlit).
    fn cloud_normal<'a>(&mut self, words: impl Iterator<Item = &'a str>) {
        let n: Vec<f32> = words.take(3).filter_map(|w| w.parse().ok()).collect();
        match n[..] {
            [x, y, z] if x.is_finite() && y.is_finite() && z.is_finite() => {
                self.out.normals.push([x, y, z])
            }
            _ => {
                self.keep_normals = false;
                self.out.normals = Vec::new();
            }
        }
    }

    /// An `l` or `p` line (`first`; `words` after it): its vertex indices checked and kept as
    /// segments (a polyline split, one index a point) or points; tobj does not see it.
    fn line_or_points<'a>(
        &mut self,
        lineno: usize,
        first: &str,
        words: impl Iterator<Item = &'a str>,
    ) -> Result<(), Error> {
        let err = |msg: String| Error::model(self.path, Some(lineno), msg);
        let mut idx = Vec::new();
        for c in words {
            let v = c.split('/').next().unwrap_or("");
            let v: i64 = v
                .parse()
                .map_err(|_| err(format!("bad {first} index {c:?}")))?;
            match resolve(v, self.seen.v) {
                Some(i) if i < self.total.v => idx.push(i as u32),
                _ => {
                    return Err(err(format!(
                        "{first} vertex index {v} out of range (file has {} vertices)",
                        self.total.v
                    )))
                }
            }
        }
        if first == "p" {
            self.out.points.extend(idx);
        } else if idx.len() == 1 {
            self.out.points.push(idx[0]);
        } else {
            self.out
                .segments
                .extend(idx.windows(2).map(|w| [w[0], w[1]]));
        }
        Ok(())
    }

    /// An `f` line (`words` after the keyword): each corner checked and written with absolute
    /// 1-based indices, references to a missing UV or normal left out (counted), and the face
    /// dropped if it has fewer than three distinct corners.
    fn face<'a>(
        &mut self,
        lineno: usize,
        words: impl Iterator<Item = &'a str>,
    ) -> Result<(), Error> {
        let Pass {
            path,
            out,
            total,
            seen,
            missing_refs,
            group,
            corners,
            distinct,
            ..
        } = self;
        let err = |msg: String| Error::model(*path, Some(lineno), msg);
        let text = &mut out.text;
        // Written straight into `text` (no String per corner) and cut off again if the
        // face turns out to have fewer than three distinct corners.
        let face_start = text.len();
        text.push('f');
        corners.clear();
        for c in words {
            let mut parts = c.split('/');
            let parse = |s: Option<&str>| -> Result<Option<i64>, Error> {
                match s {
                    None | Some("") => Ok(None),
                    Some(s) => s
                        .parse::<i64>()
                        .map(Some)
                        .map_err(|_| err(format!("bad face index {s:?}"))),
                }
            };
            let v = parse(parts.next())?
                .ok_or_else(|| err(format!("face corner without a vertex: {c:?}")))?;
            let vt = parse(parts.next())?;
            let vn = parse(parts.next())?;
            let vi = match resolve(v, seen.v) {
                None if v == 0 => return Err(err("face index 0 (OBJ indices start at 1)".into())),
                Some(i) if i < total.v => i,
                _ => {
                    return Err(err(format!(
                        "face vertex index {v} out of range (file has {} vertices)",
                        total.v
                    )))
                }
            };
            let ok = |i: Option<i64>, so_far: usize, n: usize| {
                i.and_then(|i| resolve(i, so_far)).filter(|&k| k < n)
            };
            let vt_ok = ok(vt, seen.vt, total.vt);
            let vn_ok = ok(vn, seen.vn, total.vn);
            *missing_refs += usize::from(vt.is_some() && vt_ok.is_none())
                + usize::from(vn.is_some() && vn_ok.is_none());
            corners.push(vi);
            // Absolute 1-based indices: tobj then never sees a dangling reference.
            use std::fmt::Write;
            let _ = match (vt_ok, vn_ok) {
                (None, None) => write!(text, " {}", vi + 1),
                (Some(t), None) => write!(text, " {}/{}", vi + 1, t + 1),
                (None, Some(n)) => write!(text, " {}//{}", vi + 1, n + 1),
                (Some(t), Some(n)) => write!(text, " {}/{}/{}", vi + 1, t + 1, n + 1),
            };
        }
        let distinct = match corners[..] {
            [a, b, c] => 1 + usize::from(b != a) + usize::from(c != a && c != b),
            _ => {
                distinct.clear();
                distinct.extend_from_slice(corners);
                distinct.sort_unstable();
                distinct.dedup();
                distinct.len()
            }
        };
        if distinct < 3 {
            text.truncate(face_start);
            out.dropped_faces += 1;
            return Ok(());
        }
        out.face_groups.push(*group);
        text.push('\n');
        Ok(())
    }

    /// The summary warnings (how many lines were repaired, faces dropped, references ignored,
    /// vertices made white, statements ignored), and what was gathered.
    pub(super) fn finish(mut self) -> Repaired {
        if self.lossy_lines > 0 {
            let n = self.lossy_lines;
            self.warn(
                None,
                format!("{n} line(s) with non-UTF-8 names or comments: bytes replaced"),
            );
        }
        if self.out.dropped_faces > 0 {
            let n = self.out.dropped_faces;
            self.warn(
                None,
                format!("dropped {n} face(s) with fewer than 3 distinct corners"),
            );
        }
        if self.missing_refs > 0 {
            let n = self.missing_refs;
            self.warn(
                None,
                format!("{n} face corner(s) reference a missing normal or UV: ignored"),
            );
        }
        if self.out.uncoloured > 0 {
            let (n, v) = (self.out.uncoloured, self.total.v);
            self.warn(
                None,
                format!("{n} of {v} vertices have no colour where others do: white"),
            );
        }
        if !self.has_groups {
            self.out.face_groups.clear();
        }
        if self.unknown > 0 {
            let n = self.unknown;
            self.warn(None, format!("{n} unknown statement(s) ignored"));
        }
        self.out
    }
}
