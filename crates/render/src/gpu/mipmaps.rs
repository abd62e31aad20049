//! Mipmap chains of 8-bit RGBA images built on the CPU. `glGenerateMipmap` on Mesa llvmpipe
//! draws each level with a blit whose shaders LLVM compiles on first use: 110–190 ms for the
//! first texture of a context, where this takes well under a millisecond for a 256² image.
//! Building the chain here also gives mipmaps to drivers without `glGenerateMipmap` (GL 2.1
//! without framebuffer objects).
//!
//! Each level is filtered from the previous *stored* level (as a driver's blit does), with
//! the same taps as a bilinear blit sampling the centre of each destination texel: a 2×2 box
//! on even sizes, the bilinear weights on odd ones. sRGB images are averaged in linear light,
//! as GL does for SRGB8_ALPHA8; alpha always linearly.
use rayon::prelude::*;
use std::sync::OnceLock;

/// One level: width, height, RGBA8 texels (row 0 first, as level 0 was given).
pub(crate) type Level = (u32, u32, Vec<u8>);

fn decode_table() -> &'static [f32; 256] {
    static T: OnceLock<[f32; 256]> = OnceLock::new();
    T.get_or_init(|| {
        std::array::from_fn(|i| {
            let c = i as f32 / 255.0;
            if c <= 0.04045 {
                c / 12.92
            } else {
                ((c + 0.055) / 1.055).powf(2.4)
            }
        })
    })
}

/// Linear [0, 1] in 1/65535 steps to sRGB bytes: the steepest step (12.92·255/65535 of a
/// byte near black) is far below the byte's own rounding.
fn encode_table() -> &'static [u8] {
    static T: OnceLock<Vec<u8>> = OnceLock::new();
    T.get_or_init(|| {
        (0..=65535u32)
            .map(|i| {
                let l = i as f32 / 65535.0;
                let s = if l <= 0.003_130_8 {
                    l * 12.92
                } else {
                    1.055 * l.powf(1.0 / 2.4) - 0.055
                };
                (s * 255.0).round().clamp(0.0, 255.0) as u8
            })
            .collect()
    })
}

/// Source taps of each destination column (or row): (first, second, weight of second).
fn taps(src: u32, dst: u32) -> Vec<(usize, usize, f32)> {
    (0..dst)
        .map(|i| {
            let s = ((i as f32 + 0.5) * src as f32 / dst as f32 - 0.5).max(0.0);
            let a = (s.floor() as u32).min(src - 1);
            let b = (a + 1).min(src - 1);
            (a as usize, b as usize, s - a as f32)
        })
        .collect()
}

/// The next level of `src` (`w`×`h`): ⌊w/2⌋×⌊h/2⌋, at least 1×1.
pub(crate) fn half(w: u32, h: u32, src: &[u8], srgb: bool) -> Level {
    if w.is_multiple_of(2) && h.is_multiple_of(2) {
        half_even(w, h, src, srgb)
    } else {
        half_taps(w, h, src, srgb)
    }
}

/// [`half`] by the general taps: bilinear samples at the destination texels' centres.
fn half_taps(w: u32, h: u32, src: &[u8], srgb: bool) -> Level {
    let (w2, h2) = ((w / 2).max(1), (h / 2).max(1));
    let (cols, rows) = (taps(w, w2), taps(h, h2));
    let dec = decode_table();
    let enc = encode_table();
    let mut out = vec![0u8; (w2 * h2 * 4) as usize];
    out.par_chunks_mut((w2 * 4) as usize)
        .zip(rows.par_iter())
        .for_each(|(row, &(y0, y1, fy))| {
            let r0 = &src[y0 * w as usize * 4..];
            let r1 = &src[y1 * w as usize * 4..];
            for (x, &(x0, x1, fx)) in cols.iter().enumerate() {
                for c in 0..4 {
                    let lerp = |a: f32, b: f32, f: f32| a * (1.0 - f) + b * f;
                    row[x * 4 + c] = if srgb && c < 3 {
                        let get = |r: &[u8], x: usize| dec[r[x * 4 + c] as usize];
                        let top = lerp(get(r0, x0), get(r0, x1), fx);
                        let bottom = lerp(get(r1, x0), get(r1, x1), fx);
                        let v = lerp(top, bottom, fy).clamp(0.0, 1.0);
                        enc[(v * 65535.0).round() as usize]
                    } else {
                        // In byte units, each pass rounded half up to a byte, as a blit
                        // filtering in 8-bit fixed point does (llvmpipe's, exactly).
                        let get = |r: &[u8], x: usize| f32::from(r[x * 4 + c]);
                        let top = lerp(get(r0, x0), get(r0, x1), fx).round();
                        let bottom = lerp(get(r1, x0), get(r1, x1), fx).round();
                        lerp(top, bottom, fy).round().clamp(0.0, 255.0) as u8
                    };
                }
            }
        });
    (w2, h2, out)
}

/// [`half`] of even sizes, where every tap weighs ¼: the same result in integer sums (raw
/// bytes) or one table lookup per texel (sRGB), several times faster than the general taps.
fn half_even(w: u32, h: u32, src: &[u8], srgb: bool) -> Level {
    let (w2, h2) = (w / 2, h / 2);
    let (dec, enc) = (decode_table(), encode_table());
    let row_in = w as usize * 4;
    let mut out = vec![0u8; (w2 * h2 * 4) as usize];
    out.par_chunks_mut((w2 * 4) as usize)
        .zip(src.par_chunks(2 * row_in))
        .for_each(|(row, pair)| {
            let (r0, r1) = pair.split_at(row_in);
            for (x, px) in row.chunks_exact_mut(4).enumerate() {
                let o = x * 8;
                for c in 0..4 {
                    let t = [r0[o + c], r0[o + 4 + c], r1[o + c], r1[o + 4 + c]];
                    px[c] = if srgb && c < 3 {
                        let l = dec[t[0] as usize]
                            + dec[t[1] as usize]
                            + dec[t[2] as usize]
                            + dec[t[3] as usize];
                        enc[(l * (0.25 * 65535.0)).round().min(65535.0) as usize]
                    } else {
                        // Rows then columns, each average rounded half up (see `half_taps`).
                        let [a, b, c, d] = t.map(u16::from);
                        ((a + b).div_ceil(2) + (c + d).div_ceil(2)).div_ceil(2) as u8
                    };
                }
            }
        });
    (w2, h2, out)
}

/// Levels 1.. of the chain under the `w`×`h` image `rgba`, down to 1×1.
pub(crate) fn chain(w: u32, h: u32, rgba: &[u8], srgb: bool) -> Vec<Level> {
    let mut levels: Vec<Level> = Vec::new();
    let (mut cw, mut ch) = (w, h);
    while cw > 1 || ch > 1 {
        let src = levels.last().map_or(rgba, |l| l.2.as_slice());
        let next = half(cw, ch, src, srgb);
        (cw, ch) = (next.0, next.1);
        levels.push(next);
    }
    levels
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn level_sizes_follow_gl() {
        let sizes = |w, h| {
            chain(w, h, &vec![0; (w * h * 4) as usize], false)
                .iter()
                .map(|l| (l.0, l.1))
                .collect::<Vec<_>>()
        };
        assert_eq!(sizes(5, 3), [(2, 1), (1, 1)]);
        assert_eq!(sizes(256, 256).len(), 8);
        assert_eq!(sizes(1, 4), [(1, 2), (1, 1)]);
        assert!(sizes(1, 1).is_empty());
    }

    #[test]
    fn a_flat_image_stays_flat() {
        for srgb in [false, true] {
            for v in [0u8, 1, 37, 128, 200, 255] {
                let img = [v, 255 - v, v / 2, 77].repeat(7 * 6);
                for (w, h, l) in chain(7, 6, &img, srgb) {
                    assert!(l.chunks_exact(4).all(|p| p == [v, 255 - v, v / 2, 77]));
                    assert_eq!(l.len(), (w * h * 4) as usize);
                }
            }
        }
    }

    #[test]
    fn even_levels_are_box_averages() {
        // Black and white: 127.5 rounds up in raw values; in linear light the average is 0.5,
        // which is 188 in sRGB. Alpha is averaged linearly either way.
        let img = [[0, 0, 0, 0], [255, 255, 255, 255]].concat().repeat(2);
        let raw = half(2, 2, &img, false).2;
        assert_eq!(raw, [128, 128, 128, 128]);
        let srgb = half(2, 2, &img, true).2;
        assert_eq!(srgb, [188, 188, 188, 128]);
    }

    #[test]
    fn the_even_shortcut_equals_the_general_taps() {
        let img: Vec<u8> = (0..8 * 6 * 4).map(|i| (i * 97 % 256) as u8).collect();
        for srgb in [false, true] {
            let (w2, h2) = (4, 3);
            let (cols, rows) = (taps(8, w2), taps(6, h2));
            let fast = half_even(8, 6, &img, srgb).2;
            for (y, &(y0, y1, fy)) in rows.iter().enumerate() {
                for (x, &(x0, x1, fx)) in cols.iter().enumerate() {
                    assert_eq!((y1 - y0, x1 - x0, fx, fy), (1, 1, 0.5, 0.5));
                    assert_eq!((y0, x0), (2 * y, 2 * x));
                }
            }
            assert_eq!(fast, half_taps(8, 6, &img, srgb).2, "srgb {srgb}");
        }
    }

    #[test]
    fn odd_sizes_use_bilinear_taps() {
        // 3 texels to 1: the centre sample lands on the middle texel exactly.
        let img = [10u8, 0, 0, 255, 50, 0, 0, 255, 90, 0, 0, 255];
        assert_eq!(half(3, 1, &img, false).2, [50, 0, 0, 255]);
        // 5 to 2: centres at 0.75 and 3.25.
        let img: Vec<u8> = [0u8, 40, 80, 120, 160]
            .iter()
            .flat_map(|&v| [v, 0, 0, 255])
            .collect();
        assert_eq!(half(5, 1, &img, false).2, [30, 0, 0, 255, 130, 0, 0, 255]);
    }
}
