//! Reading glTF accessors with every size checked before anything is allocated: the accessor
//! (offset, count, stride) must lie inside its buffer view, the view inside the bytes its
//! buffer really has, sparse indices and values likewise, and counts stay under
//! [`MAX_ELEMENTS`]. Any component type is read (float, normalized or plain integers: COLOR_0
//! as u8/u16, KHR_mesh_quantization), so callers get `f32`s or `u32` indices.
use gltf::accessor::{DataType, Dimensions};

/// Largest element count of one accessor (and of the whole instanced scene, see `gltf.rs`):
/// 16 M vertices already take ~1 GB through the loading pipeline.
pub(crate) const MAX_ELEMENTS: usize = 1 << 24;

/// The bytes of each buffer, as resolved (exactly `byteLength` long), of each buffer view
/// that `EXT_meshopt_compression` decoded (which then replaces the view's own bytes), and of
/// each accessor that a `KHR_draco_mesh_compression` stream filled (tightly packed, in place
/// of any view the accessor names).
pub(crate) struct Buffers {
    pub(crate) buffers: Vec<Vec<u8>>,
    pub(crate) views: Vec<Option<Vec<u8>>>,
    pub(crate) draco: crate::loaders::gltf::draco::Decoded,
}

fn view_bytes<'a>(view: &gltf::buffer::View, buffers: &'a Buffers) -> Result<&'a [u8], String> {
    if let Some(Some(d)) = buffers.views.get(view.index()) {
        return Ok(d);
    }
    let data = buffers
        .buffers
        .get(view.buffer().index())
        .ok_or_else(|| format!("buffer view {}: no buffer", view.index()))?;
    view.offset()
        .checked_add(view.length())
        .and_then(|end| data.get(view.offset()..end))
        .ok_or_else(|| {
            format!(
                "buffer view {}: bytes {}..+{} lie beyond buffer {} ({} bytes)",
                view.index(),
                view.offset(),
                view.length(),
                view.buffer().index(),
                data.len()
            )
        })
}

/// `count` elements of `size` bytes, `stride` apart from `offset`, inside `data`.
fn strided(data: &[u8], offset: usize, stride: usize, count: usize, size: usize) -> Option<&[u8]> {
    if count == 0 {
        return Some(&[]);
    }
    let end = stride
        .checked_mul(count - 1)?
        .checked_add(size)?
        .checked_add(offset)?;
    data.get(offset..end)
}

fn component(bytes: &[u8], t: DataType, normalized: bool) -> f32 {
    let b = |n: usize| bytes[n];
    match t {
        DataType::F32 => f32::from_le_bytes([b(0), b(1), b(2), b(3)]),
        DataType::U8 if normalized => f32::from(b(0)) / 255.0,
        DataType::U8 => f32::from(b(0)),
        DataType::I8 if normalized => (f32::from(b(0) as i8) / 127.0).max(-1.0),
        DataType::I8 => f32::from(b(0) as i8),
        DataType::U16 if normalized => f32::from(u16::from_le_bytes([b(0), b(1)])) / 65535.0,
        DataType::U16 => f32::from(u16::from_le_bytes([b(0), b(1)])),
        DataType::I16 if normalized => {
            (f32::from(i16::from_le_bytes([b(0), b(1)])) / 32767.0).max(-1.0)
        }
        DataType::I16 => f32::from(i16::from_le_bytes([b(0), b(1)])),
        DataType::U32 => u32::from_le_bytes([b(0), b(1), b(2), b(3)]) as f32,
    }
}

/// The accessor as `dims`-wide rows of f32 (row-major, `count × dims`), sparse values applied.
/// `dims` must be one of `allowed`.
pub(crate) fn read_f32(
    acc: &gltf::Accessor,
    buffers: &Buffers,
    allowed: &[Dimensions],
) -> Result<(usize, Vec<f32>), String> {
    let i = acc.index();
    if !allowed.contains(&acc.dimensions()) {
        return Err(format!(
            "accessor {i}: type {:?} where {allowed:?} is expected",
            acc.dimensions()
        ));
    }
    let dims = acc.dimensions().multiplicity();
    let (t, norm) = (acc.data_type(), acc.normalized());
    let csize = t.size();
    let esize = csize * dims;
    // A Draco stream's accessor holds what the stream decoded, whatever its `count` says
    // (the stream's own ceilings bound it: `gltf_draco`).
    let draco = buffers.draco.get(&i);
    let count = draco.map_or(acc.count(), |d| d.len() / esize.max(1));
    if count > MAX_ELEMENTS {
        return Err(format!(
            "accessor {i}: count {count} is more than glview reads ({MAX_ELEMENTS})"
        ));
    }
    let mut out = vec![0f32; count * dims];
    let read_rows = |data: &[u8], stride: usize, rows: &mut dyn FnMut(usize, &[u8])| {
        for k in 0..data.len().div_ceil(stride.max(1)) {
            let at = k * stride;
            if at + esize <= data.len() {
                rows(k, &data[at..at + esize]);
            }
        }
    };
    let fill = |out: &mut [f32], row: &[u8]| {
        for (c, o) in out.iter_mut().enumerate() {
            *o = component(&row[c * csize..], t, norm);
        }
    };
    if let Some(d) = draco {
        // Packed by the Draco reader to exactly `count` rows of `esize` bytes.
        read_rows(d, esize, &mut |k, row| {
            fill(&mut out[k * dims..k * dims + dims], row)
        });
    } else if let Some(view) = acc.view() {
        let stride = view.stride().unwrap_or(esize).max(esize);
        let data = strided(
            view_bytes(&view, buffers)?,
            acc.offset(),
            stride,
            count,
            esize,
        )
        .ok_or_else(|| {
            format!(
                "accessor {i}: {count} elements of {esize} bytes (stride {stride}) from \
                     offset {} do not fit in buffer view {} ({} bytes)",
                acc.offset(),
                view.index(),
                view.length()
            )
        })?;
        read_rows(data, stride, &mut |k, row| {
            fill(&mut out[k * dims..k * dims + dims], row)
        });
    }
    if let Some(sparse) = acc.sparse() {
        let n = sparse.count();
        if n > count {
            return Err(format!(
                "accessor {i}: {n} sparse values for {count} elements"
            ));
        }
        let idx = sparse.indices();
        let isize = idx.index_type().size();
        let ibytes = strided(
            view_bytes(&idx.view(), buffers)?,
            idx.offset(),
            isize,
            n,
            isize,
        )
        .ok_or_else(|| format!("accessor {i}: sparse indices do not fit in their view"))?;
        let vals = sparse.values();
        let vbytes = strided(
            view_bytes(&vals.view(), buffers)?,
            vals.offset(),
            esize,
            n,
            esize,
        )
        .ok_or_else(|| format!("accessor {i}: sparse values do not fit in their view"))?;
        for k in 0..n {
            let ib = &ibytes[k * isize..];
            let target = match isize {
                1 => usize::from(ib[0]),
                2 => usize::from(u16::from_le_bytes([ib[0], ib[1]])),
                _ => u32::from_le_bytes([ib[0], ib[1], ib[2], ib[3]]) as usize,
            };
            if target >= count {
                return Err(format!(
                    "accessor {i}: sparse index {target} (entry {k}) out of range ({count} elements)"
                ));
            }
            fill(
                &mut out[target * dims..target * dims + dims],
                &vbytes[k * esize..k * esize + esize],
            );
        }
    }
    Ok((dims, out))
}

/// An index accessor (unsigned 8/16/32-bit scalars) as u32.
pub(crate) fn read_indices(acc: &gltf::Accessor, buffers: &Buffers) -> Result<Vec<u32>, String> {
    if !matches!(
        acc.data_type(),
        DataType::U8 | DataType::U16 | DataType::U32
    ) || acc.normalized()
    {
        return Err(format!(
            "accessor {}: indices must be unsigned integers, not {:?}",
            acc.index(),
            acc.data_type()
        ));
    }
    // f32 holds every integer up to 2^24 exactly, beyond MAX_ELEMENTS vertices: a larger
    // index is out of range whichever way it rounds.
    let (_, v) = read_f32(acc, buffers, &[Dimensions::Scalar])?;
    Ok(v.into_iter().map(|x| x as u32).collect())
}
