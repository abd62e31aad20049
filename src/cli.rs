//! The command line (clap). Every option here is in `--help` and the README.
use crate::platform::{Backend, GlRequest};
use crate::render::Shading;
use clap::{Parser, ValueEnum};
use std::path::PathBuf;

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Diffuse {
    /// max(N·L, 0)
    Lambert,
    /// Half-Lambert: (1 + N·L)/2.
    Wrap,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Show {
    /// The lit scene.
    Scene,
    /// Light 0's shadow depth map as grey (near = dark).
    ShadowMap,
}

#[derive(Debug, Parser)]
#[command(name = "glview", version, args_conflicts_with_subcommands = true, about = "Legacy-compatible OpenGL OBJ/MTL viewer: per-fragment Phong and shadow mapping on GL 2.1, GL ES 3.0 and GL 3.3 core.", after_help = crate::keys::help_text())]
pub struct Args {
    #[command(subcommand)]
    pub command: Option<Command>,
    /// OBJ file to show (default: the built-in glass-holder scene).
    pub model: Option<PathBuf>,
    /// Render headless into this PNG (or .jpg/.jpeg: JPEG, without the PNG's text chunks)
    /// instead of opening a window.
    #[arg(short, long, value_parser = parse_output)]
    pub output: Option<PathBuf>,
    /// Output or window size, WxH.
    #[arg(long, default_value = "1024x768", value_parser = parse_size)]
    pub size: (u32, u32),
    /// Camera yaw in degrees (0 looks from +Z towards -Z; positive moves the eye towards +X).
    #[arg(long, default_value_t = 30.0, allow_hyphen_values = true)]
    pub yaw: f32,
    /// Camera pitch in degrees (positive looks down from above).
    #[arg(long, default_value_t = 25.0, allow_hyphen_values = true)]
    pub pitch: f32,
    /// Camera distance from the target (default: fits the model).
    #[arg(long, allow_negative_numbers = true, value_parser = parse_positive)]
    pub distance: Option<f32>,
    /// Orbit target X,Y,Z in the file's coordinates (default: the bounding-box centre).
    #[arg(long, allow_hyphen_values = true)]
    pub target: Option<String>,
    /// Vertical field of view in degrees.
    #[arg(long, default_value_t = 45.0)]
    pub fov: f32,
    /// Orthographic view of this height instead of perspective.
    #[arg(long, allow_negative_numbers = true, value_parser = parse_positive)]
    pub ortho: Option<f32>,
    /// A light: point:X,Y,Z (file coordinates), dir:X,Y,Z (direction it travels) or none.
    /// Repeat for several lights (at most 4). Default: one directional light from above.
    #[arg(long = "light", allow_hyphen_values = true)]
    pub lights: Vec<String>,
    /// Light colour R,G,B in 0..1; repeat to colour lights in order (the last one repeats).
    #[arg(long = "light-color")]
    pub light_colors: Vec<String>,
    /// Global ambient light R,G,B (multiplies Ka).
    #[arg(long, default_value = "0.2,0.2,0.2")]
    pub ambient: String,
    /// Background colour R,G,B.
    #[arg(long, default_value = "0.1,0.1,0.12")]
    pub background: String,
    /// Per-fragment Phong, or the same formula per vertex (Gouraud).
    #[arg(long, value_enum, default_value_t = Shading::Phong)]
    pub shading: Shading,
    /// Diffuse term: lambert, or wrap (half-Lambert).
    #[arg(long, value_enum, default_value_t = Diffuse::Lambert)]
    pub diffuse: Diffuse,
    /// Key presses to replay before rendering, e.g. "Left Left Up" (the window's mapping).
    #[arg(long)]
    pub keys: Option<String>,
    /// Which OpenGL context to create.
    #[arg(long, value_enum, default_value_t = GlRequest::Auto)]
    pub gl: GlRequest,
    /// Headless rendering path: EGL (device platform), OSMesa, or auto (EGL, then OSMesa).
    #[arg(long, value_enum, default_value_t = Backend::Auto)]
    pub backend: Backend,
    /// Print one JSON object per frame: passes, draw calls, triangles, programs, milliseconds.
    #[arg(long)]
    pub stats: bool,
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
    /// Frames to render headless (the last one is written); >1 shows cached passes at work.
    #[arg(long, default_value_t = 1)]
    pub frames: u32,
    /// Turn shadow mapping off.
    #[arg(long)]
    pub no_shadows: bool,
    /// Shadow map size in texels (clamped to the driver's maximum). Default from the bench.
    #[arg(long, default_value_t = 2048, value_parser = clap::value_parser!(u32).range(1..))]
    pub shadow_size: u32,
    /// Percentage-closer filtering taps per lookup: 1, 4, 9 or 16 (each tap is itself a
    /// bilinear 2×2 compare). Default from the bench's Pareto front (README, Shadows).
    #[arg(long, default_value_t = 1, value_parser = parse_pcf)]
    pub pcf: u8,
    /// Constant shadow depth bias in depth-buffer units [0, 1] (added to a slope-scaled
    /// polygon offset).
    #[arg(long, default_value_t = 0.0002, allow_negative_numbers = true, value_parser = parse_bias)]
    pub shadow_bias: f32,
    /// What to draw: the scene, or the shadow map (teaching view).
    #[arg(long, value_enum, default_value_t = Show::Scene)]
    pub show: Show,
    /// Render with the CPU reference renderer (ray casting in f64, exact hard shadows)
    /// instead of OpenGL; writes --output (default glview-reference.png).
    #[arg(long)]
    pub reference: bool,
    /// Do not use the mesh cache (a second load of a large unchanged OBJ skips parsing).
    #[arg(long)]
    pub no_cache: bool,
    /// Read textures even where their path leaves the model's folder.
    #[arg(long)]
    pub allow_outside_paths: bool,
    /// Keep materials that are fully transparent (`d 0`, `Tr 1`) invisible; by default they
    /// are drawn opaque with a warning (exporters often mean opaque).
    #[arg(long)]
    pub honor_transparency: bool,
    /// Crease angle in degrees for generated normals: edges sharper than this stay sharp
    /// (files without normals; smoothing groups `s` take precedence). Default 60.
    #[arg(long, value_name = "DEG", value_parser = parse_crease, conflicts_with = "flat")]
    pub crease: Option<f32>,
    /// Generated normals are per face (faceted look).
    #[arg(long)]
    pub flat: bool,
    /// Which axis of the file points up: +Y (default), -Y, +X, -X, +Z, -Z; the model is rotated
    /// at load so it stands upright (Z-up CAD exports: --up +Z).
    #[arg(
        long,
        value_name = "AXIS",
        default_value = "+Y",
        allow_hyphen_values = true
    )]
    pub up: crate::scene::UpAxis,
    /// Base-colour texture for meshes without a material (OBJ files without an MTL, e.g. spot).
    #[arg(long, value_name = "FILE")]
    pub texture: Option<PathBuf>,
    /// Folder for F12 screenshots in the window.
    #[arg(long, default_value = ".")]
    pub screenshot_dir: PathBuf,
}

#[derive(Debug, clap::Subcommand)]
pub enum Command {
    /// Measure frame time against error for every quality knob (docs/bench/quality.*); with
    /// --load, loading speed and memory against f3d (docs/bench/load.*); with --soak N, load,
    /// render and drop the built-in scene N times and report GL objects and memory.
    Bench(BenchCommand),
}

#[derive(Debug, clap::Args)]
pub struct BenchCommand {
    /// Load, render and drop the scene this many times in one context (leak soak).
    #[arg(long)]
    pub soak: Option<u32>,
    #[command(flatten)]
    pub bench: crate::bench::BenchArgs,
}

fn parse_size(s: &str) -> Result<(u32, u32), String> {
    let (w, h) = s
        .split_once(['x', 'X'])
        .ok_or("size must be WxH, e.g. 800x600")?;
    let w: u32 = w.trim().parse().map_err(|_| format!("bad width {w:?}"))?;
    let h: u32 = h.trim().parse().map_err(|_| format!("bad height {h:?}"))?;
    if w == 0 || h == 0 || w > 32768 || h > 32768 {
        return Err(format!("size {w}x{h} out of range (1..32768)"));
    }
    Ok((w, h))
}

/// A finite number > 0; negative numbers reach here (`allow_negative_numbers`) so the error
/// says what is wrong instead of clap's "use -- -1" hint.
fn parse_positive(s: &str) -> Result<f32, String> {
    match s.parse::<f32>() {
        Ok(x) if x.is_finite() && x > 0.0 => Ok(x),
        Ok(_) => Err(format!("{s} is out of range: must be a positive number")),
        Err(_) => Err(format!("{s:?} is not a number")),
    }
}

fn parse_bias(s: &str) -> Result<f32, String> {
    match s.parse::<f32>() {
        Ok(x) if (0.0..=1.0).contains(&x) => Ok(x),
        Ok(_) => Err(format!(
            "{s} is out of range: the bias is in depth-buffer units, 0..1"
        )),
        Err(_) => Err(format!("{s:?} is not a number")),
    }
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

fn parse_crease(s: &str) -> Result<f32, String> {
    match s.parse::<f32>() {
        Ok(d) if (0.0..=180.0).contains(&d) => Ok(d),
        _ => Err(format!("crease angle must be 0..180 degrees, not {s:?}")),
    }
}

fn parse_pcf(s: &str) -> Result<u8, String> {
    match s {
        "1" | "4" | "9" | "16" => Ok(s.parse().unwrap_or(1)),
        _ => Err("PCF taps must be 1, 4, 9 or 16".into()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes() {
        assert_eq!(parse_size("640x480"), Ok((640, 480)));
        assert!(parse_size("0x480").is_err());
        assert!(parse_size("640").is_err());
    }

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
