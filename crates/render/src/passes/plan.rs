//! How a frame is drawn, decided before any pass runs: straight into the target, into an
//! offscreen float frame that post (bloom, FXAA) reads, or — without float render targets
//! (the copy path) — RGBM-encoded into the 8-bit target itself.
use super::{post, FrameStats, SceneGpu, Target};
use crate::frame::FrameSettings;
use crate::gpu::GpuRef;
use crate::Result;

/// The frame's path, from the settings and what the driver and target allow.
pub(crate) struct FramePlan {
    /// No float render targets: post copies the frame with glCopyTexSubImage2D.
    pub(crate) copy: bool,
    /// Bloom runs (asked for, and possible on this path).
    pub(crate) bloom: bool,
    /// A post step (bloom or FXAA) runs after the passes.
    pub(crate) any_post: bool,
    /// The passes draw into the offscreen float frame, not the target.
    pub(crate) offscreen: bool,
    /// The passes write RGBM into the 8-bit target (bloom on the copy path).
    pub(crate) rgbm: bool,
}

impl FramePlan {
    /// Decides the frame's path, logging in `stats` why bloom is dropped on the copy path;
    /// an error if float linear output is asked for where there are no float targets.
    pub(crate) fn new(
        gpu: &GpuRef,
        scene: &SceneGpu,
        s: &FrameSettings,
        target: &Target,
        stats: &mut FrameStats,
    ) -> Result<FramePlan> {
        let post = s.lighting.post;
        let copy = post::copy_path(gpu);
        // `--show bloom` shows the bloom buffer whether or not a strength was given.
        let mut bloom = post.bloom.strength > 0.0 || post.show_bloom;
        if copy && bloom {
            bloom = copy_path_bloom(gpu, scene, s, target, stats);
        }
        let guides = s.lighting.guides;
        if !gpu.caps.frag_depth && (guides.grid || s.lighting.translucency.log_depth) {
            return Err(crate::Error::Unsupported(format!(
                "{} writes each fragment's depth (gl_FragDepth), which {} has not \
                 (ES 2.0 without EXT_frag_depth)",
                if guides.grid { "--grid" } else { "--depth log" },
                gpu.caps.version
            )));
        }
        if post.linear_out && copy {
            return Err(crate::Error::Unsupported(format!(
                "float linear colour needs float render targets (GL 3.0, ES 3.0 with \
                 EXT_color_buffer_float); {} has none",
                gpu.caps.version
            )));
        }
        let any_post = (bloom || post.fxaa) && !post.linear_out;
        Ok(FramePlan {
            copy,
            bloom,
            any_post,
            offscreen: (any_post || post.linear_out) && !copy,
            rgbm: copy && bloom,
        })
    }
}

/// Whether bloom can run on the copy path, where the frame is RGBM in the 8-bit target:
/// RGBM takes the alpha channel (no coverage to keep), and glass blends in its shader over
/// a copy of the frame, on a unit of its own. Logs the reason when it cannot, and how glass
/// is drawn when it can.
fn copy_path_bloom(
    gpu: &GpuRef,
    scene: &SceneGpu,
    s: &FrameSettings,
    target: &Target,
    stats: &mut FrameStats,
) -> bool {
    let post = s.lighting.post;
    let glass = scene.meshes.iter().any(|m| m.translucent);
    let why = if gpu.framebuffer_samples(target.fbo) > 0 {
        Some("the target is multisampled (--aa msaa), which glCopyTexSubImage2D cannot read: use --aa ssaa")
    } else if post.transparent {
        Some("--transparent: the 8-bit frame's alpha would hold the RGBM multiplier")
    } else if glass && gpu.caps.max_texture_units <= super::units::BEHIND_UNIT {
        Some("no texture unit is left for the copy translucent surfaces blend over")
    } else {
        None
    };
    if why.is_none()
        && glass
        && s.lighting.translucency.mode == crate::frame::TranslucencyMode::Sorted
    {
        stats.pass_log.push(
            "translucent: RGBM frame: each blended draw blends in the shader over a copy of the frame; where one draw overlaps itself (a cup's walls) only its last layer shows".into(),
        );
    }
    if let Some(why) = why {
        stats.pass_log.push(format!(
            "bloom: skipped (no float render targets here, and {why}; drawn without bloom)"
        ));
        return false;
    }
    true
}
