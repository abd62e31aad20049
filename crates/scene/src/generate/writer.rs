//! OBJ and MTL text: the OBJ writer that owns the global 1-based indices, and materials.

use crate::generate::math::{normalize, V2, V3};
use crate::generate::HEADER;
use std::fmt::Write as _;

/// Appends `x` with 6 decimals; "-0.000000" is written without its sign so that tiny
/// negative rounding noise (e.g. cos(π/2)) never makes the output platform-dependent.
fn push_num(out: &mut String, x: f64) {
    let start = out.len();
    write!(out, "{x:.6}").expect("writing to a String cannot fail");
    if &out[start..] == "-0.000000" {
        out.remove(start);
    }
}

/// One triangle corner as 1-based OBJ indices.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct Vert {
    pub(super) v: u32,
    pub(super) vt: Option<u32>,
    pub(super) vn: u32,
}

/// Builds OBJ text. OBJ indices are global and 1-based across the file, so the writer owns
/// the counters and helpers only use the indices it hands out. Lines are buffered per object
/// so each object reads as tidy v / vt / vn / f blocks.
pub(super) struct ObjWriter {
    out: String,
    /// Pending `v`, `vt`, `vn` and `f` lines of the current object.
    blocks: [String; 4],
    counts: [u32; 3],
}

impl ObjWriter {
    pub(super) fn new(name: &str) -> Self {
        let out = format!("{HEADER}\nmtllib {name}.mtl\n");
        ObjWriter {
            out,
            blocks: Default::default(),
            counts: [0; 3],
        }
    }

    pub(super) fn object(&mut self, name: &str, material: &str) {
        self.flush();
        writeln!(self.out, "o {name}\nusemtl {material}").expect("String write");
    }

    fn flush(&mut self) {
        for block in &mut self.blocks {
            self.out.push_str(block);
            block.clear();
        }
    }

    fn numbers(&mut self, kind: usize, tag: &str, xs: &[f64]) -> u32 {
        let line = &mut self.blocks[kind];
        line.push_str(tag);
        for &x in xs {
            line.push(' ');
            push_num(line, x);
        }
        line.push('\n');
        self.counts[kind] += 1;
        self.counts[kind]
    }

    pub(super) fn v(&mut self, p: V3) -> u32 {
        self.numbers(0, "v", &p)
    }

    pub(super) fn vt(&mut self, uv: V2) -> u32 {
        self.numbers(1, "vt", &uv)
    }

    pub(super) fn vn(&mut self, n: V3) -> u32 {
        self.numbers(2, "vn", &normalize(n))
    }

    pub(super) fn tri(&mut self, a: Vert, b: Vert, c: Vert) {
        let f = &mut self.blocks[3];
        f.push('f');
        for k in [a, b, c] {
            match k.vt {
                Some(vt) => write!(f, " {}/{}/{}", k.v, vt, k.vn),
                None => write!(f, " {}//{}", k.v, k.vn),
            }
            .expect("String write");
        }
        f.push('\n');
    }

    /// Two triangles; `q` is counter-clockwise seen from the front.
    pub(super) fn quad(&mut self, q: [Vert; 4]) {
        self.tri(q[0], q[1], q[2]);
        self.tri(q[0], q[2], q[3]);
    }

    pub(super) fn finish(mut self) -> String {
        self.flush();
        self.out
    }
}

pub(super) struct Material {
    pub(super) name: &'static str,
    pub(super) ka: V3,
    pub(super) kd: V3,
    pub(super) ks: V3,
    pub(super) ns: f64,
    /// Dissolve; only written when the material is not opaque.
    pub(super) d: f64,
    pub(super) illum: u32,
    pub(super) map_kd: Option<&'static str>,
}

impl Material {
    /// An opaque Phong material (illum 2); the scenes only vary these four values.
    pub(super) const fn phong(name: &'static str, ka: V3, kd: V3, ks: V3, ns: f64) -> Self {
        Material {
            name,
            ka,
            kd,
            ks,
            ns,
            d: 1.0,
            illum: 2,
            map_kd: None,
        }
    }
}

/// MTL numbers use `Display` (shortest round-trip form, e.g. `0.35`, `96`): exact and stable.
pub(super) fn mtl(materials: &[Material]) -> String {
    let mut out = format!("{HEADER}\n");
    for m in materials {
        let rgb = |c: V3| format!("{} {} {}", c[0], c[1], c[2]);
        write!(
            out,
            "\nnewmtl {}\nKa {}\nKd {}\nKs {}\nNs {}\n",
            m.name,
            rgb(m.ka),
            rgb(m.kd),
            rgb(m.ks),
            m.ns
        )
        .expect("String write");
        if m.d < 1.0 {
            writeln!(out, "d {}", m.d).expect("String write");
        }
        writeln!(out, "illum {}", m.illum).expect("String write");
        if let Some(map) = m.map_kd {
            writeln!(out, "map_Kd {map}").expect("String write");
        }
    }
    out
}
