//! The options of one picture, declared once: typed values in groups ([`Options`]), with
//! serde (the JSON form a PNG's text keeps), and a table of specs ([`specs`]) from which the
//! command line's arguments, Python's keywords, the reproducing command line and
//! docs/cli.md are derived. Strings are parsed once, at the edge; [`Options::validate`]
//! needs nothing above this module.
pub mod context;
pub(crate) mod convert;
mod enums;
mod forms;
pub(crate) mod parse;
mod spec;
mod value;
mod words;

use crate::frame::{BlendFormula, EdgeMethod, Shading, TranslucencyMode};
use crate::frame::{PbrTerms, Terms};
use crate::light::LightOpt;
use crate::options::context::{Backend, GlRequest};
use crate::pbr::{Encoding, PrecomputeOn, Tonemap};
use crate::scene::UpAxis;
use crate::stereo::{AnaglyphMethod, Eye, Glasses, StereoMode};
pub use enums::{AaMode, DepthMode, Diffuse, LodMode, Show};
pub use forms::Form;
use parse::{at_least, in_range, one_of, positive, positive_or_none, unit_or_none};
use spec::declare_options;
pub use spec::{OptionError, OptionSpec};
use std::path::PathBuf;
pub use value::{Bytes, OptionValue};
pub use words::reference_markdown;

/// `--ortho`: fit the model, or a view of this height.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(untagged)]
pub enum Ortho {
    /// The bounding sphere touches the nearer pair of picture edges.
    #[serde(with = "fit")]
    Fit,
    Height(f32),
}

/// `Ortho::Fit` as the string `"fit"` in JSON.
mod fit {
    pub(crate) fn serialize<S: serde::Serializer>(s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str("fit")
    }
    pub(crate) fn deserialize<'de, D: serde::Deserializer<'de>>(d: D) -> Result<(), D::Error> {
        let s = <String as serde::Deserialize>::deserialize(d)?;
        if s == "fit" {
            Ok(())
        } else {
            Err(serde::de::Error::custom("expected \"fit\" or a height"))
        }
    }
}

/// `--lod-error` without the option: see docs/benchmarks.md, Level of detail.
pub const DEFAULT_LOD_ERROR: f32 = 1.0;

/// Samples per pixel of the CPU reference renderer's PBR integral (`--reference-samples`).
pub const DEFAULT_REFERENCE_SAMPLES: u32 = 2048;

/// The background colour without `--background`.
pub(crate) const DEFAULT_BACKGROUND: [f32; 3] = [0.1, 0.1, 0.12];

declare_options! {
    /// What to load and how.
    load: Load {
        /// The model file: OBJ (+MTL), STL, PLY, glTF/GLB (default: the built-in
        /// glass-holder scene).
        model: Option<PathBuf> = None, "model" maybe;
        /// Which axis of the file points up: +Y (default), -Y, +X, -X, +Z, -Z; the model is
        /// rotated at load so it stands upright (Z-up CAD exports: --up +Z).
        up: UpAxis = UpAxis::PosY, "up" value;
        /// Crease angle in degrees for generated normals: edges sharper than this stay
        /// sharp (files without normals; smoothing groups `s` take precedence). Default 60.
        crease: Option<f32> = None, "crease" maybe, check = in_range(0.0, 180.0);
        /// Generated normals are per face (faceted look).
        flat: bool = false, "flat" flag;
        /// Base-colour texture for meshes without a material (OBJ files without an MTL,
        /// e.g. spot).
        texture: Option<PathBuf> = None, "texture" maybe;
        /// Use glview's disk caches: the mesh cache (a second load of an unchanged large or
        /// textured model skips parsing and decoding) and the PBR tier's precomputed maps;
        /// `--no-cache` bypasses both.
        cache: bool = true, "no-cache" noflag;
        /// Bound on the mesh cache folder's total size: bytes, or with K, M, G (powers of
        /// 1024). Least recently used entries are deleted first.
        cache_size: Bytes = Bytes(1 << 30), "cache-size" value;
        /// Read textures even where their path leaves the model's folder.
        allow_outside_paths: bool = false, "allow-outside-paths" flag;
        /// Keep materials that are fully transparent (`d 0`, `Tr 1`) invisible; by default
        /// they are drawn opaque with a warning (exporters often mean opaque).
        honor_transparency: bool = false, "honor-transparency" flag;
        /// Draw every material single-sided, as glTF's `doubleSided: false`: back faces are
        /// culled in every pass (and clusters facing away are not sent). OBJ, STL and PLY say
        /// nothing about sides, so by default glview draws both; a closed model seen from
        /// outside looks the same either way. pyrender and most engines draw meshes
        /// single-sided.
        single_sided: bool = false, "single-sided" flag;
        /// Make these materials or objects/groups translucent (opacity 0.3 unless
        /// --opacity), to look at what is inside; repeatable or comma-separated.
        xray: Vec<String> = Vec::new(), "xray" list;
        /// glTF: draw this scene of the file, by index or name (default: the file's default
        /// scene). `--check` lists the scenes.
        scene: Option<String> = None, "scene" maybe;
        /// glTF KHR_materials_variants: draw this material variant, by index or name
        /// (default: the file's own materials; key V cycles, as does the serve page's variant
        /// picker). `--check` lists the variants.
        variant: Option<String> = None, "variant" maybe;
    }
    /// Where the camera is and what it sees.
    camera: Camera {
        /// Camera yaw in degrees (0 looks from +Z towards -Z; positive moves the eye
        /// towards +X).
        yaw: f32 = 30.0, "yaw" value, check = finite;
        /// Camera pitch in degrees (positive looks down from above).
        pitch: f32 = 25.0, "pitch" value, check = finite;
        /// Camera distance from the target (default: fits the model).
        distance: Option<f32> = None, "distance" maybe, check = positive_or_none;
        /// Orbit target X,Y,Z in the file's coordinates (default: the bounding-box centre).
        target: Option<[f64; 3]> = None, "target" maybe;
        /// Vertical field of view in degrees.
        fov: f32 = 45.0, "fov" value, check = fov;
        /// Orthographic view of this height instead of perspective; `--ortho` alone fits
        /// the model (its bounding sphere touches the nearer pair of picture edges).
        ortho: Option<Ortho> = None, "ortho" optional, check = ortho;
        /// A fixed near plane (default: fitted to the model's bounds).
        near: Option<f32> = None, "near" maybe, check = positive_or_none;
        /// Lens shift (Blender's Shift X): the frustum's window moves right by this
        /// fraction of the picture's width (the content moves left), an off-axis view such
        /// as a stereo eye's.
        lens_shift: f32 = 0.0, "lens-shift" value, check = finite;
        /// glTF: look through the file's camera, by index or name (camera or node): its
        /// place, direction and field of view (perspective: yfov kept, the picture's aspect
        /// used; orthographic: the height 2·ymag) set yaw, pitch, distance, target, fov,
        /// near and ortho, which are ignored with it; orbiting starts from there (key K
        /// cycles the cameras, as does the serve page's camera picker). `--check` lists them.
        view: Option<String> = None, "camera" maybe;
        /// Key presses to replay before rendering, e.g. "Left Left Up" (the window's
        /// mapping).
        keys: Option<String> = None, "keys" maybe, check = keys;
    }
    /// Lights and the legacy tier's lighting terms.
    light: Light {
        /// A light: point:X,Y,Z (file coordinates), dir:X,Y,Z (direction it travels), head (a
        /// headlight that follows the camera) or none. Repeat for several lights (at most
        /// 4). kit: the default kit of key light (casts the shadow), fill light and
        /// headlight; file: the model's own lights (glTF KHR_lights_punctual, each casting a
        /// shadow; docs/gltf/lights.md). Default: file when the model has lights, else kit.
        lights: Vec<LightOpt> = Vec::new(), "light" repeat;
        /// Light colour R,G,B in 0..1; repeat to colour lights in order (the last one
        /// repeats).
        colors: Vec<[f32; 3]> = Vec::new(), "light-color" repeat;
        /// Global ambient light R,G,B (multiplies Ka).
        ambient: [f32; 3] = [0.2, 0.2, 0.2], "ambient" value;
        /// Diffuse term: lambert, or wrap (half-Lambert).
        diffuse: Diffuse = Diffuse::Lambert, "diffuse" value;
    }
    /// Shadow mapping.
    shadow: Shadow {
        /// Shadow mapping; `--no-shadows` turns it off.
        enabled: bool = true, "no-shadows" noflag;
        /// How many lights, in order, cast shadows (default: all given lights, or all the
        /// file's own; the key light of the default kit).
        lights: Option<u8> = None, "shadow-lights" maybe;
        /// Shadow map size in texels (clamped to the driver's maximum). Default from the
        /// bench.
        size: u32 = 2048, "shadow-size" value, check = at_least(1);
        /// Percentage-closer filtering taps per lookup: 1, 4, 9 or 16 (each tap is itself a
        /// bilinear 2×2 compare). Default from the bench's Pareto front (docs/benchmarks.md).
        pcf: u8 = 1, "pcf" value, check = one_of(&[1, 4, 9, 16], "PCF taps must be 1, 4, 9 or 16");
        /// Constant shadow depth bias in depth-buffer units [0, 1] (added to a slope-scaled
        /// polygon offset).
        bias: f32 = 0.0002, "shadow-bias" value, check = bias;
    }
    /// The picture's tier, what is drawn and how surfaces combine.
    render: Render {
        /// Per-fragment Phong, the same formula per vertex (Gouraud), or the PBR/IBL tier.
        shading: Shading = Shading::Phong, "shading" value;
        /// Terms to draw, comma-separated from direct-diffuse, direct-specular,
        /// ibl-diffuse, ibl-specular, ao, shadows, emissive, normal-map (also the legacy
        /// tier's), and the glTF layers clearcoat, sheen, transmission, iridescence,
        /// anisotropy; `all` (default) or `none`.
        terms: PbrTerms = PbrTerms::default(), "terms" value;
        /// Legacy tier: terms to draw, comma-separated from ambient, diffuse, specular;
        /// `all` (default) or `none` (keys 1, 2, 3 in the legacy tier).
        legacy_terms: Terms = Terms::default(), "legacy-terms" value;
        /// What to draw: the scene, or a teaching view (shadow map, PBR maps, surface
        /// attributes).
        show: Show = Show::Scene, "show" value;
        /// With --show specular: the roughness level to show (0 = sharpest).
        show_level: u32 = 0, "show-level" value;
        /// Background colour R,G,B (default 0.1,0.1,0.12). In the PBR tier the environment
        /// is the background unless this is given.
        background: Option<[f32; 3]> = None, "background" maybe;
        /// Translucent surfaces: the nearest layer only (two passes, depth EQUAL) over
        /// whatever lies behind, background included; the same with the background masked
        /// by the stencil (never behind a translucent surface: the seed's globe); or whole
        /// meshes sorted back to front (the legacy behaviour).
        translucency: TranslucencyMode = TranslucencyMode::Nearest, "translucency" value;
        /// Blend formula of translucent layers: alpha (α·src + (1 − α)·dst) or add
        /// (α·src + dst).
        blend: BlendFormula = BlendFormula::Alpha, "blend" value;
        /// Opacity 0..1 for every translucent material (the `[` and `]` keys change it).
        opacity: Option<f32> = None, "opacity" maybe, check = unit_or_none;
        /// Depth buffer mapping: standard, or logarithmic (gl_FragDepth) for huge near/far
        /// ratios.
        depth: DepthMode = DepthMode::Standard, "depth" value;
        /// Cluster culling of large meshes; `--no-culling` sends every triangle to the GPU
        /// (the same picture but for a rare silhouette pixel where a back face won a depth
        /// tie; slower: for comparisons).
        culling: bool = true, "no-culling" noflag;
        /// Level of detail of large meshes (those with clusters): per group of clusters,
        /// the coarsest simplified level whose error seen from the view (camera or light)
        /// is at most --lod-error pixels. auto: for meshes with more triangles than the
        /// picture has pixels; on: every large mesh; off: every triangle (so does
        /// --no-culling). Depth, normals and ids read back come from the same triangles as
        /// the colour (off for every triangle). The levels are built before the first picture
        /// that draws them and kept in the mesh cache's entry: the cache makes a picture
        /// faster, never different.
        lod: LodMode = LodMode::Auto, "lod" value;
        /// The level of detail's error bound in pixels of the view (0: every triangle).
        lod_error: f32 = DEFAULT_LOD_ERROR, "lod-error" value, check = in_range(0.0, 16.0);
        /// Diameter of points (point clouds, glTF POINTS, OBJ `p`) in pixels of the
        /// picture, drawn as round disks. Default: 1.5 times a cloud's mean
        /// nearest-neighbour distance as seen from the fitted view, between 2 and 8 (a
        /// lone point or sparse POINTS: 8).
        point_size: Option<f32> = None, "point-size" maybe, check = in_range(1.0, 64.0);
        /// Draw the feature edges over the shaded model: boundary edges and those whose faces
        /// meet at more than the crease angle (--crease, default 60°); 1-pixel lines.
        edges: bool = false, "edges" flag;
        /// Draw every triangle edge over the shaded model (wins over --edges).
        wireframe: bool = false, "wireframe" flag;
        /// Draw the wireframe alone: the surface is not drawn but still hides the lines
        /// behind it (a hidden-line view); implies --wireframe.
        wireframe_only: bool = false, "wireframe-only" flag;
        /// Colour R,G,B of the edge and wireframe lines (default black, light grey with
        /// --wireframe-only).
        edge_color: Option<[f32; 3]> = None, "edge-color" maybe;
        /// Width of the edge and wireframe lines in pixels of the picture, at any zoom (1:
        /// GL lines; wider: a screen-space quad per segment, which every context draws).
        line_width: f32 = 1.0, "line-width" value, check = in_range(1.0, 64.0);
        /// How edges are drawn: lines (GL lines or quads over a polygon-offset surface), or
        /// barycentric (on the triangles, by a barycentric attribute; measured option).
        edge_method: EdgeMethod = EdgeMethod::Lines, "edge-method" value;
        /// A ground grid at the model's lowest point (in the up axis), fading with distance,
        /// receiving the model's shadow; its unit (1, 2 or 5 × 10^k, from the model's size)
        /// is written in the bottom-left corner (key Z).
        grid: bool = false, "grid" flag;
        /// An X/Y/Z orientation triad (red, green, blue) in the bottom-left corner, turning
        /// with the camera (key X).
        axes: bool = false, "axes" flag;
    }
    /// The PBR tier: environment, material overrides, precomputation.
    pbr: Pbr {
        /// PBR: environment map, a Radiance HDR (.hdr) in equirectangular layout.
        env: Option<PathBuf> = None, "env" maybe;
        /// PBR: a uniform environment of this linear radiance R,G,B instead of a file.
        env_color: Option<[f32; 3]> = None, "env-color" maybe, check = non_negative;
        /// PBR: blur of the environment behind the model, as the roughness level shown
        /// (0..1).
        env_blur: f32 = 0.0, "env-blur" value, check = unit;
        /// PBR: scale of the image-based light.
        ibl_intensity: f32 = 1.0, "ibl-intensity" value;
        /// PBR: exposure in EV (the linear colour is multiplied by 2^EV before tone
        /// mapping).
        exposure: f32 = 0.0, "exposure" value, check = finite;
        /// PBR: tone mapping before sRGB encoding (none = clamp).
        tonemap: Tonemap = Tonemap::KhronosNeutral, "tonemap" value;
        /// PBR: base colour R,G,B (linear) for every material.
        base_color: Option<[f32; 3]> = None, "base-color" maybe;
        /// PBR: metallic 0..1 for every material.
        metallic: Option<f32> = None, "metallic" maybe, check = unit_or_none;
        /// PBR: roughness 0..1 for every material.
        roughness: Option<f32> = None, "roughness" maybe, check = unit_or_none;
        /// PBR: sample E_s along Filament's dominant direction instead of R (measured
        /// option).
        dominant_direction: bool = false, "dominant-direction" flag;
        /// PBR: multiple-scattering energy compensation (measured option).
        multiscatter: bool = false, "multiscatter" flag;
        /// PBR: number of roughness levels (specular cubes), 2..8.
        ibl_levels: u32 = 5, "ibl-levels" value, check = in_range(2, 8);
        /// PBR: face size of the sharpest specular cube.
        ibl_size: u32 = 128, "ibl-size" value, check = in_range(8, 1024);
        /// PBR: face size of the irradiance cube.
        irradiance_size: u32 = 32, "irradiance-size" value, check = in_range(4, 256);
        /// PBR: GGX samples per specular texel in the precomputation.
        ibl_samples: u32 = 128, "ibl-samples" value, check = in_range(1, 65536);
        /// PBR: BRDF lookup table size.
        lut_size: u32 = 64, "lut-size" value, check = in_range(4, 1024);
        /// PBR: texture encoding of the precomputed maps (auto: 16-bit float where the
        /// driver has it, else RGBM).
        ibl_encoding: Encoding = Encoding::Auto, "ibl-encoding" value;
        /// PBR: where the maps are computed (auto: the GPU unless it is a software
        /// rasterizer, where the CPU is faster; GL 2.1 always on the CPU).
        ibl_precompute: PrecomputeOn = PrecomputeOn::Auto, "ibl-precompute" value;
        /// PBR with --reference: Monte Carlo samples per lobe and pixel.
        reference_samples: u32 = DEFAULT_REFERENCE_SAMPLES, "reference-samples" value;
    }
    /// After the lit picture: bloom, anti-aliasing, alpha.
    post: Post {
        /// No bloom (the default; overrides --bloom).
        no_bloom: bool = false, "no-bloom" flag;
        /// Bloom strength: the blurred bright parts times this are added back (0 = off).
        bloom: f32 = 0.0, "bloom" value;
        /// Bloom threshold (linear colour); a soft knee of 0.2 below it.
        bloom_threshold: f32 = 1.0, "bloom-threshold" value;
        /// Bloom Gaussian standard deviation in pixels.
        bloom_sigma: f32 = 8.0, "bloom-sigma" value;
        /// Bloom blur resolution: 1/2^N of the frame (0 = full resolution, exact).
        bloom_levels: u32 = 2, "bloom-levels" value, check = in_range(0, 5);
        /// Anti-aliasing: none, msaa (multisampled framebuffer, resolved), fxaa (post pass)
        /// or ssaa (render --aa-samples² larger, box-filtered down: the accurate one for
        /// screenshots).
        aa: AaMode = AaMode::None, "aa" value;
        /// MSAA samples (2, 4, 8) or SSAA factor per axis (2, 3, 4).
        aa_samples: u32 = 4, "aa-samples" value, check = in_range(1, 8);
        /// Transparent background: alpha = coverage in the PNG.
        transparent: bool = false, "transparent" flag;
    }
    /// The picture's size and how many frames make it.
    picture: Picture {
        /// Output or window size, WxH.
        size: (u32, u32) = (1024, 768), "size" value, check = size;
        /// Frames to render headless (the last one is written); >1 shows cached passes at
        /// work.
        frames: u32 = 1, "frames" value;
        /// Print one JSON object per frame: passes, draw calls, triangles, programs,
        /// milliseconds.
        stats: bool = false, "stats" flag;
    }
    /// glTF animations, and animated pictures (`-o` with .gif, .webp or .apng).
    motion: Motion {
        /// glTF: the animation to pose or play, by index or name, or `all`: every animation
        /// together on one clock. Default, when --time or an animated output asks for one:
        /// all, where no two drive the same node (as the glTF Sample Viewer plays them),
        /// else the first. `--check` lists them and the nodes each drives.
        animation: Option<String> = None, "animation" maybe;
        /// glTF: draw the moment this many seconds into the animation (each channel holds
        /// its first key before it and its last key after it, as glTF defines). Without it
        /// the static pose is drawn: the nodes' own transforms, skins posed by them and the
        /// meshes' own morph weights.
        time: Option<f32> = None, "time" maybe, check = non_negative_time;
        /// Animated output: frames per second (frame k shows time k/fps; a GIF at most 50).
        fps: f32 = 15.0, "fps" value, check = in_range(1.0, 60.0);
        /// Animated output: length in seconds (default: the animation's duration, or 4 s
        /// for a turntable); at most 3,600 frames.
        duration: Option<f32> = None, "duration" maybe, check = duration;
        /// Animated output: the camera turns once around the model over the duration (for
        /// a model without an animation, or with one; with --time, around that moment).
        turntable: bool = false, "turntable" flag;
    }
    /// Stereo 3D (docs/stereo.md): two parallel eyes with off-axis frusta, composed.
    stereo: StereoView {
        /// Stereo mode: anaglyph (coloured glasses), side-by-side (each eye squeezed into
        /// half the width, for 3D TVs), side-by-side-full (each eye at full size: twice as
        /// wide), over-under (squeezed into half the height), rows, columns, checkerboard
        /// (interlaced: passive 3D monitors, DLP), quad-buffer (a GL_STEREO window), or off.
        mode: StereoMode = StereoMode::Off, "stereo" value;
        /// Anaglyph colours: dubois (least squares), color, half-color or gray.
        anaglyph: AnaglyphMethod = AnaglyphMethod::Dubois, "anaglyph" value;
        /// Anaglyph glasses, left eye's filter first: red-cyan, green-magenta or amber-blue.
        glasses: Glasses = Glasses::RedCyan, "glasses" value;
        /// Swap the eyes (glasses worn the other way, a monitor's rows the other way).
        swap_eyes: bool = false, "swap-eyes" flag;
        /// Draw one eye of the stereo pair as a plain picture, at its size in the mode
        /// (half the width for side-by-side, half the height for over-under).
        eye: Option<Eye> = None, "eye" maybe;
        /// Distance between the eyes in the file's units (default: the convergence
        /// distance / 30).
        eye_separation: Option<f32> = None, "eye-separation" maybe, check = positive_or_none;
        /// Distance from the camera to the screen plane, where the eyes' pictures agree
        /// (default: the orbit distance, so the target sits on the screen).
        convergence: Option<f32> = None, "convergence" maybe, check = positive_or_none;
    }
    /// Which OpenGL context draws.
    context: Context {
        /// Which OpenGL context to create. `2.1` asks for a GL 2.1 compatibility context and
        /// always uses the GLSL 1.20 shaders, but a modern driver (Mesa) answers with its
        /// newest compatibility version, so every extension stays available; to see what an
        /// old GL 2.1 driver gives, also set MESA_GL_VERSION_OVERRIDE=2.1
        /// MESA_GLSL_VERSION_OVERRIDE=120 (and hide extensions with MESA_EXTENSION_OVERRIDE,
        /// e.g. "-GL_ARB_framebuffer_object"). `es2` draws what WebGL 1 draws: an ES context
        /// held to OpenGL ES 2.0's rules (GLSL ES 1.00; PBR as on GL 2.1), whatever later
        /// ES version the driver answers with.
        gl: GlRequest = GlRequest::Auto, "gl" value;
        /// Headless rendering path: on Linux EGL (device platform), OSMesa, or auto (EGL,
        /// then OSMesa); on Windows WGL on a hidden window (auto). EGL and OSMesa are
        /// Linux-only, WGL Windows-only.
        backend: Backend = Backend::Auto, "backend" value;
    }
}

/// Every option, in declaration order (built once).
pub fn specs() -> &'static [OptionSpec] {
    static SPECS: std::sync::OnceLock<Vec<OptionSpec>> = std::sync::OnceLock::new();
    SPECS.get_or_init(build_specs)
}

/// The spec of the option with this command-line name (or keyword, `_` for `-`).
pub fn spec(name: &str) -> Option<&'static OptionSpec> {
    let name = name.replace('_', "-");
    specs().iter().find(|s| s.name == name)
}

fn finite(v: &f32) -> Result<(), String> {
    if v.is_finite() {
        Ok(())
    } else {
        Err(format!("{v} must be finite"))
    }
}

fn unit(v: &f32) -> Result<(), String> {
    unit_or_none(&Some(*v))
}

fn fov(v: &f32) -> Result<(), String> {
    if *v > 0.0 && *v < 180.0 {
        Ok(())
    } else {
        Err(format!("{v} is out of range: must be between 0 and 180"))
    }
}

fn ortho(v: &Option<Ortho>) -> Result<(), String> {
    match v {
        Some(Ortho::Height(h)) => positive(h),
        _ => Ok(()),
    }
}

fn bias(v: &f32) -> Result<(), String> {
    if (0.0..=1.0).contains(v) {
        Ok(())
    } else {
        Err(format!(
            "{v} is out of range: the bias is in depth-buffer units, 0..1"
        ))
    }
}

fn size(v: &(u32, u32)) -> Result<(), String> {
    parse::parse_size(&format!("{}x{}", v.0, v.1)).map(|_| ())
}

fn non_negative(v: &Option<[f32; 3]>) -> Result<(), String> {
    match v {
        Some(c) if c.iter().any(|x| *x < 0.0) => Err("must not be negative".into()),
        _ => Ok(()),
    }
}

fn non_negative_time(v: &Option<f32>) -> Result<(), String> {
    match v {
        Some(t) if !(t.is_finite() && *t >= 0.0) => Err(format!(
            "{t} must be a finite number of seconds, at least 0"
        )),
        _ => Ok(()),
    }
}

/// An animated picture's length: positive, and at most ten minutes (its frames are rendered
/// and held for encoding).
fn duration(v: &Option<f32>) -> Result<(), String> {
    match v {
        Some(d) if !(d.is_finite() && *d > 0.0 && *d <= 600.0) => Err(format!(
            "{d} is out of range: a duration is more than 0 and at most 600 seconds"
        )),
        _ => Ok(()),
    }
}

fn keys(v: &Option<String>) -> Result<(), String> {
    match v {
        Some(k) => crate::keys::parse_keys(k).map(|_| ()),
        None => Ok(()),
    }
}

impl Options {
    /// The checks of every option and those between options (lights, conflicts), with no
    /// model needed. A JSON value is checked here too: serde only reads types.
    pub fn validate(&self) -> Result<(), OptionError> {
        for s in specs() {
            (s.check)(self).map_err(|m| OptionError::new(s.name, m))?;
        }
        let lights = &self.light.lights;
        if lights.len() > 1 && lights.contains(&LightOpt::None) {
            return Err(OptionError::new(
                "light",
                "none means no lights; it cannot be combined with other --light options",
            ));
        }
        for (word, opt) in [("kit", LightOpt::Kit), ("file", LightOpt::File)] {
            if lights.len() > 1 && lights.contains(&opt) {
                return Err(OptionError::new(
                    "light",
                    format!("{word} cannot be combined with other --light options"),
                ));
            }
        }
        let placed = lights.iter().filter(|l| l.spec().is_some()).count();
        let head = lights.contains(&LightOpt::Head);
        if placed + usize::from(head) > crate::light::MAX_LIGHTS {
            return Err(OptionError::new(
                "light",
                format!(
                    "{placed} lights given; at most {}",
                    crate::light::MAX_LIGHTS
                ),
            ));
        }
        if self.pbr.env.is_some() && self.pbr.env_color.is_some() {
            return Err(OptionError::new(
                "env-color",
                "cannot be used with --env (one environment at a time)",
            ));
        }
        self.validate_stereo()?;
        if self.load.flat && self.load.crease.is_some() {
            return Err(OptionError::new(
                "crease",
                "cannot be used with --flat (flat normals have no crease angle)",
            ));
        }
        Ok(())
    }

    /// Stereo's refusals: what its eyes' single-sampled targets and interlacing cannot do.
    /// (Halves of an odd side are refused for files only, `Session::write`: a window or a
    /// page of any size shows them, the last column or row repeating its neighbour.)
    fn validate_stereo(&self) -> Result<(), OptionError> {
        let mode = self.stereo.mode;
        if !mode.composed() {
            return Ok(());
        }
        if self.post.aa == AaMode::Msaa {
            return Err(OptionError::new(
                "stereo",
                "each eye is drawn into a single-sampled target: use --aa ssaa or --aa fxaa \
                 with --stereo",
            ));
        }
        if mode.interlaced() && self.post.aa == AaMode::Ssaa {
            return Err(OptionError::new(
                "stereo",
                format!(
                    "--aa ssaa would average the {mode} eyes' interlaced pixels together: use \
                     --aa fxaa"
                ),
            ));
        }
        Ok(())
    }

    /// The background colour drawn (the option's, else the default).
    pub(crate) fn background(&self) -> [f32; 3] {
        self.render.background.unwrap_or(DEFAULT_BACKGROUND)
    }
}

#[cfg(test)]
mod tests;
