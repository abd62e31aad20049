//! One chunk of an OBJ file (whole lines), parsed on its own thread: positions, normals and
//! texture coordinates as numbers, face corners with their indices encoded so that relative
//! ones can be resolved once the counts of the chunks before are known, and the few
//! statements that must be applied in file order (names, materials, smoothing groups) as
//! events. `None` = a line the fast path does not take on (the whole file falls back).

/// A missing `vt` or `vn` in a corner (tobj's `MISSING_INDEX`).
pub const MISSING: u32 = u32::MAX;
/// Marks a relative index: `REL | (seen in this chunk + index + REL_BIAS)`.
pub const REL: u32 = 1 << 31;
pub const REL_BIAS: i64 = 1 << 30;

/// A statement applied in file order, before face `face` (chunk-local) of the file.
pub struct Event {
    pub face: usize,
    /// Line number within the chunk (0-based).
    pub line: usize,
    pub kind: EventKind,
}

pub enum EventKind {
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
pub struct Chunk {
    pub lines: usize,
    pub pos: Vec<f64>,
    pub nrm: Vec<f64>,
    pub tex: Vec<f64>,
    /// Corners as (v, vt, vn); encoded until [`super::resolve`] makes them absolute.
    pub corners: Vec<[u32; 3]>,
    /// Corners per face.
    pub arity: Vec<u32>,
    pub events: Vec<Event>,
    /// Per kind (v, vt, vn): the largest `absolute index − elements seen so far in the chunk`
    /// (must stay below the chunk's base: no forward references).
    pub ahead: [i64; 3],
}

fn words(line: &[u8]) -> impl Iterator<Item = &[u8]> {
    line.split(|&b| b == b' ' || b == b'\t')
        .filter(|w| !w.is_empty())
}

/// Bytes the fast path's numeric statements may contain (anything else: fall back).
fn numeric_bytes(rest: &[u8]) -> bool {
    rest.iter().all(|&b| {
        matches!(
            b,
            b'0'..=b'9' | b'.' | b'-' | b'+' | b'/' | b'e' | b'E' | b' ' | b'\t'
        )
    })
}

fn floats<const N: usize>(rest: &[u8], out: &mut Vec<f64>) -> Option<()> {
    let mut n = 0;
    for w in words(rest) {
        if n == N {
            return None;
        }
        out.push(super::num::float(w)?);
        n += 1;
    }
    (n == N).then_some(())
}

impl Chunk {
    pub fn parse(bytes: &[u8]) -> Option<Chunk> {
        let mut c = Chunk {
            ahead: [i64::MIN; 3],
            ..Chunk::default()
        };
        let mut start = 0;
        while start < bytes.len() {
            let end = memchr(bytes, start);
            let mut line = &bytes[start..end];
            if let Some(l) = line.strip_suffix(b"\r") {
                line = l;
            }
            c.line(line)?;
            c.lines += 1;
            start = end + 1;
        }
        Some(c)
    }

    fn line(&mut self, line: &[u8]) -> Option<()> {
        // A backslash continuation (joined by the old path, with a warning).
        if line.trim_ascii_end().ends_with(b"\\") {
            return None;
        }
        match line {
            [b'v', b' ' | b'\t', rest @ ..] => {
                let n = self.pos.len();
                numeric_bytes(rest).then_some(())?;
                floats::<3>(rest, &mut self.pos)?;
                // Non-finite or beyond f32: an error on the old path.
                let ok = self.pos[n..]
                    .iter()
                    .all(|x| x.is_finite() && x.abs() <= f64::from(f32::MAX));
                ok.then_some(())
            }
            [b'v', b'n', b' ' | b'\t', rest @ ..] => {
                numeric_bytes(rest).then_some(())?;
                floats::<3>(rest, &mut self.nrm)
            }
            [b'v', b't', b' ' | b'\t', rest @ ..] => {
                numeric_bytes(rest).then_some(())?;
                let n = self.tex.len();
                floats::<3>(rest, &mut self.tex)
                    .map(|_| {
                        self.tex.pop();
                    })
                    .or_else(|| {
                        self.tex.truncate(n);
                        floats::<2>(rest, &mut self.tex)
                    })
            }
            [b'f', b' ' | b'\t', rest @ ..] => {
                numeric_bytes(rest).then_some(())?;
                self.face(rest)
            }
            [] => Some(()),
            _ => self.statement(line),
        }
    }

    fn face(&mut self, rest: &[u8]) -> Option<()> {
        let seen = [self.pos.len() / 3, self.tex.len() / 2, self.nrm.len() / 3];
        let mut n = 0u32;
        for w in words(rest) {
            let mut parts = w.splitn(3, |&b| b == b'/');
            let mut corner = [MISSING; 3];
            for (k, part) in [parts.next(), parts.next(), parts.next()]
                .into_iter()
                .enumerate()
            {
                let Some(part) = part.filter(|p| !p.is_empty()) else {
                    if k == 0 {
                        return None;
                    }
                    continue;
                };
                corner[k] = self.encode(super::num::index(part)?, seen[k], k)?;
            }
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

fn memchr(bytes: &[u8], from: usize) -> usize {
    bytes[from..]
        .iter()
        .position(|&b| b == b'\n')
        .map_or(bytes.len(), |p| from + p)
}
