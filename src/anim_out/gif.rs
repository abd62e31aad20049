//! GIF frames: each frame reduced to at most 256 colours here, then written by the `gif`
//! crate (the one the `image` crate's GifEncoder wraps, already built for it). Writing
//! palette and indices directly, rather than RGBA through `image`'s GifEncoder, keeps the
//! quantizer ours (so the tests check exactly what is written) and the trailer's write
//! error reported (`image`'s encoder writes it when dropped and drops the error).
//!
//! Quantization, per frame: a frame with at most 256 colours keeps them (lossless: flat
//! and unlit pictures); otherwise NeuQuant (`color_quant`, the quantizer `image` and `gif`
//! use) learns a 256-colour palette from the frame and every pixel takes its nearest palette colour
//! (squared RGB distance, the lowest index on ties), without dithering: dithering noise
//! differs from frame to frame and shimmers in an animation. Both steps are deterministic,
//! so the same command gives the same bytes. GIF transparency is one bit: with
//! `--transparent`, pixels of alpha under 128 are transparent and the rest opaque.
use super::delay;
use crate::image_out::Rgba;
use std::collections::HashMap;
use std::io::Write;

/// NeuQuant learns from one pixel in `sample factor` (1 to 30; 10 is its authors' balance
/// of speed and quality). A small frame has too few pixels for that: at 10, a 64×48
/// gradient of 3,072 colours trains 256 entries on 307 samples and comes out at 7.7 levels
/// of mean error, against 5.4 learning from every pixel. So the factor keeps at least
/// this many samples (every pixel below it), and is 10 at most.
const MIN_SAMPLES: usize = 30_000;

fn sample_factor(pixels: usize) -> i32 {
    (pixels / MIN_SAMPLES).clamp(1, 10) as i32
}

/// A frame as GIF stores it: an RGB palette (at most 256 entries), one index per pixel,
/// and the index that is transparent, if any.
pub struct Indexed {
    pub palette: Vec<[u8; 3]>,
    pub indices: Vec<u8>,
    pub transparent: Option<u8>,
}

impl Indexed {
    /// The frame as RGBA (the transparent index as (0, 0, 0, 0)): what a decoder shows.
    pub fn to_rgba(&self, width: u32, height: u32) -> Rgba {
        let data = self
            .indices
            .iter()
            .flat_map(|&i| match self.palette.get(usize::from(i)) {
                Some(_) if Some(i) == self.transparent => [0, 0, 0, 0],
                Some(&[r, g, b]) => [r, g, b, 255],
                None => [0, 0, 0, 0],
            })
            .collect();
        Rgba {
            width,
            height,
            data,
        }
    }
}

/// `frame` reduced to at most 256 colours, as the GIF writer stores it (module docs).
pub fn quantize(frame: &Rgba) -> Indexed {
    let opaque = |p: &[u8]| p[3] >= 128;
    let any_clear = frame.data.chunks_exact(4).any(|p| !opaque(p));
    let budget = if any_clear { 255 } else { 256 };
    let mut exact = std::collections::BTreeSet::new();
    for p in frame.data.chunks_exact(4).filter(|p| opaque(p)) {
        exact.insert([p[0], p[1], p[2]]);
        if exact.len() > budget {
            break;
        }
    }
    let palette: Vec<[u8; 3]> = if exact.len() <= budget {
        exact.into_iter().collect()
    } else {
        let samples: Vec<u8> = frame
            .data
            .chunks_exact(4)
            .filter(|p| opaque(p))
            .flat_map(|p| [p[0], p[1], p[2], 255])
            .collect();
        let nq = color_quant::NeuQuant::new(sample_factor(samples.len() / 4), budget, &samples);
        nq.color_map_rgb()
            .chunks_exact(3)
            .map(|c| [c[0], c[1], c[2]])
            .collect()
    };
    let transparent = any_clear.then_some(palette.len() as u8);
    let search = ByGreen::new(&palette);
    // Only looked up, never iterated: the hasher's seed cannot change the output.
    let mut memo: HashMap<[u8; 3], u8, foldhash::fast::RandomState> = HashMap::default();
    let indices = frame
        .data
        .chunks_exact(4)
        .map(|p| match transparent {
            Some(t) if !opaque(p) => t,
            _ => *memo
                .entry([p[0], p[1], p[2]])
                .or_insert_with(|| search.nearest([p[0], p[1], p[2]])),
        })
        .collect();
    let mut palette = palette;
    if any_clear {
        palette.push([0, 0, 0]);
    }
    Indexed {
        palette,
        indices,
        transparent,
    }
}

/// The index of the palette colour nearest to `c` (squared RGB distance; lowest index on
/// ties).
pub fn nearest(palette: &[[u8; 3]], c: [u8; 3]) -> u8 {
    let mut best = (u32::MAX, 0usize);
    for (i, p) in palette.iter().enumerate() {
        let d = distance(*p, c);
        if d < best.0 {
            best = (d, i);
        }
    }
    best.1 as u8
}

fn distance(a: [u8; 3], b: [u8; 3]) -> u32 {
    (0..3).map(|i| u32::from(a[i].abs_diff(b[i])).pow(2)).sum()
}

/// [`nearest`], fast: the palette sorted by green, searched outwards from the colour's
/// green while the green difference alone is no more than the best distance found (the
/// search NeuQuant itself uses). A frame has tens of thousands of colours; trying all 256
/// entries for each was most of a GIF's encoding time (1 s for a 640×480 frame).
struct ByGreen {
    /// (green, colour, palette index), sorted by green then index.
    entries: Vec<(u8, [u8; 3], u8)>,
}

impl ByGreen {
    fn new(palette: &[[u8; 3]]) -> ByGreen {
        let mut entries: Vec<(u8, [u8; 3], u8)> = palette
            .iter()
            .enumerate()
            .map(|(i, c)| (c[1], *c, i as u8))
            .collect();
        entries.sort_unstable();
        ByGreen { entries }
    }

    fn nearest(&self, c: [u8; 3]) -> u8 {
        let start = self.entries.partition_point(|e| e.0 < c[1]);
        let mut best = (u32::MAX, u8::MAX);
        let mut consider = |e: &(u8, [u8; 3], u8)| {
            let dg = u32::from(e.0.abs_diff(c[1])).pow(2);
            if dg > best.0 {
                return false;
            }
            let d = distance(e.1, c);
            if d < best.0 || (d == best.0 && e.2 < best.1) {
                best = (d, e.2);
            }
            true
        };
        for e in &self.entries[start..] {
            if !consider(e) {
                break;
            }
        }
        for e in self.entries[..start].iter().rev() {
            if !consider(e) {
                break;
            }
        }
        best.1
    }
}

/// A GIF being written: looping forever, each frame with its own palette.
pub(super) struct GifOut<W: Write> {
    enc: gif::Encoder<W>,
    size: (u16, u16),
    fps: f32,
}

impl<W: Write> GifOut<W> {
    pub(super) fn new(out: W, size: (u32, u32), fps: f32) -> Result<GifOut<W>, String> {
        let side = |v: u32| u16::try_from(v).ok().filter(|&v| v > 0);
        let (Some(w), Some(h)) = (side(size.0), side(size.1)) else {
            return Err(format!(
                "{}x{}: a GIF is at most 65535 pixels on a side",
                size.0, size.1
            ));
        };
        let mut enc = gif::Encoder::new(out, w, h, &[]).map_err(|e| e.to_string())?;
        enc.set_repeat(gif::Repeat::Infinite)
            .map_err(|e| e.to_string())?;
        Ok(GifOut {
            enc,
            size: (w, h),
            fps,
        })
    }

    pub(super) fn add(&mut self, frame: &Rgba, k: u32) -> Result<(), String> {
        let q = quantize(frame);
        let f = gif::Frame {
            width: self.size.0,
            height: self.size.1,
            delay: u16::try_from(delay(k, self.fps, 100.0)).unwrap_or(u16::MAX),
            // Every frame covers the whole picture; nothing of the last one needs to stay.
            dispose: gif::DisposalMethod::Background,
            transparent: q.transparent,
            palette: Some(q.palette.concat()),
            buffer: std::borrow::Cow::Owned(q.indices),
            ..gif::Frame::default()
        };
        self.enc.write_frame(&f).map_err(|e| e.to_string())
    }

    pub(super) fn finish(self) -> Result<(), String> {
        let mut out = self.enc.into_inner().map_err(|e| e.to_string())?;
        out.flush().map_err(|e| e.to_string())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn gradient(w: u32, h: u32, alpha: impl Fn(u32, u32) -> u8) -> Rgba {
        let data = (0..w * h)
            .flat_map(|i| {
                let (x, y) = (i % w, i / w);
                [
                    (x * 4) as u8,
                    (y * 5) as u8,
                    ((x + y) * 2) as u8,
                    alpha(x, y),
                ]
            })
            .collect();
        Rgba {
            width: w,
            height: h,
            data,
        }
    }

    /// A frame of at most 256 colours is written exactly.
    #[test]
    fn few_colours_are_kept() {
        let img = gradient(16, 16, |_, _| 255);
        let q = quantize(&img);
        assert_eq!(q.palette.len(), 256);
        assert_eq!(q.to_rgba(16, 16), img);
    }

    /// 3,072 colours into 256: every pixel takes its nearest palette colour and the result
    /// is the same every time. The mean error bound, 6 levels: the best palette for this
    /// gradient is near 3 (12 pixels an entry, spread over 8 to 15 levels a channel, about a
    /// quarter of that on average); NeuQuant comes to 5.4, and an undertrained palette
    /// (sample factor 10 here: 7.7) or a wrong mapping fails.
    #[test]
    fn many_colours_take_the_nearest() {
        let img = gradient(64, 48, |_, _| 255);
        let q = quantize(&img);
        assert_eq!(q.palette.len(), 256);
        assert_eq!(q.transparent, None);
        let out = q.to_rgba(64, 48);
        let mut total = 0u64;
        for (i, (p, s)) in out
            .data
            .chunks_exact(4)
            .zip(img.data.chunks_exact(4))
            .enumerate()
        {
            let c = [s[0], s[1], s[2]];
            assert_eq!(q.indices[i], nearest(&q.palette, c));
            total += (0..3).map(|j| u64::from(p[j].abs_diff(s[j]))).sum::<u64>();
        }
        let mean = total as f64 / (64.0 * 48.0 * 3.0);
        assert!(mean < 6.0, "mean error {mean}");
        let search = ByGreen::new(&q.palette);
        for c in (0..4096u32).map(|i| [(i * 7) as u8, (i * 13 / 3) as u8, (i * 29 / 7) as u8]) {
            assert_eq!(search.nearest(c), nearest(&q.palette, c), "{c:?}");
        }
        assert_eq!(quantize(&img).indices, q.indices);
    }

    /// Alpha under 128 is the transparent index, the rest opaque.
    #[test]
    fn transparency_is_one_bit() {
        let img = gradient(64, 48, |x, _| {
            if x < 8 {
                0
            } else if x < 16 {
                100
            } else {
                200
            }
        });
        let q = quantize(&img);
        let t = q.transparent.expect("a transparent index");
        assert_eq!(usize::from(t), q.palette.len() - 1);
        assert!(q.palette.len() <= 256);
        let out = q.to_rgba(64, 48);
        for (i, p) in out.data.chunks_exact(4).enumerate() {
            let x = i as u32 % 64;
            assert_eq!(p[3], if x < 16 { 0 } else { 255 }, "pixel {i}");
        }
    }
}
