//! PNG output with text chunks that say how the picture was made, so any screenshot can be
//! reproduced, plus the frame checks every render gets (no NaN-black speckles, no blank frame).
use crate::{Error, Result};
use std::path::Path;

/// What `-o FILE` writes, from the extension.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum OutputFormat {
    Png,
    Jpeg,
}

impl OutputFormat {
    pub fn of(path: &Path) -> Option<OutputFormat> {
        let ext = path.extension()?.to_string_lossy().to_ascii_lowercase();
        match ext.as_str() {
            "png" => Some(OutputFormat::Png),
            "jpg" | "jpeg" => Some(OutputFormat::Jpeg),
            _ => None,
        }
    }
}

/// A PNG's text chunks (key, value), as pictures carry them to the file.
pub(crate) type PngText = Vec<(&'static str, String)>;

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

    /// Saves as PNG (with `text` chunks) or JPEG (quality 95, no alpha, no text) by the
    /// extension; refuses other extensions.
    pub(crate) fn save(&self, path: &Path, text: &[(&str, String)]) -> Result<()> {
        match OutputFormat::of(path) {
            Some(OutputFormat::Png) => self.save_png(path, text),
            Some(OutputFormat::Jpeg) => {
                let bytes = self.jpeg_by_image(95).map_err(|message| Error::Image {
                    path: path.into(),
                    message,
                })?;
                std::fs::write(path, bytes).map_err(|e| Error::io(path, e))
            }
            None => Err(Error::Image {
                path: path.into(),
                message: "output must end in .png, .jpg or .jpeg (animated: .gif, .apng, .webp)"
                    .into(),
            }),
        }
    }

    /// The picture as JPEG bytes of `quality` (alpha dropped), and which encoder made them:
    /// libjpeg-turbo where it is installed (loaded at run time; ~12× faster), else the
    /// `image` crate's; `GLVIEW_JPEG=image` picks the latter (for measuring the two).
    pub fn jpeg_bytes(&self, quality: u8) -> Result<(Vec<u8>, &'static str)> {
        let err = |message: String| Error::Image {
            path: "(JPEG in memory)".into(),
            message,
        };
        let forced = std::env::var_os("GLVIEW_JPEG").is_some_and(|v| v == "image");
        if !forced {
            if let Some(r) = crate::platform::turbojpeg::encode_rgba(
                &self.data,
                self.width,
                self.height,
                quality,
            ) {
                return r.map(|b| (b, "libjpeg-turbo")).map_err(err);
            }
        }
        self.jpeg_by_image(quality)
            .map(|b| (b, "image"))
            .map_err(err)
    }

    /// JPEG by the `image` crate's encoder.
    fn jpeg_by_image(&self, quality: u8) -> std::result::Result<Vec<u8>, String> {
        let rgb: Vec<u8> = self
            .data
            .chunks_exact(4)
            .flat_map(|p| [p[0], p[1], p[2]])
            .collect();
        let mut out = Vec::new();
        image::codecs::jpeg::JpegEncoder::new_with_quality(&mut out, quality.clamp(1, 100))
            .encode(
                &rgb,
                self.width,
                self.height,
                image::ExtendedColorType::Rgb8,
            )
            .map_err(|e| e.to_string())?;
        Ok(out)
    }

    pub fn save_png(&self, path: &Path, text: &[(&str, String)]) -> Result<()> {
        let file = std::fs::File::create(path).map_err(|e| Error::io(path, e))?;
        self.write_png(std::io::BufWriter::new(file), text)
            .map_err(|e| Error::Image {
                path: path.into(),
                message: e.to_string(),
            })
    }

    /// The PNG file's bytes (with `text` chunks), for callers that keep pictures in memory.
    pub fn png_bytes(&self, text: &[(&str, String)]) -> Vec<u8> {
        let mut out = Vec::new();
        // Writing into memory fails only on a bad text key, and glview's keys are fixed.
        let _ = self.write_png(&mut out, text);
        out
    }

    fn write_png<W: std::io::Write>(
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
            enc.add_text_chunk(k.to_string(), v.clone())?;
        }
        let mut w = enc.write_header()?;
        w.write_image_data(&self.data)?;
        w.finish()
    }

    pub fn load_png(path: &Path) -> Result<Rgba> {
        let img = image::open(path)
            .map_err(|e| Error::Image {
                path: path.into(),
                message: e.to_string(),
            })?
            .to_rgba8();
        Ok(Rgba {
            width: img.width(),
            height: img.height(),
            data: img.into_raw(),
        })
    }
}

/// Reads the PNG's text chunks (tEXt, zTXt and iTXt) as (keyword, text).
pub fn png_text(path: &Path) -> Result<Vec<(String, String)>> {
    let file = std::fs::File::open(path).map_err(|e| Error::io(path, e))?;
    let decoder = png::Decoder::new(std::io::BufReader::new(file));
    let reader = decoder.read_info().map_err(|e| Error::Image {
        path: path.into(),
        message: e.to_string(),
    })?;
    let info = reader.info();
    let mut out: Vec<(String, String)> = info
        .uncompressed_latin1_text
        .iter()
        .map(|t| (t.keyword.clone(), t.text.clone()))
        .collect();
    for t in &info.compressed_latin1_text {
        if let Ok(s) = t.get_text() {
            out.push((t.keyword.clone(), s));
        }
    }
    for t in &info.utf8_text {
        if let Ok(s) = t.get_text() {
            out.push((t.keyword.clone(), s));
        }
    }
    Ok(out)
}

/// The framebuffer holds colour multiplied by coverage (blending over a cleared transparent
/// black, resolved or box-filtered edges); PNG wants straight alpha.
pub(crate) fn unpremultiply(img: &mut Rgba) {
    for p in img.data.chunks_exact_mut(4) {
        let a = u32::from(p[3]);
        if a > 0 && a < 255 {
            for c in &mut p[..3] {
                *c = ((u32::from(*c) * 255 + a / 2) / a).min(255) as u8;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Both JPEG encoders give the picture back within JPEG's error on a smooth gradient;
    /// under CI (where scripts/deps.sh installs libturbojpeg0) the fast one must be there.
    #[test]
    fn jpeg_encoders_agree() {
        let (w, h) = (64u32, 48u32);
        let data: Vec<u8> = (0..w * h)
            .flat_map(|i| {
                let (x, y) = (i % w, i / w);
                [(x * 4) as u8, (y * 5) as u8, 128, 255]
            })
            .collect();
        let img = Rgba {
            width: w,
            height: h,
            data,
        };
        let turbo = crate::platform::turbojpeg::available();
        if std::env::var("CI").is_ok_and(|v| v == "true") {
            assert!(
                turbo,
                "libturbojpeg0 is not installed (scripts/deps.sh installs it)"
            );
        }
        let (bytes, encoder) = img.jpeg_bytes(90).unwrap();
        assert_eq!(encoder, if turbo { "libjpeg-turbo" } else { "image" });
        let slow = crate::platform::turbojpeg::encode_rgba(&img.data, w, h + 1, 90);
        assert!(slow.is_none_or(|r| r.is_err()), "a wrong size is refused");
        let mut all = vec![(bytes, encoder), (img.jpeg_by_image(90).unwrap(), "image")];
        if let Some(t) = crate::platform::turbojpeg::encode_rgba(&img.data, w, h, 90) {
            all.push((t.unwrap(), "libjpeg-turbo"));
        }
        for (bytes, encoder) in all {
            let back = image::load_from_memory(&bytes).unwrap().to_rgba8();
            assert_eq!((back.width(), back.height()), (w, h));
            let mean = back
                .as_raw()
                .iter()
                .zip(&img.data)
                .map(|(a, b)| f64::from(a.abs_diff(*b)))
                .sum::<f64>()
                / img.data.len() as f64;
            assert!(mean < 2.0, "{encoder}: mean error {mean}");
        }
    }
}
