//! PNG output with text chunks that say how the picture was made, so any screenshot can be
//! reproduced, plus the frame checks every render gets (no NaN-black speckles, no blank frame).
use crate::{Error, Result};
pub use glview_render::image::Rgba;
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

/// Writing and reading pictures as files (the renderer's [`Rgba`] holds pixels only), and
/// JPEG encoding.
pub trait RgbaFiles: Sized {
    /// Saves as PNG (with `text` chunks) or JPEG (quality 95, no alpha, no text) by the
    /// extension; refuses other extensions.
    fn save(&self, path: &Path, text: &[(&str, String)]) -> Result<()>;
    /// The picture as JPEG bytes of `quality` (alpha dropped), and which encoder made them:
    /// libjpeg-turbo where it is installed (loaded at run time; ~12× faster), else the
    /// `image` crate's; `GLVIEW_JPEG=image` picks the latter (for measuring the two).
    fn jpeg_bytes(&self, quality: u8) -> Result<(Vec<u8>, &'static str)>;
    fn save_png(&self, path: &Path, text: &[(&str, String)]) -> Result<()>;
    fn load_png(path: &Path) -> Result<Self>;
}

impl RgbaFiles for Rgba {
    fn save(&self, path: &Path, text: &[(&str, String)]) -> Result<()> {
        match OutputFormat::of(path) {
            Some(OutputFormat::Png) => self.save_png(path, text),
            Some(OutputFormat::Jpeg) => {
                let bytes = jpeg_by_image(self, 95).map_err(|message| Error::Image {
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

    fn jpeg_bytes(&self, quality: u8) -> Result<(Vec<u8>, &'static str)> {
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
        jpeg_by_image(self, quality)
            .map(|b| (b, "image"))
            .map_err(err)
    }

    fn save_png(&self, path: &Path, text: &[(&str, String)]) -> Result<()> {
        let file = std::fs::File::create(path).map_err(|e| Error::io(path, e))?;
        self.write_png(std::io::BufWriter::new(file), text)
            .map_err(|e| Error::Image {
                path: path.into(),
                message: e.to_string(),
            })
    }

    fn load_png(path: &Path) -> Result<Rgba> {
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

/// JPEG by the `image` crate's encoder.
fn jpeg_by_image(img: &Rgba, quality: u8) -> std::result::Result<Vec<u8>, String> {
    let rgb: Vec<u8> = img
        .data
        .chunks_exact(4)
        .flat_map(|p| [p[0], p[1], p[2]])
        .collect();
    let mut out = Vec::new();
    image::codecs::jpeg::JpegEncoder::new_with_quality(&mut out, quality.clamp(1, 100))
        .encode(&rgb, img.width, img.height, image::ExtendedColorType::Rgb8)
        .map_err(|e| e.to_string())?;
    Ok(out)
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
        let mut all = vec![
            (bytes, encoder),
            (jpeg_by_image(&img, 90).unwrap(), "image"),
        ];
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
