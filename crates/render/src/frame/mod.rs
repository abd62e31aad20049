//! What a frame depends on besides the scene: camera, lights, tier and quality settings. No GL
//! here, so the CPU reference renderer, the key table and the GPU passes share these types.
use crate::camera::OrbitCamera;
use crate::light::Light;
use glam::Vec3;
use serde::Serialize;

mod lighting;
mod terms;
pub use lighting::{LightingParams, MAX_POINT_PX, MIN_POINT_PX};
pub(crate) use terms::{PbrTerms, Terms};

crate::choice! {
    /// The shading tier: the legacy formula per fragment or per vertex, or the PBR/IBL tier.
    pub enum Shading {
        Phong = "phong",
        Gouraud = "gouraud",
        /// Metallic/roughness PBR with image-based lighting (the seed document's split sum).
        Pbr = "pbr",
    }
}

impl Shading {
    /// The tier name written into PNG text and `--stats`.
    pub fn tier(self) -> &'static str {
        match self {
            Shading::Phong | Shading::Gouraud => "legacy",
            Shading::Pbr => "pbr",
        }
    }

    /// Phong → Gouraud → PBR → Phong (the `P` key).
    pub(crate) fn next(self) -> Shading {
        match self {
            Shading::Phong => Shading::Gouraud,
            Shading::Gouraud => Shading::Pbr,
            Shading::Pbr => Shading::Phong,
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct ShadowSettings {
    pub enabled: bool,
    /// Depth map size in texels (square).
    pub size: u32,
    /// Compared taps per lookup: 1, 4, 9 or 16.
    pub pcf: u8,
    /// Constant depth bias in [0, 1] depth units, on top of the slope-scaled polygon offset.
    pub bias: f32,
    /// glPolygonOffset(factor, units) in the depth pass: the slope-scaled part of the bias.
    pub slope_bias: f32,
    /// Offset of the lookup point along the surface normal, in shadow-map texels.
    pub normal_offset: f32,
}

/// The slope-scaled part of the shadow bias (no option sets it; the defaults of the options'
/// part are theirs: `ShadowSettings::default` is in `options::convert`).
pub(crate) const SHADOW_SLOPE_BIAS: f32 = 2.0;
/// The shadow lookup's offset along the normal in texels (no option sets it).
pub(crate) const SHADOW_NORMAL_OFFSET: f32 = 1.5;

/// Everything a frame depends on besides the scene. Tier-specific knobs (PBR material
/// overrides, exposure, tone mapping) are in `lighting`, so this shape stays the legacy one.
#[derive(Clone, Debug, PartialEq)]
pub struct FrameSettings {
    pub camera: OrbitCamera,
    pub lights: Vec<Light>,
    pub lighting: LightingParams,
    pub shading: Shading,
    pub background: Vec3,
    pub shadows: ShadowSettings,
    /// Draw light 0's depth map instead of the scene (teaching view).
    pub show_shadow_map: bool,
    /// Stereo 3D: the eyes drawn and composed (mode off: one picture).
    pub stereo: crate::stereo::Stereo,
}

crate::choice! {
    /// How translucent surfaces (`d` < 1 or `Tr` > 0) are drawn.
    pub enum TranslucencyMode {
        /// The second seed document's technique: translucent surfaces into depth only, then again
        /// with depth test EQUAL and blending, so only the nearest translucent layer of each
        /// pixel blends over what lies behind, background included (glTF's BLEND);
        /// independent of draw order.
        Nearest = "nearest",
        /// The nearest layer as the seed draws it for the globe: the background drawn
        /// afterwards only where the stencil says nothing was, so it never shows through a
        /// translucent surface.
        NearestMasked = "nearest-masked",
        /// Whole meshes sorted back to front by their centres and blended, back faces first
        /// (the legacy behaviour, kept for comparison).
        Sorted = "sorted",
    }
}

crate::choice! {
    /// How a translucent layer combines with what lies behind it.
    pub enum BlendFormula {
        /// C = α·C_src + (1 − α)·C_dst (the seed's 2.7)
        Alpha = "alpha",
        /// C = α·C_src + C_dst (the seed's 2.9)
        Add = "add",
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Translucency {
    pub mode: TranslucencyMode,
    pub blend: BlendFormula,
    /// `--opacity`: overrides every translucent material's opacity.
    pub opacity: Option<f32>,
    /// Logarithmic depth (the seed's 2.10), written through gl_FragDepth.
    pub log_depth: bool,
}

impl Default for Translucency {
    /// The library default is the legacy frame (sorted); the command line's is `nearest`.
    fn default() -> Self {
        Translucency {
            mode: TranslucencyMode::Sorted,
            blend: BlendFormula::Alpha,
            opacity: None,
            log_depth: false,
        }
    }
}

/// The ground grid and the orientation triad (`--grid`, `--axes`; keys `Z`, `X`).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Guides {
    /// A grid at the model's lowest point, receiving its shadow (`crate::grid::GridPlane`).
    pub grid: bool,
    /// The X/Y/Z triad in the bottom-left corner, turning with the camera.
    pub axes: bool,
    /// Pixels of the frame drawn per pixel of the picture (the SSAA factor): lines and
    /// labels keep their size.
    pub scale: f32,
    /// Which file axis is up (`--up`): the triad and the grid's axis lines name the file's
    /// axes, not the scene's turned ones.
    #[serde(skip)]
    pub up: crate::scene::UpAxis,
}

impl Default for Guides {
    fn default() -> Self {
        Guides {
            grid: false,
            axes: false,
            scale: 1.0,
            up: Default::default(),
        }
    }
}

/// Which edges are drawn over the model (`--edges`, `--wireframe`, the `E` key).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
pub enum EdgeMode {
    #[default]
    Off,
    /// Boundary and creased edges (`crate::scene::geometry::edges::EdgeSet::Feature`).
    Feature,
    /// Every triangle edge.
    Wireframe,
}

impl EdgeMode {
    /// Off → feature edges → wireframe → off (the `E` key).
    pub(crate) fn next(self) -> EdgeMode {
        match self {
            EdgeMode::Off => EdgeMode::Feature,
            EdgeMode::Feature => EdgeMode::Wireframe,
            EdgeMode::Wireframe => EdgeMode::Off,
        }
    }
}

crate::choice! {
    /// How edge lines are drawn.
    pub enum EdgeMethod {
        /// GL lines (1 pixel) or screen-space quads (wider) over a polygon-offset surface.
        Lines = "lines",
        /// On the triangles themselves: a barycentric attribute and its screen-space
        /// derivative (fwidth) give each fragment's distance to the edges (a triangle soup
        /// of three unshared corners each; silhouettes get only the inner half of a line).
        Barycentric = "barycentric",
    }
}

/// Lines over the model: which, in what colour, and whether the surface is drawn.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Edges {
    pub mode: EdgeMode,
    /// The crease angle of feature edges in degrees (the loader's, `--crease`).
    pub(crate) crease_deg: f32,
    /// The lines' colour (display values).
    pub(crate) color: [f32; 3],
    /// `--wireframe-only`: the surface is not drawn, but still hides the lines behind it
    /// (a hidden-line view); the lines then take `only_color`.
    pub(crate) surface: bool,
    pub(crate) only_color: [f32; 3],
    /// Line width in pixels of the frame drawn (`--line-width` times the SSAA factor).
    pub width: f32,
    pub(crate) method: EdgeMethod,
}

impl Default for Edges {
    fn default() -> Self {
        Edges {
            mode: EdgeMode::Off,
            crease_deg: crate::scene::geometry::normals::DEFAULT_CREASE_DEG,
            color: [0.0; 3],
            surface: true,
            only_color: [0.9; 3],
            width: 1.0,
            method: EdgeMethod::Lines,
        }
    }
}

impl Edges {
    /// The edge set of a mesh, or None when no lines are drawn.
    pub fn set(&self) -> Option<crate::scene::geometry::edges::EdgeSet> {
        match self.mode {
            EdgeMode::Off => None,
            EdgeMode::Feature => Some(crate::scene::geometry::edges::EdgeSet::Feature {
                crease_deg: self.crease_deg,
            }),
            EdgeMode::Wireframe => Some(crate::scene::geometry::edges::EdgeSet::All),
        }
    }

    /// Whether the shaded surface is drawn in colour.
    pub fn surface_shown(&self) -> bool {
        self.surface || self.mode == EdgeMode::Off
    }

    /// The lines' colour this frame.
    pub fn line_color(&self) -> [f32; 3] {
        if self.surface_shown() {
            self.color
        } else {
            self.only_color
        }
    }
}

/// The calibration constant C of the logarithmic depth
/// z_ndc = 2·ln(C·w + 1)/ln(C·far + 1) − 1: C = 1 keeps the relative depth step near
/// ln(C·far)/2²⁴ everywhere beyond w = 1/C (the seed's choice for a planet-sized range).
pub(crate) const LOG_DEPTH_C: f32 = 1.0;

/// A per-pixel teaching view drawn by the PBR program instead of the lit picture.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
pub enum AttributeView {
    #[default]
    None,
    /// Eye-space normals (normal maps applied) as n·0.5 + 0.5.
    Normals,
    /// Texture coordinates: u red, v green (fractional part).
    Uvs,
    Roughness,
    Metallic,
}

impl AttributeView {
    /// `SHOW_ATTRIBUTE` in pbr.frag.
    pub(crate) fn code(self) -> i32 {
        self as i32
    }
}

/// Bloom (the first seed document): the bright parts of the linear image — above
/// `threshold`, with a soft knee — blurred with a Gaussian and added back before the output
/// step. Off when `strength` is 0.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Bloom {
    pub strength: f32,
    pub threshold: f32,
    /// Width of the soft knee below the threshold (0 = hard cut).
    pub knee: f32,
    /// Standard deviation of the Gaussian in pixels of the full-resolution image.
    pub sigma: f32,
    /// The blur runs at 1/2^levels of the resolution (0 = full resolution).
    pub levels: u32,
}

/// The width of bloom's soft knee below the threshold (no option sets it; the defaults of
/// the `--bloom*` options are theirs: `Bloom::default` is in `options::convert`).
pub(crate) const BLOOM_KNEE: f32 = 0.2;

/// The post-processing knobs of a frame.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct Post {
    pub bloom: Bloom,
    /// FXAA over the final image.
    pub(crate) fxaa: bool,
    /// Alpha = coverage: the background is cleared transparent and not drawn.
    pub transparent: bool,
    /// `--show bloom`: the blurred bright part alone (teaching view).
    pub(crate) show_bloom: bool,
    /// The library's float colour: the frame stays in its offscreen image, linear and
    /// unclamped (before bloom, exposure, tone mapping and sRGB), and no post step runs.
    pub linear_out: bool,
}

impl Post {}

/// The frame's lights with the headlight made a directional light along the current view
/// (eye towards target), appended last; everything else unchanged. Every renderer (GPU
/// passes, the CPU reference) draws the resolved settings.
pub fn resolve(s: &FrameSettings) -> std::borrow::Cow<'_, FrameSettings> {
    match s.lighting.headlight {
        None => std::borrow::Cow::Borrowed(s),
        Some(color) => {
            let mut r = s.clone();
            // The mono camera's: a stereo pair's eyes share one headlight (and a mono view's
            // is computed exactly as before).
            let c = s.camera.centre();
            let forward = (c.target - c.eye()).normalize_or(glam::Vec3::NEG_Z);
            r.lights.push(crate::light::Light::new(
                crate::light::LightKind::Directional(forward),
                color,
            ));
            r.lighting.headlight = None;
            std::borrow::Cow::Owned(r)
        }
    }
}
