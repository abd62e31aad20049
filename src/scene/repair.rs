//! A pre-pass over the raw OBJ bytes, before tobj sees them. tobj rejects files users expect to
//! open (non-UTF-8 names, backslash continuations, empty `usemtl`) and reports errors without a
//! line number; this pass repairs what is unambiguous (with a warning) and finds the line of
//! anything that is really wrong.
use super::Warning;
use crate::error::Error;
use std::borrow::Cow;
use std::path::Path;

/// The OBJ text ready for tobj, and what was repaired.
#[derive(Default)]
pub struct Repaired {
    pub text: String,
    pub warnings: Vec<Warning>,
    /// Faces dropped because they had fewer than three distinct corners.
    pub dropped_faces: usize,
    /// Every `usemtl` name with its line, to report names no MTL defines.
    pub usemtl: Vec<(usize, String)>,
    /// The smoothing group (`s N`; 0 = `s off`) of every face passed on, in file order;
    /// empty when the file has no `s` statement (then the crease angle decides).
    pub face_groups: Vec<u32>,
    /// Every `v` position as written (after any `w` division), for lines and points.
    pub positions: Vec<[f64; 3]>,
    /// `l` statements as segments between 0-based position indices (polylines split).
    pub segments: Vec<[u32; 2]>,
    /// `p` statements as 0-based position indices.
    pub points: Vec<u32>,
    /// Vertices written without a colour in a file where others have one (made white).
    pub uncoloured: usize,
}

#[derive(Default)]
struct Counts {
    v: usize,
    vt: usize,
    vn: usize,
    /// `v` lines with a colour (6 numbers).
    coloured: usize,
}

/// Statements whose arguments are names, where a non-UTF-8 byte can be replaced safely.
fn is_name_statement(keyword: &[u8]) -> bool {
    matches!(
        keyword,
        b"#" | b"o" | b"g" | b"s" | b"usemtl" | b"mtllib" | b"newmtl"
    ) || keyword.starts_with(b"#")
}

fn keyword(line: &[u8]) -> &[u8] {
    let trimmed = line.trim_ascii_start();
    let end = trimmed
        .iter()
        .position(|b| b.is_ascii_whitespace())
        .unwrap_or(trimmed.len());
    &trimmed[..end]
}

/// A logical line: its first line number and its bytes.
type Line<'a> = (usize, Cow<'a, [u8]>);

/// Joins backslash continuations and splits into (first line number, text bytes). Lines
/// without a continuation borrow the input (no copy per line).
fn logical_lines(bytes: &[u8]) -> (Vec<Line<'_>>, usize) {
    let mut out = Vec::new();
    let mut joined = 0;
    let mut pending: Option<(usize, Vec<u8>)> = None;
    for (i, raw) in bytes.split(|&b| b == b'\n').enumerate() {
        let raw = raw.strip_suffix(b"\r").unwrap_or(raw);
        if let Some(body) = raw.trim_ascii_end().strip_suffix(b"\\") {
            let (_, buf) = pending.get_or_insert_with(|| (i + 1, Vec::new()));
            buf.extend_from_slice(body);
            buf.push(b' ');
            joined += 1;
        } else if let Some((start, mut buf)) = pending.take() {
            buf.extend_from_slice(raw);
            out.push((start, Cow::Owned(buf)));
        } else {
            out.push((i + 1, Cow::Borrowed(raw)));
        }
    }
    if let Some((start, buf)) = pending {
        out.push((start, Cow::Owned(buf)));
    }
    (out, joined)
}

fn count_elements(lines: &[Line<'_>]) -> Counts {
    let mut c = Counts::default();
    for (_, l) in lines {
        match keyword(l) {
            b"v" => {
                c.v += 1;
                if l.split(|b| b.is_ascii_whitespace())
                    .filter(|w| !w.is_empty())
                    .count()
                    == 7
                {
                    c.coloured += 1;
                }
            }
            b"vt" => c.vt += 1,
            b"vn" => c.vn += 1,
            _ => {}
        }
    }
    c
}

/// Resolves one OBJ index (1-based, or negative = relative to the elements so far).
fn resolve(index: i64, so_far: usize) -> Option<usize> {
    match index {
        0 => None,
        i if i > 0 => Some(i as usize - 1),
        i => (so_far as i64 + i).try_into().ok(),
    }
}

pub fn repair_obj(path: &Path, bytes: &[u8]) -> Result<Repaired, Error> {
    repair_obj_with_progress(path, bytes, &|_| {})
}

/// As [`repair_obj`], calling `progress(bytes scanned)` about every MiB.
pub fn repair_obj_with_progress(
    path: &Path,
    bytes: &[u8],
    progress: &dyn Fn(u64),
) -> Result<Repaired, Error> {
    if bytes.iter().take(4096).filter(|&&b| b == 0).count() > 0 {
        return Err(Error::model(
            path,
            Some(1),
            "not an OBJ file (binary data)".to_string(),
        ));
    }
    let (lines, joined) = logical_lines(bytes);
    let mut pass = Pass::new(path, bytes.len(), count_elements(&lines));
    if joined > 0 {
        pass.warn(
            None,
            format!("joined {joined} backslash line continuation(s)"),
        );
    }
    let mut scanned = 0u64;
    let mut next_report = 0u64;
    for (lineno, raw) in &lines {
        scanned += raw.len() as u64 + 1;
        if scanned >= next_report {
            progress(scanned);
            next_report = scanned + (1 << 20);
        }
        pass.statement(*lineno, raw)?;
    }
    Ok(pass.finish())
}

/// One repair pass over an OBJ file's logical lines: what has been written for tobj and
/// gathered so far (`out`), where the pass is in the file, and the counts the warnings at the
/// end report.
struct Pass<'p> {
    path: &'p Path,
    out: Repaired,
    /// Elements in the whole file: indices are checked against these.
    total: Counts,
    /// Elements before the current line: negative indices count back from these.
    seen: Counts,
    /// Only some `v` lines have a colour (the others are written out white).
    mixed_colours: bool,
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
    fn new(path: &'p Path, len: usize, total: Counts) -> Self {
        Pass {
            path,
            out: Repaired {
                text: String::with_capacity(len),
                positions: Vec::with_capacity(total.v),
                ..Repaired::default()
            },
            mixed_colours: total.coloured > 0 && total.coloured < total.v,
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

    fn warn(&mut self, line: Option<usize>, message: String) {
        self.out.warnings.push(Warning {
            file: self.path.to_path_buf(),
            line,
            message,
        });
    }

    /// Checks one logical line, gathers what it holds and writes it to the text for tobj:
    /// as it is, repaired, or not at all (statements tobj need not see, or would reject).
    fn statement(&mut self, lineno: usize, raw: &[u8]) -> Result<(), Error> {
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
            "vn" => self.seen.vn += 1,
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
    fn finish(mut self) -> Repaired {
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

/// Repairs MTL text before tobj sees it: tobj 4.0.5 panics on a colour statement with fewer
/// than three numbers. One number is a valid short form (g and b default to r); zero or two
/// are dropped with a warning naming the line.
pub fn repair_mtl(path: &Path, text: &str, warnings: &mut Vec<Warning>) -> String {
    let mut out = String::with_capacity(text.len());
    for (i, line) in text.lines().enumerate() {
        let mut words = line.split_whitespace();
        let kw = words.next().unwrap_or("");
        if matches!(kw, "Ka" | "Kd" | "Ks" | "Ke" | "Kt" | "Tf") {
            let nums: Vec<&str> = words.collect();
            match nums.len() {
                1 => {
                    out.push_str(&format!("{kw} {0} {0} {0}\n", nums[0]));
                    continue;
                }
                0 | 2 => {
                    warnings.push(Warning {
                        file: path.to_path_buf(),
                        line: Some(i + 1),
                        message: format!(
                            "{kw} needs 1 or 3 numbers, has {}: line ignored",
                            nums.len()
                        ),
                    });
                    continue;
                }
                _ => {}
            }
        }
        out.push_str(line);
        out.push('\n');
    }
    out
}

/// Where a material's statements are in its MTL file, for warnings that name the line.
#[derive(Clone, Debug, Default)]
pub struct MtlLines {
    /// The last `d` or `Tr` line.
    pub opacity: Option<usize>,
    /// The last `Ns` line.
    pub shininess: Option<usize>,
    /// Every texture statement: (line, keyword, argument as written).
    pub maps: Vec<(usize, String, String)>,
}

/// Finds, per `newmtl` name, the lines of the statements warnings refer to.
pub fn mtl_lines(text: &str) -> std::collections::HashMap<String, MtlLines> {
    let mut out = std::collections::HashMap::new();
    let mut cur: Option<String> = None;
    for (i, line) in text.lines().enumerate() {
        let t = line.trim();
        let kw = t.split_whitespace().next().unwrap_or("");
        if kw == "newmtl" {
            let name = t[6..].trim().to_string();
            out.entry(name.clone()).or_insert_with(MtlLines::default);
            cur = Some(name);
            continue;
        }
        let Some(e) = cur.as_ref().and_then(|c| out.get_mut(c)) else {
            continue;
        };
        let e: &mut MtlLines = e;
        match kw {
            "d" | "Tr" => e.opacity = Some(i + 1),
            "Ns" => e.shininess = Some(i + 1),
            k if k.starts_with("map_")
                || matches!(k, "bump" | "disp" | "decal" | "refl" | "norm") =>
            {
                e.maps
                    .push((i + 1, k.to_string(), t[k.len()..].trim().to_string()))
            }
            _ => {}
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn run(s: &[u8]) -> Result<Repaired, Error> {
        repair_obj(Path::new("t.obj"), s)
    }

    #[test]
    fn nan_position_names_the_line() {
        let e = run(b"v 0 0 0\nv nan 0 0\n").err().unwrap().to_string();
        assert_eq!(e, "t.obj:2: vertex position is not finite: nan");
    }

    #[test]
    fn overflow_is_not_finite() {
        assert!(run(b"v 1e400 0 0\n").is_err());
    }

    #[test]
    fn index_zero_and_out_of_range() {
        let e = run(b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n").err().unwrap();
        assert!(e.to_string().starts_with("t.obj:4: face index 0"), "{e}");
        let e = run(b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n").err().unwrap();
        assert!(e.to_string().contains("out of range"), "{e}");
        let e = run(b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf -1 -2 -4\n")
            .err()
            .unwrap();
        assert!(e.to_string().contains(":4:"), "{e}");
    }

    #[test]
    fn relative_indices_become_absolute() {
        let r = run(b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf -3 -2 -1\n").unwrap();
        assert!(r.text.contains("f 1 2 3\n"));
    }

    #[test]
    fn degenerate_faces_dropped_and_counted() {
        let r = run(b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2\nf 1 1 2\nf 1 2 3\n").unwrap();
        assert_eq!(r.dropped_faces, 2);
        assert!(r.text.contains("f 1 2 3"));
    }

    #[test]
    fn continuation_crlf_and_empty_usemtl() {
        let r = run(b"v 0 0 0\r\nv 1 0 \\\r\n 0\r\nv 0 1 0\r\nusemtl\r\nf 1 2 3\r\n").unwrap();
        assert!(r.text.contains("v 1 0   0"), "{}", r.text);
        assert_eq!(r.warnings.len(), 2);
    }

    #[test]
    fn non_utf8_names_repaired_numbers_refused() {
        let r = run(b"# caf\xe9\no caf\xe9\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
        assert!(r.warnings[0].message.contains("non-UTF-8"));
        let e = run(b"v 0 \xff 0\n").err().unwrap();
        assert_eq!(
            e.to_string(),
            "t.obj:1: non-UTF-8 bytes where a number should be"
        );
    }

    #[test]
    fn missing_normal_reference_dropped() {
        let r = run(b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1//1 2//1 3//1\n").unwrap();
        assert!(r.text.contains("f 1 2 3\n"));
        assert!(r
            .warnings
            .iter()
            .any(|w| w.message.contains("missing normal")));
    }

    #[test]
    fn short_mtl_colours_repaired() {
        let mut w = Vec::new();
        let t = repair_mtl(
            Path::new("m.mtl"),
            "newmtl a\nKd 0.5\nKa\nKs 1 2\nNs 3\n",
            &mut w,
        );
        assert_eq!(t, "newmtl a\nKd 0.5 0.5 0.5\nNs 3\n");
        assert_eq!(w.len(), 2);
        assert_eq!(
            w[1].to_string(),
            "m.mtl:4: Ks needs 1 or 3 numbers, has 2: line ignored"
        );
    }

    #[test]
    fn positions_beyond_f32_refused() {
        let e = run(b"v 0 6.4e39 0\n").err().unwrap();
        assert!(
            e.to_string()
                .contains("t.obj:1: vertex position out of range"),
            "{e}"
        );
    }

    #[test]
    fn binary_garbage_refused() {
        assert!(run(b"\x00\x01\x02garbage").is_err());
    }
}
