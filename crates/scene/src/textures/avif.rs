//! AVIF images (EXT_texture_avif): the container read by `avif-parse` (safe Rust), the size
//! checked from the AV1 sequence header before anything is decoded, the colour and alpha
//! streams decoded by libdav1d (`crate::textures::dav1d`, native builds, loaded at run time), and the
//! planes turned into RGBA8 here: the stream's matrix (BT.601, BT.709, BT.2020, SMPTE 240,
//! FCC, identity) and range, 8 to 12 bits, chroma upsampled bilinearly from sites at the
//! centre of each 2×2 (or 2×1) block as libyuv's filter does, alpha un-premultiplied where
//! the file says it is premultiplied. Transfer functions are taken as the texture slot's
//! (sRGB or linear, as for PNG); rotation and mirror properties are not applied.
#[cfg(feature = "native")]
use super::dav1d;

/// One decoded AV1 frame: its planes as samples (8 to 12 bits each, widened to u16), luma
/// then, unless monochrome, the two chroma planes of `chroma` size.
#[derive(Clone, Debug)]
pub struct Frame {
    pub width: usize,
    pub height: usize,
    pub bits: u32,
    /// 0 monochrome, 1 4:2:0, 2 4:2:2, 3 4:4:4 (dav1d's Dav1dPixelLayout).
    pub layout: u32,
    /// ISO/IEC 23091-2 matrix coefficients (0 identity, 1 BT.709, 6 BT.601, ...).
    pub matrix: u32,
    pub full_range: bool,
    pub chroma: (usize, usize),
    pub planes: [Vec<u16>; 3],
}

#[cfg(not(feature = "native"))]
mod dav1d {
    //! No AV1 decoder outside native builds: AVIF textures fall back to their own images.
    pub(crate) fn available() -> bool {
        false
    }

    pub(crate) fn decode(_: &[u8], _: u32) -> Result<super::Frame, String> {
        Err("no AV1 decoder in this build".into())
    }
}

/// Whether `bytes` start an AVIF file: an `ftyp` box whose brands name `avif` or `avis`.
pub(crate) fn is_avif(bytes: &[u8]) -> bool {
    if bytes.get(4..8) != Some(b"ftyp") {
        return false;
    }
    let len = bytes
        .get(..4)
        .map_or(0, |b| u32::from_be_bytes([b[0], b[1], b[2], b[3]]) as usize);
    let ftyp = &bytes[..len.clamp(8, bytes.len().min(256))];
    ftyp.get(8..)
        .unwrap_or_default()
        .chunks_exact(4)
        .any(|b| b == b"avif" || b == b"avis")
}

/// Whether AVIF images can be decoded here (libdav1d loads).
pub fn available() -> bool {
    dav1d::available()
}

/// The image `bytes` as (width, height, RGBA8), within `max_side` on each axis (4× that is
/// refused before decoding; larger than it, downscaled as other formats are) and
/// `max_pixels` in all.
pub(crate) fn decode(
    bytes: &[u8],
    max_side: u32,
    max_pixels: u64,
) -> Result<(u32, u32, Vec<u8>), String> {
    boxes_fit(bytes)?;
    // The parser has no `unsafe` and returns errors for what it checks; a panic on what it
    // missed would still be a bug of ours to the user, so it becomes the image's error too.
    let parsed =
        std::panic::catch_unwind(|| avif_parse::read_avif(&mut std::io::Cursor::new(bytes)));
    let avif = parsed
        .map_err(|_| "not a readable AVIF file: the parser failed on it".to_string())?
        .map_err(|e| format!("not a readable AVIF file: {e}"))?;
    let meta = avif
        .primary_item_metadata()
        .map_err(|e| format!("not a readable AVIF file: {e}"))?;
    let (w, h) = (meta.max_frame_width.get(), meta.max_frame_height.get());
    if w > max_side * 4 || h > max_side * 4 || u64::from(w) * u64::from(h) > max_pixels {
        return Err(format!(
            "image header says {w}x{h}: refused before decoding"
        ));
    }
    let limit = u32::try_from(max_pixels).unwrap_or(u32::MAX);
    let color = dav1d::decode(&avif.primary_item, limit)?;
    let alpha = match &avif.alpha_item {
        Some(a) => Some(dav1d::decode(a, limit)?),
        None => None,
    };
    if let Some(a) = &alpha {
        if (a.width, a.height) != (color.width, color.height) {
            return Err("the alpha image is not the colour image's size".into());
        }
    }
    let rgba = to_rgba8(&color, alpha.as_ref(), avif.premultiplied_alpha)?;
    let (cw, ch) = (color.width as u32, color.height as u32);
    let (tw, th) = crate::textures::target_size(cw, ch, max_side);
    if (tw, th) == (cw, ch) {
        return Ok((cw, ch, rgba));
    }
    let mut d = crate::textures::BoxDownscaler::new((cw, ch), (tw, th));
    for row in rgba.chunks_exact(cw as usize * 4) {
        d.push_rgba_row(row);
    }
    Ok((tw, th, d.finish()))
}

/// Every box of the top level and of `meta`, `iprp` and `ipco` lies within its container:
/// avif-parse reserves a box's stated size before it reads it, so a 251-byte file whose
/// `iloc` says 4 GB reserved 4 GB (found by the avif fuzz target).
fn boxes_fit(bytes: &[u8]) -> Result<(), String> {
    fn walk(b: &[u8], skip: usize) -> Result<(), String> {
        let word = |at: usize| u32::from_be_bytes([b[at], b[at + 1], b[at + 2], b[at + 3]]);
        let mut at = skip;
        while at + 8 <= b.len() {
            let kind = &b[at + 4..at + 8];
            let left = (b.len() - at) as u64;
            let (size, head) = match word(at) {
                0 => (left, 8),
                1 if at + 16 <= b.len() => (
                    (u64::from(word(at + 8)) << 32) | u64::from(word(at + 12)),
                    16,
                ),
                1 => (u64::MAX, 16),
                n => (u64::from(n), 8),
            };
            if size < head as u64 || size > left {
                return Err(format!(
                    "not a readable AVIF file: its {:?} box says {size} bytes, past its container",
                    String::from_utf8_lossy(kind)
                ));
            }
            let inner = &b[at + head..at + size as usize];
            match kind {
                // `meta` is a full box: version and flags before its children.
                b"meta" => walk(inner, 4)?,
                b"iprp" | b"ipco" => walk(inner, 0)?,
                _ => {}
            }
            at += size as usize;
        }
        Ok(())
    }
    walk(bytes, 0)
}

/// (Kr, Kb) of matrix coefficients `m` (ISO/IEC 23091-2); None for identity (GBR).
fn kr_kb(m: u32) -> Result<Option<(f32, f32)>, String> {
    Ok(Some(match m {
        0 => return Ok(None),
        1 => (0.2126, 0.0722),
        4 => (0.30, 0.11),
        7 => (0.212, 0.087),
        9 => (0.2627, 0.0593),
        // BT.470BG, BT.601 and "unspecified", as libavif reads them.
        2 | 5 | 6 => (0.299, 0.114),
        m => {
            return Err(format!(
                "AVIF matrix coefficients {m} are not ones glview reads"
            ))
        }
    }))
}

/// Sample `v` of a `bits`-bit plane as [0, 1] (luma, alpha) in full or limited range.
fn unit(v: u16, bits: u32, full: bool) -> f32 {
    unit_f(f32::from(v), bits, full)
}

fn unit_f(v: f32, bits: u32, full: bool) -> f32 {
    let max = ((1u32 << bits) - 1) as f32;
    if full {
        v / max
    } else {
        let s = (1u32 << (bits - 8)) as f32;
        (v - 16.0 * s) / (219.0 * s)
    }
}

/// A chroma sample as [-0.5, 0.5].
fn centred(v: f32, bits: u32, full: bool) -> f32 {
    let half = (1u32 << (bits - 1)) as f32;
    if full {
        (v - half) / ((1u32 << bits) - 1) as f32
    } else {
        (v - half) / (224.0 * (1u32 << (bits - 8)) as f32)
    }
}

/// Bilinear weights and neighbours along one axis: luma index `x` of a plane subsampled by
/// 2 reads chroma at (x + 0.5) / 2 - 0.5, clamped at the edges (3:1 weights).
fn taps(x: usize, n: usize, halved: bool) -> (usize, usize, f32) {
    if !halved {
        return (x, x, 0.0);
    }
    let c = x / 2;
    let other = if x.is_multiple_of(2) {
        c.saturating_sub(1)
    } else {
        (c + 1).min(n - 1)
    };
    (c, other, 0.25)
}

fn to8(x: f32) -> u8 {
    (x.clamp(0.0, 1.0) * 255.0).round() as u8
}

/// The frame (and its alpha frame) as RGBA8, top row first.
fn to_rgba8(c: &Frame, alpha: Option<&Frame>, premultiplied: bool) -> Result<Vec<u8>, String> {
    let matrix = kr_kb(c.matrix)?;
    let (w, h, (cw, ch)) = (c.width, c.height, c.chroma);
    let (sub_x, sub_y) = (c.layout == 1 || c.layout == 2, c.layout == 1);
    let mut out = vec![0u8; w * h * 4];
    for y in 0..h {
        let (y0, y1, fy) = taps(y, ch, sub_y);
        for x in 0..w {
            let luma = unit(c.planes[0][y * w + x], c.bits, c.full_range);
            // The chroma samples, interpolated (still in the plane's units).
            let (u, v) = if c.layout == 0 {
                let half = (1u32 << (c.bits - 1)) as f32;
                (half, half)
            } else {
                let (x0, x1, fx) = taps(x, cw, sub_x);
                let at = |p: &[u16]| {
                    let s = |yy: usize, xx: usize| f32::from(p[yy * cw + xx]);
                    let top = s(y0, x0) * (1.0 - fx) + s(y0, x1) * fx;
                    let bottom = s(y1, x0) * (1.0 - fx) + s(y1, x1) * fx;
                    top * (1.0 - fy) + bottom * fy
                };
                (at(&c.planes[1]), at(&c.planes[2]))
            };
            let (r, g, b) = match matrix {
                // Identity: G = Y, B = U, R = V, each a sample like luma.
                None if c.layout != 0 => {
                    let full = |s: f32| unit_f(s, c.bits, c.full_range);
                    (full(v), luma, full(u))
                }
                None => (luma, luma, luma),
                Some((kr, kb)) => {
                    let (u, v) = (
                        centred(u, c.bits, c.full_range),
                        centred(v, c.bits, c.full_range),
                    );
                    let r = luma + 2.0 * (1.0 - kr) * v;
                    let b = luma + 2.0 * (1.0 - kb) * u;
                    (r, (luma - kr * r - kb * b) / (1.0 - kr - kb), b)
                }
            };
            let a = alpha.map_or(1.0, |a| {
                unit(a.planes[0][y * w + x], a.bits, a.full_range).clamp(0.0, 1.0)
            });
            let un = |x: f32| if premultiplied && a > 0.0 { x / a } else { x };
            let o = (y * w + x) * 4;
            out[o..o + 4].copy_from_slice(&[to8(un(r)), to8(un(g)), to8(un(b)), to8(a)]);
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn frame(layout: u32, matrix: u32, full: bool, planes: [Vec<u16>; 3]) -> Frame {
        let chroma = match layout {
            0 => (0, 0),
            1 => (1, 1),
            _ => (2, 2),
        };
        Frame {
            width: 2,
            height: 2,
            bits: 8,
            layout,
            matrix,
            full_range: full,
            chroma,
            planes,
        }
    }

    #[test]
    fn the_ftyp_brands_say_avif() {
        let mut f = vec![0, 0, 0, 24];
        f.extend(b"ftypmif1\0\0\0\0mif1avif");
        assert!(is_avif(&f));
        f[20..24].copy_from_slice(b"heic");
        assert!(!is_avif(&f));
        assert!(!is_avif(b"\x89PNG\r\n\x1a\n"));
    }

    #[test]
    fn identity_full_range_is_the_samples_themselves() {
        // G, B, R planes (Y, U, V) of a lossless AVIF.
        let f = frame(
            3,
            0,
            true,
            [
                vec![10, 20, 30, 40],
                vec![1, 2, 3, 4],
                vec![200, 210, 220, 230],
            ],
        );
        let rgba = to_rgba8(&f, None, false).unwrap();
        assert_eq!(&rgba[..8], &[200, 10, 1, 255, 210, 20, 2, 255]);
    }

    #[test]
    fn bt601_limited_range_greys_and_primaries_are_their_known_values() {
        // Limited-range grey (Y 16..235, chroma 128) is grey; BT.601 red is (81, 90, 240).
        let g = frame(
            3,
            6,
            false,
            [
                vec![16, 235, 126, 81],
                vec![128, 128, 128, 90],
                vec![128, 128, 128, 240],
            ],
        );
        let rgba = to_rgba8(&g, None, false).unwrap();
        assert_eq!(&rgba[..3], &[0, 0, 0]);
        assert_eq!(&rgba[4..7], &[255, 255, 255]);
        assert_eq!(&rgba[8..11], &[128, 128, 128]);
        let red = &rgba[12..15];
        assert!(red[0] >= 253 && red[1] <= 2 && red[2] <= 2, "{red:?}");
    }

    #[test]
    fn subsampled_chroma_is_bilinear_from_block_centres_and_alpha_unpremultiplies() {
        // One chroma sample for the 2×2 block: every pixel reads it whole.
        let f = frame(1, 1, true, [vec![128; 4], vec![128], vec![200]]);
        let rgba = to_rgba8(&f, None, false).unwrap();
        assert!(rgba.chunks_exact(4).all(|p| p == &rgba[..4]));
        assert!(rgba[0] > rgba[1], "V > 128 is red: {:?}", &rgba[..4]);
        let a = frame(0, 2, true, [vec![255, 128, 0, 64], vec![], vec![]]);
        let c = frame(3, 0, true, [vec![32; 4], vec![32; 4], vec![32; 4]]);
        let rgba = to_rgba8(&c, Some(&a), true).unwrap();
        assert_eq!(&rgba[..4], &[32, 32, 32, 255]);
        assert_eq!(rgba[7], 128);
        assert_eq!(rgba[4], 64, "32 over alpha 128/255 is 63.75");
        assert_eq!(rgba[11], 0);
    }

    #[test]
    fn unknown_matrices_are_refused() {
        let f = frame(3, 14, true, [vec![0; 4], vec![0; 4], vec![0; 4]]);
        assert!(to_rgba8(&f, None, false)
            .unwrap_err()
            .contains("matrix coefficients 14"));
    }
}
