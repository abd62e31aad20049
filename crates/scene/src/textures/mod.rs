//! Texture decoding with bounded memory. The header is read first and the pixel count decides
//! what happens before any pixel is decoded: too many source pixels → refused; more than the
//! texture budget → downscaled. PNG is downscaled while it is decoded, row by row (a box
//! filter into u64 sums), so a 20000×20000 grayscale PNG never exists in memory at full size;
//! other formats are decoded whole only when that fits in four times the final size.

pub mod avif;
#[cfg(feature = "native")]
#[allow(unsafe_code)]
pub mod dav1d;
pub mod ktx2;
pub mod path;
use crate::model::material::{Texture, TextureOptions};
use image::ImageFormat;
use std::path::{Path, PathBuf};

/// Source images with more pixels than this are refused before decoding: even streamed, the
/// inflate and filter work grows with the pixel count (a 32768² image).
pub(crate) const MAX_SOURCE_PIXELS: u64 = 1 << 30;
/// Decoded textures hold at most this many pixels (8192², 256 MiB as RGBA8); larger images
/// are downscaled, keeping their aspect ratio.
pub(crate) const MAX_TEXTURE_PIXELS: u64 = 1 << 26;
/// Largest side when the caller gives no driver limit (`TextureOptions::max_dimension` 0).
const DEFAULT_MAX_SIDE: u32 = 16384;

/// The size a `w`×`h` image is decoded to: within `max_side` and [`MAX_TEXTURE_PIXELS`].
pub(crate) fn target_size(w: u32, h: u32, max_side: u32) -> (u32, u32) {
    let mut s = 1.0f64;
    s = s.min(f64::from(max_side) / f64::from(w.max(h)));
    let px = f64::from(w) * f64::from(h);
    s = s.min((MAX_TEXTURE_PIXELS as f64 / px).sqrt());
    if s >= 1.0 {
        return (w, h);
    }
    let fit = |x: u32| ((f64::from(x) * s) as u32).clamp(1, max_side);
    (fit(w), fit(h))
}

fn max_side(opts: TextureOptions) -> u32 {
    if opts.max_dimension == 0 {
        DEFAULT_MAX_SIDE
    } else {
        opts.max_dimension
    }
}

/// An image file's bytes: read whole through the loads' resources (a file, or the browser's
/// fetched bytes), or held by a container (a glTF `data:` URI or buffer view).
#[derive(Clone, Copy)]
struct Source<'a>(&'a [u8]);

impl<'a> Source<'a> {
    fn open(self) -> std::io::Cursor<&'a [u8]> {
        std::io::Cursor::new(self.0)
    }
    fn reader(self) -> Result<image::ImageReader<std::io::Cursor<&'a [u8]>>, String> {
        image::ImageReader::new(self.open())
            .with_guessed_format()
            .map_err(|e| e.to_string())
    }
}

/// Largest image file read (a PNG is then decoded row by row; the bounds on the pixels
/// follow from its header).
const MAX_IMAGE_FILE: u64 = 1 << 30;

/// The bytes of image file `path`, through the loads' resources.
fn read_file(path: &Path, limit: u64) -> Result<Vec<u8>, String> {
    let files = crate::load::resources::current();
    match files.kind(path).map_err(|e| e.to_string())? {
        crate::load::resources::Kind::File(n) if n > limit => {
            Err(format!("image file over {} MiB", limit >> 20))
        }
        crate::load::resources::Kind::File(_) => files.read(path, limit).map_err(|e| e.to_string()),
        _ => Err("not a regular file".into()),
    }
}

/// Reads only the header: (format, width, height).
fn header(src: Source) -> Result<(Option<ImageFormat>, u32, u32), String> {
    let reader = src.reader()?;
    let format = reader.format();
    if format.is_none() {
        return Err("not an image in a known format".into());
    }
    let (w, h) = reader
        .into_dimensions()
        .map_err(|e| format!("unreadable image: {e}"))?;
    Ok((format, w, h))
}

/// If the texture at `t.path` was decoded smaller than its file, the sentence saying so
/// (for a warning); re-reads only the header.
pub(crate) fn downscale_note(t: &Texture) -> Option<String> {
    let bytes = read_file(&t.path, MAX_IMAGE_FILE).ok()?;
    let (_, w, h) = header(Source(&bytes)).ok()?;
    ((w, h) != (t.width, t.height)).then(|| {
        format!(
            "texture {w}x{h} downscaled to {}x{} (at most {} pixels and the largest side allowed)",
            t.width, t.height, MAX_TEXTURE_PIXELS
        )
    })
}

/// Decodes an image file already resolved (and checked against the folder rule).
pub(crate) fn decode(path: PathBuf, opts: TextureOptions) -> Result<Texture, String> {
    let bytes = read_file(&path, MAX_IMAGE_FILE)?;
    let (width, height, rgba) = decode_from(Source(&bytes), opts)?;
    Ok(Texture {
        path,
        image: None,
        width,
        height,
        rgba,
    })
}

/// Decodes an image held in memory (image `index` of the container `path`), with the same
/// bounds as a file.
pub(crate) fn decode_bytes(
    bytes: &[u8],
    path: PathBuf,
    index: usize,
    opts: TextureOptions,
) -> Result<Texture, String> {
    let (width, height, rgba) = decode_from(Source(bytes), opts)?;
    Ok(Texture {
        path,
        image: Some(index),
        width,
        height,
        rgba,
    })
}

/// Largest KTX2 or AVIF file decoded (neither is decoded from a stream).
const MAX_WHOLE_BYTES: u64 = 256 << 20;

/// The bytes of `src` if they are a `what` file (`is`), within [`MAX_WHOLE_BYTES`]; None if
/// not.
fn whole_bytes<'a>(
    src: Source<'a>,
    is: fn(&[u8]) -> bool,
    what: &str,
) -> Result<Option<&'a [u8]>, String> {
    if !is(src.0) {
        return Ok(None);
    }
    if src.0.len() as u64 > MAX_WHOLE_BYTES {
        return Err(format!("{what} file over {} MiB", MAX_WHOLE_BYTES >> 20));
    }
    Ok(Some(src.0))
}

fn decode_from(src: Source, opts: TextureOptions) -> Result<(u32, u32, Vec<u8>), String> {
    if let Some(bytes) = whole_bytes(src, crate::textures::ktx2::is_ktx2, "KTX2")? {
        return crate::textures::ktx2::decode(bytes, max_side(opts));
    }
    if let Some(bytes) = whole_bytes(src, crate::textures::avif::is_avif, "AVIF")? {
        return crate::textures::avif::decode(bytes, max_side(opts), MAX_SOURCE_PIXELS);
    }
    let (format, w, h) = header(src)?;
    let max = max_side(opts);
    let pixels = u64::from(w) * u64::from(h);
    if w == 0 || h == 0 || w > max * 4 || h > max * 4 || pixels > MAX_SOURCE_PIXELS {
        return Err(format!(
            "image header says {w}x{h}: refused before decoding"
        ));
    }
    let (tw, th) = target_size(w, h, max);
    let rgba = if format == Some(ImageFormat::Png) {
        decode_png(src, (w, h), (tw, th))?
    } else {
        decode_whole(src, (w, h), (tw, th))?
    };
    Ok((tw, th, rgba))
}

/// Non-streamable formats: decoded whole, allowed only while source plus result stay within
/// four times the result (or 16 MiB for small images).
fn decode_whole(src: Source, (w, h): (u32, u32), (tw, th): (u32, u32)) -> Result<Vec<u8>, String> {
    let final_bytes = u64::from(tw) * u64::from(th) * 4;
    let budget = (4 * final_bytes).max(16 << 20);
    if u64::from(w) * u64::from(h) * 4 + final_bytes > budget {
        return Err(format!(
            "{w}x{h} is too large to decode within {} MiB (only PNG is downscaled while \
             decoding); refused before decoding",
            budget >> 20
        ));
    }
    let mut reader = src.reader()?;
    let mut limits = image::Limits::default();
    limits.max_alloc = Some(budget);
    reader.limits(limits);
    let img = reader
        .decode()
        .map_err(|e| format!("cannot decode: {e}"))?
        .into_rgba8();
    if (tw, th) == (w, h) {
        return Ok(img.into_raw());
    }
    let mut d = BoxDownscaler::new((w, h), (tw, th));
    for row in img.as_raw().chunks_exact(w as usize * 4) {
        d.push_rgba_row(row);
    }
    Ok(d.finish())
}

/// PNG, decoded row by row into the downscaler: memory is the result plus a few rows.
fn decode_png(src: Source, (w, h): (u32, u32), (tw, th): (u32, u32)) -> Result<Vec<u8>, String> {
    let mut decoder = png::Decoder::new_with_limits(src.open(), png::Limits { bytes: 64 << 20 });
    decoder.set_transformations(png::Transformations::normalize_to_color8());
    let mut reader = decoder
        .read_info()
        .map_err(|e| format!("unreadable image: {e}"))?;
    if reader.info().interlaced {
        // Adam7 rows arrive out of order; decode whole within the same bound instead.
        return decode_whole(src, (w, h), (tw, th));
    }
    let (color, _) = reader.output_color_type();
    let mut d = BoxDownscaler::new((w, h), (tw, th));
    let mut rgba = vec![0u8; w as usize * 4];
    while let Some(row) = reader
        .next_row()
        .map_err(|e| format!("cannot decode: {e}"))?
    {
        to_rgba(color, row.data(), &mut rgba);
        d.push_rgba_row(&rgba);
    }
    if d.rows_in < h {
        return Err(format!(
            "cannot decode: image data ends after {} rows",
            d.rows_in
        ));
    }
    Ok(d.finish())
}

/// One decoded PNG row of 8-bit `color` samples as RGBA8. Plain index loops, here and in
/// [`BoxDownscaler::push_rgba_row`]: they run once per source pixel (400 M for a 20,000²
/// image), and the tests' build (opt-level 1) calls every iterator adapter's `next` as a
/// function, which made a decode take ~35 s instead of a few.
fn to_rgba(color: png::ColorType, data: &[u8], rgba: &mut [u8]) {
    let n = rgba.len() / 4;
    let channels = color.samples();
    let mut x = 0;
    while x < n {
        let (s, o) = (x * channels, x * 4);
        let p = match color {
            png::ColorType::Grayscale => [data[s], data[s], data[s], 255],
            png::ColorType::GrayscaleAlpha => [data[s], data[s], data[s], data[s + 1]],
            png::ColorType::Rgb => [data[s], data[s + 1], data[s + 2], 255],
            _ => [data[s], data[s + 1], data[s + 2], data[s + 3]],
        };
        rgba[o..o + 4].copy_from_slice(&p);
        x += 1;
    }
}

/// Area (box) downscaling of RGBA8 rows as they arrive: output pixel (i, j) averages the
/// source pixels whose row and column fall in its bin.
pub(crate) struct BoxDownscaler {
    w: u32,
    h: u32,
    tw: u32,
    th: u32,
    /// Source column where each output column's bin starts (tw + 1 entries).
    col_start: Vec<u32>,
    /// Source column past each output column's bin (tw entries).
    col_end: Vec<u32>,
    sums: Vec<u64>,
    counts: Vec<u64>,
    out: Vec<u8>,
    out_row: u32,
    rows_in: u32,
}

impl BoxDownscaler {
    pub(crate) fn new((w, h): (u32, u32), (tw, th): (u32, u32)) -> Self {
        let col_start: Vec<u32> = (0..=tw)
            .map(|j| (u64::from(j) * u64::from(w) / u64::from(tw)) as u32)
            .collect();
        // A bin holds at least its first column, and none beyond the row.
        let col_end = (0..tw as usize)
            .map(|j| col_start[j + 1].max(col_start[j] + 1).min(w))
            .collect();
        BoxDownscaler {
            w,
            h,
            tw,
            th,
            col_start,
            col_end,
            sums: vec![0; tw as usize * 4],
            counts: vec![0; tw as usize],
            out: Vec::with_capacity(tw as usize * th as usize * 4),
            out_row: 0,
            rows_in: 0,
        }
    }

    fn bin_of_row(&self, y: u32) -> u32 {
        ((u64::from(y) * u64::from(self.th)) / u64::from(self.h)) as u32
    }

    /// One source row, `w` RGBA8 pixels; rows beyond `h` are ignored.
    pub(crate) fn push_rgba_row(&mut self, row: &[u8]) {
        if self.rows_in >= self.h {
            return;
        }
        if (self.tw, self.th) == (self.w, self.h) {
            // Full size: the row is the output row.
            self.out.extend_from_slice(&row[..self.w as usize * 4]);
            self.out_row += 1;
            self.rows_in += 1;
            return;
        }
        let bin = self.bin_of_row(self.rows_in);
        while self.out_row < bin {
            self.flush_row();
        }
        let mut j = 0;
        while j < self.tw as usize {
            let (a, b) = (self.col_start[j] as usize, self.col_end[j] as usize);
            let mut sum = [0u64; 4];
            let mut i = a * 4;
            while i < b * 4 {
                sum[0] += u64::from(row[i]);
                sum[1] += u64::from(row[i + 1]);
                sum[2] += u64::from(row[i + 2]);
                sum[3] += u64::from(row[i + 3]);
                i += 4;
            }
            let s = &mut self.sums[j * 4..j * 4 + 4];
            s[0] += sum[0];
            s[1] += sum[1];
            s[2] += sum[2];
            s[3] += sum[3];
            self.counts[j] += (b - a) as u64;
            j += 1;
        }
        self.rows_in += 1;
    }

    fn flush_row(&mut self) {
        let mut j = 0;
        while j < self.tw as usize {
            let n = if self.counts[j] > 0 {
                self.counts[j]
            } else {
                1
            };
            let s = &self.sums[j * 4..j * 4 + 4];
            // An average of bytes: at most 255.
            let v = |c: usize| ((s[c] + n / 2) / n) as u8;
            self.out.extend_from_slice(&[v(0), v(1), v(2), v(3)]);
            j += 1;
        }
        self.sums.fill(0);
        self.counts.fill(0);
        self.out_row += 1;
    }

    /// The downscaled RGBA8 image, `tw`×`th`.
    pub(crate) fn finish(mut self) -> Vec<u8> {
        while self.out_row < self.th {
            self.flush_row();
        }
        self.out
    }
}

/// An image file's bytes (PNG, JPEG, WebP, BMP, TGA, GIF, HDR, KTX2, AVIF) decoded as a
/// texture is, within the same bounds (refused before decoding when too large, downscaled
/// past the texture budget): width, height and RGBA8 pixels, top row first. For tools and
/// the fuzz targets; a model's textures are decoded by its loader.
pub fn decode_image(bytes: &[u8]) -> std::result::Result<(u32, u32, Vec<u8>), String> {
    let t = decode_bytes(
        bytes,
        std::path::PathBuf::from("<bytes>"),
        0,
        crate::model::material::TextureOptions::default(),
    )?;
    Ok((t.width, t.height, t.rgba))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn targets_respect_side_and_pixel_budget() {
        assert_eq!(target_size(64, 64, 16384), (64, 64));
        assert_eq!(target_size(20000, 20000, 16384), (8192, 8192));
        assert_eq!(target_size(4000, 1000, 2048), (2048, 512));
        let (w, h) = target_size(30000, 3000, 16384);
        assert!(
            u64::from(w) * u64::from(h) <= MAX_TEXTURE_PIXELS && w <= 16384,
            "{w}x{h}"
        );
    }

    #[test]
    fn box_filter_averages_bins() {
        // 4x2 → 2x1: each output pixel is the mean of a 2x2 block.
        let rows = [
            [
                0u8, 0, 0, 255, 100, 100, 100, 255, 10, 10, 10, 255, 30, 30, 30, 255,
            ],
            [
                200u8, 200, 200, 255, 100, 100, 100, 255, 50, 50, 50, 255, 70, 70, 70, 255,
            ],
        ];
        let mut d = BoxDownscaler::new((4, 2), (2, 1));
        for r in &rows {
            d.push_rgba_row(r);
        }
        assert_eq!(d.finish(), vec![100, 100, 100, 255, 40, 40, 40, 255]);
    }

    #[test]
    fn full_size_rows_pass_through() {
        let mut d = BoxDownscaler::new((2, 2), (2, 2));
        d.push_rgba_row(&[1, 2, 3, 4, 5, 6, 7, 8]);
        d.push_rgba_row(&[9, 10, 11, 12, 13, 14, 15, 16]);
        assert_eq!(d.finish(), (1..=16).collect::<Vec<u8>>());
    }

    /// Each output pixel is the rounded mean of the source pixels in its bin (columns from
    /// `i·w/tw` up to `(i+1)·w/tw`, rows whose `y·th/h` is its row), computed here pixel by
    /// pixel.
    #[test]
    fn a_noisy_image_is_the_mean_of_each_bin() {
        let (w, h, tw, th) = (37u32, 23u32, 10u32, 7u32);
        let px = |x: u32, y: u32, c: u32| ((x * 131 + y * 71 + c * 29) ^ (x * y)) as u8;
        let mut d = BoxDownscaler::new((w, h), (tw, th));
        for y in 0..h {
            let row: Vec<u8> = (0..w * 4).map(|i| px(i / 4, y, i % 4)).collect();
            d.push_rgba_row(&row);
        }
        let got = d.finish();
        let bin = |v: u32, n: u32, t: u32| v * t / n;
        for (o, &g) in got.iter().enumerate() {
            let (o, c) = (o as u32 / 4, o as u32 % 4);
            let (i, j) = (o % tw, o / tw);
            let (mut sum, mut n) = (0u32, 0u32);
            for y in (0..h).filter(|&y| bin(y, h, th) == j) {
                for x in i * w / tw..((i + 1) * w / tw).max(i * w / tw + 1) {
                    sum += u32::from(px(x, y, c));
                    n += 1;
                }
            }
            assert_eq!(u32::from(g), (sum + n / 2) / n, "pixel {i},{j} channel {c}");
        }
    }

    #[test]
    fn odd_ratios_cover_every_output_pixel() {
        let mut d = BoxDownscaler::new((7, 5), (3, 2));
        for _ in 0..5 {
            d.push_rgba_row(&[9u8; 28]);
        }
        assert_eq!(d.finish(), [9u8; 24].to_vec());
    }
}
