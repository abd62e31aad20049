//! Measurements: image error against a reference — the figures peers publish tolerances in
//! (mean absolute error, a high percentile, the share of pixels off by more than a threshold)
//! and a structural one (SSIM, image-compare's MSSIM over 8×8 windows, worst RGB channel),
//! and the linear-light error the PBR checks use — and the process's resident memory with
//! its trend, which the leak checks use. `--diff`, the library's pictures (supersampling),
//! the benchmarks and the tests all measure with these.
use crate::image_out::Rgba;
use serde::Serialize;

use glview_render::image::differences::Differences;
pub use glview_render::image::differences::WRONG_THRESHOLD;

#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct ImageError {
    /// Mean absolute error over all pixels and RGB channels, 0–255.
    pub mae: f64,
    /// 99th percentile of the per-pixel largest channel error, 0–255.
    pub p99: f64,
    /// Largest channel error anywhere, 0–255.
    pub max: f64,
    /// Share of pixels (0–1) whose largest channel error exceeds [`WRONG_THRESHOLD`].
    pub wrong: f64,
    /// Mean SSIM (1 = identical), worst of the three channels.
    pub ssim: f64,
}

/// Compares `image` with `reference` (same size, RGBA8; alpha is ignored). Pixels where
/// `ignore` is true count as exact: they take the reference's value before any metric.
pub fn compare(image: &Rgba, reference: &Rgba, ignore: &[bool]) -> crate::Result<ImageError> {
    if (image.width, image.height) != (reference.width, reference.height) {
        return Err(crate::Error::Usage(format!(
            "cannot compare {}x{} with {}x{}",
            image.width, image.height, reference.width, reference.height
        )));
    }
    let masked;
    let image = if ignore.iter().any(|&i| i) {
        let mut m = image.clone();
        for ((px, r), &skip) in m
            .data
            .chunks_exact_mut(4)
            .zip(reference.data.chunks_exact(4))
            .zip(ignore)
        {
            if skip {
                px.copy_from_slice(r);
            }
        }
        masked = m;
        &masked
    } else {
        image
    };
    let d = Differences::of(
        image
            .data
            .chunks_exact(4)
            .zip(reference.data.chunks_exact(4)),
    );
    Ok(ImageError {
        mae: d.mean(),
        p99: d.percentile(0.99),
        max: d.max(),
        wrong: d.wrong(),
        ssim: ssim(image, reference)?,
    })
}

/// Averages each `k`×`k` block of `img` (a box filter, as a multisample resolve does),
/// rounding to nearest. Factor 1 (or 0) returns `img` itself: every picture without
/// supersampling comes through here, and a per-pixel copy of it cost 2.6 ms at 640×480.
pub fn downsample(img: Rgba, k: u32) -> Rgba {
    if k <= 1 {
        return img;
    }
    let (w, h) = (img.width / k, img.height / k);
    let mut data = Vec::with_capacity((w * h * 4) as usize);
    let n = k * k;
    for y in 0..h {
        for x in 0..w {
            let mut sum = [0u32; 4];
            for dy in 0..k {
                for dx in 0..k {
                    let p = img.pixel(x * k + dx, y * k + dy);
                    for c in 0..4 {
                        sum[c] += u32::from(p[c]);
                    }
                }
            }
            data.extend(sum.map(|s| ((s + n / 2) / n) as u8));
        }
    }
    Rgba {
        width: w,
        height: h,
        data,
    }
}

fn to_rgb(img: &Rgba) -> crate::Result<image::RgbImage> {
    let rgb: Vec<u8> = img
        .data
        .chunks_exact(4)
        .flat_map(|p| [p[0], p[1], p[2]])
        .collect();
    image::RgbImage::from_raw(img.width, img.height, rgb)
        .ok_or_else(|| crate::Error::Usage("image buffer has the wrong length".into()))
}

fn ssim(a: &Rgba, b: &Rgba) -> crate::Result<f64> {
    let alg = image_compare::Algorithm::MSSIMSimple;
    image_compare::rgb_similarity_structure(&alg, &to_rgb(a)?, &to_rgb(b)?)
        .map(|s| s.score)
        .map_err(|e| crate::Error::Usage(format!("SSIM: {e}")))
}

/// Mean and max of the largest channel's linear (sRGB-decoded) difference over the pixels
/// where `hit` is set, and how many there are.
pub fn linear_error(gpu: &Rgba, reference: &Rgba, hit: &[bool]) -> (f64, f64, usize) {
    let lin = |p: &[u8]| [0, 1, 2].map(|i| crate::pbr::srgb_decode(f64::from(p[i]) / 255.0));
    let (mut sum, mut max, mut n) = (0.0, 0.0f64, 0usize);
    for ((a, b), &h) in gpu
        .data
        .chunks_exact(4)
        .zip(reference.data.chunks_exact(4))
        .zip(hit)
    {
        if h {
            let (la, lb) = (lin(a), lin(b));
            let d = (0..3).map(|i| (la[i] - lb[i]).abs()).fold(0.0, f64::max);
            sum += d;
            max = max.max(d);
            n += 1;
        }
    }
    (sum / n.max(1) as f64, max, n)
}

/// This process's resident memory in KiB (Linux `/proc/self/statm`; 0 where unreadable).
pub fn rss_kib() -> u64 {
    std::fs::read_to_string("/proc/self/statm")
        .ok()
        .and_then(|s| {
            s.split_whitespace()
                .nth(1)
                .and_then(|v| v.parse::<u64>().ok())
        })
        .map_or(0, |pages| pages * 4)
}

/// Least-squares slope of `samples` against their index: resident memory on llvmpipe jumps
/// between levels 16 MiB apart from round to round, so a before/after pair says nothing and a
/// trend over every round does.
pub fn trend_per_round(samples: &[u64]) -> f64 {
    let n = samples.len() as f64;
    if samples.len() < 2 {
        return 0.0;
    }
    let mx = (n - 1.0) / 2.0;
    let my = samples.iter().map(|&v| v as f64).sum::<f64>() / n;
    let (mut sxy, mut sxx) = (0.0, 0.0);
    for (i, &v) in samples.iter().enumerate() {
        sxy += (i as f64 - mx) * (v as f64 - my);
        sxx += (i as f64 - mx).powi(2);
    }
    sxy / sxx
}

#[cfg(test)]
mod tests {
    #[test]
    fn trend() {
        assert_eq!(super::trend_per_round(&[5, 7, 9, 11]), 2.0);
        assert!(super::trend_per_round(&[3, 9, 3, 9, 3, 9, 3, 9]).abs() < 1.0);
        assert_eq!(super::trend_per_round(&[1]), 0.0);
    }

    use super::*;

    fn image(w: u32, h: u32, f: impl Fn(u32, u32) -> [u8; 3]) -> Rgba {
        let mut data = Vec::new();
        for y in 0..h {
            for x in 0..w {
                let [r, g, b] = f(x, y);
                data.extend_from_slice(&[r, g, b, 255]);
            }
        }
        Rgba {
            width: w,
            height: h,
            data,
        }
    }

    #[test]
    fn identical_images_have_no_error() {
        let a = image(32, 16, |x, y| [(x * 8) as u8, (y * 16) as u8, 77]);
        let e = compare(&a, &a, &[]).unwrap();
        assert_eq!((e.mae, e.p99, e.max, e.wrong), (0.0, 0.0, 0.0, 0.0));
        assert!((e.ssim - 1.0).abs() < 1e-9, "{}", e.ssim);
    }

    #[test]
    fn known_differences() {
        let a = image(10, 10, |_, _| [100, 100, 100]);
        // One pixel in ten is off by 30 in red only; the rest by 2 in blue.
        let b = image(10, 10, |x, _| {
            if x == 0 {
                [130, 100, 100]
            } else {
                [100, 100, 102]
            }
        });
        let e = compare(&b, &a, &[]).unwrap();
        assert!((e.mae - (10.0 * 30.0 + 90.0 * 2.0) / 300.0).abs() < 1e-12);
        assert_eq!(e.max, 30.0);
        assert_eq!(e.p99, 30.0);
        assert!((e.wrong - 0.1).abs() < 1e-12);
        assert!(e.ssim < 1.0);
    }

    #[test]
    fn ignored_pixels_count_as_exact() {
        let a = image(10, 10, |_, _| [100, 100, 100]);
        let b = image(
            10,
            10,
            |x, _| if x == 0 { [200, 100, 100] } else { [100; 3] },
        );
        let ignore: Vec<bool> = (0..100).map(|i| i % 10 == 0).collect();
        assert_eq!(compare(&b, &a, &ignore).unwrap().max, 0.0);
    }

    #[test]
    fn box_downsample() {
        let a = image(4, 2, |x, y| [(x * 10 + y) as u8, 0, 255]);
        let d = downsample(a.clone(), 2);
        assert_eq!((d.width, d.height), (2, 1));
        // (0 + 10 + 1 + 11) / 4 = 5.5 rounds to 6; (20 + 30 + 21 + 31) / 4 = 25.5 to 26.
        assert_eq!(d.pixel(0, 0), [6, 0, 255, 255]);
        assert_eq!(d.pixel(1, 0), [26, 0, 255, 255]);
        // Factor 1 (and 0, treated as 1) is the image itself.
        for k in [0, 1] {
            let same = downsample(a.clone(), k);
            assert_eq!((same.width, same.height, &same.data), (4, 2, &a.data));
        }
    }

    #[test]
    fn sizes_must_match() {
        let a = image(4, 4, |_, _| [0; 3]);
        let b = image(4, 5, |_, _| [0; 3]);
        assert!(compare(&a, &b, &[]).is_err());
    }
}
