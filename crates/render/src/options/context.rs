//! Which GL context a picture asks for (`--gl`) and where headless frames are drawn
//! (`--backend`): words of the options; the native library makes the contexts.

crate::choice! {
    /// The context a user asks for with `--gl`.
    pub enum GlRequest {
        /// The best that works: GL 3.3 core, then GL ES 3.0, then GL 2.1.
        Auto = "auto",
        /// Desktop GL 2.1 (GLSL 1.20), compatibility profile.
        Gl21 = "2.1",
        /// OpenGL ES 3.0 (GLSL ES 3.00).
        Es3 = "es3",
        /// OpenGL 3.3 core (GLSL 3.30).
        Core = "core",
        /// OpenGL ES 2.0 (GLSL ES 1.00), WebGL 1's features: both tiers (PBR as on GL 2.1),
        /// shadows compared in the shader. A later ES context is held to ES 2.0's rules.
        Es2 = "es2",
    }
}

impl GlRequest {
    /// The concrete requests to try, in order.
    pub fn candidates(self) -> &'static [GlRequest] {
        match self {
            GlRequest::Auto => &[GlRequest::Core, GlRequest::Es3, GlRequest::Gl21],
            GlRequest::Gl21 => &[GlRequest::Gl21],
            GlRequest::Es3 => &[GlRequest::Es3],
            GlRequest::Core => &[GlRequest::Core],
            GlRequest::Es2 => &[GlRequest::Es2],
        }
    }
}

crate::choice! {
    /// Where headless frames are rendered (`--backend`).
    pub enum Backend {
        /// EGL, then OSMesa on Linux; WGL on Windows.
        Auto = "auto",
        /// EGL's device platform, surfaceless (Linux).
        Egl = "egl",
        /// Mesa's OSMesa, loaded at run time (Linux).
        Osmesa = "osmesa",
        /// A hidden window's WGL context (Windows).
        Wgl = "wgl",
    }
}
