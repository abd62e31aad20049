//! Difference images with numbers: `--diff A,B` and `--diff-against FILE.png`.
use super::canvas;
use crate::image_out::Rgba;
use crate::image_out::RgbaFiles;
use crate::metrics::{compare, ImageError};
use crate::options::Options;
use crate::{Error, Result};
use glview_render::image::differences::Differences;
use std::path::{Path, PathBuf};

/// The numbers of a comparison, in 0–255 units where they are errors.
#[derive(Clone, Copy, Debug, serde::Serialize)]
pub struct DiffNumbers {
    pub(crate) mean: f64,
    pub(crate) max: f64,
    pub(crate) p99: f64,
    /// Share of pixels (0–1) whose largest channel differs by more than 8/255.
    pub(crate) over_8: f64,
    /// 1 − SSIM (worst channel).
    pub(crate) one_minus_ssim: f64,
}

impl From<ImageError> for DiffNumbers {
    fn from(e: ImageError) -> Self {
        DiffNumbers {
            mean: e.mae,
            max: e.max,
            p99: e.p99,
            over_8: e.wrong,
            one_minus_ssim: (1.0 - e.ssim).max(0.0),
        }
    }
}

impl DiffNumbers {
    pub(crate) fn table(&self, a: &str, b: &str) -> String {
        format!(
            "{a} against {b}:\n  mean      {:.3}/255\n  max       {:.0}/255\n  99th pct  {:.0}/255\n  > 8/255   {:.3} % of pixels\n  1 - SSIM  {:.5}\n",
            self.mean,
            self.max,
            self.p99,
            self.over_8 * 100.0,
            self.one_minus_ssim
        )
    }
}

/// The numbers over the pixels `covered` marks only (the model's, where the two panes'
/// backgrounds differ by design): mean, max, 99th percentile and share over 8/255 count
/// those pixels alone; 1 − SSIM is the whole picture's with every other pixel made equal.
/// None when nothing is covered.
pub(crate) fn over_pixels(a: &Rgba, b: &Rgba, covered: &[bool]) -> Result<Option<DiffNumbers>> {
    let n = covered.iter().filter(|&&c| c).count();
    if n == 0 {
        return Ok(None);
    }
    let ignore: Vec<bool> = covered.iter().map(|c| !c).collect();
    let ssim = compare(a, b, &ignore)?.ssim;
    let pairs = a.data.chunks_exact(4).zip(b.data.chunks_exact(4));
    let d = Differences::of(pairs.zip(covered).filter(|(_, &c)| c).map(|(p, _)| p));
    Ok(Some(DiffNumbers {
        mean: d.mean(),
        max: d.max(),
        p99: d.percentile(0.99),
        over_8: d.wrong(),
        one_minus_ssim: (1.0 - ssim).max(0.0),
    }))
}

/// The union of two panes' coverage.
pub(crate) fn union(a: &[bool], b: &[bool]) -> Vec<bool> {
    a.iter().zip(b).map(|(x, y)| *x || *y).collect()
}

/// A colour scale from black through purple and orange to pale yellow (perceptually ordered).
fn heat(t: f64) -> [u8; 3] {
    const STOPS: [[f64; 3]; 5] = [
        [0.0, 0.0, 0.0],
        [0.34, 0.06, 0.43],
        [0.73, 0.21, 0.33],
        [0.98, 0.55, 0.04],
        [0.99, 1.0, 0.64],
    ];
    let t = t.clamp(0.0, 1.0) * 4.0;
    let i = (t.floor() as usize).min(3);
    let f = t - i as f64;
    [0, 1, 2].map(|c| ((STOPS[i][c] * (1.0 - f) + STOPS[i + 1][c] * f) * 255.0).round() as u8)
}

/// |a − b| (largest channel) on the colour scale, the largest difference at the top, with a
/// scale bar and its range written under the image. Given `covered` (the model's pixels),
/// every other pixel is 0: two tiers' backgrounds differ by design (the PBR tier's sky, the
/// legacy tier's flat colour), and would otherwise fill the picture and its scale.
pub(crate) fn difference_image(a: &Rgba, b: &Rgba, covered: Option<&[bool]>) -> Rgba {
    let d: Vec<u8> = a
        .data
        .chunks_exact(4)
        .zip(b.data.chunks_exact(4))
        .enumerate()
        .map(|(i, (p, q))| match covered {
            Some(c) if !c.get(i).copied().unwrap_or(false) => 0,
            _ => (0..3).map(|c| p[c].abs_diff(q[c])).max().unwrap_or(0),
        })
        .collect();
    let max = d.iter().copied().max().unwrap_or(0).max(1);
    let bar = 2 * canvas::STRIP;
    let mut out = canvas::blank(a.width, a.height + bar, [24, 24, 28]);
    for (i, v) in d.iter().enumerate() {
        let c = heat(f64::from(*v) / f64::from(max));
        out.data[i * 4..i * 4 + 3].copy_from_slice(&c);
    }
    for x in 0..a.width {
        let c = heat(f64::from(x) / f64::from(a.width.max(2) - 1));
        for y in a.height + 2..a.height + canvas::STRIP - 2 {
            let o = ((y * a.width + x) * 4) as usize;
            out.data[o..o + 3].copy_from_slice(&c);
        }
    }
    let label = format!("|A-B| 0..{max}/255");
    canvas::text(
        &mut out,
        2,
        a.height + canvas::STRIP,
        &label,
        [235, 235, 235],
    );
    out
}

fn sibling(path: &Path, suffix: &str) -> PathBuf {
    let stem = path
        .file_stem()
        .and_then(|s| s.to_str())
        .unwrap_or("glview");
    path.with_file_name(format!("{stem}-{suffix}.png"))
}

/// Two tiers' pictures of one model compared: what `--diff A,B` writes and prints.
pub struct TierDiff {
    /// The tiers' names, in order.
    pub(crate) names: [String; 2],
    pub a: Rgba,
    pub b: Rgba,
    /// `difference_image` of the two over the model's pixels (the background is 0).
    pub image: Rgba,
    /// Over the whole picture, backgrounds included.
    pub(crate) numbers: DiffNumbers,
    /// Over the model's pixels (the union of both panes' coverage); None when neither
    /// covers any.
    pub(crate) model: Option<DiffNumbers>,
    pub(crate) model_pixels: usize,
}

impl TierDiff {
    pub fn json(&self) -> serde_json::Value {
        serde_json::json!({
            "a": self.names[0],
            "b": self.names[1],
            "numbers": self.numbers,
            "model": self.model,
            "model_pixels": self.model_pixels,
            "pixels": self.a.width * self.a.height,
        })
    }
}

/// Renders two tiers of `args`' model on one camera and compares them.
pub fn diff_tiers(args: &crate::options::Options, tiers_arg: &str) -> Result<TierDiff> {
    let tiers = super::parse_tiers(tiers_arg, "--diff")?;
    if tiers.len() != 2 {
        return Err(Error::Usage(
            "--diff takes exactly two tiers, e.g. phong,pbr".into(),
        ));
    }
    let (mut scene, clusters) = crate::session::load_scene_prepared(args)?;
    crate::session::pose_scene(args, &mut scene)?;
    let mut panes = super::render_panes_with(args, scene, clusters, &tiers, true)?;
    let covered = union(&panes.coverage[0], &panes.coverage[1]);
    let (b, a) = (panes.images.pop(), panes.images.pop());
    let (a, b) = (a.expect("two panes"), b.expect("two panes"));
    let (image, numbers, model) = diff_images(&a, &b, Some(&covered))?;
    Ok(TierDiff {
        names: [tiers[0].name(), tiers[1].name()],
        image,
        numbers,
        model,
        model_pixels: covered.iter().filter(|&&c| c).count(),
        a,
        b,
    })
}

/// Two pictures of one size compared: the difference image, the numbers over every pixel
/// and, given which pixels are the model's, over those (and the image shows only those).
pub fn diff_images(
    a: &Rgba,
    b: &Rgba,
    covered: Option<&[bool]>,
) -> Result<(Rgba, DiffNumbers, Option<DiffNumbers>)> {
    let numbers = DiffNumbers::from(compare(a, b, &[])?);
    let model = match covered {
        Some(c) => over_pixels(a, b, c)?,
        None => None,
    };
    Ok((difference_image(a, b, covered), numbers, model))
}

/// `--diff A,B`: both renders, the difference image and the numbers (table on stdout, JSON
/// beside the images).
pub fn run_diff(args: &Options, tiers_arg: &str, out: &Path) -> Result<()> {
    let d = diff_tiers(args, tiers_arg)?;
    let [na, nb] = &d.names;
    d.a.save_png(&sibling(out, na), &[])?;
    d.b.save_png(&sibling(out, nb), &[])?;
    d.image
        .save_png(out, &[("glview.diff", format!("{na},{nb}"))])?;
    let json = d.json();
    let json_path = out.with_extension("json");
    std::fs::write(
        &json_path,
        serde_json::to_string_pretty(&json).unwrap_or_default(),
    )
    .map_err(|e| Error::io(&json_path, e))?;
    // The model's numbers first: they are what the picture shows.
    match &d.model {
        Some(m) => print!(
            "{}",
            m.table(
                &format!("{na} on the model's {} pixels", d.model_pixels),
                nb
            )
        ),
        None => println!("(no model pixels in either pane)"),
    }
    print!(
        "{}",
        d.numbers.table(
            &format!("{na} over the whole picture (backgrounds too)"),
            nb
        )
    );
    println!("{json}");
    Ok(())
}

/// `--diff-against FILE.png`: the render against a stored picture. A missing picture is
/// written from the render and the run fails saying so; a mismatch beyond `threshold` (mean
/// error in 1/255) writes the render and the difference image beside it and fails. The
/// render goes to `output`, else beside the stored picture.
pub fn diff_against(
    args: &Options,
    output: Option<&Path>,
    stored: &Path,
    threshold: f64,
) -> Result<()> {
    let out = output.map_or_else(|| sibling(stored, "render"), Path::to_path_buf);
    crate::session::render_headless(args, &out)?;
    let render = Rgba::load_png(&out)?;
    if !stored.exists() {
        render.save_png(stored, &[])?;
        return Err(Error::Usage(format!(
            "{}: no stored picture; wrote this render there: check it and keep it",
            stored.display()
        )));
    }
    let reference = Rgba::load_png(stored)?;
    if (reference.width, reference.height) != (render.width, render.height) {
        return Err(Error::Usage(format!(
            "{}: stored picture is {}x{}, the render {}x{} (see {})",
            stored.display(),
            reference.width,
            reference.height,
            render.width,
            render.height,
            out.display()
        )));
    }
    let numbers = DiffNumbers::from(compare(&render, &reference, &[])?);
    print!("{}", numbers.table("render", &stored.display().to_string()));
    if numbers.mean > threshold {
        let d = sibling(&out, "diff");
        difference_image(&render, &reference, None).save_png(&d, &[])?;
        return Err(Error::Usage(format!(
            "{}: the render differs by a mean of {:.3}/255 (threshold {threshold}); wrote {} and {}",
            stored.display(),
            numbers.mean,
            out.display(),
            d.display()
        )));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn img(px: &[[u8; 3]]) -> Rgba {
        Rgba {
            width: px.len() as u32,
            height: 1,
            data: px.iter().flat_map(|p| [p[0], p[1], p[2], 255]).collect(),
        }
    }

    #[test]
    fn model_numbers_count_the_covered_pixels_only() {
        // Backgrounds 255 apart; the model's two pixels differ by (3, 0, 0) and (0, 30, 0).
        let a = img(&[[0, 0, 0], [10, 10, 10], [50, 50, 50], [0, 0, 0]]);
        let b = img(&[[255; 3], [13, 10, 10], [50, 80, 50], [255; 3]]);
        let covered = [false, true, true, false];
        let m = over_pixels(&a, &b, &covered).unwrap().unwrap();
        assert_eq!(m.mean, 33.0 / 6.0);
        assert_eq!((m.max, m.p99, m.over_8), (30.0, 30.0, 0.5));
        let whole = DiffNumbers::from(compare(&a, &b, &[]).unwrap());
        assert_eq!(whole.max, 255.0);
        // The same model on different backgrounds: zero on the model.
        let c = img(&[[255; 3], [10, 10, 10], [50, 50, 50], [255; 3]]);
        let m = over_pixels(&a, &c, &covered).unwrap().unwrap();
        assert_eq!(
            (m.mean, m.max, m.p99, m.over_8, m.one_minus_ssim),
            (0.0, 0.0, 0.0, 0.0, 0.0)
        );
        assert!(over_pixels(&a, &c, &[false; 4]).unwrap().is_none());
    }

    #[test]
    fn the_difference_picture_is_zero_off_the_model() {
        let a = img(&[[0, 0, 0], [10, 10, 10], [50, 50, 50]]);
        let b = img(&[[255; 3], [13, 10, 10], [50, 80, 50]]);
        let d = difference_image(&a, &b, Some(&[false, true, true]));
        assert_eq!(&d.data[..3], &[0, 0, 0]);
        assert_ne!(&d.data[4..7], &[0, 0, 0]);
        let whole = difference_image(&a, &b, None);
        assert_ne!(&whole.data[..3], &[0, 0, 0]);
    }

    #[test]
    fn coverage_is_the_union() {
        assert_eq!(
            union(&[true, false, false], &[false, false, true]),
            [true, false, true]
        );
    }
}
