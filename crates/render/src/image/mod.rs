//! Pictures as the renderer reads them back and draws over them: RGBA8, top row first, and
//! their PNG encoding (in memory: writing a file is the caller's); [`canvas`] draws labels.
pub mod canvas;
pub mod differences;

/// An RGBA8 image, row 0 at the top.
#[derive(Clone, Debug, PartialEq)]
pub struct Rgba {
    pub width: u32,
    pub height: u32,
    pub data: Vec<u8>,
}

impl Rgba {
    pub fn pixel(&self, x: u32, y: u32) -> [u8; 4] {
        let i = ((y * self.width + x) * 4) as usize;
        [
            self.data[i],
            self.data[i + 1],
            self.data[i + 2],
            self.data[i + 3],
        ]
    }

    /// Whether every pixel has the same colour (a blank frame).
    pub fn is_uniform(&self) -> bool {
        self.data.chunks_exact(4).all(|p| p == &self.data[..4])
    }

    /// The PNG file's bytes (with `text` chunks), for callers that keep pictures in memory.
    pub fn png_bytes(&self, text: &[(&str, String)]) -> Vec<u8> {
        let mut out = Vec::new();
        // Writing into memory fails only on a bad text key, and glview's keys are fixed.
        let _ = self.write_png(&mut out, text);
        out
    }

    /// The PNG with `text` chunks, written to `out`.
    pub fn write_png<W: std::io::Write>(
        &self,
        out: W,
        text: &[(&str, String)],
    ) -> std::result::Result<(), png::EncodingError> {
        let mut enc = png::Encoder::new(out, self.width, self.height);
        enc.set_color(png::ColorType::Rgba);
        enc.set_depth(png::BitDepth::Eight);
        // zlib level 3 instead of the crate's default 6: measured on the bunny at 640×480
        // and the built-in scene at 1024×768, encode 10.0 → 4.2 ms and 13.4 → 8.1 ms for
        // files 3–5 % larger (level 1: 2–4 ms but 45 % larger). Batches are encode-bound
        // after the frame.
        enc.set_deflate_compression(png::DeflateCompression::Level(3));
        for (k, v) in text {
            // tEXt holds Latin-1 only; a model path in Cyrillic, Greek or CJK letters goes
            // in an iTXt (UTF-8) chunk, which every reader of tEXt also reads.
            if v.chars().all(|c| (c as u32) < 0x100) {
                enc.add_text_chunk(k.to_string(), v.clone())?;
            } else {
                enc.add_itxt_chunk(k.to_string(), v.clone())?;
            }
        }
        let mut w = enc.write_header()?;
        w.write_image_data(&self.data)?;
        w.finish()
    }
}
