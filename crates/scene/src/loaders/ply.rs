//! PLY (ASCII, binary little- and big-endian) read as a stream, so a gzipped file is never
//! inflated whole. Element counts are checked before anything is allocated: against what the
//! file can hold when its size is known, and against [`MAX_ELEMENTS`] always; arrays grow
//! only as data really arrives, so a header promising 200 M vertices over a stream of zeros
//! stops at the limit instead of at the allocator. Any extra property, `vertex_index` or
//! `vertex_indices`, `comment` and `obj_info` lines are accepted.
use crate::loaders::gltf::accessor::MAX_ELEMENTS;
use crate::loaders::tokens::Tokens;
use glam::DVec3;
use std::io::{BufRead, Read};

/// What a PLY file gave (positions, polygons as flat corners + sizes, optional normals and
/// colours); errors are `(line, message)`.
pub(crate) struct Raw {
    pub(crate) positions: Vec<DVec3>,
    pub(crate) corners: Vec<u32>,
    pub(crate) sizes: Vec<u32>,
    pub(crate) normals: Option<Vec<[f32; 3]>>,
    pub(crate) colors: Option<Vec<[f32; 3]>>,
}

type Fail = (Option<usize>, String);

#[derive(Clone, Copy, PartialEq, Debug)]
enum Ty {
    I8,
    U8,
    I16,
    U16,
    I32,
    U32,
    F32,
    F64,
}

impl Ty {
    fn parse(s: &str) -> Option<Ty> {
        Some(match s {
            "char" | "int8" => Ty::I8,
            "uchar" | "uint8" => Ty::U8,
            "short" | "int16" => Ty::I16,
            "ushort" | "uint16" => Ty::U16,
            "int" | "int32" => Ty::I32,
            "uint" | "uint32" => Ty::U32,
            "float" | "float32" => Ty::F32,
            "double" | "float64" => Ty::F64,
            _ => return None,
        })
    }
    fn size(self) -> usize {
        match self {
            Ty::I8 | Ty::U8 => 1,
            Ty::I16 | Ty::U16 => 2,
            Ty::I32 | Ty::U32 | Ty::F32 => 4,
            Ty::F64 => 8,
        }
    }
}

struct Prop {
    name: String,
    ty: Ty,
    /// The count type of a list property.
    list: Option<Ty>,
}

struct Element {
    name: String,
    count: usize,
    props: Vec<Prop>,
}

#[derive(Clone, Copy, PartialEq)]
enum Encoding {
    Ascii,
    Le,
    Be,
}

/// Reads one header line (at most 4 KiB).
fn line<R: BufRead>(r: &mut R, n: &mut usize) -> Result<String, Fail> {
    let mut v = Vec::new();
    r.by_ref()
        .take(4096)
        .read_until(b'\n', &mut v)
        .map_err(|e| (Some(*n + 1), e.to_string()))?;
    *n += 1;
    if v.is_empty() {
        return Err((Some(*n), "PLY header has no end_header".into()));
    }
    Ok(String::from_utf8_lossy(&v).trim().to_string())
}

fn header<R: BufRead>(r: &mut R, n: &mut usize) -> Result<(Encoding, Vec<Element>), Fail> {
    if line(r, n)? != "ply" {
        return Err((None, "not a PLY file (no 'ply' magic)".into()));
    }
    let mut enc = None;
    let mut elems: Vec<Element> = Vec::new();
    loop {
        if *n > 100_000 {
            return Err((Some(*n), "PLY header of more than 100,000 lines".into()));
        }
        let l = line(r, n)?;
        let w: Vec<&str> = l.split_whitespace().collect();
        let err = |m: String| Err((Some(*n), m));
        match w.as_slice() {
            ["end_header"] => break,
            [] | ["comment", ..] | ["obj_info", ..] => {}
            ["format", f, _] => {
                enc = Some(match *f {
                    "ascii" => Encoding::Ascii,
                    "binary_little_endian" => Encoding::Le,
                    "binary_big_endian" => Encoding::Be,
                    _ => return err(format!("unknown PLY format {f:?}")),
                })
            }
            ["element", name, count] => {
                let count = count.parse::<usize>().map_err(|_| {
                    (
                        Some(*n),
                        format!("element {name}: count {count:?} is not a number"),
                    )
                })?;
                if count > MAX_ELEMENTS {
                    return err(format!(
                        "header claims {count} {name} elements, more than glview reads \
                         ({MAX_ELEMENTS})"
                    ));
                }
                elems.push(Element {
                    name: name.to_string(),
                    count,
                    props: Vec::new(),
                });
            }
            ["property", "list", ct, it, name] => match (Ty::parse(ct), Ty::parse(it)) {
                (Some(c), Some(t)) if c != Ty::F32 && c != Ty::F64 => {
                    let Some(e) = elems.last_mut() else {
                        return err("property before any element".into());
                    };
                    e.props.push(Prop {
                        name: name.to_string(),
                        ty: t,
                        list: Some(c),
                    })
                }
                _ => return err(format!("property list {ct} {it}: unknown types")),
            },
            ["property", ty, name] => {
                let Some(t) = Ty::parse(ty) else {
                    return err(format!("property {name}: unknown type {ty:?}"));
                };
                let Some(e) = elems.last_mut() else {
                    return err("property before any element".into());
                };
                e.props.push(Prop {
                    name: name.to_string(),
                    ty: t,
                    list: None,
                })
            }
            _ => return err(format!("unknown PLY header line {l:?}")),
        }
    }
    let enc = enc.ok_or((None, "PLY header has no format line".into()))?;
    Ok((enc, elems))
}

/// Reads a PLY stream. `size` (the bytes after the header, when known) lets element counts
/// be checked against the file before reading.
pub(crate) fn read<R: BufRead>(mut r: R, size: Option<u64>) -> Result<Raw, Fail> {
    let mut n = 0;
    let (enc, elems) = header(&mut r, &mut n)?;
    if let Some(size) = size {
        // Every element takes at least one byte (ASCII: a digit; binary: its properties).
        // (ASCII: a digit and a separator per value.)
        let need: u64 = elems
            .iter()
            .map(|e| {
                let min: usize = match enc {
                    Encoding::Ascii => 2 * e.props.len(),
                    _ => e.props.iter().map(|p| p.list.unwrap_or(p.ty).size()).sum(),
                };
                e.count as u64 * min.max(1) as u64
            })
            .sum();
        if need > size {
            return Err((
                None,
                format!("header claims elements needing {need} bytes; the file has {size}"),
            ));
        }
    }
    let mut out = Raw {
        positions: Vec::new(),
        corners: Vec::new(),
        sizes: Vec::new(),
        normals: None,
        colors: None,
    };
    let mut body = Body {
        enc,
        toks: Tokens::new(r, n + 1),
    };
    for e in &elems {
        body.element(e, &mut out)?;
    }
    Ok(out)
}

struct Body<R> {
    enc: Encoding,
    toks: Tokens<R>,
}

impl<R: BufRead> Body<R> {
    fn value(&mut self, ty: Ty, what: &dyn Fn() -> String) -> Result<f64, Fail> {
        if self.enc == Encoding::Ascii {
            return self
                .toks
                .number(&what())
                .map_err(|m| (Some(self.toks.line), m));
        }
        let mut b = [0u8; 8];
        let s = &mut b[..ty.size()];
        self.toks_reader()
            .read_exact(s)
            .map_err(|_| (None, format!("{}: the file ends here", what())))?;
        if self.enc == Encoding::Be {
            s.reverse();
        }
        Ok(match ty {
            Ty::I8 => f64::from(b[0] as i8),
            Ty::U8 => f64::from(b[0]),
            Ty::I16 => f64::from(i16::from_le_bytes([b[0], b[1]])),
            Ty::U16 => f64::from(u16::from_le_bytes([b[0], b[1]])),
            Ty::I32 => f64::from(i32::from_le_bytes([b[0], b[1], b[2], b[3]])),
            Ty::U32 => f64::from(u32::from_le_bytes([b[0], b[1], b[2], b[3]])),
            Ty::F32 => f64::from(f32::from_le_bytes([b[0], b[1], b[2], b[3]])),
            Ty::F64 => f64::from_le_bytes(b),
        })
    }

    fn toks_reader(&mut self) -> &mut R {
        self.toks.reader()
    }

    fn element(&mut self, e: &Element, out: &mut Raw) -> Result<(), Fail> {
        let find = |n: &[&str]| e.props.iter().position(|p| n.contains(&p.name.as_str()));
        let is_vertex = e.name == "vertex";
        let is_face = e.name == "face";
        let xyz = [find(&["x"]), find(&["y"]), find(&["z"])];
        let nrm = [find(&["nx"]), find(&["ny"]), find(&["nz"])];
        let rgb = [
            find(&["red", "r"]),
            find(&["green", "g"]),
            find(&["blue", "b"]),
        ];
        let idx = find(&["vertex_indices", "vertex_index"]);
        if is_vertex && xyz.iter().any(|p| p.is_none()) && e.count > 0 {
            return Err((None, "vertex element has no x, y, z properties".into()));
        }
        if is_face && idx.is_none() && e.count > 0 {
            return Err((None, "face element has no vertex_indices list".into()));
        }
        let has_n = is_vertex && nrm.iter().all(|p| p.is_some());
        let has_c = is_vertex && rgb.iter().all(|p| p.is_some());
        let mut normals = Vec::new();
        let mut colors = Vec::new();
        let mut vals = vec![0f64; e.props.len()];
        for i in 0..e.count {
            for (k, p) in e.props.iter().enumerate() {
                let what = || format!("{} {i} property {}", e.name, p.name);
                let Some(ct) = p.list else {
                    vals[k] = self.value(p.ty, &what)?;
                    continue;
                };
                let len = self.value(ct, &what)?;
                if !(0.0..=f64::from(u16::MAX)).contains(&len) || len.fract() != 0.0 {
                    return Err((None, format!("{}: list length {len}", what())));
                }
                let take = is_face && Some(k) == idx;
                for _ in 0..len as usize {
                    let v = self.value(p.ty, &what)?;
                    if take {
                        if v < 0.0 || v.fract() != 0.0 || v >= out.positions.len() as f64 {
                            return Err((
                                Some(self.toks.line).filter(|_| self.enc == Encoding::Ascii),
                                format!(
                                    "face {i}: vertex index {v} out of range (file has {} vertices)",
                                    out.positions.len()
                                ),
                            ));
                        }
                        out.corners.push(v as u32);
                    }
                }
                if take {
                    out.sizes.push(len as u32);
                    if out.corners.len() > 4 * MAX_ELEMENTS {
                        return Err((
                            None,
                            format!("face {i}: more than {} corners in all", 4 * MAX_ELEMENTS),
                        ));
                    }
                }
            }
            if is_vertex {
                let g = |p: [Option<usize>; 3]| p.map(|k| vals[k.unwrap_or(0)]);
                let [x, y, z] = g(xyz);
                let p = DVec3::new(x, y, z);
                if !p.is_finite() || p.abs().max_element() > f64::from(f32::MAX) {
                    return Err((
                        Some(self.toks.line).filter(|_| self.enc == Encoding::Ascii),
                        format!("vertex {i} position is not finite: {p}"),
                    ));
                }
                out.positions.push(p);
                if has_n {
                    normals.push(g(nrm).map(|v| v as f32));
                }
                if has_c {
                    // uchar colours are 0..255, float ones 0..1.
                    let scale = |k: Option<usize>| match e.props[k.unwrap_or(0)].ty {
                        Ty::U8 => 1.0 / 255.0,
                        Ty::U16 => 1.0 / 65535.0,
                        _ => 1.0,
                    };
                    colors.push(
                        [0, 1, 2].map(|c| (vals[rgb[c].unwrap_or(0)] * scale(rgb[c])) as f32),
                    );
                }
            }
        }
        if is_vertex {
            out.normals = has_n.then_some(normals);
            out.colors = has_c.then_some(colors);
        }
        Ok(())
    }
}
