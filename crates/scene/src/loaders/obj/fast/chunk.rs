//! One chunk of an OBJ file (whole lines), parsed on its own thread: positions, normals and
//! texture coordinates as numbers, face corners with their indices encoded so that relative
//! ones can be resolved once the counts of the chunks before are known, and the few
//! statements that must be applied in file order (names, materials, smoothing groups) as
//! events. `None` = a line the fast path does not take on (the whole file falls back).

/// A missing `vt` or `vn` in a corner (tobj's `MISSING_INDEX`).
pub(crate) const MISSING: u32 = u32::MAX;
/// Marks a relative index: `REL | (seen in this chunk + index + REL_BIAS)`.
pub(crate) const REL: u32 = 1 << 31;
pub(crate) const REL_BIAS: i64 = 1 << 30;

use crate::loaders::obj::fast::scan::Scan;

/// A statement applied in file order, before face `face` (chunk-local) of the file.
pub(crate) struct Event {
    pub(crate) face: usize,
    /// Line number within the chunk (0-based).
    pub(crate) line: usize,
    pub(crate) kind: EventKind,
}

pub(crate) enum EventKind {
    /// `o` or `g`: the model name as tobj takes it.
    Name(String),
    /// `usemtl`: the name as repair records it, and as tobj looks it up.
    UseMtl(String, String),
    /// `mtllib`: the path as tobj passes it to the material loader.
    MtlLib(String),
    /// `s`: the smoothing group (0 = off).
    Smooth(u32),
}

#[derive(Default)]
pub(crate) struct Chunk {
    pub(crate) lines: usize,
    pub(crate) pos: Vec<f64>,
    pub(crate) nrm: Vec<f64>,
    pub(crate) tex: Vec<f64>,
    /// Corners as (v, vt, vn); encoded until [`crate::loaders::obj::fast::resolve`] makes them absolute.
    pub(crate) corners: Vec<[u32; 3]>,
    /// Corners per face.
    pub(crate) arity: Vec<u32>,
    pub(crate) events: Vec<Event>,
    /// Per kind (v, vt, vn): the largest `absolute index − elements seen so far in the chunk`
    /// (must stay below the chunk's base: no forward references).
    pub(crate) ahead: [i64; 3],
}

impl Chunk {
    pub(crate) fn parse(bytes: &[u8]) -> Option<Chunk> {
        let mut c = Chunk {
            ahead: [i64::MIN; 3],
            ..Chunk::default()
        };
        let mut s = Scan::new(bytes);
        while s.i < bytes.len() {
            match s.rest() {
                [b'v', b' ' | b'\t', ..] => {
                    s.i += 2;
                    for _ in 0..3 {
                        s.blanks();
                        let x = s.float()?;
                        // Non-finite or beyond f32: an error on the old path.
                        (x.is_finite() && x.abs() <= f64::from(f32::MAX)).then_some(())?;
                        c.pos.push(x);
                    }
                }
                [b'v', b'n', b' ' | b'\t', ..] => {
                    s.i += 3;
                    for _ in 0..3 {
                        s.blanks();
                        c.nrm.push(s.float()?);
                    }
                }
                [b'v', b't', b' ' | b'\t', ..] => {
                    s.i += 3;
                    for _ in 0..2 {
                        s.blanks();
                        c.tex.push(s.float()?);
                    }
                    // tobj reads two numbers; a third (w) is allowed and ignored.
                    s.blanks();
                    if !s.at_line_end() {
                        s.float()?;
                    }
                }
                [b'f', b' ' | b'\t', ..] => {
                    s.i += 2;
                    c.face(&mut s)?;
                }
                _ => {
                    let end = s.rest().iter().position(|&b| b == b'\n');
                    let end = end.map_or(bytes.len(), |p| s.i + p);
                    let line = &bytes[s.i..end];
                    c.statement(line.strip_suffix(b"\r").unwrap_or(line))?;
                    s.i = end;
                }
            }
            s.blanks();
            s.end_line().then_some(())?;
            c.lines += 1;
        }
        Some(c)
    }

    fn face(&mut self, s: &mut Scan) -> Option<()> {
        let seen = [self.pos.len() / 3, self.tex.len() / 2, self.nrm.len() / 3];
        let mut n = 0u32;
        loop {
            s.blanks();
            if s.at_line_end() {
                break;
            }
            let mut corner = [MISSING; 3];
            corner[0] = self.encode(s.index()?, seen[0], 0)?;
            // `v`, `v/`, `v/vt`, `v//vn`, `v/vt/vn`, `v/vt/` (empty parts are absent).
            if s.eat(b'/') {
                if !s.at_sep() && s.rest().first() != Some(&b'/') {
                    corner[1] = self.encode(s.index()?, seen[1], 1)?;
                }
                if s.eat(b'/') && !s.at_sep() {
                    corner[2] = self.encode(s.index()?, seen[2], 2)?;
                }
            }
            s.at_sep().then_some(())?;
            self.corners.push(corner);
            n += 1;
        }
        (n >= 3).then_some(())?;
        self.arity.push(n);
        Some(())
    }

    fn encode(&mut self, i: i64, seen: usize, kind: usize) -> Option<u32> {
        let seen = seen as i64;
        if i > 0 {
            let abs = i - 1;
            (abs < i64::from(REL)).then_some(())?;
            self.ahead[kind] = self.ahead[kind].max(abs - seen);
            Some(abs as u32)
        } else if i < 0 {
            let r = seen + i + REL_BIAS;
            (0..REL_BIAS * 2 - 1).contains(&r).then_some(())?;
            Some(REL | r as u32)
        } else {
            None
        }
    }

    /// Statements other than numbers, read as the old path reads them (UTF-8 text, split on
    /// Unicode whitespace, names taken with tobj's and repair's own expressions).
    fn statement(&mut self, line: &[u8]) -> Option<()> {
        // A backslash continuation (joined by the old path, with a warning).
        if line.trim_ascii_end().ends_with(b"\\") {
            return None;
        }
        let line = std::str::from_utf8(line).ok()?;
        if line.contains('\r') {
            return None;
        }
        let mut words = line.split_whitespace();
        let first = words.next().unwrap_or("");
        let kind = match first {
            "" | "vp" => return Some(()),
            w if w.starts_with('#') => return Some(()),
            "o" | "g" => {
                let size = line.chars().next()?.len_utf8();
                let name = line[size..].trim();
                let name = if name.is_empty() {
                    "unnamed_object"
                } else {
                    name
                };
                EventKind::Name(name.to_string())
            }
            "usemtl" => {
                let tobj_name = line.split_once(' ').unwrap_or_default().1.trim();
                if line.trim() == "usemtl" || tobj_name.is_empty() {
                    return None;
                }
                let name = line.trim()[6..].trim().to_string();
                EventKind::UseMtl(name, tobj_name.to_string())
            }
            "mtllib" => EventKind::MtlLib(line.split_once(' ').unwrap_or_default().1.trim().into()),
            "s" => {
                let arg = words.next().unwrap_or("0");
                EventKind::Smooth(if arg.eq_ignore_ascii_case("off") {
                    0
                } else {
                    arg.parse::<u32>().unwrap_or(0)
                })
            }
            _ => return None,
        };
        self.events.push(Event {
            face: self.arity.len(),
            line: self.lines,
            kind,
        });
        Some(())
    }
}
