//! The window's on-screen overlay: an RGBA picture composed on the CPU (text with font8x8)
//! drawn over the frame's top-left corner with alpha blending.
use super::{Renderer, Target};
use crate::gpu::mesh::GpuMesh;
use crate::gpu::program::Program;
use crate::gpu::state::{Blend, RenderState};
use crate::gpu::texture::{Pixels, Sampling, Texture2d, TextureFormat};
use crate::gpu::GpuRef;
use crate::image::Rgba;
use crate::shader::cache::ProgramKey;
use crate::Result;

pub(crate) fn key() -> ProgramKey {
    ProgramKey::new("overlay", "show_depth.vert", "overlay.frag")
}

impl Renderer {
    /// Draws `img` (top row first) 1:1 at the top-left of `target`.
    pub fn draw_overlay(&mut self, img: &Rgba, target: &Target) -> Result<()> {
        let gpu = self.gpu.clone();
        let program = self.programs.borrow_mut().get(&key())?;
        let (w, h) = (img.width.min(target.width), img.height.min(target.height));
        let rect = [0, target.height - h, w, h];
        blend_image(&gpu, &program, self.res.quad(&gpu)?, img, target.fbo, rect)
    }
}

/// Blends `img` (rows top first, straight alpha) into `rect` ([x, y, w, h] from the
/// lower-left, as GL's viewport) of framebuffer `fbo` with the overlay `program` and `quad`,
/// then restores the default state: the window's overlay and the frame's guides (which
/// share the program) draw so. One draw call.
pub(crate) fn blend_image(
    gpu: &GpuRef,
    program: &Program,
    quad: &GpuMesh,
    img: &Rgba,
    fbo: Option<glow::Framebuffer>,
    rect: [u32; 4],
) -> Result<()> {
    let tex = Texture2d::new(
        gpu,
        TextureFormat::Rgba8,
        img.width,
        img.height,
        Pixels::U8(&img.data),
        Sampling::NEAREST,
    )?;
    program.bind();
    tex.bind(0);
    program.set_i32("uImage", 0);
    gpu.bind_framebuffer(fbo);
    let [x, y, w, h] = rect;
    gpu.viewport(x, y, w, h);
    gpu.apply(&RenderState {
        blend: Blend::Alpha,
        ..RenderState::overlay()
    });
    quad.draw();
    gpu.apply(&RenderState::default());
    Ok(())
}
