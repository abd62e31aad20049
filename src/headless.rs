//! Headless rendering: a context from EGL (device platform, own framebuffer object) or OSMesa
//! (client memory, no framebuffer object needed) on Linux, or WGL on a hidden window (own
//! framebuffer object) on Windows; one renderer, PNG out.
use crate::error::{Error, Result};
use crate::gpu::framebuffer::Framebuffer;
use crate::gpu::{Gpu, GpuRef};
use crate::image_out::Rgba;
#[cfg(not(windows))]
use crate::platform::egl::EglHeadless;
#[cfg(not(windows))]
use crate::platform::osmesa::{OsMesaContext, OsMesaProfile};
#[cfg(windows)]
use crate::platform::wgl::WglHeadless;
use crate::platform::{Backend, GlRequest};
use crate::render::Target;

enum Platform {
    /// Held only to keep the context alive until the `Gpu` is dropped.
    #[cfg(not(windows))]
    #[allow(dead_code)]
    Egl(EglHeadless),
    #[cfg(not(windows))]
    OsMesa(OsMesaContext),
    /// Held only to keep the context alive until the `Gpu` is dropped.
    #[cfg(windows)]
    #[allow(dead_code)]
    Wgl(WglHeadless),
}

/// A current headless context with a render target of a fixed size. Field order is drop
/// order: the target and the `Gpu` go before the platform context they live in.
pub struct Headless {
    /// A multisampled target drawn into instead of `fbo` (`--aa msaa`), resolved on read.
    msaa: Option<Framebuffer>,
    fbo: Option<Framebuffer>,
    pub gpu: GpuRef,
    platform: Platform,
    pub(crate) width: u32,
    pub(crate) height: u32,
}

#[cfg(not(windows))]
fn osmesa_profile(r: GlRequest) -> Option<OsMesaProfile> {
    match r {
        GlRequest::Core => Some(OsMesaProfile::Core33),
        GlRequest::Gl21 | GlRequest::Auto => Some(OsMesaProfile::Compat21),
        GlRequest::Es3 | GlRequest::Es2 => None,
    }
}

impl Headless {
    pub fn new(backend: Backend, gl: GlRequest, width: u32, height: u32) -> Result<Headless> {
        crate::platform::keep_freed_heap();
        crate::native_hooks();
        Self::on_platform(backend, gl, width, height)
    }

    #[cfg(not(windows))]
    fn on_platform(backend: Backend, gl: GlRequest, width: u32, height: u32) -> Result<Headless> {
        if backend == Backend::Wgl {
            return Err(Error::Unsupported(
                "--backend wgl is Windows' (here: egl or osmesa)".into(),
            ));
        }
        let mut errors = Vec::new();
        if matches!(backend, Backend::Auto | Backend::Egl) {
            match Self::egl(gl, width, height) {
                Ok(h) => return Ok(h),
                Err(e) => errors.push(e.to_string()),
            }
        }
        if matches!(backend, Backend::Auto | Backend::Osmesa) {
            match Self::osmesa(gl, width, height) {
                Ok(h) => return Ok(h),
                Err(e) => errors.push(e.to_string()),
            }
        }
        Err(Error::Context(errors.join("; ")))
    }

    #[cfg(windows)]
    fn on_platform(backend: Backend, gl: GlRequest, width: u32, height: u32) -> Result<Headless> {
        if matches!(backend, Backend::Egl | Backend::Osmesa) {
            return Err(Error::Unsupported(format!(
                "--backend {} is Linux's; on Windows headless pictures use WGL (--backend wgl \
                 or auto)",
                backend.word()
            )));
        }
        let wgl = WglHeadless::new(gl, width, height)?;
        let gpu = Gpu::new(wgl.glow_context());
        let fbo = fbo_target(&gpu, width, height, "headless WGL", "")?;
        Ok(Headless {
            msaa: None,
            fbo: Some(fbo),
            gpu,
            platform: Platform::Wgl(wgl),
            width,
            height,
        })
    }

    #[cfg(not(windows))]
    fn egl(gl: GlRequest, width: u32, height: u32) -> Result<Headless> {
        let egl = EglHeadless::new(gl)?;
        let gpu = Gpu::with_es2_ceiling(egl.glow_context(), gl == GlRequest::Es2);
        let fbo = fbo_target(
            &gpu,
            width,
            height,
            "EGL headless",
            "; use --backend osmesa",
        )?;
        Ok(Headless {
            msaa: None,
            fbo: Some(fbo),
            gpu,
            platform: Platform::Egl(egl),
            width,
            height,
        })
    }

    #[cfg(not(windows))]
    fn osmesa(gl: GlRequest, width: u32, height: u32) -> Result<Headless> {
        let mut errors = Vec::new();
        let candidates: Vec<OsMesaProfile> = gl
            .candidates()
            .iter()
            .filter_map(|r| osmesa_profile(*r))
            .collect();
        if candidates.is_empty() {
            return Err(Error::Unsupported(
                "OSMesa offers desktop GL only, not GL ES".into(),
            ));
        }
        for profile in candidates {
            match OsMesaContext::new(profile, width, height) {
                Ok(ctx) => {
                    let gpu = Gpu::new(ctx.glow_context());
                    crate::platform::require_gl21(&gpu.caps)?;
                    check_size(&gpu, width, height)?;
                    return Ok(Headless {
                        msaa: None,
                        fbo: None,
                        gpu,
                        platform: Platform::OsMesa(ctx),
                        width,
                        height,
                    });
                }
                Err(e) => errors.push(e.to_string()),
            }
        }
        Err(Error::Context(format!("OSMesa: {}", errors.join("; "))))
    }

    /// Whether [`Headless::reset_target`] can give this context another size (not an
    /// OSMesa buffer).
    pub(crate) fn resizable(&self) -> bool {
        self.fbo.is_some()
    }

    /// Gives the context a render target of `width`×`height` and no multisampling, so one
    /// context serves pictures of any size (the test fixture renders many in one process).
    /// OSMesa draws into a buffer fixed at creation: there only the same size is accepted.
    pub(crate) fn reset_target(&mut self, width: u32, height: u32) -> Result<()> {
        self.msaa = None;
        if (width, height) == (self.width, self.height) {
            return Ok(());
        }
        if self.fbo.is_none() {
            return Err(Error::Unsupported(
                "an OSMesa context keeps the size it was made with".into(),
            ));
        }
        check_size(&self.gpu, width, height)?;
        // The old target goes before the new one is made: peak memory of one target.
        self.fbo = None;
        self.fbo = Some(Framebuffer::color_depth(&self.gpu, width, height)?);
        (self.width, self.height) = (width, height);
        Ok(())
    }

    /// Draws into a multisampled target of `samples` samples from now on (`--aa msaa`).
    /// Needs framebuffer objects with multisampling (GL 3.0, ES 3.0); OSMesa has neither.
    pub fn enable_msaa(&mut self, samples: u32) -> Result<()> {
        let c = &self.gpu.caps;
        if self.fbo.is_none() || c.major < 3 {
            return Err(Error::Unsupported(format!(
                "--aa msaa needs multisampled framebuffer objects (GL 3.0 / ES 3.0); {} on {} \
                 has none: use --aa ssaa",
                c.version,
                self.backend_name()
            )));
        }
        if samples > c.max_samples {
            return Err(Error::Unsupported(format!(
                "--aa msaa --aa-samples {samples}: {} allows at most {} samples",
                c.renderer, c.max_samples
            )));
        }
        self.msaa = Some(Framebuffer::color_depth_samples(
            &self.gpu,
            self.width,
            self.height,
            samples,
        )?);
        Ok(())
    }

    pub fn target(&self) -> Target {
        Target {
            fbo: self.msaa.as_ref().or(self.fbo.as_ref()).map(|f| f.raw),
            width: self.width,
            height: self.height,
        }
    }

    /// Stencil bits of the render target: OSMesa's buffer has 8; the EGL target's
    /// renderbuffer is depth24-stencil8 where the driver has packed depth-stencil.
    pub(crate) fn stencil_bits(&self) -> u32 {
        match self.platform {
            #[cfg(not(windows))]
            Platform::OsMesa(_) => 8,
            _ if self.gpu.caps.depth_stencil => 8,
            _ => 0,
        }
    }

    pub fn backend_name(&self) -> &'static str {
        match self.platform {
            #[cfg(not(windows))]
            Platform::Egl(_) => "egl",
            #[cfg(not(windows))]
            Platform::OsMesa(_) => "osmesa",
            #[cfg(windows)]
            Platform::Wgl(_) => "wgl",
        }
    }

    /// The rendered frame, top row first.
    pub fn read(&self) -> Rgba {
        let data = match &self.platform {
            #[cfg(not(windows))]
            Platform::OsMesa(ctx) => ctx.read_rgba(&self.gpu.gl),
            _ => {
                if let (Some(ms), Some(f)) = (&self.msaa, &self.fbo) {
                    ms.resolve_into(f);
                }
                if let Some(f) = &self.fbo {
                    f.bind();
                }
                self.gpu.read_rgba(self.width, self.height)
            }
        };
        Rgba {
            width: self.width,
            height: self.height,
            data,
        }
    }
}

/// The framebuffer object a surfaceless (EGL) or hidden-window (WGL) context renders into:
/// refused below GL 2.1, without framebuffer objects (`instead` says what to use then) or
/// past the driver's sizes.
fn fbo_target(gpu: &GpuRef, w: u32, h: u32, what: &str, instead: &str) -> Result<Framebuffer> {
    crate::platform::require_gl21(&gpu.caps)?;
    if !gpu.caps.fbo {
        return Err(Error::Unsupported(format!(
            "{what} renders into a framebuffer object, and this {} driver has none{instead}",
            gpu.caps.version
        )));
    }
    check_size(gpu, w, h)?;
    Framebuffer::color_depth(gpu, w, h)
}

fn check_size(gpu: &Gpu, w: u32, h: u32) -> Result<()> {
    let c = &gpu.caps;
    let max = if c.fbo && c.max_renderbuffer_size > 0 {
        c.max_renderbuffer_size.min(c.max_viewport.0)
    } else {
        c.max_viewport.0.min(c.max_viewport.1)
    };
    if w > max || h > max {
        return Err(Error::Unsupported(format!(
            "size {w}x{h} exceeds the driver's maximum of {max}x{max}"
        )));
    }
    Ok(())
}
