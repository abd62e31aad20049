//! `KHR_draco_mesh_compression`: a primitive whose attributes and indices are one Draco stream
//! in a buffer view, decoded by the pure-Rust `draco-core` crate (no `unsafe`, and ceilings on
//! what one stream may decode: see docs/gltf/extensions.md for why it and not libdraco). Each
//! decoded attribute is re-packed tightly in its accessor's own component type, so the one
//! accessor reader ([`crate::loaders::gltf::accessor::read_f32`]) then treats it like any other bytes:
//! normalized integers, quantized positions already restored by Draco, colours, joints and
//! weights all follow the accessor's `componentType` and `normalized` as the extension says.
//! A stream is decoded once per file however many nodes instance its mesh.
//!
//! The decoded geometry is what is drawn: where a stream decodes more (or fewer) points or
//! corners than its accessors' `count` say (FBX2glTF writes the source mesh's count for
//! parts Draco split at seams), the decoded counts are used, as three.js's DRACOLoader and
//! the extension's "render the decompressed Draco geometry directly" do, with one warning
//! per file; an index past the decoded points stays an error (`gltf_primitive`).
use crate::loaders::gltf::accessor::MAX_ELEMENTS;
use draco_core::{DataType as Dt, DecodeLimits, DecoderBuffer, MeshDecoder, PointIndex};
use gltf::accessor::DataType;
use serde_json::Value;
use std::collections::HashMap;

/// All Draco streams of one file together decode to at most this many attribute bytes (the
/// decoder's own ceiling per stream is what remains of it), so a file of many small streams
/// that each claim the most cannot add up to unbounded memory.
pub(crate) const MAX_DECODED_BYTES: u64 = 1 << 30;

const EXT: &str = "KHR_draco_mesh_compression";

/// The decoded bytes of every accessor that a Draco stream fills, by accessor index, packed
/// `count × components` in the accessor's component type.
pub(crate) type Decoded = HashMap<usize, Vec<u8>>;

/// Decodes every Draco primitive of the file. An error names the mesh and primitive; a
/// warning (one for the file) says which primitives' accessor counts were not the stream's.
pub(crate) fn decode_all(
    doc: &gltf::Document,
    buffers: &[Vec<u8>],
) -> Result<(Decoded, Option<String>), String> {
    let mut out = Decoded::new();
    let mut miscounted = Miscounted::default();
    // Which stream filled an accessor: two primitives may share one stream (and its
    // accessors), but two streams may not both claim an accessor.
    let mut filled_by: HashMap<usize, usize> = HashMap::new();
    let mut budget = MAX_DECODED_BYTES;
    for mesh in doc.meshes() {
        for p in mesh.primitives() {
            let Some(ext) = p.extension_value(EXT) else {
                continue;
            };
            let where_ = format!("mesh {} primitive {}", mesh.index(), p.index());
            let view = ext
                .get("bufferView")
                .and_then(Value::as_u64)
                .and_then(|v| doc.views().nth(usize::try_from(v).ok()?));
            let mut off = None;
            let stream = stream(view, buffers).and_then(|s| {
                let to = Fill {
                    budget: &mut budget,
                    filled_by: &mut filled_by,
                    out: &mut out,
                    off: &mut off,
                };
                primitive(&p, ext, s, to)
            });
            stream.map_err(|e| format!("{where_}: {EXT}: {e}"))?;
            if let Some(off) = off {
                miscounted.note(&where_, off);
            }
        }
    }
    Ok((out, miscounted.warning()))
}

/// Where a stream's count was not its accessor's: the first such, and how many.
#[derive(Default)]
struct Miscounted {
    count: usize,
    first: Option<String>,
}

impl Miscounted {
    fn note(&mut self, primitive: &str, off: String) {
        self.count += 1;
        self.first.get_or_insert(format!("{primitive}: {off}"));
    }

    fn warning(&self) -> Option<String> {
        let first = self.first.as_ref()?;
        let n = self.count;
        let which = if n == 1 {
            "a Draco primitive decodes".to_string()
        } else {
            format!("{n} Draco primitives decode")
        };
        Some(format!(
            "{EXT}: {which} another count than its accessors say ({first}); the decoded \
             geometry is drawn, as three.js draws it"
        ))
    }
}

/// What one stream fills: the file's remaining byte budget, which stream filled each
/// accessor, the decoded accessors, and the first count that was not its accessor's.
struct Fill<'a> {
    budget: &'a mut u64,
    filled_by: &'a mut HashMap<usize, usize>,
    out: &'a mut Decoded,
    off: &'a mut Option<String>,
}

/// The compressed bytes of the extension's `bufferView`, and its index.
fn stream<'a>(
    view: Option<gltf::buffer::View>,
    buffers: &'a [Vec<u8>],
) -> Result<(usize, &'a [u8]), String> {
    let view = view.ok_or("bufferView is missing or does not exist")?;
    let bytes = buffers
        .get(view.buffer().index())
        .and_then(|d| d.get(view.offset()..view.offset().checked_add(view.length())?))
        .ok_or_else(|| format!("buffer view {} lies outside its buffer", view.index()))?;
    Ok((view.index(), bytes))
}

/// Decodes the stream `(view, bytes)` of primitive `p` into the accessors it fills.
fn primitive(
    p: &gltf::Primitive,
    ext: &Value,
    (view, bytes): (usize, &[u8]),
    to: Fill,
) -> Result<(), String> {
    let Fill {
        budget,
        filled_by,
        out,
        off,
    } = to;
    let Some(ids) = ext.get("attributes").and_then(Value::as_object) else {
        return Err("attributes is missing".into());
    };
    // Accessors this stream fills: the indices and each attribute named in the extension.
    let mut targets = Vec::new();
    if let Some(a) = p.indices() {
        targets.push(a.index());
    }
    for (semantic, a) in p.attributes() {
        if ids.contains_key(&semantic.to_string()) {
            targets.push(a.index());
        }
    }
    if targets
        .iter()
        .all(|t| filled_by.get(t).is_some_and(|&v| v == view))
    {
        return Ok(()); // Already decoded for another primitive sharing the stream.
    }
    if let Some(t) = targets.iter().find(|t| filled_by.contains_key(t)) {
        return Err(format!("accessor {t} is filled by two Draco streams"));
    }
    let index_acc = match (p.mode(), p.indices()) {
        (gltf::mesh::Mode::Triangles, Some(acc)) => Some(acc),
        (gltf::mesh::Mode::Points, None) => None,
        (m, _) => {
            return Err(format!(
                "mode {m:?} with{} indices cannot hold a Draco mesh",
                if p.indices().is_some() { "" } else { "out" }
            ))
        }
    };
    let mesh = decode(bytes, *budget)?;
    let mut used = 0u64;
    if let Some(acc) = index_acc {
        let packed = indices(&mesh, &acc, off)?;
        used += packed.len() as u64;
        out.insert(acc.index(), packed);
    }
    for (semantic, acc) in p.attributes() {
        let name = semantic.to_string();
        let Some(id) = ids.get(&name) else {
            continue;
        };
        let id = id
            .as_u64()
            .and_then(|x| u32::try_from(x).ok())
            .ok_or_else(|| format!("attribute id of {name} is not a number"))?;
        let att = mesh
            .attribute_by_unique_id(id)
            .ok_or_else(|| format!("{name}: the stream has no attribute {id}"))?;
        let packed = attribute(&mesh, att, &acc, off).map_err(|e| format!("{name}: {e}"))?;
        used += packed.len() as u64;
        out.insert(acc.index(), packed);
    }
    *budget = budget.saturating_sub(used);
    for t in targets {
        filled_by.insert(t, view);
    }
    Ok(())
}

/// Decodes one stream under ceilings: glview's per-accessor element limit, and what remains
/// of the file's byte budget.
fn decode(bytes: &[u8], budget: u64) -> Result<draco_core::Mesh, String> {
    let limits = DecodeLimits::default()
        .with_max_points(MAX_ELEMENTS as u64)
        .with_max_faces((MAX_ELEMENTS / 3) as u64)
        .with_max_decoded_bytes(budget);
    let mut buffer = DecoderBuffer::new(bytes).with_limits(limits);
    let mut mesh = draco_core::Mesh::new();
    // The decoder has no `unsafe` and returns errors for what it checks; a panic on what it
    // missed would still be a bug of ours to the user, so it becomes the file's error too.
    let decoded = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        MeshDecoder::new().decode(&mut buffer, &mut mesh)
    }));
    match decoded {
        Ok(Ok(())) => Ok(mesh),
        Ok(Err(e)) => Err(format!("cannot decode: {e}")),
        Err(_) => Err("cannot decode: the Draco decoder failed on this stream".into()),
    }
}

/// The faces as the index accessor's component type (all of them: a count other than the
/// accessor's is noted in `off`).
fn indices(
    mesh: &draco_core::Mesh,
    acc: &gltf::Accessor,
    off: &mut Option<String>,
) -> Result<Vec<u8>, String> {
    let corners = mesh.faces().as_flattened();
    if corners.len() != acc.count() {
        off.get_or_insert(format!(
            "{} indices where accessor {} says {}",
            corners.len(),
            acc.index(),
            acc.count()
        ));
    }
    let t = acc.data_type();
    let mut out = Vec::with_capacity(corners.len() * t.size());
    for c in corners {
        write(&mut out, f64::from(c.0), t)
            .ok_or_else(|| format!("index {} does not fit accessor {}", c.0, acc.index()))?;
    }
    Ok(out)
}

/// One decoded attribute, point by point (through the stream's point-to-value map), as
/// `acc`'s component type. The component count must be the accessor's; every decoded point
/// is kept (a point count other than the accessor's is noted in `off`).
fn attribute(
    mesh: &draco_core::Mesh,
    att: &draco_core::PointAttribute,
    acc: &gltf::Accessor,
    off: &mut Option<String>,
) -> Result<Vec<u8>, String> {
    let n = mesh.num_points();
    let dims = acc.dimensions().multiplicity();
    if usize::from(att.num_components()) != dims {
        return Err(format!(
            "the stream decodes values of {} components, accessor {} says {dims}",
            att.num_components(),
            acc.index(),
        ));
    }
    if n != acc.count() {
        off.get_or_insert(format!(
            "{n} points where accessor {} says {}",
            acc.index(),
            acc.count()
        ));
    }
    let from = att.data_type();
    let width = from.byte_length();
    let stride = usize::try_from(att.byte_stride()).unwrap_or(0);
    if width == 0 || stride < width * dims {
        return Err(format!("value type {from:?} cannot be read"));
    }
    let data = att.buffer().data();
    let t = acc.data_type();
    let mut out = Vec::with_capacity(n * dims * t.size());
    for point in 0..n {
        let at = att.mapped_index(PointIndex(point as u32)).0 as usize;
        let row = at
            .checked_mul(stride)
            .and_then(|s| data.get(s..s.checked_add(width * dims)?))
            .ok_or_else(|| format!("point {point} maps to value {at}, which is not there"))?;
        for c in row.chunks_exact(width) {
            let v = read(c, from).ok_or_else(|| format!("value type {from:?} is not numeric"))?;
            write(&mut out, v, t)
                .ok_or_else(|| format!("value {v} does not fit component type {t:?}"))?;
        }
    }
    Ok(out)
}

/// One little-endian scalar of Draco type `t` (every type up to 32 bits is exact in f64).
fn read(b: &[u8], t: Dt) -> Option<f64> {
    let a = |n: usize| -> Option<[u8; 8]> {
        let mut x = [0u8; 8];
        x[..n].copy_from_slice(b.get(..n)?);
        Some(x)
    };
    Some(match t {
        Dt::Int8 => f64::from(*b.first()? as i8),
        Dt::Uint8 | Dt::Bool => f64::from(*b.first()?),
        Dt::Int16 => f64::from(i16::from_le_bytes(a(2)?[..2].try_into().ok()?)),
        Dt::Uint16 => f64::from(u16::from_le_bytes(a(2)?[..2].try_into().ok()?)),
        Dt::Int32 => f64::from(i32::from_le_bytes(a(4)?[..4].try_into().ok()?)),
        Dt::Uint32 => f64::from(u32::from_le_bytes(a(4)?[..4].try_into().ok()?)),
        Dt::Int64 => i64::from_le_bytes(a(8)?) as f64,
        Dt::Uint64 => u64::from_le_bytes(a(8)?) as f64,
        Dt::Float32 => f64::from(f32::from_le_bytes(a(4)?[..4].try_into().ok()?)),
        Dt::Float64 => f64::from_le_bytes(a(8)?),
        Dt::Invalid => return None,
    })
}

/// Appends `v` as a glTF component of type `t`; None if it is not a value of that type (an
/// integer type's range, or a non-finite float).
fn write(out: &mut Vec<u8>, v: f64, t: DataType) -> Option<()> {
    let int = |lo: f64, hi: f64| (v.fract() == 0.0 && (lo..=hi).contains(&v)).then_some(v);
    match t {
        DataType::I8 => out.push((int(-128.0, 127.0)? as i8) as u8),
        DataType::U8 => out.push(int(0.0, 255.0)? as u8),
        DataType::I16 => out.extend((int(-32768.0, 32767.0)? as i16).to_le_bytes()),
        DataType::U16 => out.extend((int(0.0, 65535.0)? as u16).to_le_bytes()),
        DataType::U32 => out.extend((int(0.0, f64::from(u32::MAX))? as u32).to_le_bytes()),
        DataType::F32 => out.extend((v.is_finite().then_some(v)? as f32).to_le_bytes()),
    }
    Some(())
}

#[cfg(test)]
mod tests {
    use crate::loaders::gltf::accessor::{read_f32, read_indices, Buffers};
    use gltf::accessor::Dimensions as D;
    use gltf::mesh::Semantic;
    use std::path::Path;

    fn rigged_simple() -> (gltf::Document, Buffers) {
        let dir = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
            .join("tests/data/khronos/draco/RiggedSimple");
        let bytes = std::fs::read(dir.join("RiggedSimple.gltf")).unwrap();
        let doc = gltf::Gltf::from_slice_without_validation(&bytes)
            .unwrap()
            .document;
        let buffers =
            crate::loaders::gltf::buffers::buffers(&doc, None, (&dir, false), &mut |_| {}).unwrap();
        let draco = crate::loaders::gltf::draco::decode_all(&doc, &buffers)
            .unwrap()
            .0;
        let views = vec![None; doc.views().len()];
        (
            doc,
            Buffers {
                buffers,
                views,
                draco,
            },
        )
    }

    /// Khronos' RiggedSimple carries JOINTS_0 (u16) and WEIGHTS_0 in its Draco stream beside
    /// POSITION and NORMAL: every decoded value is what such a value must be (a joint of the
    /// skin where it weighs, weights summing to one, unit normals, positions inside the
    /// accessor's own min/max, indices inside the vertex count).
    #[test]
    fn every_attribute_of_a_skinned_stream_decodes_to_valid_values() {
        let (doc, b) = rigged_simple();
        let p = doc.meshes().next().unwrap().primitives().next().unwrap();
        let joints_n = doc.skins().next().unwrap().joints().count() as f32;
        let get = |s: Semantic, d: D| read_f32(&p.get(&s).unwrap(), &b, &[d]).unwrap().1;
        let (j, w) = (
            get(Semantic::Joints(0), D::Vec4),
            get(Semantic::Weights(0), D::Vec4),
        );
        let n = p.get(&Semantic::Positions).unwrap().count();
        assert_eq!((j.len(), w.len()), (n * 4, n * 4));
        for (jr, wr) in j.chunks_exact(4).zip(w.chunks_exact(4)) {
            let sum: f32 = wr.iter().sum();
            assert!((sum - 1.0).abs() < 1e-3, "weights {wr:?}");
            for (jj, ww) in jr.iter().zip(wr) {
                assert!(
                    jj.fract() == 0.0 && (*ww == 0.0 || *jj < joints_n),
                    "{jr:?} {wr:?}"
                );
            }
        }
        for q in get(Semantic::Normals, D::Vec3).chunks_exact(3) {
            let len = (q[0] * q[0] + q[1] * q[1] + q[2] * q[2]).sqrt();
            assert!((len - 1.0).abs() < 1e-2, "normal {q:?}");
        }
        let acc = p.get(&Semantic::Positions).unwrap();
        let bound = |v: Option<gltf::json::Value>| -> Vec<f32> {
            serde_json::from_value(v.unwrap()).unwrap()
        };
        let (lo, hi) = (bound(acc.min()), bound(acc.max()));
        for q in get(Semantic::Positions, D::Vec3).chunks_exact(3) {
            for k in 0..3 {
                let slack = (hi[k] - lo[k]) * 1e-3;
                assert!(q[k] >= lo[k] - slack && q[k] <= hi[k] + slack, "{q:?}");
            }
        }
        let idx = read_indices(&p.indices().unwrap(), &b).unwrap();
        assert_eq!(idx.len(), p.indices().unwrap().count());
        assert!(idx.iter().all(|&i| (i as usize) < n));
    }
}
