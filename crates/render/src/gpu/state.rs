//! Fixed-function state as one value. Passes describe the state they draw with in a
//! [`RenderState`]; [`Gpu::apply`] is the one place that turns it into GL calls, and it skips
//! the calls whose part of the state has not changed since the last apply.
use super::Gpu;
use glow::HasContext;

/// Which faces to cull.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Cull {
    None,
    Front,
    Back,
}

/// Depth comparison.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum DepthFunc {
    Less,
    LessEqual,
    Equal,
}

/// Colour blending. Alpha composes with (ONE, ONE_MINUS_SRC_ALPHA): over an opaque frame
/// (alpha 1) it stays 1, over a transparent background (`--transparent`) it becomes the
/// coverage α + (1 − α)·α_dst.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Blend {
    Off,
    /// C = α·C_src + (1 − α)·C_dst
    Alpha,
    /// C = α·C_src + C_dst
    Additive,
}

/// Stencil test and write: pass where `(stencil & mask) <func> reference`, and on pass write
/// `reference` (REPLACE) when `write` is set.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Stencil {
    pub(crate) func: StencilFunc,
    pub(crate) reference: u8,
    pub(crate) write: bool,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum StencilFunc {
    Always,
    NotEqual,
}

/// Everything a draw depends on besides program, buffers and textures.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct RenderState {
    /// None: no depth test.
    pub(crate) depth: Option<DepthFunc>,
    pub(crate) depth_write: bool,
    pub(crate) blend: Blend,
    pub(crate) cull: Cull,
    pub(crate) stencil: Option<Stencil>,
    pub(crate) color_write: bool,
    /// glPolygonOffset(factor, units) for filled polygons.
    pub(crate) polygon_offset: Option<(f32, f32)>,
}

impl Default for RenderState {
    /// Opaque drawing: depth test LESS with writes, no blending, no culling, no stencil.
    fn default() -> Self {
        RenderState {
            depth: Some(DepthFunc::Less),
            depth_write: true,
            blend: Blend::Off,
            cull: Cull::None,
            stencil: None,
            color_write: true,
            polygon_offset: None,
        }
    }
}

impl RenderState {
    /// Full-screen passes: no depth test or writes.
    pub(crate) fn overlay() -> Self {
        RenderState {
            depth: None,
            depth_write: false,
            ..Default::default()
        }
    }
}

impl Gpu {
    /// Makes `s` the current state, touching only what differs from the last applied state.
    pub(crate) fn apply(&self, s: &RenderState) {
        let last = self.state.get();
        let changed = |f: &dyn Fn(&RenderState) -> bool| last.is_none_or(|l| f(&l));
        let gl = &self.gl;
        // SAFETY: fixed-function state calls with valid enums; no preconditions.
        unsafe {
            if changed(&|l| l.depth != s.depth) {
                match s.depth {
                    Some(f) => {
                        gl.enable(glow::DEPTH_TEST);
                        gl.depth_func(match f {
                            DepthFunc::Less => glow::LESS,
                            DepthFunc::LessEqual => glow::LEQUAL,
                            DepthFunc::Equal => glow::EQUAL,
                        });
                    }
                    None => gl.disable(glow::DEPTH_TEST),
                }
            }
            if changed(&|l| l.depth_write != s.depth_write) {
                gl.depth_mask(s.depth_write);
            }
            if changed(&|l| l.blend != s.blend) {
                match s.blend {
                    Blend::Off => gl.disable(glow::BLEND),
                    Blend::Alpha | Blend::Additive => {
                        gl.enable(glow::BLEND);
                        let dst = if s.blend == Blend::Alpha {
                            glow::ONE_MINUS_SRC_ALPHA
                        } else {
                            glow::ONE
                        };
                        // glBlendFuncSeparate is core since GL 1.4.
                        gl.blend_func_separate(glow::SRC_ALPHA, dst, glow::ONE, dst);
                    }
                }
            }
            if changed(&|l| l.cull != s.cull) {
                match s.cull {
                    Cull::None => gl.disable(glow::CULL_FACE),
                    Cull::Front | Cull::Back => {
                        gl.enable(glow::CULL_FACE);
                        gl.cull_face(if s.cull == Cull::Front {
                            glow::FRONT
                        } else {
                            glow::BACK
                        });
                    }
                }
            }
            if changed(&|l| l.stencil != s.stencil) {
                match s.stencil {
                    None => gl.disable(glow::STENCIL_TEST),
                    Some(st) => {
                        gl.enable(glow::STENCIL_TEST);
                        let func = match st.func {
                            StencilFunc::Always => glow::ALWAYS,
                            StencilFunc::NotEqual => glow::NOTEQUAL,
                        };
                        gl.stencil_func(func, i32::from(st.reference), 0xff);
                        let pass = if st.write { glow::REPLACE } else { glow::KEEP };
                        gl.stencil_op(glow::KEEP, glow::KEEP, pass);
                        gl.stencil_mask(if st.write { 0xff } else { 0 });
                    }
                }
            }
            if changed(&|l| l.color_write != s.color_write) {
                let c = s.color_write;
                gl.color_mask(c, c, c, c);
            }
            if changed(&|l| l.polygon_offset != s.polygon_offset) {
                match s.polygon_offset {
                    Some((factor, units)) => {
                        gl.enable(glow::POLYGON_OFFSET_FILL);
                        gl.polygon_offset(factor, units);
                    }
                    None => gl.disable(glow::POLYGON_OFFSET_FILL),
                }
            }
        }
        self.state.set(Some(*s));
    }

    /// Binds a framebuffer object, or the default framebuffer for None, and sets the viewport.
    pub(crate) fn bind_target(&self, fbo: Option<glow::Framebuffer>, width: u32, height: u32) {
        self.bind_framebuffer(fbo);
        self.viewport(0, 0, width, height);
    }

    /// Samples per pixel of a framebuffer (0: single-sampled), e.g. whether the copy-to-texture
    /// post path may read it (glCopyTexSubImage2D refuses multisampled sources).
    pub(crate) fn framebuffer_samples(&self, fbo: Option<glow::Framebuffer>) -> u32 {
        self.bind_framebuffer(fbo);
        // SAFETY: a state query on the bound framebuffer.
        unsafe { self.gl.get_parameter_i32(glow::SAMPLES).max(0) as u32 }
    }

    /// The framebuffer bound now (None: the default one), to bind back after a pass.
    /// In the browser from this layer's record (glow's query panics there on the default
    /// framebuffer; see `Bound`).
    pub(crate) fn bound_framebuffer(&self) -> Option<glow::Framebuffer> {
        if cfg!(target_arch = "wasm32") {
            self.recorded_framebuffer()
        } else {
            // SAFETY: a plain query on the current context.
            unsafe { self.gl.get_parameter_framebuffer(glow::FRAMEBUFFER_BINDING) }
        }
    }

    pub fn bind_framebuffer(&self, fbo: Option<glow::Framebuffer>) {
        // SAFETY: fbo is None or a live framebuffer of this context.
        unsafe { self.gl.bind_framebuffer(glow::FRAMEBUFFER, fbo) }
        self.record_framebuffer(fbo);
    }

    /// Which of the default framebuffer's colour buffers draws go to: `BACK_LEFT` or
    /// `BACK_RIGHT` of a quad-buffered (GL_STEREO) window, `BACK` otherwise. Desktop GL only.
    pub(crate) fn draw_buffer(&self, buffer: u32) {
        // SAFETY: a buffer enum of the bound default framebuffer.
        unsafe { self.gl.draw_buffer(buffer) }
    }

    pub(crate) fn viewport(&self, x: u32, y: u32, width: u32, height: u32) {
        // SAFETY: no preconditions.
        unsafe {
            self.gl
                .viewport(x as i32, y as i32, width as i32, height as i32)
        }
    }

    /// Clears depth (and stencil, where the target has one), and colour too when given. The
    /// write masks a clear obeys are opened for it and restored afterwards, so a clear leaves
    /// the render state as it found it.
    pub(crate) fn clear(&self, color: Option<[f32; 3]>) {
        self.clear_rgba(color.map(|[r, g, b]| [r, g, b, 1.0]));
    }

    /// [`Gpu::clear`] with an alpha for the colour.
    pub(crate) fn clear_rgba(&self, color: Option<[f32; 4]>) {
        // SAFETY: no preconditions.
        unsafe {
            self.gl.depth_mask(true);
            self.gl.stencil_mask(0xff);
            let mut bits = glow::DEPTH_BUFFER_BIT | glow::STENCIL_BUFFER_BIT;
            if let Some([r, g, b, a]) = color {
                self.gl.color_mask(true, true, true, true);
                self.gl.clear_color(r, g, b, a);
                bits |= glow::COLOR_BUFFER_BIT;
            }
            self.gl.clear(bits);
        }
        if let Some(s) = self.state.get() {
            // SAFETY: restoring masks to the tracked values.
            unsafe {
                self.gl.depth_mask(s.depth_write);
                let c = s.color_write;
                self.gl.color_mask(c, c, c, c);
                let writes = s.stencil.is_some_and(|st| st.write);
                self.gl.stencil_mask(if writes { 0xff } else { 0 });
            }
        }
    }

    /// Limits drawing to rectangle `[x, y, width, height]` of the bound framebuffer (None:
    /// the scissor test off, as every other pass expects it).
    pub(crate) fn scissor(&self, rect: Option<[u32; 4]>) {
        // SAFETY: no preconditions.
        unsafe {
            match rect {
                Some([x, y, w, h]) => {
                    self.gl.enable(glow::SCISSOR_TEST);
                    self.gl.scissor(x as i32, y as i32, w as i32, h as i32);
                }
                None => self.gl.disable(glow::SCISSOR_TEST),
            }
        }
    }

    /// Clears a rectangle only (a pane of a side-by-side frame) with the scissor test.
    pub(crate) fn clear_rect(&self, rect: [u32; 4], color: Option<[f32; 4]>) {
        // SAFETY: no preconditions.
        unsafe {
            self.gl.enable(glow::SCISSOR_TEST);
            self.gl.scissor(
                rect[0] as i32,
                rect[1] as i32,
                rect[2] as i32,
                rect[3] as i32,
            );
        }
        self.clear_rgba(color);
        // SAFETY: no preconditions.
        unsafe { self.gl.disable(glow::SCISSOR_TEST) }
    }
}
