//! Off-screen rendering through Mesa's OSMesa, loaded with `dlopen` at run time.
//!
//! There is no link-time dependency on libOSMesa: the binary starts on systems
//! without it (Mesa >= 25.1 removed OSMesa) and only [`OsMesaContext::new`]
//! reports [`OsMesaError::NotFound`].
//!
//! OSMesa contexts are current per thread: use an [`OsMesaContext`] and its
//! glow context only on the thread that created it (the type is neither `Send`
//! nor `Sync`), and keep at most one alive per thread, since creating one makes
//! it the thread's current context.

use std::ffi::{c_char, c_int, c_uint, c_void, CStr};
use std::ptr;

use libloading::Library;

/// Sonames to try: `.so.8` is current Mesa, `.so.6` the older name.
const LIB_NAMES: [&str; 2] = ["libOSMesa.so.8", "libOSMesa.so.6"];

// Constants from Mesa's include/GL/osmesa.h.
const OSMESA_RGBA: c_uint = 0x1908; // = GL_RGBA
const OSMESA_Y_UP: c_int = 0x11;
const OSMESA_FORMAT: c_int = 0x22;
const OSMESA_DEPTH_BITS: c_int = 0x30;
const OSMESA_STENCIL_BITS: c_int = 0x31;
const OSMESA_ACCUM_BITS: c_int = 0x32;
const OSMESA_PROFILE: c_int = 0x33;
const OSMESA_CORE_PROFILE: c_int = 0x34;
const OSMESA_COMPAT_PROFILE: c_int = 0x35;
const OSMESA_CONTEXT_MAJOR_VERSION: c_int = 0x36;
const OSMESA_CONTEXT_MINOR_VERSION: c_int = 0x37;
const GL_UNSIGNED_BYTE: c_uint = 0x1401;
/// llvmpipe's largest render target; checking here gives a clear error
/// instead of a huge allocation followed by a failing OSMesaMakeCurrent.
const MAX_SIZE: u32 = 16384;

type RawContext = *mut c_void;
type CreateAttribsFn = unsafe extern "C" fn(*const c_int, RawContext) -> RawContext;
type CreateExtFn = unsafe extern "C" fn(c_uint, c_int, c_int, c_int, RawContext) -> RawContext;
type MakeCurrentFn = unsafe extern "C" fn(RawContext, *mut c_void, c_uint, c_int, c_int) -> u8;
type GetProcAddressFn = unsafe extern "C" fn(*const c_char) -> *const c_void;
type DestroyFn = unsafe extern "C" fn(RawContext);
type PixelStoreFn = unsafe extern "C" fn(c_int, c_int);

#[derive(Debug, thiserror::Error)]
pub enum OsMesaError {
    #[error("OSMesa is not available: could not load libOSMesa.so.8 or libOSMesa.so.6 ({0}); install libosmesa6 or use --backend egl")]
    NotFound(String),
    #[error("OSMesa: missing symbol {0}")]
    Symbol(String),
    #[error("OSMesa could not create a {0} context")]
    CreateContext(String),
    #[error("OSMesa could not make the context current")]
    MakeCurrent,
    #[error("invalid size {0}x{1}")]
    Size(u32, u32),
}

/// Which context to ask OSMesa for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum OsMesaProfile {
    /// Compatibility profile, at least 2.1: Mesa 22.3 returns 4.5 compat;
    /// `MESA_GL_VERSION_OVERRIDE=2.1 MESA_GLSL_VERSION_OVERRIDE=120` pins 2.1.
    Compat21,
    /// Core profile, at least 3.3 (Mesa 22.3 returns 4.5 core). Fails with
    /// `CreateContext` when MESA_GL_VERSION_OVERRIDE caps the version below 3.3.
    Core33,
}

/// An OSMesa context rendering into an owned RGBA8 buffer.
pub(crate) struct OsMesaContext {
    ctx: RawContext,
    get_proc_address: GetProcAddressFn,
    destroy: DestroyFn,
    /// One `u32` per RGBA8 pixel (also gives 4-byte alignment). OSMesa keeps
    /// a pointer to it, so it is never resized; moving the Vec keeps the heap
    /// address. Bottom row first (OSMESA_Y_UP = 1).
    buf: Vec<u32>,
    width: u32,
    height: u32,
    /// Declared last so it is dropped last: fields drop in declaration order,
    /// after `Drop::drop` destroyed the context, and the function pointers
    /// above point into this library.
    _lib: Library,
}

fn load_library() -> Result<Library, OsMesaError> {
    let mut errors = Vec::new();
    for name in LIB_NAMES {
        // SAFETY: libOSMesa's initialisers only set up Mesa's own global state.
        match unsafe { Library::new(name) } {
            Ok(lib) => return Ok(lib),
            Err(e) => errors.push(e.to_string()),
        }
    }
    Err(OsMesaError::NotFound(errors.join("; ")))
}

/// Copies a function pointer out of `lib`; the caller keeps `lib` alive.
fn sym<T: Copy>(lib: &Library, name: &str) -> Result<T, OsMesaError> {
    // SAFETY: every call site names T as the C signature osmesa.h gives `name`.
    unsafe { lib.get::<T>(name.as_bytes()) }
        .map(|s| *s)
        .map_err(|_| OsMesaError::Symbol(name.to_owned()))
}

fn create_context(lib: &Library, profile: OsMesaProfile) -> Result<RawContext, OsMesaError> {
    let (prof, major, minor, what) = match profile {
        OsMesaProfile::Compat21 => (OSMESA_COMPAT_PROFILE, 2, 1, "compatibility 2.1"),
        OsMesaProfile::Core33 => (OSMESA_CORE_PROFILE, 3, 3, "core 3.3"),
    };
    let ctx = match sym::<CreateAttribsFn>(lib, "OSMesaCreateContextAttribs") {
        Ok(create) => {
            #[rustfmt::skip]
            let attribs = [
                OSMESA_FORMAT, OSMESA_RGBA as c_int,
                OSMESA_DEPTH_BITS, 24, OSMESA_STENCIL_BITS, 8, OSMESA_ACCUM_BITS, 0,
                OSMESA_PROFILE, prof,
                OSMESA_CONTEXT_MAJOR_VERSION, major, OSMESA_CONTEXT_MINOR_VERSION, minor,
                0,
            ];
            // SAFETY: the list is 0-terminated and outlives the call; no share context.
            unsafe { create(attribs.as_ptr(), ptr::null_mut()) }
        }
        // Before Mesa 10.6 only the Ext entry point exists, and it makes a
        // legacy context, which is fine for 2.1 but cannot give core 3.3.
        Err(e) if profile == OsMesaProfile::Core33 => return Err(e),
        Err(_) => {
            let create: CreateExtFn = sym(lib, "OSMesaCreateContextExt")?;
            // SAFETY: plain integer arguments; no share context.
            unsafe { create(OSMESA_RGBA, 24, 8, 0, ptr::null_mut()) }
        }
    };
    if ctx.is_null() {
        return Err(OsMesaError::CreateContext(what.to_owned()));
    }
    Ok(ctx)
}

impl OsMesaContext {
    /// Loads the library, creates a context with a 24-bit depth buffer and
    /// 8-bit stencil, and makes it current on this thread on an owned RGBA8
    /// buffer of `width` x `height`.
    pub(crate) fn new(
        profile: OsMesaProfile,
        width: u32,
        height: u32,
    ) -> Result<Self, OsMesaError> {
        if width == 0 || height == 0 || width > MAX_SIZE || height > MAX_SIZE {
            return Err(OsMesaError::Size(width, height));
        }
        let lib = load_library()?;
        let make_current: MakeCurrentFn = sym(&lib, "OSMesaMakeCurrent")?;
        let pixel_store: PixelStoreFn = sym(&lib, "OSMesaPixelStore")?;
        let get_proc_address = sym(&lib, "OSMesaGetProcAddress")?;
        let destroy = sym(&lib, "OSMesaDestroyContext")?;
        let ctx = create_context(&lib, profile)?;
        // From here on, Drop destroys the context if anything fails.
        let mut this = Self {
            ctx,
            get_proc_address,
            destroy,
            buf: vec![0; width as usize * height as usize],
            width,
            height,
            _lib: lib,
        };
        let (w, h) = (width as c_int, height as c_int); // <= MAX_SIZE, so no overflow
        let buf = this.buf.as_mut_ptr().cast();
        // SAFETY: ctx is live; buf holds w*h RGBA8 pixels and stays allocated
        // at this address until after Drop destroyed the context.
        let ok = unsafe { make_current(this.ctx, buf, GL_UNSIGNED_BYTE, w, h) };
        if ok == 0 {
            return Err(OsMesaError::MakeCurrent);
        }
        // Pin the default (row 0 = bottom, as in GL) so read_rgba's flip is right.
        // SAFETY: a context is current on this thread.
        unsafe { pixel_store(OSMESA_Y_UP, 1) };
        Ok(this)
    }

    /// A glow context whose functions come from OSMesaGetProcAddress.
    ///
    /// Use it only on this thread and drop it before `self`: its function
    /// pointers point into the library `self` owns.
    pub(crate) fn glow_context(&self) -> glow::Context {
        let get = self.get_proc_address;
        // SAFETY: our context is current on this thread (made so in `new`),
        // which glow needs to query GL_VERSION; `get` takes a C string.
        unsafe { glow::Context::from_loader_function_cstr(|name: &CStr| get(name.as_ptr())) }
    }

    #[cfg(test)] // only the unit tests call it
    pub(crate) fn size(&self) -> (u32, u32) {
        (self.width, self.height)
    }

    /// The rendered pixels, RGBA8, top row first. OSMesa's buffer stays in
    /// GL's bottom-up order (OSMESA_Y_UP = 1) and the rows are flipped here.
    /// Calls glFinish through `gl` first: llvmpipe renders asynchronously and
    /// only writes our buffer when flushed.
    pub(crate) fn read_rgba(&self, gl: &glow::Context) -> Vec<u8> {
        use glow::HasContext;
        // SAFETY: glFinish has no preconditions beyond a current context.
        unsafe { gl.finish() };
        let row = self.width as usize * 4;
        let len = row * self.height as usize;
        // SAFETY: buf holds exactly `len` initialised bytes and GL has finished
        // writing them; the slice lives only for this copy.
        let src = unsafe { std::slice::from_raw_parts(self.buf.as_ptr().cast::<u8>(), len) };
        src.chunks_exact(row).rev().flatten().copied().collect()
    }

    /// Whether the library can be loaded at all (for tests / `--info`).
    #[cfg(test)] // only the unit tests call it
    pub(crate) fn available() -> bool {
        load_library().is_ok()
    }
}

impl Drop for OsMesaContext {
    fn drop(&mut self) {
        // SAFETY: ctx came from OSMesaCreateContext* and is destroyed once,
        // on its own thread (the type is !Send); Mesa unbinds it if current.
        // `buf` and `_lib` are dropped only after this returns.
        unsafe { (self.destroy)(self.ctx) };
    }
}

impl From<OsMesaError> for crate::Error {
    fn from(e: OsMesaError) -> crate::Error {
        crate::Error::Osmesa(e.to_string())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glow::HasContext;

    const BLUE: [u8; 4] = [0, 0, 255, 255];
    const RED: [u8; 4] = [255, 0, 0, 255];

    /// `None` (the test passes with a note) when OSMesa is missing, except in
    /// CI, where a missing library must fail the run instead of hiding it.
    fn context(profile: OsMesaProfile) -> Option<OsMesaContext> {
        if !OsMesaContext::available() {
            let ci = std::env::var("CI").is_ok_and(|v| v == "true");
            assert!(!ci, "OSMesa is missing in CI: apt-get install libosmesa6");
            eprintln!("note: OSMesa not installed, skipping");
            return None;
        }
        Some(OsMesaContext::new(profile, 64, 32).expect("OSMesa context"))
    }

    /// Clears to blue, then the bottom-left 16x4 to red, checking every pixel
    /// of the top-down readback; returns GL_VERSION.
    fn clear_and_read(profile: OsMesaProfile) -> Option<String> {
        let ctx = context(profile)?;
        assert_eq!(ctx.size(), (64, 32));
        let gl = ctx.glow_context();
        // SAFETY: ctx is current on this thread and outlives gl.
        unsafe {
            gl.clear_color(0.0, 0.0, 1.0, 1.0);
            gl.clear(glow::COLOR_BUFFER_BIT);
        }
        let px = ctx.read_rgba(&gl);
        assert_eq!(px.len(), 64 * 32 * 4);
        assert!(px.chunks_exact(4).all(|p| p == BLUE));
        // SAFETY: as above.
        unsafe {
            gl.enable(glow::SCISSOR_TEST);
            gl.scissor(0, 0, 16, 4); // GL window coordinates: y = 0 is the bottom row
            gl.clear_color(1.0, 0.0, 0.0, 1.0);
            gl.clear(glow::COLOR_BUFFER_BIT);
            gl.disable(glow::SCISSOR_TEST);
        }
        let px = ctx.read_rgba(&gl);
        for (i, p) in px.chunks_exact(4).enumerate() {
            let (x, y) = (i % 64, i / 64);
            let want = if x < 16 && y >= 28 { RED } else { BLUE };
            assert_eq!(p, want, "pixel x={x} y={y} (top row = 0)");
        }
        // SAFETY: as above.
        let version = unsafe { gl.get_parameter_string(glow::VERSION) };
        assert!(!version.is_empty());
        Some(version)
    }

    #[test]
    fn compat21_clear_readback_and_flip() {
        if let Some(v) = clear_and_read(OsMesaProfile::Compat21) {
            eprintln!("Compat21 GL_VERSION: {v}");
        }
    }

    #[test]
    fn core33_clear_readback_and_flip() {
        if let Some(v) = clear_and_read(OsMesaProfile::Core33) {
            eprintln!("Core33 GL_VERSION: {v}");
            assert!(v.starts_with("3.") || v.starts_with("4."), "{v}");
        }
    }

    #[test]
    fn zero_size_is_rejected() {
        // Checked before loading the library, so this runs everywhere.
        let r = OsMesaContext::new(OsMesaProfile::Compat21, 0, 32);
        assert!(matches!(r, Err(OsMesaError::Size(0, 32))));
        let r = OsMesaContext::new(OsMesaProfile::Core33, 64, 0);
        assert!(matches!(r, Err(OsMesaError::Size(64, 0))));
    }
}
