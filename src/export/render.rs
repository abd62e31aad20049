//! The export's pictures: every view of the grid as the compare view draws it (Phong | PBR
//! on one camera, one session, the scene uploaded once) with the difference numbers over
//! the model's pixels (`--diff phong,pbr`'s), each tier's pane encoded as JPEG or PNG.
use super::{ExportOptions, Grid};
use crate::compare::{crop, phong_pbr};
use crate::image_out::Rgba;
use crate::image_out::RgbaFiles;
use crate::options::AaMode;
use crate::{Error, Result};

/// One view's difference numbers over the model's pixels (in 1/255 and a share 0–1).
#[derive(Clone, Copy, Debug, serde::Serialize)]
pub(crate) struct ViewNumbers {
    pub(crate) mean: f64,
    pub(crate) p99: f64,
    pub(crate) over_8: f64,
    pub(crate) pixels: usize,
}

/// The rendered grid: per view, the encoded Phong and PBR pictures and their numbers.
pub(crate) struct Rendered {
    /// The scene's name.
    pub(crate) model: String,
    /// "image/jpeg" or "image/png".
    pub(crate) mime: &'static str,
    pub(crate) phong: Vec<Vec<u8>>,
    pub(crate) pbr: Vec<Vec<u8>>,
    /// None where neither tier covers a pixel (the model is out of view).
    pub(crate) numbers: Vec<Option<ViewNumbers>>,
}

impl Rendered {
    /// Encoded bytes of every picture.
    pub(crate) fn bytes(&self) -> u64 {
        self.phong
            .iter()
            .chain(&self.pbr)
            .map(|p| p.len() as u64)
            .sum()
    }
}

/// Renders every view of `grid` through one session.
pub(crate) fn render(opts: &ExportOptions, grid: &Grid) -> Result<Rendered> {
    if opts.options.post.aa != AaMode::None {
        // The compare view's panes are viewports of one single-sampled target; a picture
        // antialiased otherwise would not be the one the numbers were measured on.
        return Err(Error::Usage(
            "export draws single-sampled views (as the compare view); drop --aa".into(),
        ));
    }
    if !(1..=100).contains(&opts.quality) {
        return Err(Error::Usage("--quality must be 1 to 100".into()));
    }
    // Each pane is the picture's own width (side-by-side-full's twice --size's).
    let (w, _) = crate::view::settings::output_size(&opts.options);
    let mut session = crate::session::Session::new();
    let model = session.scene(&opts.options)?.name.clone();
    let bar = crate::progress::start("export", grid.len() as u64, crate::progress::Unit::Items);
    let mut out = Rendered {
        model,
        mime: if opts.png { "image/png" } else { "image/jpeg" },
        phong: Vec::with_capacity(grid.len()),
        pbr: Vec::with_capacity(grid.len()),
        numbers: Vec::with_capacity(grid.len()),
    };
    // A live-only page has no pictures: the scene was loaded for its name (and its errors).
    let views = if opts.live == super::Live::Only {
        0
    } else {
        grid.len()
    };
    for v in 0..views {
        let mut o = opts.options.clone();
        (o.camera.yaw, o.camera.pitch) = grid.angles(v);
        let drawn = phong_pbr(&mut session, &o, true)?;
        let phong = crop(&drawn.image, 0, w);
        let pbr = crop(&drawn.image, w, w);
        out.phong.push(encode(&phong, opts)?);
        out.pbr.push(encode(&pbr, opts)?);
        out.numbers
            .push(drawn.numbers.map(|(d, pixels)| ViewNumbers {
                mean: d.mean,
                p99: d.p99,
                over_8: d.over_8,
                pixels,
            }));
        if let Some(b) = &bar {
            b.set(v as u64 + 1);
        }
    }
    if let Some(b) = &bar {
        b.finish(None);
    }
    Ok(out)
}

fn encode(img: &Rgba, opts: &ExportOptions) -> Result<Vec<u8>> {
    if opts.png {
        Ok(img.png_bytes(&[]))
    } else {
        Ok(img.jpeg_bytes(opts.quality)?.0)
    }
}
