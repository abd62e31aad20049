//! `EXT_meshopt_compression`: buffer views whose bytes are meshoptimizer-encoded in another
//! buffer, decoded by the `meshopt` crate (its decoders are safe on untrusted input; sizes are
//! checked here before anything is allocated). The view's own buffer is then usually a
//! placeholder without a URI (`"fallback": true`), which is never read.
use crate::loaders::gltf::accessor::MAX_ELEMENTS;
use serde_json::Value;

/// An output row of `N` bytes (`Default` for any `N`, unlike arrays over 32).
#[derive(Clone, Copy)]
struct Row<const N: usize>([u8; N]);
impl<const N: usize> Default for Row<N> {
    fn default() -> Self {
        Row([0; N])
    }
}

fn vertices<const N: usize>(src: &[u8], count: usize) -> meshopt::Result<Vec<u8>> {
    let v: Vec<Row<N>> = meshopt::decode_vertex_buffer(src, count)?;
    Ok(v.iter().flat_map(|r| r.0).collect())
}

fn exp<const N: usize>(data: &mut [u8]) {
    let mut rows: Vec<[u32; N]> = data
        .chunks_exact(4 * N)
        .map(|c| {
            std::array::from_fn(|k| u32::from_le_bytes(c[4 * k..4 * k + 4].try_into().unwrap()))
        })
        .collect();
    meshopt::decode_filter_exp(&mut rows);
    for (c, r) in data.chunks_exact_mut(4 * N).zip(rows) {
        for (k, x) in r.iter().enumerate() {
            c[4 * k..4 * k + 4].copy_from_slice(&x.to_le_bytes());
        }
    }
}

macro_rules! by_stride {
    ($s:expr, $f:ident, $args:tt, $($n:literal)*) => {
        match $s {
            $( $n => $f::<$n> $args, )*
            _ => unreachable!(),
        }
    };
}

fn i16_rows(data: &[u8]) -> Vec<[i16; 4]> {
    data.chunks_exact(8)
        .map(|c| std::array::from_fn(|k| i16::from_le_bytes([c[2 * k], c[2 * k + 1]])))
        .collect()
}

fn put_i16_rows(data: &mut [u8], rows: &[[i16; 4]]) {
    for (c, r) in data.chunks_exact_mut(8).zip(rows) {
        for (k, x) in r.iter().enumerate() {
            c[2 * k..2 * k + 2].copy_from_slice(&x.to_le_bytes());
        }
    }
}

/// The decoded bytes of one view, from its extension object `ext`.
pub(crate) fn decode(ext: &Value, buffers: &[Vec<u8>]) -> Result<Vec<u8>, String> {
    let num = |k: &str| ext.get(k).and_then(Value::as_u64).map(|x| x as usize);
    let text =
        |k: &str, d: &'static str| ext.get(k).and_then(Value::as_str).unwrap_or(d).to_string();
    let (Some(b), Some(len), Some(stride), Some(count)) = (
        num("buffer"),
        num("byteLength"),
        num("byteStride"),
        num("count"),
    ) else {
        return Err("EXT_meshopt_compression needs buffer, byteLength, byteStride, count".into());
    };
    let off = num("byteOffset").unwrap_or(0);
    let src = buffers
        .get(b)
        .and_then(|d| d.get(off..off.checked_add(len)?))
        .ok_or_else(|| format!("compressed bytes {off}..+{len} lie outside buffer {b}"))?;
    if count > MAX_ELEMENTS {
        return Err(format!(
            "count {count} is more than glview reads ({MAX_ELEMENTS})"
        ));
    }
    let mode = text("mode", "ATTRIBUTES");
    let filter = text("filter", "NONE");
    let mut out = match (mode.as_str(), stride) {
        ("ATTRIBUTES", s) if s % 4 == 0 && (4..=256).contains(&s) => {
            by_stride!(s, vertices, (src, count),
            4 8 12 16 20 24 28 32 36 40 44 48 52 56 60 64 68 72 76 80 84 88 92 96 100 104 108 112
            116 120 124 128 132 136 140 144 148 152 156 160 164 168 172 176 180 184 188 192 196
            200 204 208 212 216 220 224 228 232 236 240 244 248 252 256)
        }
        ("TRIANGLES", 2) => meshopt::decode_index_buffer::<u16>(src, count)
            .map(|v| v.iter().flat_map(|x| x.to_le_bytes()).collect()),
        ("TRIANGLES", 4) => meshopt::decode_index_buffer::<u32>(src, count)
            .map(|v| v.iter().flat_map(|x| x.to_le_bytes()).collect()),
        ("INDICES", 2) => meshopt::decode_index_sequence::<u16>(src, count)
            .map(|v| v.iter().flat_map(|x| x.to_le_bytes()).collect()),
        ("INDICES", 4) => meshopt::decode_index_sequence::<u32>(src, count)
            .map(|v| v.iter().flat_map(|x| x.to_le_bytes()).collect()),
        (m, s) => return Err(format!("mode {m} with byteStride {s} is not valid")),
    }
    .map_err(|e| format!("cannot decode: {e}"))?;
    match (filter.as_str(), stride) {
        ("NONE", _) => {}
        ("OCTAHEDRAL", 4) => {
            let mut rows: Vec<[i8; 4]> = out
                .chunks_exact(4)
                .map(|c| [c[0] as i8, c[1] as i8, c[2] as i8, c[3] as i8])
                .collect();
            meshopt::decode_filter_oct(&mut rows);
            out = rows.iter().flatten().map(|&x| x as u8).collect();
        }
        ("OCTAHEDRAL", 8) => {
            let mut rows = i16_rows(&out);
            meshopt::decode_filter_oct(&mut rows);
            put_i16_rows(&mut out, &rows);
        }
        ("QUATERNION", 8) => {
            let mut rows = i16_rows(&out);
            meshopt::decode_filter_quat(&mut rows);
            put_i16_rows(&mut out, &rows);
        }
        ("EXPONENTIAL", s) if s % 4 == 0 && s <= 64 => by_stride!(s / 4, exp, (&mut out),
            1 2 3 4 5 6 7 8 9 10 11 12 13 14 15 16),
        (f, s) => return Err(format!("filter {f} with byteStride {s} is not supported")),
    }
    Ok(out)
}
