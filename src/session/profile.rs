//! Where one picture's time went (`--stats`).
use crate::scene::profile::LoadProfile;
use serde::Serialize;
use std::time::Instant;

/// Where one picture's time went (`--stats` adds it to the last frame's line as `profile`,
/// printed once the PNG is written). Stages that did not run because their result was kept
/// are zero / null.
#[derive(Debug, Default, Serialize)]
pub struct Profile {
    /// The loader's own stages (read, repair, parse, textures, meshes, normals, finish).
    pub(crate) load: Option<LoadProfile>,
    /// Loading as seen from here (arguments to scene, textures included). It runs on another
    /// thread while the context is made, so the two overlap.
    pub(crate) load_ms: f64,
    /// Of `load_ms`: large meshes reordered and cut into clusters (`scene::clusters`).
    pub(crate) clusters_ms: f64,
    pub(crate) context_ms: f64,
    /// Vertex/index buffers and textures to the GPU.
    pub(crate) upload_ms: f64,
    /// Scenes uploaded for this picture (0 when a kept one drew it: a change of camera,
    /// tier, exposure, bloom or terms uploads nothing).
    pub scene_uploads: u32,
    /// `--time`: the scene posed for this picture and its posed meshes uploaded again
    /// (None when it already stood at that moment, or nothing moves).
    pub pose: Option<crate::render::PoseCost>,
    /// Environment maps made (read or computed, and uploaded) for this picture: 0 when the
    /// context already had them, whichever of its scenes made them.
    pub environments_made: u64,
    /// Programs compiled and linked during the frames, and the time it took.
    pub(crate) programs_compiled: usize,
    pub(crate) compile_ms: f64,
    /// Wall time of each frame to glFinish (compiles and map precomputation included).
    pub frames_ms: Vec<f64>,
    /// Each image texture uploaded for this picture (name, size, ms), the PBR tier's
    /// included (made in its first frame).
    pub(crate) textures: Vec<crate::gpu::TextureCost>,
    pub readback_ms: f64,
    pub(crate) encode_ms: f64,
    pub(crate) total_ms: f64,
}

pub(super) fn ms(since: Instant) -> f64 {
    since.elapsed().as_secs_f64() * 1e3
}
