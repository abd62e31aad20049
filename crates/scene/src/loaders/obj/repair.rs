//! A pre-pass over the raw OBJ bytes, before tobj sees them. tobj rejects files users expect to
//! open (non-UTF-8 names, backslash continuations, empty `usemtl`) and reports errors without a
//! line number; this pass repairs what is unambiguous (with a warning) and finds the line of
//! anything that is really wrong.
use crate::error::Error;
use crate::model::Warning;
use std::borrow::Cow;
use std::path::Path;

#[path = "repair_pass.rs"]
mod pass;
use pass::Pass;

/// The OBJ text ready for tobj, and what was repaired.
#[derive(Default)]
pub(crate) struct Repaired {
    pub(crate) text: String,
    pub(crate) warnings: Vec<Warning>,
    /// Faces dropped because they had fewer than three distinct corners.
    pub(crate) dropped_faces: usize,
    /// Every `usemtl` name with its line, to report names no MTL defines.
    pub(crate) usemtl: Vec<(usize, String)>,
    /// The smoothing group (`s N`; 0 = `s off`) of every face passed on, in file order;
    /// empty when the file has no `s` statement (then the crease angle decides).
    pub(crate) face_groups: Vec<u32>,
    /// Every `v` position as written (after any `w` division), for lines and points.
    pub(crate) positions: Vec<[f64; 3]>,
    /// `l` statements as segments between 0-based position indices (polylines split).
    pub(crate) segments: Vec<[u32; 2]>,
    /// `p` statements as 0-based position indices.
    pub(crate) points: Vec<u32>,
    /// Vertices written without a colour in a file where others have one (made white).
    pub(crate) uncoloured: usize,
    /// A file without faces (a point cloud, or lines and points): every `v` line's colour
    /// (`v x y z r g b`, white where a line has none), or empty where no line has one.
    pub(crate) colours: Vec<[f32; 3]>,
    /// A file without faces with as many `vn` as `v` lines: the i-th normal is the i-th
    /// vertex's (as cloud exporters write them); empty otherwise or if one is malformed.
    pub(crate) normals: Vec<[f32; 3]>,
}

#[derive(Default)]
struct Counts {
    v: usize,
    vt: usize,
    vn: usize,
    /// `v` lines with a colour (6 numbers).
    coloured: usize,
    f: usize,
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
            b"f" => c.f += 1,
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

#[cfg(test)] // only the unit tests call it
pub(crate) fn repair_obj(path: &Path, bytes: &[u8]) -> Result<Repaired, Error> {
    repair_obj_with_progress(path, bytes, &|_| {})
}

/// As [`repair_obj`], calling `progress(bytes scanned)` about every MiB.
pub(crate) fn repair_obj_with_progress(
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

/// Repairs MTL text before tobj sees it: tobj 4.0.5 panics on a colour statement with fewer
/// than three numbers. One number is a valid short form (g and b default to r); zero or two
/// are dropped with a warning naming the line.
pub(crate) fn repair_mtl(path: &Path, text: &str, warnings: &mut Vec<Warning>) -> String {
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
pub(crate) struct MtlLines {
    /// The last `d` or `Tr` line.
    pub(crate) opacity: Option<usize>,
    /// The last `Ns` line.
    pub(crate) shininess: Option<usize>,
    /// Every texture statement: (line, keyword, argument as written).
    pub(crate) maps: Vec<(usize, String, String)>,
}

/// Finds, per `newmtl` name, the lines of the statements warnings refer to.
pub(crate) fn mtl_lines(text: &str) -> std::collections::HashMap<String, MtlLines> {
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
