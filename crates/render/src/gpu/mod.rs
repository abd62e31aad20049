//! The only layer that calls GL (and so the only `unsafe` besides `platform`). Every GL object
//! is owned by one wrapper that deletes it in `Drop`; wrappers hold an `Rc<Gpu>`, so the
//! context's function table outlives them. The platform context itself must outlive the
//! `Gpu` (the caller drops renderers before the platform context).
pub(crate) mod buffer;
pub(crate) mod caps;
pub mod framebuffer;
pub(crate) mod instances;
pub(crate) mod mesh;
pub(crate) mod mipmaps;
pub mod program;
pub(crate) mod query;
pub(crate) mod state;
pub mod texture;

pub use caps::{Caps, Dialect};
use glow::HasContext;
use std::cell::{Cell, RefCell};
use std::rc::Rc;

/// A GL context's functions plus what the driver can do and a count of live GL objects
/// (for leak tests: it must return to its start value when resources are dropped).
pub struct Gpu {
    pub gl: glow::Context,
    pub caps: Caps,
    live: Cell<i64>,
    /// The render state last applied (None: unknown, set everything next time).
    state: Cell<Option<state::RenderState>>,
    /// Image textures uploaded since the last [`Gpu::take_texture_costs`], for `--stats`.
    texture_costs: RefCell<Vec<TextureCost>>,
    /// What this layer bound where (see [`Bound`]).
    bound: RefCell<Bound>,
}

/// The active texture unit, each unit's 2D texture and the framebuffer, as this layer bound
/// them. glow's binding queries panic on WebGL when nothing is bound (it looks the null up
/// as one of its objects), so in the browser this record answers them; natively the driver
/// is asked, as before. Every binding goes through this layer there (the web crate makes no
/// GL call of its own).
#[derive(Default)]
struct Bound {
    unit: u32,
    textures_2d: Vec<(u32, glow::Texture)>,
    framebuffer: Option<glow::Framebuffer>,
}

/// What one image texture cost to upload: mipmaps, format conversion and the GL calls, up to
/// glFinish (wall time).
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct TextureCost {
    pub(crate) name: String,
    pub(crate) width: u32,
    pub(crate) height: u32,
    pub(crate) ms: f64,
}

pub type GpuRef = Rc<Gpu>;

impl Gpu {
    pub fn new(gl: glow::Context) -> Rc<Gpu> {
        Self::with_es2_ceiling(gl, false)
    }

    /// [`Gpu::new`], held to OpenGL ES 2.0's rules (GLSL ES 1.00, WebGL 1's features) when
    /// `es2` is set and the context is ES: what `--gl es2` asks for, whatever later ES
    /// version the driver answered with.
    pub fn with_es2_ceiling(gl: glow::Context, es2: bool) -> Rc<Gpu> {
        let caps = Caps::probe(&gl, es2);
        enable_point_sprites(&gl, &caps);
        Rc::new(Gpu {
            gl,
            caps,
            live: Cell::new(0),
            state: Cell::new(None),
            texture_costs: RefCell::new(Vec::new()),
            bound: RefCell::new(Bound::default()),
        })
    }

    /// GL objects created through this layer and not yet deleted.
    pub fn live_objects(&self) -> i64 {
        self.live.get()
    }

    pub(crate) fn created(&self) {
        self.live.set(self.live.get() + 1);
    }

    pub(crate) fn deleted(&self) {
        self.live.set(self.live.get() - 1);
    }

    pub(crate) fn record_texture(&self, cost: TextureCost) {
        self.texture_costs.borrow_mut().push(cost);
    }

    /// The image textures uploaded since the last call, in upload order.
    pub fn take_texture_costs(&self) -> Vec<TextureCost> {
        self.texture_costs.take()
    }

    pub(crate) fn active_unit(&self, unit: u32) {
        // SAFETY: selecting a texture unit the caller keeps below the driver's limit.
        unsafe { self.gl.active_texture(glow::TEXTURE0 + unit) };
        self.bound.borrow_mut().unit = unit;
    }

    /// Binds `t` (a live texture of this context, or none) as the active unit's 2D texture.
    pub(crate) fn bind_texture_2d(&self, t: Option<glow::Texture>) {
        // SAFETY: t is None or a live 2D texture of this context (the callers' own).
        unsafe { self.gl.bind_texture(glow::TEXTURE_2D, t) };
        let mut b = self.bound.borrow_mut();
        let unit = b.unit;
        b.textures_2d.retain(|(u, _)| *u != unit);
        if let Some(t) = t {
            b.textures_2d.push((unit, t));
        }
    }

    /// The active unit's 2D texture.
    pub(crate) fn bound_texture_2d(&self) -> Option<glow::Texture> {
        if cfg!(target_arch = "wasm32") {
            let b = self.bound.borrow();
            b.textures_2d
                .iter()
                .find(|(u, _)| *u == b.unit)
                .map(|(_, t)| *t)
        } else {
            // SAFETY: a binding query on the current context.
            unsafe { self.gl.get_parameter_texture(glow::TEXTURE_BINDING_2D) }
        }
    }

    /// A deleted texture is bound nowhere any more (GL unbinds it from every unit).
    pub(crate) fn forget_texture(&self, t: glow::Texture) {
        self.bound.borrow_mut().textures_2d.retain(|(_, b)| *b != t);
    }

    pub(crate) fn record_framebuffer(&self, f: Option<glow::Framebuffer>) {
        self.bound.borrow_mut().framebuffer = f;
    }

    /// A deleted framebuffer that was bound leaves the default one bound.
    pub(crate) fn forget_framebuffer(&self, f: glow::Framebuffer) {
        let mut b = self.bound.borrow_mut();
        if b.framebuffer == Some(f) {
            b.framebuffer = None;
        }
    }

    pub(crate) fn recorded_framebuffer(&self) -> Option<glow::Framebuffer> {
        self.bound.borrow().framebuffer
    }

    /// Checks `glGetError` once, at a pass boundary (never after every call: it stalls).
    pub fn check_error(&self, pass: &str) -> crate::Result<()> {
        // SAFETY: glGetError has no preconditions on a current context.
        let code = unsafe { self.gl.get_error() };
        if code == glow::NO_ERROR {
            Ok(())
        } else {
            Err(crate::Error::Gl {
                code,
                pass: pass.to_string(),
            })
        }
    }

    pub fn finish(&self) {
        // SAFETY: no preconditions.
        unsafe { self.gl.finish() }
    }

    /// Whether the bound draw framebuffer is multisampled (its colour cannot be copied into a
    /// texture with glCopyTexSubImage2D).
    pub(crate) fn framebuffer_multisampled(&self) -> bool {
        // SAFETY: GL_SAMPLE_BUFFERS is a plain integer query of every GL version here.
        unsafe { self.gl.get_parameter_i32(glow::SAMPLE_BUFFERS) > 0 }
    }

    /// Reads the bound read framebuffer as RGBA8, top row first (GL's rows are bottom-up).
    pub fn read_rgba(&self, width: u32, height: u32) -> Vec<u8> {
        let (w, h) = (width as usize, height as usize);
        let mut buf = vec![0u8; w * h * 4];
        let top_first = self.read_pixels(
            width,
            height,
            glow::RGBA,
            glow::UNSIGNED_BYTE,
            1,
            &mut buf,
            true,
        );
        if !top_first {
            flip_rows(&mut buf, w * 4);
        }
        buf
    }

    /// Reads the bound read framebuffer's depth as u32 whose top 24 bits are the depth (a
    /// 24-bit buffer's value; `0xFFFFFF` is the far plane), and whether the rows are top
    /// first (else bottom first, GL's order). Desktop GL only: ES 3.0 has no depth read-back.
    /// With a stencil buffer beside the depth (`stencil`) it reads DEPTH_STENCIL as
    /// UNSIGNED_INT_24_8, which Mesa copies as stored (depth above the stencil byte); else
    /// DEPTH_COMPONENT as UNSIGNED_INT, whose top 24 bits are the same depth: on llvmpipe at
    /// 640x480 0.16 against 0.27 ms, and the FLOAT read the generic path takes was 0.35.
    pub(crate) fn read_depth_u32(
        &self,
        width: u32,
        height: u32,
        stencil: bool,
    ) -> (Vec<u32>, bool) {
        let mut buf = vec![0u32; width as usize * height as usize];
        let (format, ty) = if stencil {
            (glow::DEPTH_STENCIL, glow::UNSIGNED_INT_24_8)
        } else {
            (glow::DEPTH_COMPONENT, glow::UNSIGNED_INT)
        };
        let top_first = self.read_pixels(
            width,
            height,
            format,
            ty,
            4,
            bytemuck::cast_slice_mut(&mut buf),
            true,
        );
        (buf, top_first)
    }

    /// `glReadPixels` of the whole `width`×`height` into `buf` (which must hold exactly what
    /// `format`/`ty` give with rows aligned to `align`): bottom row first (GL's order), or
    /// with `top_first` asked for, top row first where the driver can (MESA_pack_invert);
    /// returns whether the rows are top first.
    #[allow(clippy::too_many_arguments)]
    fn read_pixels(
        &self,
        width: u32,
        height: u32,
        format: u32,
        ty: u32,
        align: i32,
        buf: &mut [u8],
        top_first: bool,
    ) -> bool {
        const PACK_INVERT_MESA: u32 = 0x8758;
        let invert = top_first && self.caps.pack_invert;
        // SAFETY: the caller sized buf for width*height pixels of format/ty at this
        // alignment; PACK_INVERT_MESA is set only where the extension exists, and reset.
        unsafe {
            self.gl.pixel_store_i32(glow::PACK_ALIGNMENT, align);
            if invert {
                self.gl.pixel_store_i32(PACK_INVERT_MESA, 1);
            }
            self.gl.read_pixels(
                0,
                0,
                width as i32,
                height as i32,
                format,
                ty,
                glow::PixelPackData::Slice(Some(buf)),
            );
            if invert {
                self.gl.pixel_store_i32(PACK_INVERT_MESA, 0);
            }
        }
        invert
    }
}

impl Gpu {
    /// Reads the bound read framebuffer's float colour as RGBA f32, bottom row first (GL
    /// order; cube-face rows are stored that way).
    pub(crate) fn read_rgba_f32(&self, width: u32, height: u32) -> Vec<f32> {
        let mut buf = vec![0f32; width as usize * height as usize * 4];
        let bytes = bytemuck::cast_slice_mut(&mut buf);
        self.read_pixels(width, height, glow::RGBA, glow::FLOAT, 4, bytes, false);
        buf
    }
}

/// Flips an image vertically in place (GL bottom-up ↔ PNG top-down).
pub(crate) fn flip_rows(buf: &mut [u8], row_bytes: usize) {
    let rows = buf.len() / row_bytes.max(1);
    for y in 0..rows / 2 {
        let (top, bottom) = buf.split_at_mut((rows - 1 - y) * row_bytes);
        top[y * row_bytes..(y + 1) * row_bytes].swap_with_slice(&mut bottom[..row_bytes]);
    }
}

/// Points take their size from the vertex shader's `gl_PointSize` and their disks from
/// `gl_PointCoord`, on every context, once at set-up (no pass changes these): desktop GL
/// needs `GL_PROGRAM_POINT_SIZE` (2.1's `GL_VERTEX_PROGRAM_POINT_SIZE`, the same enum)
/// enabled, else the size is `glPointSize`'s 1; GL 2.1 and compatibility profiles
/// also need `GL_POINT_SPRITE`, else `gl_PointCoord` is undefined (Mesa gives 0). Core
/// profiles always make sprites and reject the enum; ES has neither enable (its vertex
/// shader's `gl_PointSize` is always used).
fn enable_point_sprites(gl: &glow::Context, caps: &Caps) {
    const PROGRAM_POINT_SIZE: u32 = 0x8642;
    const POINT_SPRITE: u32 = 0x8861;
    if caps.embedded {
        return;
    }
    // SAFETY: glEnable of two enums; glGetError drains what a context that rejects one
    // leaves behind, so no pass reports it.
    unsafe {
        gl.enable(PROGRAM_POINT_SIZE);
        let e = gl.get_error();
        if e != glow::NO_ERROR {
            log::warn!("{}: GL_PROGRAM_POINT_SIZE: GL error 0x{e:x}", caps.version);
        }
        if !caps.core_profile {
            gl.enable(POINT_SPRITE);
            // A core context that reports an overridden version (MESA_GL_VERSION_OVERRIDE=2.1
            // on a 3.x core window) rejects it: its points are always sprites.
            let e = gl.get_error();
            if e != glow::NO_ERROR {
                log::debug!("{}: GL_POINT_SPRITE: GL error 0x{e:x}", caps.version);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn flip() {
        let mut b = vec![1, 2, 3, 4, 5, 6];
        super::flip_rows(&mut b, 2);
        assert_eq!(b, vec![5, 6, 3, 4, 1, 2]);
    }
}
