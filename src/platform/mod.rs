//! Context creation: EGL headless (device platform, surfaceless), OSMesa (loaded at run time)
//! and the window (winit + glutin-winit, in `window`). Each gives a `glow::Context`; the same
//! renderer draws in all of them.
pub mod egl;
pub mod osmesa;
pub mod window;

use serde::Serialize;

/// The context a user asks for with `--gl`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum, Serialize)]
pub enum GlRequest {
    /// The best that works: GL 3.3 core, then GL ES 3.0, then GL 2.1.
    Auto,
    /// Desktop GL 2.1 (GLSL 1.20), compatibility profile.
    #[value(name = "2.1")]
    Gl21,
    /// OpenGL ES 3.0 (GLSL ES 3.00).
    Es3,
    /// OpenGL 3.3 core (GLSL 3.30).
    Core,
}

impl GlRequest {
    /// The concrete requests to try, in order.
    pub fn candidates(self) -> &'static [GlRequest] {
        match self {
            GlRequest::Auto => &[GlRequest::Core, GlRequest::Es3, GlRequest::Gl21],
            GlRequest::Gl21 => &[GlRequest::Gl21],
            GlRequest::Es3 => &[GlRequest::Es3],
            GlRequest::Core => &[GlRequest::Core],
        }
    }
}

/// Where headless frames are rendered (`--backend`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum, Serialize)]
pub enum Backend {
    /// EGL, then OSMesa.
    Auto,
    Egl,
    Osmesa,
}

/// What glutin is asked for, per request; shared by the EGL headless and the window paths.
pub(crate) fn context_attributes(
    request: GlRequest,
    window: Option<raw_window_handle::RawWindowHandle>,
) -> glutin::context::ContextAttributes {
    use glutin::context::{ContextApi, ContextAttributesBuilder, GlProfile, Version};
    let b = ContextAttributesBuilder::new();
    match request {
        GlRequest::Es3 => b.with_context_api(ContextApi::Gles(Some(Version::new(3, 0)))),
        GlRequest::Core => b
            .with_context_api(ContextApi::OpenGl(Some(Version::new(3, 3))))
            .with_profile(GlProfile::Core),
        GlRequest::Gl21 | GlRequest::Auto => b
            .with_context_api(ContextApi::OpenGl(Some(Version::new(2, 1))))
            .with_profile(GlProfile::Compatibility),
    }
    .build(window)
}
