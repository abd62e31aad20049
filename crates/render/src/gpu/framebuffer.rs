//! Framebuffer objects: the headless colour+depth target, and depth-only shadow targets.
use super::texture::Texture2d;

/// Where a colour target draws: a level of a 2D texture (the only target the passes use; a
/// cube-map face was here once and went unused).
pub(crate) enum ColorAttachment<'a> {
    Level(&'a Texture2d, u32),
}
use super::GpuRef;
use crate::{Error, Result};
use glow::HasContext;

pub(crate) struct Renderbuffer {
    gpu: GpuRef,
    raw: glow::Renderbuffer,
}

impl Drop for Renderbuffer {
    fn drop(&mut self) {
        // SAFETY: deleting our own renderbuffer once.
        unsafe { self.gpu.gl.delete_renderbuffer(self.raw) };
        self.gpu.deleted();
    }
}

fn renderbuffer_ms(
    gpu: &GpuRef,
    format: u32,
    w: u32,
    h: u32,
    samples: u32,
) -> Result<Renderbuffer> {
    // SAFETY: creating and allocating a new renderbuffer.
    unsafe {
        let raw = gpu.gl.create_renderbuffer().map_err(Error::Unsupported)?;
        gpu.created();
        gpu.gl.bind_renderbuffer(glow::RENDERBUFFER, Some(raw));
        if samples > 0 {
            gpu.gl.renderbuffer_storage_multisample(
                glow::RENDERBUFFER,
                samples as i32,
                format,
                w as i32,
                h as i32,
            );
        } else {
            gpu.gl
                .renderbuffer_storage(glow::RENDERBUFFER, format, w as i32, h as i32);
        }
        Ok(Renderbuffer {
            gpu: gpu.clone(),
            raw,
        })
    }
}

/// The depth renderbuffer of a colour target, attached to the bound framebuffer: with stencil
/// where the driver has packed depth-stencil (the nearest-layer translucency masks the
/// background with it), 24-bit depth where it can (ES 2.0 without OES_depth24: 16-bit).
fn depth_renderbuffer(gpu: &GpuRef, w: u32, h: u32, samples: u32) -> Result<Renderbuffer> {
    let stencil = gpu.caps.depth_stencil;
    let format = if stencil {
        glow::DEPTH24_STENCIL8
    } else if gpu.caps.depth24 {
        glow::DEPTH_COMPONENT24
    } else {
        glow::DEPTH_COMPONENT16
    };
    let d = renderbuffer_ms(gpu, format, w, h, samples)?;
    // ES 2.0 has no DEPTH_STENCIL_ATTACHMENT: OES_packed_depth_stencil attaches the one
    // buffer at both points.
    let points: &[u32] = match (stencil, gpu.caps.es2) {
        (false, _) => &[glow::DEPTH_ATTACHMENT],
        (true, false) => &[glow::DEPTH_STENCIL_ATTACHMENT],
        (true, true) => &[glow::DEPTH_ATTACHMENT, glow::STENCIL_ATTACHMENT],
    };
    for &point in points {
        // SAFETY: attaching our renderbuffer to the bound framebuffer.
        unsafe {
            gpu.gl.framebuffer_renderbuffer(
                glow::FRAMEBUFFER,
                point,
                glow::RENDERBUFFER,
                Some(d.raw),
            );
        }
    }
    Ok(d)
}

pub struct Framebuffer {
    gpu: GpuRef,
    pub raw: glow::Framebuffer,
    _attachments: Vec<Renderbuffer>,
    pub(crate) width: u32,
    pub(crate) height: u32,
}

impl Framebuffer {
    fn create(gpu: &GpuRef, w: u32, h: u32) -> Result<Framebuffer> {
        if !gpu.caps.fbo {
            return Err(Error::Unsupported(
                "this driver has no framebuffer objects (GL_ARB/EXT_framebuffer_object)".into(),
            ));
        }
        // SAFETY: creating and binding a new framebuffer.
        unsafe {
            let raw = gpu.gl.create_framebuffer().map_err(Error::Unsupported)?;
            gpu.created();
            gpu.gl.bind_framebuffer(glow::FRAMEBUFFER, Some(raw));
            gpu.record_framebuffer(Some(raw));
            Ok(Framebuffer {
                gpu: gpu.clone(),
                raw,
                _attachments: Vec::new(),
                width: w,
                height: h,
            })
        }
    }

    fn check(&self) -> Result<()> {
        // SAFETY: status query of the bound framebuffer.
        let status = unsafe { self.gpu.gl.check_framebuffer_status(glow::FRAMEBUFFER) };
        if status == glow::FRAMEBUFFER_COMPLETE {
            Ok(())
        } else {
            Err(Error::Unsupported(format!(
                "framebuffer incomplete (status {status:#x})"
            )))
        }
    }

    /// RGBA8 colour + 24-bit depth renderbuffers (with 8 stencil bits where the driver has
    /// packed depth-stencil): the headless render target.
    pub fn color_depth(gpu: &GpuRef, w: u32, h: u32) -> Result<Framebuffer> {
        Self::color_depth_samples(gpu, w, h, 0)
    }

    /// [`Framebuffer::color_depth`] with `samples` samples per pixel (0 = single-sampled);
    /// resolve with [`Framebuffer::resolve_into`].
    pub fn color_depth_samples(gpu: &GpuRef, w: u32, h: u32, samples: u32) -> Result<Framebuffer> {
        let mut fb = Self::create(gpu, w, h)?;
        // RGBA8 (OES_rgb8_rgba8's same enum on ES 2.0).
        let color = renderbuffer_ms(gpu, glow::RGBA8, w, h, samples)?;
        // SAFETY: attaching our renderbuffer to the bound framebuffer.
        unsafe {
            gpu.gl.framebuffer_renderbuffer(
                glow::FRAMEBUFFER,
                glow::COLOR_ATTACHMENT0,
                glow::RENDERBUFFER,
                Some(color.raw),
            );
        }
        let depth = depth_renderbuffer(gpu, w, h, samples)?;
        fb._attachments = vec![color, depth];
        fb.check()?;
        Ok(fb)
    }

    /// A depth-only target writing into `depth` (no colour: draw and read buffers NONE; ES
    /// 2.0 has no buffer selection, and a framebuffer without colour needs none there).
    fn depth_only(gpu: &GpuRef, depth: &Texture2d) -> Result<Framebuffer> {
        let fb = Self::create(gpu, depth.width, depth.height)?;
        // SAFETY: attaching a live depth texture; DrawBuffers(NONE) exists in every context
        // that has FBOs (GL 2.0+, ES 3.0).
        unsafe {
            let gl = &gpu.gl;
            gl.framebuffer_texture_2d(
                glow::FRAMEBUFFER,
                glow::DEPTH_ATTACHMENT,
                glow::TEXTURE_2D,
                Some(depth.raw),
                0,
            );
            if !gpu.caps.es2 {
                gl.draw_buffers(&[glow::NONE]);
                gl.read_buffer(glow::NONE);
            }
        }
        fb.check()?;
        Ok(fb)
    }

    /// The target a shadow map is drawn into: depth-only into a depth texture or, where
    /// there are none ([`super::Caps::packed_shadow`]), colour into the packed-depth RGBA8
    /// texture with a depth renderbuffer for the nearest surface.
    pub(crate) fn shadow(gpu: &GpuRef, map: &Texture2d) -> Result<Framebuffer> {
        if gpu.caps.packed_shadow() {
            Self::color_texture(
                gpu,
                ColorAttachment::Level(map, 0),
                map.width,
                map.height,
                true,
            )
        } else {
            Self::depth_only(gpu, map)
        }
    }

    /// A colour target drawing into one level of a 2D texture or one face (and level) of a
    /// cube map, with a depth renderbuffer when `depth` is set.
    pub(crate) fn color_texture(
        gpu: &GpuRef,
        attachment: ColorAttachment,
        width: u32,
        height: u32,
        depth: bool,
    ) -> Result<Framebuffer> {
        let mut fb = Self::create(gpu, width, height)?;
        let (target, raw, level) = match attachment {
            ColorAttachment::Level(t, level) => (glow::TEXTURE_2D, t.raw, level),
        };
        // SAFETY: attaching a live texture level to the bound framebuffer.
        unsafe {
            gpu.gl.framebuffer_texture_2d(
                glow::FRAMEBUFFER,
                glow::COLOR_ATTACHMENT0,
                target,
                Some(raw),
                level as i32,
            );
        }
        if depth {
            fb._attachments
                .push(depth_renderbuffer(gpu, width, height, 0)?);
        }
        fb.check()?;
        Ok(fb)
    }

    /// Resolves this (multisampled) framebuffer's colour into `dst` (glBlitFramebuffer:
    /// GL 3.0, ES 3.0 or the FBO extensions).
    pub fn resolve_into(&self, dst: &Framebuffer) {
        self.resolve_into_raw(Some(dst.raw), dst.width, dst.height);
    }

    /// [`Framebuffer::resolve_into`] the default framebuffer (a window's back buffer) of
    /// this framebuffer's size: MSAA in the window.
    pub(crate) fn resolve_into_default(&self) {
        self.resolve_into_raw(None, self.width, self.height);
    }

    /// Copies this framebuffer's colour, pixel for pixel, into rectangle `[x, y, w, h]` of
    /// `dst` (None: the default framebuffer), which must be this one's size
    /// (glBlitFramebuffer, nearest: exact).
    pub(crate) fn blit_to(&self, dst: Option<glow::Framebuffer>, [x, y, w, h]: [u32; 4]) {
        debug_assert_eq!((w, h), (self.width, self.height));
        // SAFETY: both framebuffers are complete; the rectangles are the same size.
        unsafe {
            let gl = &self.gpu.gl;
            gl.bind_framebuffer(glow::READ_FRAMEBUFFER, Some(self.raw));
            gl.bind_framebuffer(glow::DRAW_FRAMEBUFFER, dst);
            gl.blit_framebuffer(
                0,
                0,
                w as i32,
                h as i32,
                x as i32,
                y as i32,
                (x + w) as i32,
                (y + h) as i32,
                glow::COLOR_BUFFER_BIT,
                glow::NEAREST,
            );
            gl.bind_framebuffer(glow::FRAMEBUFFER, dst);
        }
    }

    fn resolve_into_raw(&self, dst: Option<glow::Framebuffer>, width: u32, height: u32) {
        // SAFETY: both framebuffers are complete and of the same size (the caller's).
        unsafe {
            let gl = &self.gpu.gl;
            gl.bind_framebuffer(glow::READ_FRAMEBUFFER, Some(self.raw));
            gl.bind_framebuffer(glow::DRAW_FRAMEBUFFER, dst);
            gl.blit_framebuffer(
                0,
                0,
                self.width as i32,
                self.height as i32,
                0,
                0,
                width as i32,
                height as i32,
                glow::COLOR_BUFFER_BIT,
                glow::NEAREST,
            );
            gl.bind_framebuffer(glow::FRAMEBUFFER, None);
            self.gpu.record_framebuffer(None);
        }
    }

    pub fn bind(&self) {
        // SAFETY: binding our own framebuffer.
        unsafe {
            self.gpu
                .gl
                .bind_framebuffer(glow::FRAMEBUFFER, Some(self.raw))
        }
        self.gpu.record_framebuffer(Some(self.raw));
    }
}

impl Drop for Framebuffer {
    fn drop(&mut self) {
        // SAFETY: deleting our own framebuffer once; attachments are dropped after it.
        unsafe { self.gpu.gl.delete_framebuffer(self.raw) };
        self.gpu.forget_framebuffer(self.raw);
        self.gpu.deleted();
    }
}
