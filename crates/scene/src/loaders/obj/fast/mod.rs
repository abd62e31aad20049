//! The fast OBJ path: one pass over the bytes that does what `crate::loaders::obj::repair` and tobj do
//! together, for files where that is certain. The file is cut into chunks at line ends and
//! the chunks are parsed in parallel (`chunk`); element counts are prefix-summed so
//! relative indices resolve (`resolve`); then one ordered pass applies names, materials and
//! smoothing groups and builds tobj's own `Model`s with its vertex order and dedup
//! (`build`), so the loader's later stages are unchanged. Anything else (an unknown
//! statement, a quirk the repair pass fixes or reports, an error) returns `None` and the
//! caller runs the old path, which stays the reference (`tests/fast_parse.rs`).
mod build;
mod chunk;
mod scan;

use chunk::{Chunk, MISSING, REL, REL_BIAS};
use rayon::prelude::*;
use std::path::Path;

pub(crate) use build::Parsed;

/// Which OBJ parser [`crate::loaders::obj`] runs.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Parser {
    /// The fast path where it applies, the old path otherwise.
    #[default]
    Auto,
    /// Repair pre-pass + tobj always (`GLVIEW_OBJ_PARSER=tobj`).
    Tobj,
    /// As `Auto` with chunks of about this many bytes (tests: many chunks in small files).
    Chunked(usize),
}

impl Parser {
    /// The parser the environment asks for: `GLVIEW_OBJ_PARSER=tobj` forces the old path
    /// (for comparisons and the load benchmark).
    pub(crate) fn from_env() -> Parser {
        match std::env::var("GLVIEW_OBJ_PARSER") {
            Ok(v) if v.eq_ignore_ascii_case("tobj") => Parser::Tobj,
            _ => Parser::Auto,
        }
    }
}

/// Smaller chunks than this are not worth a thread.
const MIN_CHUNK: usize = 256 << 10;

/// Cuts `bytes` into pieces of about `size` bytes that end just after a `\n`.
fn split(bytes: &[u8], size: usize) -> Vec<&[u8]> {
    let size = size.max(1);
    let mut out = Vec::new();
    let mut rest = bytes;
    while rest.len() > size {
        let cut = rest[size..]
            .iter()
            .position(|&b| b == b'\n')
            .map_or(rest.len(), |p| size + p + 1);
        let (a, b) = rest.split_at(cut);
        out.push(a);
        rest = b;
    }
    if !rest.is_empty() || out.is_empty() {
        out.push(rest);
    }
    out
}

/// Parses an OBJ file on the fast path; `None` when the old path must run instead.
/// `mtl` loads a material library as tobj's loader callback would (same order of calls).
pub(crate) fn parse(
    bytes: &[u8],
    chunk: Option<usize>,
    progress: &(dyn Fn(u64) + Sync),
    mtl: &mut dyn FnMut(&Path) -> tobj::MTLLoadResult,
) -> Option<Parsed> {
    // Binary data is refused by the old path.
    if bytes.iter().take(4096).any(|&b| b == 0) {
        return None;
    }
    let done = std::sync::atomic::AtomicU64::new(0);
    let auto = (bytes.len() / (rayon::current_num_threads() * 8)).max(MIN_CHUNK);
    let pieces = split(bytes, chunk.unwrap_or(auto));
    let mut chunks = pieces
        .par_iter()
        .map(|p| {
            let c = Chunk::parse(p);
            let d = done.fetch_add(p.len() as u64, std::sync::atomic::Ordering::Relaxed);
            progress(d + p.len() as u64);
            c
        })
        .collect::<Option<Vec<Chunk>>>()?;
    let bases = prefix(&chunks)?;
    chunks
        .par_iter_mut()
        .zip(&bases)
        .try_for_each(|(c, b)| resolve(c, b).ok_or(()))
        .ok()?;
    Some(build::build(chunks, &bases, mtl))
}

/// Where a chunk starts: elements (v, vt, vn), faces and lines before it.
pub(crate) struct Base {
    pub(crate) elems: [usize; 3],
    pub(crate) faces: usize,
    pub(crate) lines: usize,
}

fn prefix(chunks: &[Chunk]) -> Option<Vec<Base>> {
    let mut b = Base {
        elems: [0; 3],
        faces: 0,
        lines: 0,
    };
    let mut out = Vec::with_capacity(chunks.len() + 1);
    for c in chunks {
        let next = Base {
            elems: [
                b.elems[0] + c.pos.len() / 3,
                b.elems[1] + c.tex.len() / 2,
                b.elems[2] + c.nrm.len() / 3,
            ],
            faces: b.faces + c.arity.len(),
            lines: b.lines + c.lines,
        };
        out.push(b);
        b = next;
    }
    // Indices are u32 with `MISSING` and the relative flag kept out of range.
    (b.elems.iter().all(|&n| n < REL as usize)).then_some(())?;
    out.push(b);
    Some(out)
}

/// Makes a chunk's corners absolute 0-based indices; `None` for an index before the first
/// element or after the ones defined so far, or a face with fewer than 3 distinct vertices
/// (the old path drops it with a warning).
fn resolve(c: &mut Chunk, base: &Base) -> Option<()> {
    for k in 0..3 {
        (c.ahead[k] < base.elems[k] as i64).then_some(())?;
    }
    for corner in &mut c.corners {
        for (x, &b) in corner.iter_mut().zip(&base.elems) {
            if *x != MISSING && *x & REL != 0 {
                let abs = b as i64 + i64::from(*x & !REL) - REL_BIAS;
                (abs >= 0).then_some(())?;
                *x = abs as u32;
            }
        }
    }
    let mut at = 0;
    for &n in &c.arity {
        let face = &c.corners[at..at + n as usize];
        at += n as usize;
        let distinct = match face {
            [a, b, c] => 1 + usize::from(b[0] != a[0]) + usize::from(c[0] != a[0] && c[0] != b[0]),
            _ => {
                let mut v: Vec<u32> = face.iter().map(|c| c[0]).collect();
                v.sort_unstable();
                v.dedup();
                v.len()
            }
        };
        (distinct >= 3).then_some(())?;
    }
    Some(())
}
