//! libdav1d, the AV1 decoder, loaded at run time (as libturbojpeg and OSMesa are) for
//! EXT_texture_avif: Debian 12's `libdav1d6` (dav1d 1.0, ABI 6) or a newer `libdav1d.so.7`
//! (ABI 7, told apart by `dav1d_version_api`, which only it has); `libdav1d.dll` or
//! `dav1d.dll` beside glview.exe on Windows. Where none loads, AVIF images are not decoded
//! and a texture falls back to its own source (`scene::gltf`). The `image` crate's AVIF
//! decoder links dav1d ≥ 1.3 at build time (Debian 12 has 1.0), and no pure-Rust AV1
//! decoder builds for wasm32 or compiles in the CI's budget (rav1d: ~86 s of CPU):
//! docs/gltf/compression.md. What leaves here is plain planes, bounds checked; the
//! container and the colour conversion are safe code in `textures::avif`. Native builds only
//! (the `native` feature): elsewhere `textures::avif` has no decoder.
mod ffi;
use super::avif::Frame;
use ffi::*;
use libloading::Library;
use std::ffi::c_void;
use std::sync::OnceLock;

#[cfg(windows)]
const LIB_NAMES: &[&str] = &["libdav1d.dll", "dav1d.dll"];
#[cfg(not(windows))]
const LIB_NAMES: &[&str] = &["libdav1d.so.7", "libdav1d.so.6"];

type VersionApiFn = unsafe extern "C" fn() -> std::ffi::c_uint;

struct Api {
    /// 6 or 7: which prefix of Dav1dSequenceHeader the pictures point to.
    abi: u32,
    default_settings: DefaultSettingsFn,
    open: OpenFn,
    data_create: DataCreateFn,
    data_unref: DataUnrefFn,
    send_data: SendDataFn,
    get_picture: GetPictureFn,
    picture_unref: PictureUnrefFn,
    close: CloseFn,
    /// Kept loaded for the process's life: the function pointers point into it.
    _lib: Library,
}

fn api() -> Option<&'static Api> {
    static API: OnceLock<Option<Api>> = OnceLock::new();
    API.get_or_init(|| {
        LIB_NAMES.iter().find_map(|name| {
            // SAFETY: libdav1d's initialisers set up nothing but its own state.
            let lib = unsafe { Library::new(name) }.ok()?;
            // SAFETY: each type is the C signature dav1d's headers give the symbol (the
            // same in ABI 6 and 7); `dav1d_version_api` exists from ABI 7 on.
            unsafe {
                let abi = match lib.get::<VersionApiFn>(b"dav1d_version_api") {
                    Ok(f) if (f() >> 16) & 0xFF == 7 => 7,
                    Ok(_) => return None,
                    Err(_) => 6,
                };
                Some(Api {
                    abi,
                    default_settings: *lib.get(b"dav1d_default_settings").ok()?,
                    open: *lib.get(b"dav1d_open").ok()?,
                    data_create: *lib.get(b"dav1d_data_create").ok()?,
                    data_unref: *lib.get(b"dav1d_data_unref").ok()?,
                    send_data: *lib.get(b"dav1d_send_data").ok()?,
                    get_picture: *lib.get(b"dav1d_get_picture").ok()?,
                    picture_unref: *lib.get(b"dav1d_picture_unref").ok()?,
                    close: *lib.get(b"dav1d_close").ok()?,
                    _lib: lib,
                })
            }
        })
    })
    .as_ref()
}

/// Whether libdav1d could be loaded.
pub fn available() -> bool {
    api().is_some()
}

/// The library's error codes: DAV1D_ERR(EAGAIN) (also 11 on Windows).
const EAGAIN: i32 = DAV1D_EAGAIN;

/// Decodes the first frame of the AV1 stream `obu` (at most `max_pixels` pixels: dav1d
/// refuses larger frames before allocating them). Err: not available, or why not.
pub fn decode(obu: &[u8], max_pixels: u32) -> Result<Frame, String> {
    let api = api().ok_or("no AV1 decoder: libdav1d is not installed (Debian: libdav1d6)")?;
    // SAFETY: the settings are the library's defaults, changed only in plain fields; every
    // pointer handed to dav1d is one it gave or a zeroed struct of its own layout, and every
    // context, data and picture is released on every path.
    unsafe {
        let mut s: Dav1dSettings = std::mem::zeroed();
        (api.default_settings)(&mut s);
        // glview decodes images in parallel already; 0 would be one thread per core each.
        s.n_threads = 1;
        s.max_frame_delay = 1;
        s.all_layers = 0;
        s.frame_size_limit = max_pixels;
        // No log lines on stderr for broken streams: the caller words one warning.
        s.logger.callback = std::ptr::null();
        let mut ctx: *mut c_void = std::ptr::null_mut();
        if (api.open)(&mut ctx, &s) < 0 {
            return Err("the AV1 decoder could not start".into());
        }
        let mut data: Dav1dData = std::mem::zeroed();
        let buf = (api.data_create)(&mut data, obu.len());
        if buf.is_null() {
            (api.close)(&mut ctx);
            return Err("the AV1 decoder has no memory for the stream".into());
        }
        std::ptr::copy_nonoverlapping(obu.as_ptr(), buf, obu.len());
        let mut pic: Dav1dPicture = std::mem::zeroed();
        let result = loop {
            if data.sz > 0 {
                let r = (api.send_data)(ctx, &mut data);
                if r < 0 && r != EAGAIN {
                    break Err(format!("the AV1 stream does not decode (dav1d error {r})"));
                }
            }
            match (api.get_picture)(ctx, &mut pic) {
                EAGAIN if data.sz > 0 => continue,
                EAGAIN => break Err("the AV1 stream holds no picture".into()),
                r if r < 0 => {
                    break Err(format!("the AV1 stream does not decode (dav1d error {r})"))
                }
                _ => {}
            }
            let frame = frame_of(api.abi, &pic);
            (api.picture_unref)(&mut pic);
            break frame;
        };
        if data.sz > 0 {
            (api.data_unref)(&mut data);
        }
        (api.close)(&mut ctx);
        result
    }
}

/// The planes of a picture dav1d returned, copied out row by row.
///
/// # Safety
/// `pic` is a picture `dav1d_get_picture` filled with the layout of ABI `abi`.
unsafe fn frame_of(abi: u32, pic: &Dav1dPicture) -> Result<Frame, String> {
    let p = pic.p;
    let (Ok(w), Ok(h)) = (usize::try_from(p.w), usize::try_from(p.h)) else {
        return Err("the AV1 picture has no size".into());
    };
    if w == 0 || h == 0 || !(8..=12).contains(&p.bpc) || p.layout > 3 || pic.seq_hdr.is_null() {
        return Err("the AV1 picture is not one glview reads".into());
    }
    let (matrix, full_range) = if abi == 6 {
        let sh = &*pic.seq_hdr.cast::<SeqHdr6>();
        (sh.mtrx, sh.color_range != 0)
    } else {
        let sh = &*pic.seq_hdr.cast::<SeqHdr7>();
        (sh.mtrx, sh.color_range != 0)
    };
    let chroma = match p.layout {
        0 => (0, 0),
        1 => (w.div_ceil(2), h.div_ceil(2)),
        2 => (w.div_ceil(2), h),
        _ => (w, h),
    };
    let wide = p.bpc > 8;
    let plane = |i: usize, (pw, ph): (usize, usize)| -> Vec<u16> {
        let stride = pic.stride[usize::from(i > 0)];
        let base = pic.data[i].cast::<u8>().cast_const();
        let mut out = Vec::with_capacity(pw * ph);
        for y in 0..ph {
            let row = base.offset(y as isize * stride);
            if wide {
                let row = std::slice::from_raw_parts(row.cast::<u16>(), pw);
                out.extend_from_slice(row);
            } else {
                out.extend(
                    std::slice::from_raw_parts(row, pw)
                        .iter()
                        .map(|&v| u16::from(v)),
                );
            }
        }
        out
    };
    let planes = if p.layout == 0 {
        [plane(0, (w, h)), Vec::new(), Vec::new()]
    } else {
        [plane(0, (w, h)), plane(1, chroma), plane(2, chroma)]
    };
    Ok(Frame {
        width: w,
        height: h,
        bits: p.bpc as u32,
        layout: p.layout,
        matrix,
        full_range,
        chroma,
        planes,
    })
}
