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
