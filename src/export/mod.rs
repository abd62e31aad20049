//! `glview export MODEL -o lesson.html`: a lesson page for a learning platform. A grid of
//! turntable views (yaw × pitch) of the Phong and PBR tiers, drawn through one session,
//! embedded in one self-contained HTML file (pictures as data URIs, plain ES5 script, no
//! request) that a student turns with drag, keys and wheel; optionally packaged as SCORM 1.2
//! (`--scorm lesson.zip`) that reports completion to the LMS. It lives in the library (not
//! the command line) because Python's `glview.export` writes the same page.
mod grid;
mod keywords;
pub mod live;
mod page;
mod render;
pub mod scorm;
pub mod zip;

pub use grid::Grid;
pub use live::Live;
pub use page::START_SCRIPT;

use crate::options::Options;
use crate::{Error, Result};
use std::path::{Path, PathBuf};

/// The export's own options (the picture's are `options`): what the command line's `glview
/// export` and Python's `glview.export` fill.
#[derive(Clone, Debug)]
pub struct ExportOptions {
    /// The picture options every view starts from: model, lights, PBR settings, and the
    /// camera whose yaw and pitch are the grid's first view (`glview MODEL -o`'s).
    pub options: Options,
    /// Views around the model (yaw steps of 360/N degrees), 1 to 360.
    pub yaw_steps: u32,
    /// Rows of pitch, centred on the options' pitch (1 to 15).
    pub pitch_steps: u32,
    /// Degrees between two pitch rows.
    pub pitch_step: f32,
    /// JPEG quality 1–100 of the pictures (ignored with `png`).
    pub quality: u8,
    /// Lossless PNG pictures instead of JPEG (each view exactly `glview -o`'s; larger).
    pub png: bool,
    /// The page's heading (default: the model's name).
    pub title: Option<String>,
    /// A caption the teacher gives, shown under the title.
    pub caption: Option<String>,
    /// Warn when the page is larger than this many bytes.
    pub max_size: Option<u64>,
    /// Also write the page as a SCORM 1.2 package (zip) here.
    pub scorm: Option<PathBuf>,
    /// Whether the page draws live in the browser (`--live`, `--live-only`).
    pub live: Live,
    /// The browser build's folder for `live` (default: `$GLVIEW_WEB_DIR`, else `web/` beside
    /// the executable's folder, i.e. `target/web`).
    pub web_dir: Option<PathBuf>,
}

/// JPEG quality by measurement on the bunny at 640×480 (scripts/export_quality.py,
/// docs/export.md): at 85 a picture is 13.5 kB with a mean error of 0.51/255 against the PNG
/// (99th percentile 8/255); 90 costs 16 % more for 0.04/255 less, 80 saves 9 % for 0.05/255
/// more. The default grid's 360 pictures make a 6.5 MB page, within the 10 MB budget.
pub const DEFAULT_QUALITY: u8 = 85;

impl Default for ExportOptions {
    fn default() -> Self {
        let mut options = Options::default();
        options.picture.size = (640, 480);
        ExportOptions {
            options,
            yaw_steps: 36,
            pitch_steps: 5,
            pitch_step: 15.0,
            quality: DEFAULT_QUALITY,
            png: false,
            title: None,
            caption: None,
            max_size: None,
            scorm: None,
            live: Live::Off,
            web_dir: None,
        }
    }
}

/// A written (or built) export: the page, and what it cost.
pub struct Export {
    /// The HTML page.
    pub html: String,
    /// Number of views (grid cells); each has a Phong and a PBR picture.
    pub views: usize,
    /// Bytes of the pictures (encoded, before base64).
    pub picture_bytes: u64,
    /// The page's title (`--title`, else the model's name).
    pub title: String,
    /// One line: views, size, where.
    pub summary: String,
}

/// The page of `opts`, built in memory.
pub fn build(opts: &ExportOptions) -> Result<Export> {
    let grid = Grid::of(opts)?;
    let rendered = render::render(opts, &grid)?;
    let picture_bytes = rendered.bytes();
    let title = opts.title.clone().unwrap_or_else(|| rendered.model.clone());
    let live = match opts.live {
        Live::Off => None,
        Live::Live | Live::Only => Some(live::payload(opts)?),
    };
    let html = page::html(opts, &grid, &rendered, &title, live.as_ref());
    let views = grid.len();
    let (w, h) = opts.options.picture.size;
    let pictures = match opts.live {
        Live::Only => "no pictures".to_string(),
        _ => format!(
            "{views} views x 2 tiers of {} at {w}x{h}, {} pictures",
            rendered.model,
            if opts.png { "PNG" } else { "JPEG" }
        ),
    };
    let drawn = live.as_ref().map_or(String::new(), |l| {
        let [r, m, e] = l.bytes.map(|b| b as f64 / 1e6);
        format!(", drawn live (gzipped: renderer {r:.2} MB, files {m:.2} MB, maps {e:.2} MB)")
    });
    let summary = format!("{pictures}{drawn}, page {:.2} MB", html.len() as f64 / 1e6);
    Ok(Export {
        html,
        views,
        picture_bytes,
        title,
        summary,
    })
}

/// `glview export`: the page written to `path` (and the SCORM package where asked); a
/// warning when the page exceeds `max_size`.
pub fn write(opts: &ExportOptions, path: &Path) -> Result<Export> {
    let export = build(opts)?;
    std::fs::write(path, &export.html).map_err(|e| Error::io(path, e))?;
    if let Some(max) = opts.max_size {
        if export.html.len() as u64 > max {
            log::warn!(
                "{}: {} bytes, over --max-size {max} (fewer steps, a smaller size or a lower \
                 --quality make it smaller)",
                path.display(),
                export.html.len()
            );
        }
    }
    if let Some(zip) = &opts.scorm {
        let description = opts.caption.clone().unwrap_or_default();
        scorm::write(zip, &export.html, &export.title, &description)?;
    }
    Ok(export)
}
