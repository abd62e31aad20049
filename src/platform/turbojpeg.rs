//! libjpeg-turbo's TurboJPEG API, loaded at run time (as OSMesa is): where the library is
//! installed (Debian's `libturbojpeg0`) JPEG encoding is ~12× faster than the `image` crate's
//! encoder (800×600 at quality 75: 0.6 ms against 7.4 ms, docs/serve.md), which is a third of
//! a full-size preview frame of `glview serve`; where it is missing, callers fall back to
//! `image`. The `turbojpeg` crate would link the library at build time (and its current
//! release needs libjpeg-turbo 3, newer than Debian 12's 2.1).
use libloading::Library;
use std::ffi::{c_char, c_int, c_uchar, c_ulong, c_void};
use std::sync::OnceLock;

const LIB_NAMES: &[&str] = &["libturbojpeg.so.0", "libturbojpeg.so"];
/// TJPF_RGBA and TJSAMP_420 of turbojpeg.h (2.x and 3.x alike).
const TJPF_RGBA: c_int = 7;
const TJSAMP_420: c_int = 2;

type Handle = *mut c_void;
type InitFn = unsafe extern "C" fn() -> Handle;
#[allow(clippy::type_complexity)]
type CompressFn = unsafe extern "C" fn(
    Handle,
    *const c_uchar,
    c_int,
    c_int,
    c_int,
    c_int,
    *mut *mut c_uchar,
    *mut c_ulong,
    c_int,
    c_int,
    c_int,
) -> c_int;
type FreeFn = unsafe extern "C" fn(*mut c_uchar);
type DestroyFn = unsafe extern "C" fn(Handle) -> c_int;
type ErrorFn = unsafe extern "C" fn(Handle) -> *const c_char;

struct Api {
    init: InitFn,
    compress: CompressFn,
    free: FreeFn,
    destroy: DestroyFn,
    error: ErrorFn,
    /// Kept loaded for the process's life: the function pointers point into it.
    _lib: Library,
}

fn api() -> Option<&'static Api> {
    static API: OnceLock<Option<Api>> = OnceLock::new();
    API.get_or_init(|| {
        let lib = LIB_NAMES.iter().find_map(|name| {
            // SAFETY: libturbojpeg's initialisers set up nothing but its own state.
            unsafe { Library::new(name) }.ok()
        })?;
        // SAFETY: each type is the C signature turbojpeg.h gives the symbol.
        let api = unsafe {
            Api {
                init: *lib.get::<InitFn>(b"tjInitCompress").ok()?,
                compress: *lib.get::<CompressFn>(b"tjCompress2").ok()?,
                free: *lib.get::<FreeFn>(b"tjFree").ok()?,
                destroy: *lib.get::<DestroyFn>(b"tjDestroy").ok()?,
                error: *lib.get::<ErrorFn>(b"tjGetErrorStr2").ok()?,
                _lib: lib,
            }
        };
        Some(api)
    })
    .as_ref()
}

/// Whether libturbojpeg could be loaded.
pub fn available() -> bool {
    api().is_some()
}

/// RGBA pixels (top row first, alpha ignored) as a 4:2:0 JPEG of `quality` (1–100); None
/// when the library is not installed; Err with its message when it fails.
pub(crate) fn encode_rgba(
    rgba: &[u8],
    width: u32,
    height: u32,
    quality: u8,
) -> Option<Result<Vec<u8>, String>> {
    let api = api()?;
    if rgba.len() != width as usize * height as usize * 4 || width == 0 || height == 0 {
        return Some(Err(format!("{width}x{height}: not the size of the pixels")));
    }
    let (w, h) = (c_int::try_from(width).ok()?, c_int::try_from(height).ok()?);
    // SAFETY: the handle is used on this thread only and destroyed below; `rgba` holds
    // width × height RGBA pixels (checked above); the output buffer is allocated by
    // tjCompress2, copied, and freed with tjFree as turbojpeg.h requires.
    unsafe {
        let handle = (api.init)();
        if handle.is_null() {
            return Some(Err("tjInitCompress failed".into()));
        }
        let mut buf: *mut c_uchar = std::ptr::null_mut();
        let mut size: c_ulong = 0;
        let rc = (api.compress)(
            handle,
            rgba.as_ptr(),
            w,
            w * 4,
            h,
            TJPF_RGBA,
            &mut buf,
            &mut size,
            TJSAMP_420,
            c_int::from(quality.clamp(1, 100)),
            0,
        );
        let out = if rc == 0 && !buf.is_null() {
            Ok(std::slice::from_raw_parts(buf, size as usize).to_vec())
        } else {
            let msg = (api.error)(handle);
            Err(if msg.is_null() {
                "tjCompress2 failed".to_string()
            } else {
                std::ffi::CStr::from_ptr(msg).to_string_lossy().into_owned()
            })
        };
        if !buf.is_null() {
            (api.free)(buf);
        }
        (api.destroy)(handle);
        Some(out)
    }
}
