//! Anti-aliasing for a target the renderer does not own (the window's back buffer): MSAA
//! draws into a multisampled framebuffer resolved into it by a blit; SSAA draws k times
//! larger on each axis into a texture and box-filters it down (`box.frag`, the GPU twin of
//! the headless path's CPU filter). Headless does the same with its own targets (see
//! `Headless::enable_msaa` and the enlarged SSAA context). FXAA needs nothing here: it is a
//! post pass of every frame.
use super::{Renderer, Target};
use crate::gpu::framebuffer::{ColorAttachment, Framebuffer};
use crate::gpu::state::RenderState;
use crate::gpu::texture::{Pixels, Sampling, Texture2d, TextureFormat};
use crate::gpu::GpuRef;
use crate::shader::cache::ProgramKey;
use crate::{Error, Result};

/// What the window asks for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum WindowAa {
    None,
    Msaa(u32),
    /// The factor per axis (1–4).
    Ssaa(u32),
}

enum Offscreen {
    Msaa(Framebuffer),
    Ssaa(Texture2d, Framebuffer),
}

/// The offscreen target of a window frame, remade when the window's size changes.
pub struct AaTarget {
    mode: WindowAa,
    offscreen: Option<(u32, u32, Offscreen)>,
}

pub(crate) fn box_key() -> ProgramKey {
    ProgramKey::new("box", "show_depth.vert", "box.frag")
}

impl AaTarget {
    /// Checks that this context can do `mode` (the same refusals as headless).
    pub fn new(gpu: &GpuRef, mode: WindowAa) -> Result<AaTarget> {
        let c = &gpu.caps;
        match mode {
            WindowAa::Msaa(samples) => {
                if !c.fbo || c.major < 3 {
                    return Err(Error::Unsupported(format!(
                        "--aa msaa needs multisampled framebuffer objects (GL 3.0 / ES 3.0); {} \
                         in the window has none: use --aa ssaa or --aa fxaa",
                        c.version
                    )));
                }
                if samples > c.max_samples {
                    return Err(Error::Unsupported(format!(
                        "--aa msaa --aa-samples {samples}: {} allows at most {} samples",
                        c.renderer, c.max_samples
                    )));
                }
            }
            WindowAa::Ssaa(k) if k > 1 && !c.fbo => {
                return Err(Error::Unsupported(format!(
                    "--aa ssaa in the window draws into a larger framebuffer object; {} has \
                     none: use --aa fxaa (or headless --backend osmesa, whose buffer is enlarged)",
                    c.version
                )));
            }
            _ => {}
        }
        Ok(AaTarget {
            mode,
            offscreen: None,
        })
    }

    /// The factor per axis the frame is drawn at (SSAA), else 1.
    pub fn scale(&self) -> u32 {
        match self.mode {
            WindowAa::Ssaa(k) => k.clamp(1, 4),
            _ => 1,
        }
    }

    /// Where a `w`×`h` window frame is drawn: the window itself (`window`) or the offscreen
    /// target, made or remade for this size.
    pub fn target(&mut self, gpu: &GpuRef, window: Target) -> Result<Target> {
        let (w, h) = (window.width, window.height);
        let k = self.scale();
        if self.mode == WindowAa::None || (k == 1 && !matches!(self.mode, WindowAa::Msaa(_))) {
            return Ok(window);
        }
        if !matches!(&self.offscreen, Some((ow, oh, _)) if (*ow, *oh) == (w, h)) {
            // Free the old one first: a large SSAA target twice over may not fit.
            self.offscreen = None;
            let o = match self.mode {
                WindowAa::Msaa(samples) => {
                    Offscreen::Msaa(Framebuffer::color_depth_samples(gpu, w, h, samples)?)
                }
                _ => {
                    let color = Texture2d::new(
                        gpu,
                        TextureFormat::Rgba8,
                        w * k,
                        h * k,
                        Pixels::None,
                        Sampling::NEAREST,
                    )?;
                    let fb = Framebuffer::color_texture(
                        gpu,
                        ColorAttachment::Level(&color, 0),
                        w * k,
                        h * k,
                        true,
                    )?;
                    Offscreen::Ssaa(color, fb)
                }
            };
            self.offscreen = Some((w, h, o));
        }
        let (_, _, o) = self.offscreen.as_ref().expect("made above");
        let fb = match o {
            Offscreen::Msaa(f) | Offscreen::Ssaa(_, f) => f,
        };
        Ok(Target {
            fbo: Some(fb.raw),
            width: fb.width,
            height: fb.height,
        })
    }

    /// Puts the drawn frame into the window (`window`): resolve or box filter.
    pub fn present(&self, renderer: &mut Renderer, window: &Target) -> Result<()> {
        match &self.offscreen {
            None => Ok(()),
            Some((_, _, Offscreen::Msaa(f))) => {
                f.resolve_into_default();
                Ok(())
            }
            Some((_, _, Offscreen::Ssaa(color, _))) => {
                renderer.box_filter(color, self.scale(), window)
            }
        }
    }
}

impl Renderer {
    /// Draws `large` (k times the target's size on each axis) into `target`, each pixel the
    /// mean of its k×k block.
    pub(crate) fn box_filter(&mut self, large: &Texture2d, k: u32, target: &Target) -> Result<()> {
        let gpu = self.gpu.clone();
        let p = self.programs.borrow_mut().get(&box_key())?;
        p.bind();
        large.bind(0);
        p.set_i32("uImage", 0);
        p.set_i32("uK", k as i32);
        p.set_vec2(
            "uTexel",
            glam::Vec2::new(1.0 / large.width as f32, 1.0 / large.height as f32),
        );
        gpu.bind_framebuffer(target.fbo);
        gpu.viewport(0, 0, target.width, target.height);
        gpu.apply(&RenderState::overlay());
        self.res.quad(&gpu)?.draw();
        gpu.apply(&RenderState::default());
        Ok(())
    }
}
