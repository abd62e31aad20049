//! KTX2 textures with Basis Universal payloads (`KHR_texture_basisu`: ETC1S/BasisLZ and UASTC,
//! zstd-supercompressed or not), transcoded on load to RGBA8 by the pure-Rust `basisu` crate
//! (a port of the reference transcoder, bit-exact to it), so every context uploads them as it
//! uploads a PNG. The values pass through as stored: sRGB or linear is the slot's to say, as
//! for any other image. Memory is bounded as for the other whole-image formats: the largest
//! mip level that fits the texture budget is transcoded (a KTX2 file usually carries its
//! chain), and a level is refused before transcoding if it would not fit in four times the
//! final size.
use crate::textures::{target_size, BoxDownscaler, MAX_SOURCE_PIXELS};
use basisu::{DecodeFlags, TargetFormat, Transcoder};

/// The KTX 2.0 file identifier.
const MAGIC: [u8; 12] = [
    0xAB, b'K', b'T', b'X', b' ', b'2', b'0', 0xBB, b'\r', b'\n', 0x1A, b'\n',
];

/// Whether `head` (a file's first bytes) starts a KTX2 file.
pub(crate) fn is_ktx2(head: &[u8]) -> bool {
    head.starts_with(&MAGIC)
}

/// The first (largest) level of `t` that needs no downscaling within `max_side`, else level
/// 0: (level, width, height).
fn level(t: &Transcoder, max_side: u32) -> Result<(u32, u32, u32), String> {
    let mut first = None;
    for l in 0..t.level_count() {
        let i = t
            .image_level_info(l)
            .map_err(|e| format!("KTX2 level {l}: {e:?}"))?;
        let (w, h) = (i.width, i.height);
        if w > 0 && h > 0 && target_size(w, h, max_side) == (w, h) {
            return Ok((l, w, h));
        }
        first.get_or_insert((l, w, h));
    }
    first.ok_or_else(|| "KTX2 file without levels".into())
}

fn u32_at(b: &[u8], at: usize) -> Option<u64> {
    Some(u64::from(u32::from_le_bytes(
        b.get(at..at + 4)?.try_into().ok()?,
    )))
}

fn u64_at(b: &[u8], at: usize) -> Option<u64> {
    Some(u64::from_le_bytes(b.get(at..at + 8)?.try_into().ok()?))
}

/// The header's claims checked against the file before the transcoder sees them: it
/// allocates what a level's `uncompressedByteLength` says (a file claiming a terabyte aborts
/// the process: found by `gltf_ktx2::broken_ktx2_files_are_warnings_naming_the_image`). One
/// 2D image; every region inside the file; a level's uncompressed size at most its 4×4
/// blocks at 16 bytes (UASTC's, ETC1S's is 8).
fn check_header(b: &[u8]) -> Result<(), String> {
    let short = || "KTX2 header is truncated".to_string();
    let field = |at: usize| u32_at(b, at).ok_or_else(short);
    let (w, h, depth, layers, faces, levels) = (
        field(20)?,
        field(24)?,
        field(28)?,
        field(32)?,
        field(36)?,
        field(40)?,
    );
    if w == 0 || h == 0 || depth > 1 || layers > 1 || faces != 1 || levels > 32 {
        return Err(format!(
            "KTX2 header: {w}x{h}, depth {depth}, {layers} layers, {faces} faces, {levels} \
             levels is not one 2D texture"
        ));
    }
    if w * h > MAX_SOURCE_PIXELS {
        return Err(format!("KTX2 header says {w}x{h}: refused before decoding"));
    }
    let len = b.len() as u64;
    let inside = |off: Option<u64>, n: Option<u64>, what: &str| -> Result<(), String> {
        let (off, n) = (off.ok_or_else(short)?, n.ok_or_else(short)?);
        match off.checked_add(n) {
            Some(end) if end <= len => Ok(()),
            _ => Err(format!(
                "KTX2 {what} ({off}..+{n}) lies outside the file ({len} bytes)"
            )),
        }
    };
    inside(u32_at(b, 48), u32_at(b, 52), "data format descriptor")?;
    inside(u32_at(b, 56), u32_at(b, 60), "key/value data")?;
    inside(u64_at(b, 64), u64_at(b, 72), "supercompression data")?;
    for l in 0..levels.max(1) {
        let at = 80 + 24 * l as usize;
        inside(u64_at(b, at), u64_at(b, at + 8), &format!("level {l}"))?;
        let blocks = (w >> l).max(1).div_ceil(4) * (h >> l).max(1).div_ceil(4);
        let unpacked = u64_at(b, at + 16).ok_or_else(short)?;
        if unpacked > blocks * 16 {
            return Err(format!(
                "KTX2 level {l} claims {unpacked} bytes for {blocks} blocks: refused"
            ));
        }
    }
    Ok(())
}

/// Transcodes the KTX2 `bytes` to RGBA8 within `max_side`: (width, height, pixels).
pub(crate) fn decode(bytes: &[u8], max_side: u32) -> Result<(u32, u32, Vec<u8>), String> {
    check_header(bytes)?;
    let t = Transcoder::new(bytes)
        .map_err(|e| format!("not a Basis Universal KTX2 texture ({e:?})"))?;
    if t.is_video() || t.face_count() != 1 {
        return Err("a KTX2 video or cube map is not a glTF texture".into());
    }
    let (l, w, h) = level(&t, max_side)?;
    let pixels = u64::from(w) * u64::from(h);
    if w == 0 || h == 0 || pixels > MAX_SOURCE_PIXELS {
        return Err(format!(
            "KTX2 level {l} says {w}x{h}: refused before decoding"
        ));
    }
    let (tw, th) = target_size(w, h, max_side);
    let final_bytes = u64::from(tw) * u64::from(th) * 4;
    if pixels * 4 + final_bytes > (4 * final_bytes).max(16 << 20) {
        return Err(format!(
            "KTX2 level {l} ({w}x{h}) is too large to transcode within the texture budget; \
             refused before decoding"
        ));
    }
    // The transcoder checks what it reads; a panic on what it missed is still this file's
    // error, not the viewer's.
    let rgba = std::panic::catch_unwind(|| t.transcode(l, TargetFormat::Rgba32, DecodeFlags::NONE))
        .map_err(|_| "cannot transcode: the Basis Universal transcoder failed".to_string())?
        .map_err(|e| format!("cannot transcode: {e:?}"))?;
    if rgba.len() as u64 != pixels * 4 {
        return Err(format!("transcoded {} bytes for {w}x{h}", rgba.len()));
    }
    if (tw, th) == (w, h) {
        return Ok((w, h, rgba));
    }
    let mut d = BoxDownscaler::new((w, h), (tw, th));
    for row in rgba.chunks_exact(w as usize * 4) {
        d.push_rgba_row(row);
    }
    Ok((tw, th, d.finish()))
}
