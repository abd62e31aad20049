//! The command line (clap): the modes and where pictures go; the options of the picture
//! itself are [`Options`] (flattened in). Every option is in `--help` and the README.
use crate::options::Options;
pub use crate::options::{AaMode, DepthMode, Diffuse, Show};
use clap::Parser;
use std::path::PathBuf;

#[derive(Debug, Parser)]
#[command(name = "glview", version, args_conflicts_with_subcommands = true, about = "Legacy-compatible OpenGL OBJ/MTL viewer: per-fragment Phong and shadow mapping on GL 2.1, GL ES 3.0 and GL 3.3 core.", after_help = crate::keys::help_text())]
pub struct Args {
    #[command(subcommand)]
    pub command: Option<Command>,
    /// Render headless into this PNG (or .jpg/.jpeg: JPEG, without the PNG's text chunks)
    /// instead of opening a window.
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
    #[command(flatten)]
    pub opts: Options,
}

/// The modes read the picture's options through the arguments (`args.yaw`).
impl std::ops::Deref for Args {
    type Target = Options;
    fn deref(&self) -> &Options {
        &self.opts
    }
}

impl std::ops::DerefMut for Args {
    fn deref_mut(&mut self) -> &mut Options {
        &mut self.opts
    }
}

impl Args {
    /// Parses `words` (without the program name) and keeps them for the PNG text's
    /// reproducing command line (non-UTF-8 words are kept lossily there, exactly here).
    pub fn from_words<I, T>(words: I) -> Result<Args, clap::Error>
    where
        I: IntoIterator<Item = T>,
        T: Into<std::ffi::OsString>,
    {
        let words: Vec<std::ffi::OsString> = words.into_iter().map(Into::into).collect();
        let mut args =
            Args::try_parse_from(std::iter::once("glview".into()).chain(words.iter().cloned()))?;
        args.opts.words = words
            .iter()
            .map(|w| w.to_string_lossy().into_owned())
            .collect();
        Ok(args)
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
    /// OBJ file (default: the built-in scene).
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
    #[arg(long, default_value = "320x240", value_parser = crate::options::parse::parse_size)]
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

/// Output files are PNG or JPEG, decided by the extension; anything else is refused before
/// rendering rather than written as PNG bytes under a misleading name.
fn parse_output(s: &str) -> Result<PathBuf, String> {
    let p = PathBuf::from(s);
    match crate::image_out::OutputFormat::of(&p) {
        Some(_) => Ok(p),
        None => Err(format!("{s}: output must end in .png, .jpg or .jpeg")),
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
            let e = Args::try_parse_from(args).unwrap_err().to_string();
            assert!(!e.contains("-- -"), "{args:?}: {e}");
            assert!(
                e.contains("range") || e.contains("must") || e.contains("not in"),
                "{args:?}: {e}"
            );
        }
        let a = Args::try_parse_from(["glview", "-o", "x.JPG", "--up", "-Z"]).unwrap();
        assert_eq!(a.up, crate::scene::UpAxis::NegZ);
    }

    #[test]
    fn cli_is_consistent() {
        use clap::CommandFactory;
        Args::command().debug_assert();
    }
}
