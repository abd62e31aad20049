//! The window's on-screen overlay: an RGBA picture composed on the CPU (text with font8x8)
//! drawn over the frame's top-left corner with alpha blending.
use super::{Renderer, Target};
use crate::gpu::state::{Blend, RenderState};
use crate::gpu::texture::{Pixels, Sampling, Texture2d, TextureFormat};
use crate::image_out::Rgba;
use crate::shader::cache::ProgramKey;
use crate::Result;

pub(crate) fn key() -> ProgramKey {
    ProgramKey::new("overlay", "show_depth.vert", "overlay.frag")
}

impl Renderer {
    /// Draws `img` (top row first) 1:1 at the top-left of `target`.
    pub fn draw_overlay(&mut self, img: &Rgba, target: &Target) -> Result<()> {
        let gpu = self.gpu.clone();
        let tex = Texture2d::new(
            &gpu,
            TextureFormat::Rgba8,
            img.width,
            img.height,
            Pixels::U8(&img.data),
            Sampling::NEAREST,
        )?;
        let program = self.programs.borrow_mut().get(&key())?;
        program.bind();
        tex.bind(0);
        program.set_i32("uImage", 0);
        gpu.bind_framebuffer(target.fbo);
        let (w, h) = (img.width.min(target.width), img.height.min(target.height));
        gpu.viewport(0, target.height - h, w, h);
        gpu.apply(&RenderState {
            blend: Blend::Alpha,
            ..RenderState::overlay()
        });
        self.res.quad(&gpu)?.draw();
        gpu.apply(&RenderState::default());
        Ok(())
    }
}
