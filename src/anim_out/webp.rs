//! Animated WebP: lossless VP8L frames from `image-webp` (pure Rust, already built for
//! EXT_texture_webp), wrapped here in the extended container's animation chunks (RIFF
//! "WEBP", VP8X, ANIM, one ANMF per frame; Google's "WebP Container Specification").
//! `image-webp` encodes stills only; this muxer is about a hundred lines, where the libwebp
//! wrappers (`webp-animation` over `libwebp-sys`) compile libwebp's C sources in every clean
//! build, which the CI budget cannot pay for (docs/animated.md). Lossless frames decode to
//! exactly the stills; the price is files larger than lossy WebP.
use super::delay;
use crate::image_out::Rgba;
use std::io::{Seek, SeekFrom, Write};

/// VP8X flags: the file is animated; its frames carry alpha.
const ANIMATION: u8 = 0x02;
const ALPHA: u8 = 0x10;

/// A VP8L frame is at most 16384 pixels on a side (14-bit sizes in its header).
const MAX_SIDE: u32 = 16384;

pub(super) struct WebpOut<W: Write + Seek> {
    out: W,
    /// Where the RIFF header starts: its length and the VP8X flags are written at the end.
    start: u64,
    size: (u32, u32),
    fps: f32,
    alpha: bool,
}

fn io(e: std::io::Error) -> String {
    e.to_string()
}

/// Little-endian 24-bit field, as the container stores sizes and durations.
fn u24(v: u32) -> [u8; 3] {
    let b = v.to_le_bytes();
    [b[0], b[1], b[2]]
}

impl<W: Write + Seek> WebpOut<W> {
    pub(super) fn new(mut out: W, size: (u32, u32), fps: f32) -> Result<WebpOut<W>, String> {
        if size.0 == 0 || size.1 == 0 || size.0 > MAX_SIDE || size.1 > MAX_SIDE {
            return Err(format!(
                "{}x{}: a lossless WebP frame is at most {MAX_SIDE} pixels on a side",
                size.0, size.1
            ));
        }
        let start = out.stream_position().map_err(io)?;
        out.write_all(b"RIFF\0\0\0\0WEBP").map_err(io)?;
        let mut vp8x = vec![ANIMATION, 0, 0, 0];
        vp8x.extend(u24(size.0 - 1));
        vp8x.extend(u24(size.1 - 1));
        chunk(&mut out, b"VP8X", &vp8x)?;
        // Background colour (BGRA; a hint, unused as every frame covers the canvas), then
        // the loop count: 0 = forever.
        chunk(&mut out, b"ANIM", &[0, 0, 0, 0, 0, 0])?;
        Ok(WebpOut {
            out,
            start,
            size,
            fps,
            alpha: false,
        })
    }

    pub(super) fn add(&mut self, frame: &Rgba, k: u32) -> Result<(), String> {
        let vp8l = vp8l(frame, &mut self.alpha)?;
        let mut anmf = Vec::with_capacity(16 + vp8l.len());
        anmf.extend(u24(0)); // x / 2
        anmf.extend(u24(0)); // y / 2
        anmf.extend(u24(self.size.0 - 1));
        anmf.extend(u24(self.size.1 - 1));
        anmf.extend(u24(delay(k, self.fps, 1000.0).min(0xFF_FFFF)));
        // Do not blend (the frame replaces the canvas), do not dispose.
        anmf.push(0b10);
        anmf.extend(vp8l);
        chunk(&mut self.out, b"ANMF", &anmf)
    }

    /// Writes the RIFF length and the alpha flag, now known.
    pub(super) fn finish(mut self) -> Result<(), String> {
        let end = self.out.stream_position().map_err(io)?;
        let riff = u32::try_from(end - self.start - 8)
            .map_err(|_| "the WebP is over 4 GiB, more than RIFF can hold".to_string())?;
        self.out.seek(SeekFrom::Start(self.start + 4)).map_err(io)?;
        self.out.write_all(&riff.to_le_bytes()).map_err(io)?;
        if self.alpha {
            // RIFF header (12) + VP8X chunk header (8): the flags byte.
            self.out
                .seek(SeekFrom::Start(self.start + 20))
                .map_err(io)?;
            self.out.write_all(&[ANIMATION | ALPHA]).map_err(io)?;
        }
        self.out.seek(SeekFrom::Start(end)).map_err(io)?;
        self.out.flush().map_err(io)
    }
}

/// Writes a RIFF chunk: tag, length, data, and a pad byte after odd-length data.
fn chunk<W: Write>(out: &mut W, tag: &[u8; 4], data: &[u8]) -> Result<(), String> {
    let len = u32::try_from(data.len()).map_err(|_| "a WebP chunk over 4 GiB".to_string())?;
    out.write_all(tag).map_err(io)?;
    out.write_all(&len.to_le_bytes()).map_err(io)?;
    out.write_all(data).map_err(io)?;
    if data.len() % 2 == 1 {
        out.write_all(&[0]).map_err(io)?;
    }
    Ok(())
}

/// The frame as a VP8L chunk (tag, length, data, pad): `image-webp` writes a simple-format
/// file (RIFF header, then that one chunk), whose chunk is taken as it is. Opaque frames
/// are encoded as RGB (no alpha channel to code); otherwise `alpha` is set.
fn vp8l(frame: &Rgba, alpha: &mut bool) -> Result<Vec<u8>, String> {
    let opaque = frame.data.chunks_exact(4).all(|p| p[3] == 255);
    let mut file = Vec::new();
    let enc = image_webp::WebPEncoder::new(&mut file);
    let r = if opaque {
        let rgb: Vec<u8> = frame
            .data
            .chunks_exact(4)
            .flat_map(|p| [p[0], p[1], p[2]])
            .collect();
        enc.encode(&rgb, frame.width, frame.height, image_webp::ColorType::Rgb8)
    } else {
        *alpha = true;
        enc.encode(
            &frame.data,
            frame.width,
            frame.height,
            image_webp::ColorType::Rgba8,
        )
    };
    r.map_err(|e| e.to_string())?;
    match file.get(12..16) {
        Some(b"VP8L") => Ok(file.split_off(12)),
        _ => Err("image-webp wrote no VP8L chunk".into()),
    }
}

#[cfg(test)]
mod tests {
    use super::super::{encode, AnimFormat};
    use crate::image_out::Rgba;

    fn frame(k: u8, alpha: u8) -> Rgba {
        let data = (0..5 * 3u32)
            .flat_map(|i| [i as u8 * 10, k * 40, 200 - i as u8, alpha])
            .collect();
        Rgba {
            width: 5,
            height: 3,
            data,
        }
    }

    /// Odd sizes (padded chunks), opaque and translucent frames: `image-webp`'s decoder
    /// reads the file back frame for frame, the alpha flag set only where a frame has alpha,
    /// and the durations are the rounded ms of 1/fps adding up (24 fps: 42, 41, 42).
    #[test]
    fn frames_read_back() {
        for alpha in [255u8, 128] {
            let frames: Vec<Rgba> = (0..3).map(|k| frame(k, alpha)).collect();
            let bytes = encode(AnimFormat::Webp, &frames, 24.0).unwrap();
            assert_eq!(bytes[20] & super::ALPHA != 0, alpha != 255);
            let mut d = image_webp::WebPDecoder::new(std::io::Cursor::new(bytes)).unwrap();
            assert!(d.is_animated());
            assert_eq!((d.dimensions(), d.num_frames()), ((5, 3), 3));
            assert_eq!(d.loop_duration(), 125);
            let channels = if d.has_alpha() { 4 } else { 3 };
            for (k, f) in frames.iter().enumerate() {
                let mut buf = vec![0; 5 * 3 * channels];
                let ms = d.read_frame(&mut buf).unwrap();
                assert_eq!(ms, [42, 41, 42][k]);
                let want: Vec<u8> = f
                    .data
                    .chunks_exact(4)
                    .flat_map(|p| p[..channels].to_vec())
                    .collect();
                assert_eq!(buf, want, "alpha {alpha}, frame {k}");
            }
        }
    }
}
