//! `glview export MODEL -o lesson.html [--scorm lesson.zip]`: the command line of the
//! library's lesson page (glview::export), whose options it fills.
use glview::export::{ExportOptions, Live, DEFAULT_QUALITY};
use glview::options::{Bytes, OptionValue};
use std::path::PathBuf;

#[derive(Debug, clap::Args)]
pub struct ExportCommand {
    /// Model file (default: the built-in scene).
    pub model: Option<PathBuf>,
    /// The page (one self-contained HTML file).
    #[arg(short, long, default_value = "lesson.html")]
    pub output: PathBuf,
    /// Views around the model: yaw steps of 360/N degrees from the view options' yaw.
    #[arg(long, default_value_t = 36)]
    pub yaw_steps: u32,
    /// Rows of pitch, centred on the view options' pitch.
    #[arg(long, default_value_t = 5)]
    pub pitch_steps: u32,
    /// Degrees between two pitch rows.
    #[arg(long, default_value_t = 15.0)]
    pub pitch_step: f32,
    /// Size of each picture (one picture pixel per CSS pixel in the page).
    #[arg(long, default_value = "640x480", value_parser = parse_size)]
    pub size: (u32, u32),
    /// JPEG quality of the pictures, 1–100 (docs/export.md has the measurement).
    #[arg(long, default_value_t = DEFAULT_QUALITY)]
    pub quality: u8,
    /// Lossless PNG pictures (each exactly `glview -o`'s; several times larger).
    #[arg(long)]
    pub png: bool,
    /// The page's title (default: the model's name); also the SCORM package's.
    #[arg(long)]
    pub title: Option<String>,
    /// A caption under the title; also the SCORM package's description.
    #[arg(long)]
    pub caption: Option<String>,
    /// Warn when the page is larger than this: bytes, or with K, M, G (powers of 1024).
    #[arg(long, value_parser = parse_bytes)]
    pub max_size: Option<u64>,
    /// Also write the page as a SCORM 1.2 package (a zip any LMS imports) here.
    #[arg(long, value_name = "FILE.zip")]
    pub scorm: Option<PathBuf>,
    /// Draw live in the browser (glview's renderer compiled to wasm, the model's files and
    /// the environment maps in the page), the pictures kept as the fallback (docs/web.md).
    #[arg(long)]
    pub live: bool,
    /// As --live without the pictures: a smaller page that shows nothing without WebGL.
    #[arg(long, conflicts_with = "live")]
    pub live_only: bool,
    /// The browser build's folder for --live (default: $GLVIEW_WEB_DIR, else target/web
    /// beside the executable's folder); `bash scripts/build_web.sh` makes it.
    #[arg(long, value_name = "DIR")]
    pub web_dir: Option<PathBuf>,
    /// Any view options of glview after `--` (yaw and pitch of the first view, lights, ...).
    #[arg(last = true)]
    pub view_options: Vec<String>,
}

fn parse_size(s: &str) -> Result<(u32, u32), String> {
    <(u32, u32) as OptionValue>::parse_word(s)
}

fn parse_bytes(s: &str) -> Result<u64, String> {
    Bytes::parse_word(s).map(|b| b.0)
}

impl ExportCommand {
    /// The export's options: the words after `--` through the options' own parser.
    pub fn options(&self) -> glview::Result<ExportOptions> {
        let mut options = glview::Options::from_words(self.view_options.iter().cloned())?;
        if self.model.is_some() {
            options.load.model.clone_from(&self.model);
        }
        options.picture.size = self.size;
        Ok(ExportOptions {
            options,
            yaw_steps: self.yaw_steps,
            pitch_steps: self.pitch_steps,
            pitch_step: self.pitch_step,
            quality: self.quality,
            png: self.png,
            title: self.title.clone(),
            caption: self.caption.clone(),
            max_size: self.max_size,
            scorm: self.scorm.clone(),
            live: match (self.live, self.live_only) {
                (_, true) => Live::Only,
                (true, false) => Live::Live,
                (false, false) => Live::Off,
            },
            web_dir: self.web_dir.clone(),
        })
    }

    pub fn run(&self) -> glview::Result<()> {
        let start = std::time::Instant::now();
        let opts = self.options()?;
        let export = glview::export::write(&opts, &self.output)?;
        eprintln!(
            "export: {} written to {} in {:.1} s ({:.1} kB of pictures per view){}",
            export.summary,
            self.output.display(),
            start.elapsed().as_secs_f64(),
            export.picture_bytes as f64 / export.views.max(1) as f64 / 1e3,
            opts.scorm
                .as_ref()
                .map(|z| format!("; SCORM package {}", z.display()))
                .unwrap_or_default()
        );
        Ok(())
    }
}
