//! The options of one picture: what the command line, a batch line, a PNG's reproducing text
//! and the Python binding's keyword arguments all become. Each option is declared, documented
//! and validated once, here (clap's value parsers for ranges; [`Options::validate`] for what
//! needs more than one value); `glview --help` and the README's table show these docs.
mod enums;
pub(crate) mod parse;
mod words;

use crate::frame::Shading;
use crate::platform::{Backend, GlRequest};
pub use enums::{AaMode, DepthMode, Diffuse, Show};
use std::path::PathBuf;

#[derive(Clone, Debug, clap::Args)]
pub struct Options {
    /// The words these options were parsed from (the program name and the mode's own words
    /// excluded): their serde form and the PNG text's reproducing command line are made from
    /// them, so an option typed as `--yaw=5` is reproduced as typed.
    #[arg(skip)]
    pub words: Vec<String>,
    /// OBJ file to show (default: the built-in glass-holder scene).
    pub model: Option<PathBuf>,
    /// Output or window size, WxH.
    #[arg(long, default_value = "1024x768", value_parser = parse::parse_size)]
    pub size: (u32, u32),
    /// Camera yaw in degrees (0 looks from +Z towards -Z; positive moves the eye towards +X).
    #[arg(long, default_value_t = 30.0, allow_hyphen_values = true)]
    pub yaw: f32,
    /// Camera pitch in degrees (positive looks down from above).
    #[arg(long, default_value_t = 25.0, allow_hyphen_values = true)]
    pub pitch: f32,
    /// Camera distance from the target (default: fits the model).
    #[arg(long, allow_negative_numbers = true, value_parser = parse::parse_positive)]
    pub distance: Option<f32>,
    /// Orbit target X,Y,Z in the file's coordinates (default: the bounding-box centre).
    #[arg(long, allow_hyphen_values = true)]
    pub target: Option<String>,
    /// Vertical field of view in degrees.
    #[arg(long, default_value_t = 45.0)]
    pub fov: f32,
    /// Orthographic view of this height instead of perspective; `--ortho` alone fits the
    /// model (its bounding sphere touches the nearer pair of picture edges).
    #[arg(long, num_args = 0..=1, allow_negative_numbers = true, value_parser = parse::parse_positive)]
    pub ortho: Option<Option<f32>>,
    /// A light: point:X,Y,Z (file coordinates), dir:X,Y,Z (direction it travels), head (a
    /// headlight that follows the camera) or none. Repeat for several lights (at most 4).
    /// Default: a kit of key light (casts the shadow), fill light and headlight.
    #[arg(long = "light", allow_hyphen_values = true)]
    pub lights: Vec<String>,
    /// Light colour R,G,B in 0..1; repeat to colour lights in order (the last one repeats).
    #[arg(long = "light-color")]
    pub light_colors: Vec<String>,
    /// Global ambient light R,G,B (multiplies Ka).
    #[arg(long, default_value = "0.2,0.2,0.2")]
    pub ambient: String,
    /// Background colour R,G,B (default 0.1,0.1,0.12). In the PBR tier the environment is the
    /// background unless this is given.
    #[arg(long)]
    pub background: Option<String>,
    /// Per-fragment Phong, the same formula per vertex (Gouraud), or the PBR/IBL tier.
    #[arg(long, value_enum, default_value_t = Shading::Phong)]
    pub shading: Shading,
    /// PBR: environment map, a Radiance HDR (.hdr) in equirectangular layout.
    #[arg(long, conflicts_with = "env_color")]
    pub env: Option<PathBuf>,
    /// PBR: a uniform environment of this linear radiance R,G,B instead of a file.
    #[arg(long)]
    pub env_color: Option<String>,
    /// PBR: blur of the environment behind the model, as the roughness level shown (0..1).
    #[arg(long, default_value_t = 0.0)]
    pub env_blur: f32,
    /// PBR: scale of the image-based light.
    #[arg(long, default_value_t = 1.0)]
    pub ibl_intensity: f32,
    /// PBR: exposure in EV (the linear colour is multiplied by 2^EV before tone mapping).
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    pub exposure: f32,
    /// PBR: tone mapping before sRGB encoding (none = clamp).
    #[arg(long, value_enum, default_value_t = crate::pbr::Tonemap::KhronosNeutral)]
    pub tonemap: crate::pbr::Tonemap,
    /// No bloom (the default; overrides --bloom).
    #[arg(long)]
    pub no_bloom: bool,
    /// Bloom strength: the blurred bright parts times this are added back (0 = off).
    #[arg(long, default_value_t = 0.0)]
    pub bloom: f32,
    /// Bloom threshold (linear colour); a soft knee of 0.2 below it.
    #[arg(long, default_value_t = 1.0)]
    pub bloom_threshold: f32,
    /// Bloom Gaussian standard deviation in pixels.
    #[arg(long, default_value_t = 8.0)]
    pub bloom_sigma: f32,
    /// Bloom blur resolution: 1/2^N of the frame (0 = full resolution, exact).
    #[arg(long, default_value_t = 2, value_parser = clap::value_parser!(u32).range(0..=5))]
    pub bloom_levels: u32,
    /// Anti-aliasing: none, msaa (multisampled framebuffer, resolved), fxaa (post pass) or
    /// ssaa (render --aa-samples² larger, box-filtered down: the accurate one for screenshots).
    #[arg(long, value_enum, default_value_t = AaMode::None)]
    pub aa: AaMode,
    /// MSAA samples (2, 4, 8) or SSAA factor per axis (2, 3, 4).
    #[arg(long, default_value_t = 4, value_parser = clap::value_parser!(u32).range(1..=8))]
    pub aa_samples: u32,
    /// Transparent background: alpha = coverage in the PNG.
    #[arg(long)]
    pub transparent: bool,
    /// PBR: base colour R,G,B (linear) for every material.
    #[arg(long)]
    pub base_color: Option<String>,
    /// PBR: metallic 0..1 for every material.
    #[arg(long)]
    pub metallic: Option<f32>,
    /// PBR: roughness 0..1 for every material.
    #[arg(long)]
    pub roughness: Option<f32>,
    /// PBR terms to draw, comma-separated from direct-diffuse, direct-specular, ibl-diffuse,
    /// ibl-specular, ao, shadows, emissive, normal-map (also the legacy tier's); `all`
    /// (default) or `none`.
    #[arg(long, default_value = "all")]
    pub terms: String,
    /// PBR: sample E_s along Filament's dominant direction instead of R (measured option).
    #[arg(long)]
    pub dominant_direction: bool,
    /// PBR: multiple-scattering energy compensation (measured option).
    #[arg(long)]
    pub multiscatter: bool,
    /// PBR: number of roughness levels (specular cubes), 2..8.
    #[arg(long, default_value_t = 5, value_parser = clap::value_parser!(u32).range(2..=8))]
    pub ibl_levels: u32,
    /// PBR: face size of the sharpest specular cube.
    #[arg(long, default_value_t = 128, value_parser = clap::value_parser!(u32).range(8..=1024))]
    pub ibl_size: u32,
    /// PBR: face size of the irradiance cube.
    #[arg(long, default_value_t = 32, value_parser = clap::value_parser!(u32).range(4..=256))]
    pub irradiance_size: u32,
    /// PBR: GGX samples per specular texel in the precomputation.
    #[arg(long, default_value_t = 128, value_parser = clap::value_parser!(u32).range(1..=65536))]
    pub ibl_samples: u32,
    /// PBR: BRDF lookup table size.
    #[arg(long, default_value_t = 64, value_parser = clap::value_parser!(u32).range(4..=1024))]
    pub lut_size: u32,
    /// PBR: texture encoding of the precomputed maps (auto: 16-bit float where the driver has
    /// it, else RGBM).
    #[arg(long, value_enum, default_value_t = crate::pbr::Encoding::Auto)]
    pub ibl_encoding: crate::pbr::Encoding,
    /// Translucent surfaces: the nearest layer only (two passes, depth EQUAL, stencil-masked
    /// background), or whole meshes sorted back to front (the legacy behaviour).
    #[arg(long, value_enum, default_value_t = crate::frame::TranslucencyMode::Nearest)]
    pub translucency: crate::frame::TranslucencyMode,
    /// Blend formula of translucent layers: alpha (α·src + (1 − α)·dst) or add (α·src + dst).
    #[arg(long, value_enum, default_value_t = crate::frame::BlendFormula::Alpha)]
    pub blend: crate::frame::BlendFormula,
    /// Opacity 0..1 for every translucent material (the `[` and `]` keys change it).
    #[arg(long)]
    pub opacity: Option<f32>,
    /// Make these materials or objects/groups translucent (opacity 0.3 unless --opacity), to
    /// look at what is inside; repeatable or comma-separated.
    #[arg(long, value_delimiter = ',')]
    pub xray: Vec<String>,
    /// Depth buffer mapping: standard, or logarithmic (gl_FragDepth) for huge near/far ratios.
    #[arg(long, value_enum, default_value_t = DepthMode::Standard)]
    pub depth: DepthMode,
    /// A fixed near plane (default: fitted to the model's bounds).
    #[arg(long)]
    pub near: Option<f32>,
    /// PBR: where the maps are computed (auto: the GPU unless it is a software rasterizer,
    /// where the CPU is faster; GL 2.1 always on the CPU).
    #[arg(long, value_enum, default_value_t = crate::pbr::PrecomputeOn::Auto)]
    pub ibl_precompute: crate::pbr::PrecomputeOn,
    /// PBR with --reference: Monte Carlo samples per lobe and pixel.
    #[arg(long, default_value_t = crate::reference::pbr::DEFAULT_SAMPLES)]
    pub reference_samples: u32,
    /// Diffuse term: lambert, or wrap (half-Lambert).
    #[arg(long, value_enum, default_value_t = Diffuse::Lambert)]
    pub diffuse: Diffuse,
    /// Key presses to replay before rendering, e.g. "Left Left Up" (the window's mapping).
    #[arg(long)]
    pub keys: Option<String>,
    /// Which OpenGL context to create. `2.1` asks for a GL 2.1 compatibility context and
    /// always uses the GLSL 1.20 shaders, but a modern driver (Mesa) answers with its newest
    /// compatibility version, so every extension stays available; to see what an old GL 2.1
    /// driver gives, also set MESA_GL_VERSION_OVERRIDE=2.1 MESA_GLSL_VERSION_OVERRIDE=120
    /// (and hide extensions with MESA_EXTENSION_OVERRIDE, e.g. "-GL_ARB_framebuffer_object").
    #[arg(long, value_enum, default_value_t = GlRequest::Auto)]
    pub gl: GlRequest,
    /// Headless rendering path: EGL (device platform), OSMesa, or auto (EGL, then OSMesa).
    #[arg(long, value_enum, default_value_t = Backend::Auto)]
    pub backend: Backend,
    /// Print one JSON object per frame: passes, draw calls, triangles, programs, milliseconds.
    #[arg(long)]
    pub stats: bool,
    /// Send every triangle of large meshes to the GPU (no cluster culling; the same picture
    /// but for a rare silhouette pixel where a back face won a depth tie; slower: for
    /// comparisons).
    #[arg(long)]
    pub no_culling: bool,
    /// Frames to render headless (the last one is written); >1 shows cached passes at work.
    #[arg(long, default_value_t = 1)]
    pub frames: u32,
    /// How many lights, in order, cast shadows (default: all given lights; the key light of
    /// the default kit).
    #[arg(long)]
    pub shadow_lights: Option<u8>,
    /// Turn shadow mapping off.
    #[arg(long)]
    pub no_shadows: bool,
    /// Shadow map size in texels (clamped to the driver's maximum). Default from the bench.
    #[arg(long, default_value_t = 2048, value_parser = clap::value_parser!(u32).range(1..))]
    pub shadow_size: u32,
    /// Percentage-closer filtering taps per lookup: 1, 4, 9 or 16 (each tap is itself a
    /// bilinear 2×2 compare). Default from the bench's Pareto front (README, Shadows).
    #[arg(long, default_value_t = 1, value_parser = parse::parse_pcf)]
    pub pcf: u8,
    /// Constant shadow depth bias in depth-buffer units [0, 1] (added to a slope-scaled
    /// polygon offset).
    #[arg(long, default_value_t = 0.0002, allow_negative_numbers = true, value_parser = parse::parse_bias)]
    pub shadow_bias: f32,
    /// What to draw: the scene, or a teaching view (shadow map, PBR maps, surface attributes).
    #[arg(long, value_enum, default_value_t = Show::Scene)]
    pub show: Show,
    /// With --show specular: the roughness level to show (0 = sharpest).
    #[arg(long, default_value_t = 0)]
    pub show_level: u32,
    /// Do not use glview's disk caches: the mesh cache (a second load of an unchanged large or
    /// textured model skips parsing and decoding) and the PBR tier's precomputed maps.
    #[arg(long)]
    pub no_cache: bool,
    /// Bound on the mesh cache folder's total size: bytes, or with K, M, G (powers of 1024).
    /// Least recently used entries are deleted first.
    #[arg(long, default_value = "1G", value_parser = parse::parse_bytes)]
    pub cache_size: u64,
    /// Read textures even where their path leaves the model's folder.
    #[arg(long)]
    pub allow_outside_paths: bool,
    /// Keep materials that are fully transparent (`d 0`, `Tr 1`) invisible; by default they
    /// are drawn opaque with a warning (exporters often mean opaque).
    #[arg(long)]
    pub honor_transparency: bool,
    /// Draw every material single-sided, as glTF's `doubleSided: false`: back faces are culled
    /// in every pass (and clusters facing away are not sent). OBJ, STL and PLY say nothing
    /// about sides, so by default glview draws both; a closed model seen from outside looks
    /// the same either way. pyrender and most engines draw meshes single-sided.
    #[arg(long)]
    pub single_sided: bool,
    /// Crease angle in degrees for generated normals: edges sharper than this stay sharp
    /// (files without normals; smoothing groups `s` take precedence). Default 60.
    #[arg(long, value_name = "DEG", value_parser = parse::parse_crease, conflicts_with = "flat")]
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
}
