//! Safe wrappers for the fixed-function state the passes change, so `render` has no `unsafe`.
use super::Gpu;
use glow::HasContext;

/// Which faces to cull.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Cull {
    None,
    Front,
    Back,
}

impl Gpu {
    /// Binds a framebuffer object, or the default framebuffer for None, and sets the viewport.
    pub fn bind_target(&self, fbo: Option<glow::Framebuffer>, width: u32, height: u32) {
        // SAFETY: fbo is None or a live framebuffer of this context.
        unsafe {
            self.gl.bind_framebuffer(glow::FRAMEBUFFER, fbo);
            self.gl.viewport(0, 0, width as i32, height as i32);
        }
    }

    pub fn viewport(&self, x: u32, y: u32, width: u32, height: u32) {
        // SAFETY: no preconditions.
        unsafe {
            self.gl
                .viewport(x as i32, y as i32, width as i32, height as i32)
        }
    }

    /// Clears depth, and colour too when given.
    pub fn clear(&self, color: Option<[f32; 3]>) {
        // SAFETY: no preconditions; depth writes are enabled first so the clear takes effect.
        unsafe {
            self.gl.depth_mask(true);
            let mut bits = glow::DEPTH_BUFFER_BIT;
            if let Some([r, g, b]) = color {
                self.gl.color_mask(true, true, true, true);
                self.gl.clear_color(r, g, b, 1.0);
                bits |= glow::COLOR_BUFFER_BIT;
            }
            self.gl.clear(bits);
        }
    }

    /// Depth test (LESS) on or off, and depth writes.
    pub fn depth(&self, test: bool, write: bool) {
        // SAFETY: no preconditions.
        unsafe {
            if test {
                self.gl.enable(glow::DEPTH_TEST);
                self.gl.depth_func(glow::LESS);
            } else {
                self.gl.disable(glow::DEPTH_TEST);
            }
            self.gl.depth_mask(write);
        }
    }

    /// Alpha blending of colour (SRC_ALPHA, ONE_MINUS_SRC_ALPHA) on or off.
    pub fn blend(&self, on: bool) {
        // SAFETY: no preconditions.
        unsafe {
            if on {
                self.gl.enable(glow::BLEND);
                // Colour is blended; destination alpha stays 1, so PNGs and screenshots are
                // opaque where glass was drawn (glBlendFuncSeparate is core since GL 1.4).
                self.gl.blend_func_separate(
                    glow::SRC_ALPHA,
                    glow::ONE_MINUS_SRC_ALPHA,
                    glow::ZERO,
                    glow::ONE,
                );
            } else {
                self.gl.disable(glow::BLEND);
            }
        }
    }

    pub fn cull(&self, cull: Cull) {
        // SAFETY: no preconditions.
        unsafe {
            match cull {
                Cull::None => self.gl.disable(glow::CULL_FACE),
                Cull::Front | Cull::Back => {
                    self.gl.enable(glow::CULL_FACE);
                    self.gl.cull_face(if cull == Cull::Front {
                        glow::FRONT
                    } else {
                        glow::BACK
                    });
                }
            }
        }
    }

    /// Slope-scaled depth offset for filled polygons (`glPolygonOffset(factor, units)`).
    pub fn polygon_offset(&self, offset: Option<(f32, f32)>) {
        // SAFETY: no preconditions.
        unsafe {
            match offset {
                Some((factor, units)) => {
                    self.gl.enable(glow::POLYGON_OFFSET_FILL);
                    self.gl.polygon_offset(factor, units);
                }
                None => self.gl.disable(glow::POLYGON_OFFSET_FILL),
            }
        }
    }

    pub fn color_writes(&self, on: bool) {
        // SAFETY: no preconditions.
        unsafe { self.gl.color_mask(on, on, on, on) }
    }
}
