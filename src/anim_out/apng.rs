//! APNG frames through the `png` crate (the stills' encoder, at the stills' compression
//! level): lossless, every frame the whole picture, so frame k decodes to exactly the
//! still of its moment. The first frame is also the default image, which viewers without
//! APNG show.
use crate::image_out::Rgba;
use std::io::Write;

pub(super) struct ApngOut<W: Write> {
    writer: png::Writer<W>,
}

/// A frame's delay as APNG's fraction of a second: 1/fps exactly for any fps with at most
/// two decimals (100 / (100·fps), reduced), so every frame has the same delay.
fn delay_fraction(fps: f32) -> (u16, u16) {
    let den = (f64::from(fps) * 100.0).round().clamp(1.0, 65535.0) as u32;
    let g = gcd(100, den);
    ((100 / g) as u16, (den / g) as u16)
}

fn gcd(a: u32, b: u32) -> u32 {
    if b == 0 {
        a
    } else {
        gcd(b, a % b)
    }
}

impl<W: Write> ApngOut<W> {
    pub(super) fn new(
        out: W,
        size: (u32, u32),
        fps: f32,
        frames: u32,
    ) -> Result<ApngOut<W>, String> {
        let mut enc = png::Encoder::new(out, size.0, size.1);
        enc.set_color(png::ColorType::Rgba);
        enc.set_depth(png::BitDepth::Eight);
        enc.set_deflate_compression(png::DeflateCompression::Level(3));
        let e = |e: png::EncodingError| e.to_string();
        enc.set_animated(frames, 0).map_err(e)?;
        let (num, den) = delay_fraction(fps);
        enc.set_frame_delay(num, den).map_err(e)?;
        // Each frame replaces the whole picture (no blending over the last one).
        enc.set_blend_op(png::BlendOp::Source).map_err(e)?;
        enc.set_dispose_op(png::DisposeOp::None).map_err(e)?;
        let writer = enc.write_header().map_err(e)?;
        Ok(ApngOut { writer })
    }

    pub(super) fn add(&mut self, frame: &Rgba) -> Result<(), String> {
        self.writer
            .write_image_data(&frame.data)
            .map_err(|e| e.to_string())
    }

    pub(super) fn finish(self) -> Result<(), String> {
        self.writer.finish().map_err(|e| e.to_string())
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn delay_is_one_over_fps() {
        assert_eq!(super::delay_fraction(15.0), (1, 15));
        assert_eq!(super::delay_fraction(12.5), (2, 25));
        assert_eq!(super::delay_fraction(60.0), (1, 60));
        assert_eq!(super::delay_fraction(23.97), (100, 2397));
    }
}
