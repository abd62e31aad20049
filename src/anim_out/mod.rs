//! Animated pictures: GIF, APNG and animated WebP, encoded one frame at a time as the frames
//! are drawn, so no frame is held after it is encoded (memory is one frame plus the
//! encoder's output). The frame loop is the session's (`session::animated`); this module
//! only turns RGBA frames into files, and knows nothing of scenes or GL.
//!
//! Why each encoder (docs/animated.md has the measurements):
//! - GIF: the `image` crate's `GifEncoder` (already built for texture decoding), fed frames
//!   this module has already reduced to at most 256 colours ([`gif::quantize`]), so the
//!   encoder's own quantizer never runs and what is written is exactly what the tests check.
//! - APNG: the `png` crate (already the stills' encoder); lossless, so each frame decodes
//!   to exactly the still of the same moment.
//! - WebP: `image-webp` (already built for EXT_texture_webp) encodes lossless VP8L stills;
//!   `webp` wraps them in the animation chunks (VP8X, ANIM, ANMF) by hand. The libwebp
//!   wrappers compile libwebp's C sources, which the CI budget cannot pay for.
mod apng;
pub mod gif;
mod webp;

use crate::image_out::Rgba;
use std::io::{Seek, Write};
use std::path::Path;

/// At most this many frames in one animated picture (4 minutes at 15 fps): each is drawn
/// and encoded, and a longer picture is a video, not a figure for a report.
pub const MAX_FRAMES: u32 = 3600;

/// Which animated picture `-o FILE` writes, from the extension (`.png` stays a still).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum AnimFormat {
    Gif,
    Apng,
    Webp,
}

impl AnimFormat {
    pub fn of(path: &Path) -> Option<AnimFormat> {
        let ext = path.extension()?.to_string_lossy().to_ascii_lowercase();
        match ext.as_str() {
            "gif" => Some(AnimFormat::Gif),
            "apng" => Some(AnimFormat::Apng),
            "webp" => Some(AnimFormat::Webp),
            _ => None,
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            AnimFormat::Gif => "GIF",
            AnimFormat::Apng => "APNG",
            AnimFormat::Webp => "WebP",
        }
    }

    /// Why `fps` cannot be written in this format, if it cannot: a GIF's delays are whole
    /// hundredths of a second and browsers play delays under 2/100 s at 1/10 s, so a GIF
    /// above 50 fps would play slower than asked.
    pub fn check_fps(self, fps: f32) -> Result<(), String> {
        if self == AnimFormat::Gif && fps > 50.0 {
            return Err(format!(
                "--fps {fps}: a GIF plays at most 50 frames per second (its delays are in 1/100 s and browsers slow down shorter ones); use .webp or .apng"
            ));
        }
        Ok(())
    }
}

/// How long frame `k` of an animation at `fps` is shown, in 1/`unit` s, for formats whose
/// delays are whole units (GIF: 100, WebP: 1000): the delays of frames 0..k add up to
/// k/fps rounded, so the picture keeps time over its length instead of drifting by the
/// rounding of every frame (15 fps in GIF: 7, 6, 7, 7, 6, 7, ... hundredths).
pub fn delay(k: u32, fps: f32, unit: f64) -> u32 {
    let at = |i: u32| (f64::from(i) * unit / f64::from(fps)).round();
    (at(k + 1) - at(k)).max(1.0) as u32
}

/// An animated picture being written: frames go in one at a time with [`AnimWriter::add`];
/// [`AnimWriter::finish`] completes the file. `W` must seek because a WebP's RIFF header
/// holds the file's length, known at the end.
pub struct AnimWriter<W: Write + Seek> {
    inner: Inner<W>,
    size: (u32, u32),
    frames: u32,
    added: u32,
}

enum Inner<W: Write + Seek> {
    Gif(gif::GifOut<W>),
    Apng(apng::ApngOut<W>),
    Webp(webp::WebpOut<W>),
}

impl<W: Write + Seek> AnimWriter<W> {
    /// A writer of `frames` frames of `size` at `fps` into `out`; errors are one line.
    pub fn new(
        format: AnimFormat,
        out: W,
        size: (u32, u32),
        fps: f32,
        frames: u32,
    ) -> Result<AnimWriter<W>, String> {
        format.check_fps(fps)?;
        if !(fps.is_finite() && fps > 0.0) {
            return Err(format!(
                "--fps {fps}: frames per second must be more than 0"
            ));
        }
        if frames == 0 || frames > MAX_FRAMES {
            return Err(format!(
                "{frames} frames: an animated picture has 1 to {MAX_FRAMES}"
            ));
        }
        let inner = match format {
            AnimFormat::Gif => Inner::Gif(gif::GifOut::new(out, size, fps)?),
            AnimFormat::Apng => Inner::Apng(apng::ApngOut::new(out, size, fps, frames)?),
            AnimFormat::Webp => Inner::Webp(webp::WebpOut::new(out, size, fps)?),
        };
        Ok(AnimWriter {
            inner,
            size,
            frames,
            added: 0,
        })
    }

    /// Encodes the next frame (the picture's size, straight alpha).
    pub fn add(&mut self, frame: &Rgba) -> Result<(), String> {
        if (frame.width, frame.height) != self.size {
            return Err(format!(
                "frame {} is {}x{}, the picture {}x{}",
                self.added, frame.width, frame.height, self.size.0, self.size.1
            ));
        }
        if self.added == self.frames {
            return Err(format!("more than the {} frames announced", self.frames));
        }
        let k = self.added;
        match &mut self.inner {
            Inner::Gif(g) => g.add(frame, k)?,
            Inner::Apng(a) => a.add(frame)?,
            Inner::Webp(w) => w.add(frame, k)?,
        }
        self.added += 1;
        Ok(())
    }

    /// Completes the file (every announced frame must have been added). Pass `&mut` a
    /// writer to keep it: the encoders own theirs.
    pub fn finish(self) -> Result<(), String> {
        if self.added != self.frames {
            return Err(format!(
                "{} of the {} frames announced were added",
                self.added, self.frames
            ));
        }
        match self.inner {
            Inner::Gif(g) => g.finish(),
            Inner::Apng(a) => a.finish(),
            Inner::Webp(w) => w.finish(),
        }
    }
}

/// Encodes `frames` at `fps` into the bytes of an animated picture (for tests, the bench and
/// callers that keep pictures in memory).
pub fn encode(format: AnimFormat, frames: &[Rgba], fps: f32) -> Result<Vec<u8>, String> {
    let first = frames.first().ok_or("no frames to encode")?;
    let n = u32::try_from(frames.len()).map_err(|_| "too many frames".to_string())?;
    let mut out = std::io::Cursor::new(Vec::new());
    let mut w = AnimWriter::new(format, &mut out, (first.width, first.height), fps, n)?;
    for f in frames {
        w.add(f)?;
    }
    w.finish()?;
    Ok(out.into_inner())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The rounded delays add up to the exact time at every frame, so a long picture does
    /// not drift.
    #[test]
    fn delays_keep_time() {
        for (fps, unit) in [
            (15.0f32, 100.0),
            (15.0, 1000.0),
            (24.0, 100.0),
            (7.5, 1000.0),
        ] {
            let mut sum = 0u32;
            for k in 0..600u32 {
                let d = delay(k, fps, unit);
                let exact = unit / f64::from(fps);
                assert!((f64::from(d) - exact).abs() <= 1.0, "{fps} {unit} {k}: {d}");
                sum += d;
                let at = (f64::from(k + 1) * unit / f64::from(fps)).round() as u32;
                assert_eq!(sum, at, "{fps} fps, frame {k}");
            }
        }
        assert_eq!(
            (0..3).map(|k| delay(k, 15.0, 100.0)).collect::<Vec<_>>(),
            [7, 6, 7]
        );
    }
}
