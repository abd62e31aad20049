//! The lighting part of a frame's settings: each tier's knobs, translucency, post-processing,
//! lines and guides, as the passes and the CPU reference read them. No GL.
use super::terms::{PbrTerms, Terms};
use glam::DVec3;

/// What the formula and the frame's passes take besides lights and materials. Its `Default`
/// is the options' defaults converted (in `options::convert`, where the defaults live).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightingParams {
    pub ambient: DVec3,
    /// Half-Lambert: (1 + N·L)/2 instead of max(N·L, 0).
    pub wrap: bool,
    pub terms: Terms,
    /// The PBR tier's knobs (unused by the legacy formula).
    pub pbr: crate::pbr::PbrParams,
    pub pbr_terms: PbrTerms,
    /// The PBR tier's output step (the legacy tier's output is the fixed-function clamp).
    pub output: crate::pbr::OutputParams,
    /// How translucent surfaces are drawn (both tiers).
    pub translucency: crate::frame::Translucency,
    /// A per-pixel teaching view instead of the lit picture (`--show normals`, ...).
    pub attribute_view: crate::frame::AttributeView,
    /// Bloom, FXAA, transparent background.
    pub post: crate::frame::Post,
    /// A headlight of this colour: a directional light travelling along the view, resolved
    /// from the camera every frame (see `frame::resolve`).
    pub headlight: Option<glam::Vec3>,
    /// How many of the lights (the first ones) cast shadows.
    pub shadow_casters: u8,
    /// Diameter of points in pixels of a picture `point_size.1` pixels high (the frame
    /// scales it with its viewport: SSAA, a window resized).
    pub point_size: (f32, u32),
    /// Lines over the model (`--edges`, `--wireframe`).
    pub edges: crate::frame::Edges,
    /// The ground grid and the axes triad (`--grid`, `--axes`).
    pub guides: crate::frame::Guides,
}

/// The default point size's bounds in pixels: small enough that a dense scan stays a
/// surface of dots, large enough that a sparse one (or glTF POINTS) shows round dots.
pub const MIN_POINT_PX: f32 = 2.0;
pub const MAX_POINT_PX: f32 = 8.0;
