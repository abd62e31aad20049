//! Headless EGL: the device platform (Mesa's software device on a machine without a GPU), a
//! surfaceless context, and the caller's own framebuffer object to render into.
use super::GlRequest;
use crate::{Error, Result};
use glutin::api::egl::context::PossiblyCurrentContext;
use glutin::api::egl::device::Device;
use glutin::api::egl::display::Display;
use glutin::config::{Api, ConfigSurfaceTypes, ConfigTemplateBuilder};
use glutin::prelude::*;

/// A current, surfaceless EGL context. Drop everything made with its `glow::Context` first,
/// and drop it on the thread it is current on (it is released from there, then destroyed).
pub(crate) struct EglHeadless {
    context: PossiblyCurrentContext,
    display: Display,
}

impl EglHeadless {
    /// Tries every EGL device and each candidate context in order; the error lists every
    /// attempt so a user sees why nothing worked.
    pub(crate) fn new(request: GlRequest) -> Result<EglHeadless> {
        let mut tried = Vec::new();
        let devices = Device::query_devices().map_err(|e| Error::Context(format!("EGL: {e}")))?;
        for device in devices {
            // SAFETY: no raw display handle is passed, so the device platform opens its own.
            let display = match unsafe { Display::with_device(&device, None) } {
                Ok(d) => d,
                Err(e) => {
                    tried.push(format!("device {:?}: {e}", device.name()));
                    continue;
                }
            };
            for &candidate in request.candidates() {
                match Self::create(&display, candidate) {
                    Ok(context) => return Ok(EglHeadless { context, display }),
                    Err(e) => tried.push(format!("{candidate:?} on {:?}: {e}", device.name())),
                }
            }
        }
        if tried.is_empty() {
            tried.push("no EGL devices".into());
        }
        Err(Error::Context(format!("EGL: {}", tried.join("; "))))
    }

    fn create(display: &Display, request: GlRequest) -> Result<PossiblyCurrentContext, String> {
        let api = match request {
            GlRequest::Es3 => Api::GLES3,
            GlRequest::Es2 => Api::GLES2,
            _ => Api::OPENGL,
        };
        // Surfaceless: no surface type is needed (the default asks for window surfaces).
        let template = ConfigTemplateBuilder::new()
            .with_api(api)
            .with_surface_type(ConfigSurfaceTypes::empty())
            .build();
        // SAFETY: the template holds no raw handles.
        let config = unsafe { display.find_configs(template) }
            .map_err(|e| e.to_string())?
            .next()
            .ok_or("no matching EGL config")?;
        // SAFETY: attributes carry no window handle; the context is made current at once.
        let not_current =
            unsafe { display.create_context(&config, &super::context_attributes(request, None)) }
                .map_err(|e| e.to_string())?;
        not_current
            .make_current_surfaceless()
            .map_err(|e| e.to_string())
    }

    pub(crate) fn glow_context(&self) -> glow::Context {
        // SAFETY: the context is current on this thread and its display lives in self.
        unsafe {
            glow::Context::from_loader_function_cstr(|name| self.display.get_proc_address(name))
        }
    }
}

impl Drop for EglHeadless {
    /// Releases the context from this thread before glutin destroys it. EGL only marks a
    /// context that is current for deletion, to be freed when it is released, and a thread
    /// that ends does not release it: each library renderer (a thread of its own) kept its
    /// llvmpipe context, ~2 MB bare and ~30 MB once it had drawn and compiled, for good.
    /// Only this context is released: another one made current since stays current.
    fn drop(&mut self) {
        if self.context.is_current() {
            let _ = self.context.make_not_current_in_place();
        }
    }
}
