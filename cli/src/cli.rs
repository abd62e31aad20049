//! The command line (clap): the modes and where pictures go. The picture's options are
//! [`Options`]; their arguments are made from the option specs ([`PictureArgs`]), so each
//! is declared, parsed and documented once, in `options`.
use clap::builder::{PossibleValue, PossibleValuesParser};
use clap::{Arg, ArgAction, ArgMatches, Parser};
use glview::image_out::RgbaFiles;
pub use glview::options::AaMode;
use glview::options::{specs, Form, OptionSpec, Options};
use std::path::PathBuf;

#[derive(Debug, Parser)]
#[command(name = "glview", version, args_conflicts_with_subcommands = true, about = "glview: a model viewer (OBJ/MTL, STL, PLY, glTF) with Phong and PBR tiers, shadows and translucency on GL 2.1, GL ES 3.0 and GL 3.3; headless PNGs, comparisons, batches and a Python API.", after_help = glview::keys::help_text())]
pub struct Args {
    #[command(subcommand)]
    pub command: Option<Command>,
    /// Render headless into this PNG (or .jpg/.jpeg: JPEG, without the PNG's text chunks)
    /// instead of opening a window; .gif, .apng or .webp: an animated picture of the
    /// animation or of --turntable (docs/animated.md).
    #[arg(short, long, value_parser = parse_output)]
    pub output: Option<PathBuf>,
    /// Side by side: render these tiers (phong, gouraud, pbr, reference, reference-pbr) next to
    /// each other on one camera, each pane --size, with labels, into --output.
    #[arg(long, value_name = "A,B,...")]
    pub compare: Option<String>,
    /// Difference of two tiers: writes OUT-A.png, OUT-B.png, the difference image OUT and
    /// OUT.json, and prints mean, max, 99th percentile, share > 8/255 and 1 − SSIM.
    #[arg(long, value_name = "A,B", conflicts_with = "compare")]
    pub diff: Option<String>,
    /// Compare the render with a stored picture (CI regression): missing → written and an
    /// error; mean difference above --threshold → render and difference image written, error.
    #[arg(long, value_name = "FILE.png", conflicts_with_all = ["compare", "diff"])]
    pub diff_against: Option<PathBuf>,
    /// With --diff-against: the mean difference (in 1/255) allowed.
    #[arg(long, default_value_t = 0.5)]
    pub threshold: f64,
    /// Print what the driver provides (version, GLSL, extensions that matter) and exit.
    #[arg(long)]
    pub info: bool,
    /// Compile every shader permutation for this driver's dialect and exit (a diagnostic for
    /// old drivers; the tests run it in every dialect).
    #[arg(long)]
    pub compile_shaders: bool,
    /// Check MODEL without rendering: counts, every problem with file and line, textures,
    /// generated normals, bounds. Exit 0 if it would render.
    #[arg(long)]
    pub check: bool,
    /// Render with the CPU reference renderer (ray casting in f64, exact hard shadows)
    /// instead of OpenGL; writes --output (default glview-reference.png).
    #[arg(long)]
    pub reference: bool,
    /// Folder for F12 screenshots in the window.
    #[arg(long, default_value = ".")]
    pub screenshot_dir: PathBuf,
    /// Render again the picture a PNG of glview's was drawn from: its options (the JSON in
    /// its `glview.options` text) into --output (default glview-repro.png).
    #[arg(long, value_name = "FILE.png", conflicts_with_all = ["compare", "diff", "diff_against"])]
    pub repro: Option<PathBuf>,
    /// Print the options reference (Markdown, docs/options.md) generated from the options'
    /// declaration, and exit.
    #[arg(long, hide = true)]
    pub options_reference: bool,
    #[command(flatten)]
    pub opts: PictureArgs,
}

/// The picture's options as command-line arguments, made from the option specs, and the
/// first problem with them (kept, not raised in clap's parse, so it is printed as every
/// other error is: one `error:` line, exit code 1; [`Args::options`] returns it).
#[derive(Clone, Debug, Default)]
pub struct PictureArgs(pub Options, pub Option<glview::options::OptionError>);

fn arg_of(s: &'static OptionSpec) -> Arg {
    if s.name == "model" {
        return Arg::new("model")
            .value_name("MODEL")
            .help(s.summary())
            .long_help(s.doc.trim_end());
    }
    let default = s
        .default
        .as_deref()
        .filter(|d| !d.is_empty())
        .map(|d| format!(" [default: {d}]"))
        .unwrap_or_default();
    let mut a = Arg::new(s.name)
        .long(s.name)
        .value_name(s.name.to_uppercase().replace('-', "_"))
        .help(format!("{}{default}", s.summary()))
        .long_help(format!("{}{default}", s.doc.trim_end()));
    a = match s.form {
        Form::Flag | Form::NoFlag => a.action(ArgAction::SetTrue),
        Form::Optional => a
            .num_args(0..=1)
            .default_missing_value("")
            .allow_negative_numbers(true)
            .value_name("HEIGHT"),
        Form::Value => a.action(ArgAction::Set).allow_hyphen_values(true),
        Form::Repeat => a.action(ArgAction::Append).allow_hyphen_values(true),
        Form::List => a.action(ArgAction::Append).value_delimiter(','),
    };
    if !s.choices.is_empty() {
        let values: Vec<PossibleValue> = s
            .choices
            .iter()
            .map(|(w, d)| PossibleValue::new(*w).help(*d))
            .collect();
        a = a.value_parser(PossibleValuesParser::new(values));
    }
    a
}

impl clap::FromArgMatches for PictureArgs {
    fn from_arg_matches(m: &ArgMatches) -> Result<Self, clap::Error> {
        let mut p = PictureArgs::default();
        p.update_from_arg_matches(m)?;
        Ok(p)
    }

    /// Every given argument through its spec's setter, then the options' checks: a bad
    /// value is the same error here as in a batch line or a Python keyword.
    fn update_from_arg_matches(&mut self, m: &ArgMatches) -> Result<(), clap::Error> {
        let (o, problem) = (&mut self.0, &mut self.1);
        for s in specs() {
            let given: Vec<&str> = match s.form {
                Form::Flag | Form::NoFlag => {
                    if m.get_flag(s.name) {
                        vec![""]
                    } else {
                        Vec::new()
                    }
                }
                _ => m
                    .get_many::<String>(s.name)
                    .into_iter()
                    .flatten()
                    .map(String::as_str)
                    .collect(),
            };
            for v in given {
                if let Err(msg) = s.set(o, v) {
                    problem.get_or_insert(glview::options::OptionError::new(s.name, msg));
                }
            }
        }
        if problem.is_none() {
            *problem = o.validate().err();
        }
        Ok(())
    }
}

impl clap::Args for PictureArgs {
    fn augment_args(cmd: clap::Command) -> clap::Command {
        cmd.args(specs().iter().map(arg_of))
    }

    fn augment_args_for_update(cmd: clap::Command) -> clap::Command {
        Self::augment_args(cmd)
    }
}

/// The modes read the picture's options through the arguments (`args.yaw`).
impl std::ops::Deref for Args {
    type Target = Options;
    fn deref(&self) -> &Options {
        &self.opts.0
    }
}

impl std::ops::DerefMut for Args {
    fn deref_mut(&mut self) -> &mut Options {
        &mut self.opts.0
    }
}

impl Args {
    /// The picture's options, or the first problem with them.
    pub fn options(&self) -> glview::Result<&Options> {
        match &self.opts.1 {
            Some(e) => Err(e.clone().into()),
            None => Ok(&self.opts.0),
        }
    }

    /// Parses `words` (without the program name).
    pub fn from_words<I, T>(words: I) -> Result<Args, clap::Error>
    where
        I: IntoIterator<Item = T>,
        T: Into<std::ffi::OsString> + Clone,
    {
        Args::try_parse_from(
            std::iter::once(std::ffi::OsString::from("glview"))
                .chain(words.into_iter().map(Into::into)),
        )
    }
}

#[derive(Debug, clap::Subcommand)]
pub enum Command {
    /// Measure frame time against error for every quality knob (docs/bench/quality.*); with
    /// --load, loading speed and memory against f3d (docs/bench/load.*); with --soak N, load,
    /// render and drop the built-in scene N times and report GL objects and memory.
    Bench(BenchCommand),
    /// A contact sheet: turntable views (columns) × tiers (rows) in one labelled PNG.
    Sheet(SheetCommand),
    /// Many pictures in one process and one GL context: JOBS has one job per line, a model
    /// and options as on this command line (shell quoting; `#` comments), each with
    /// `--output`. Failed jobs are reported by line and the rest still render.
    Batch(BatchCommand),
    /// Serve the viewer to browsers: PATH (a model, or a folder of models; default the
    /// built-in scene) rendered here, streamed to every page that opens the printed address
    /// (docs/serve.md). The picture options are every viewer's defaults; `--size` is also
    /// the largest view a viewer may ask for.
    Serve(Box<ServeCommand>),
    /// A lesson page for a learning platform: a turntable grid of Phong and PBR views in
    /// one self-contained HTML file (no server, no WebGL), optionally a SCORM 1.2 package
    /// (docs/export.md).
    Export(Box<crate::export::ExportCommand>),
}

#[derive(Debug, clap::Args)]
pub struct ServeCommand {
    /// Address and port to listen on (port 0: any free one; the printed address has it).
    #[arg(long, default_value = "127.0.0.1:8080")]
    pub bind: String,
    /// Viewers at once; the next one is told the server is full.
    #[arg(long, default_value_t = 32)]
    pub max_viewers: usize,
    /// The token the page, its files and the socket require (default: a random one).
    #[arg(long, conflicts_with = "no_token")]
    pub token: Option<String>,
    /// No token (only on a loopback address).
    #[arg(long)]
    pub no_token: bool,
    /// Seconds a socket may stay silent before it is closed (the page pings every 20 s).
    #[arg(long, default_value_t = 120)]
    pub idle_timeout: u64,
    /// Milliseconds after the last input until the full-size lossless still.
    #[arg(long, default_value_t = 150)]
    pub still_delay: u64,
    /// While input arrives: the previews' size, as a factor of the view's.
    #[arg(long, default_value_t = 0.5)]
    pub drag_scale: f32,
    /// While input arrives: the previews' JPEG quality.
    #[arg(long, default_value_t = 75)]
    pub drag_quality: u8,
    /// Scenes kept uploaded at once (folder mode: viewers on different models).
    #[arg(long, default_value_t = 4)]
    pub keep_scenes: usize,
    /// Connections at once from one address (page loads and viewers); more are closed at
    /// once. Behind a reverse proxy every connection is the proxy's: raise it there.
    #[arg(long, default_value_t = 64)]
    pub max_per_address: usize,
    /// The address viewers open when it is not the bind address (a reverse proxy, a DNS
    /// name): printed instead, and its host is one the `Host` header may name.
    #[arg(long)]
    pub public_url: Option<String>,
    /// A site whose pages may frame the viewer (`https://lms.example`; repeatable): the
    /// page's CSP `frame-ancestors` names it (otherwise only this server may frame it). With
    /// an `https://` `--public-url` the cookie is then SameSite=None; Secure, so it works in
    /// the frame. The server prints an iframe snippet.
    #[arg(long = "embed-origin")]
    pub embed_origin: Vec<String>,
    /// Render threads, each with its own context and scenes; a model's viewers are kept on
    /// one while it has no more than its share (default: a quarter of the cores, 1 to 4:
    /// the network, the encoders and the loads share them, and llvmpipe spreads each frame
    /// over every core already). docs/serve.md.
    #[arg(long)]
    pub render_threads: Option<usize>,
    /// Viewers at once from one address (one student's script cannot take every place).
    #[arg(long, default_value_t = 8)]
    pub max_viewers_per_address: usize,
    /// The browser build (`bash scripts/build_web.sh`) for local mode, where a page that
    /// can draw renders the view itself and the server sends it only the view's state
    /// (default: `$GLVIEW_WEB_DIR`, else `web/` beside the executable's folder; without one
    /// every page gets the stream). docs/serve.md, "Local mode".
    #[arg(long, conflicts_with = "stream_only")]
    pub web_dir: Option<PathBuf>,
    /// Stream every page's frames (no local mode).
    #[arg(long)]
    pub stream_only: bool,
    #[command(flatten)]
    pub opts: PictureArgs,
}

#[derive(Debug, clap::Args)]
pub struct BatchCommand {
    /// The jobs file (`-` for standard input).
    pub jobs: PathBuf,
    /// Also run every job as its own `glview` process afterwards and print both rates
    /// (the measurement behind the README's pictures-per-second figure).
    #[arg(long)]
    pub compare_processes: bool,
}

#[derive(Debug, clap::Args)]
pub struct SheetCommand {
    /// Model file (default: the built-in scene).
    pub model: Option<PathBuf>,
    /// Number of turntable views (yaw 0, 360/N, ...).
    #[arg(long, default_value_t = 6)]
    pub views: u32,
    /// Explicit views instead: YAW:PITCH,YAW:PITCH,...
    #[arg(long)]
    pub angles: Option<String>,
    /// Rows: tiers (phong, gouraud, pbr, reference, reference-pbr).
    #[arg(long, default_value = "phong,pbr")]
    pub tiers: String,
    /// Size of each cell.
    #[arg(long, default_value = "320x240", value_parser = parse_size)]
    pub size: (u32, u32),
    #[arg(short, long, default_value = "sheet.png")]
    pub output: PathBuf,
    /// Any view options of glview after `--` (lights, PBR settings, ...).
    #[arg(last = true)]
    pub view_options: Vec<String>,
}

/// `glview bench ...`: the benchmarks are the command-line program's own tools, not the
/// library's, so their options are parsed there (`glview bench --help` lists them).
#[derive(Debug, clap::Args)]
#[command(disable_help_flag = true)]
pub struct BenchCommand {
    /// The benchmark's options (`--load`, `--frame`, `--soak N`, ...; `--help` lists them).
    #[arg(trailing_var_arg = true, allow_hyphen_values = true)]
    pub words: Vec<String>,
}

fn parse_size(s: &str) -> Result<(u32, u32), String> {
    <(u32, u32) as glview::options::OptionValue>::parse_word(s)
}

impl SheetCommand {
    /// `glview sheet`: the sheet of these options, written to `--output`.
    pub fn run(&self) -> glview::Result<()> {
        // The words after `--` are the user's: they go through the options' own parser (its
        // checks and messages); the sheet's model is set on the result.
        let mut options = glview::Options::from_words(self.view_options.iter().cloned())?;
        if self.model.is_some() {
            options.load.model.clone_from(&self.model);
        }
        let sheet = glview::compare::sheet::Sheet {
            options,
            views: self.views,
            angles: self.angles.clone(),
            tiers: self.tiers.clone(),
            size: self.size,
        };
        let (img, text, summary) = glview::compare::sheet::sheet_image(&sheet)?;
        img.save_png(&self.output, &text)?;
        eprintln!("sheet: {summary} written to {}", self.output.display());
        Ok(())
    }
}

/// Output files are PNG or JPEG stills, or GIF, APNG or WebP animated pictures, decided by
/// the extension; anything else is refused before rendering rather than written as PNG
/// bytes under a misleading name.
fn parse_output(s: &str) -> Result<PathBuf, String> {
    let p = PathBuf::from(s);
    let still = glview::image_out::OutputFormat::of(&p).is_some();
    if still || glview::anim_out::AnimFormat::of(&p).is_some() {
        Ok(p)
    } else {
        Err(format!(
            "{s}: output must end in .png, .jpg or .jpeg (animated: .gif, .apng or .webp)"
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn negative_and_zero_values_are_range_errors() {
        for args in [
            &["glview", "--distance", "-1"][..],
            &["glview", "--ortho", "-2"],
            &["glview", "--shadow-bias", "-0.1"],
            &["glview", "--shadow-size", "0"],
            &["glview", "-o", "out.bmp"],
        ] {
            // Output names are clap's to refuse; option values the options' checks'.
            let e = match Args::try_parse_from(args) {
                Ok(a) => a.options().unwrap_err().to_string(),
                Err(e) => e.to_string(),
            };
            assert!(!e.contains("-- -"), "{args:?}: {e}");
            assert!(
                e.contains("range") || e.contains("must") || e.contains("not in"),
                "{args:?}: {e}"
            );
        }
        let a = Args::try_parse_from(["glview", "-o", "x.JPG", "--up", "-Z"]).unwrap();
        assert_eq!(a.load.up, glview::scene::UpAxis::NegZ);
    }

    #[test]
    fn cli_is_consistent() {
        use clap::CommandFactory;
        Args::command().debug_assert();
    }
}
