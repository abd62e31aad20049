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
    /// Render headless into this PNG instead of opening a window.
    #[arg(short, long)]
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
    #[arg(long)]
    pub distance: Option<f32>,
    /// Orbit target X,Y,Z in the file's coordinates (default: the bounding-box centre).
    #[arg(long, allow_hyphen_values = true)]
    pub target: Option<String>,
    /// Vertical field of view in degrees.
    #[arg(long, default_value_t = 45.0)]
    pub fov: f32,
    /// Orthographic view of this height instead of perspective.
    #[arg(long)]
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
    #[arg(long, default_value_t = 2048)]
    pub shadow_size: u32,
    /// Percentage-closer filtering taps per lookup: 1, 4, 9 or 16 (each tap is itself a
    /// bilinear 2×2 compare). Default from the bench's Pareto front (README, Shadows).
    #[arg(long, default_value_t = 1, value_parser = parse_pcf)]
    pub pcf: u8,
    /// Constant shadow depth bias in depth-buffer units [0, 1] (added to a slope-scaled
    /// polygon offset).
    #[arg(long, default_value_t = 0.0002)]
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
    /// Bound on the mesh cache folder's total size: bytes, or with K, M, G (powers of 1024).
    /// Least recently used entries are deleted first.
    #[arg(long, default_value = "1G", value_parser = parse_bytes)]
    pub cache_size: u64,
    /// Read textures even where their path leaves the model's folder.
    #[arg(long)]
    pub allow_outside_paths: bool,
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

fn parse_bytes(s: &str) -> Result<u64, String> {
    let s = s.trim();
    let (num, shift) = match s.as_bytes().last() {
        Some(b'K' | b'k') => (&s[..s.len() - 1], 10),
        Some(b'M' | b'm') => (&s[..s.len() - 1], 20),
        Some(b'G' | b'g') => (&s[..s.len() - 1], 30),
        _ => (s, 0),
    };
    num.parse::<u64>()
        .ok()
        .and_then(|n| n.checked_mul(1 << shift))
        .ok_or_else(|| format!("{s:?}: expected bytes, e.g. 1G, 512M or 1048576"))
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
    fn byte_counts() {
        assert_eq!(parse_bytes("1G"), Ok(1 << 30));
        assert_eq!(parse_bytes("512M"), Ok(512 << 20));
        assert_eq!(parse_bytes("1000"), Ok(1000));
        assert!(parse_bytes("lots").is_err());
    }

    #[test]
    fn sizes() {
        assert_eq!(parse_size("640x480"), Ok((640, 480)));
        assert!(parse_size("0x480").is_err());
        assert!(parse_size("640").is_err());
    }

    #[test]
    fn cli_is_consistent() {
        use clap::CommandFactory;
        Args::command().debug_assert();
    }
}
