//! dav1d's C API as loaded at run time: libdav1d.so.6 (dav1d 1.0.0–1.2.x, Debian 12) and
//! libdav1d.so.7 (dav1d 1.3.0 and later, Debian 13). Offsets checked with gcc against the
//! headers of Debian 12's libdav1d-dev 1.0.0-2+deb12u1 and upstream 1.2.1, 1.3.0, 1.5.3.
// Field names follow dav1d's headers; most fields are only there for the layout.
#![allow(non_camel_case_types, dead_code)]
use std::ffi::{c_char, c_int, c_uint, c_void};

/// Dav1dUserData (common.h): 16 bytes.
#[repr(C)]
pub(crate) struct Dav1dUserData {
    pub(crate) data: *const u8,
    pub(crate) r#ref: *mut c_void, // struct Dav1dRef *
}

/// Dav1dDataProps (common.h): 48 bytes, same in ABI 6 and 7.
#[repr(C)]
pub(crate) struct Dav1dDataProps {
    pub(crate) timestamp: i64,
    pub(crate) duration: i64,
    pub(crate) offset: i64,
    pub(crate) size: usize,
    pub(crate) user_data: Dav1dUserData,
}

/// Dav1dData (data.h): 72 bytes, same in ABI 6 and 7.
#[repr(C)]
pub(crate) struct Dav1dData {
    pub(crate) data: *const u8,
    pub(crate) sz: usize,
    pub(crate) r#ref: *mut c_void, // struct Dav1dRef *
    pub(crate) m: Dav1dDataProps,
}

/// Dav1dPicAllocator (picture.h): 24 bytes. Left as dav1d_default_settings sets it.
#[repr(C)]
pub(crate) struct Dav1dPicAllocator {
    pub(crate) cookie: *mut c_void,
    pub(crate) alloc_picture_callback:
        Option<unsafe extern "C" fn(*mut Dav1dPicture, *mut c_void) -> c_int>,
    pub(crate) release_picture_callback:
        Option<unsafe extern "C" fn(*mut Dav1dPicture, *mut c_void)>,
}

/// Dav1dLogger (dav1d.h): 16 bytes. The callback takes a va_list, which stable Rust cannot
/// receive, so it is left null (no logging) or as dav1d_default_settings sets it.
#[repr(C)]
pub(crate) struct Dav1dLogger {
    pub(crate) cookie: *mut c_void,
    pub(crate) callback: *const c_void,
}

/// Dav1dSettings (dav1d.h): 96 bytes in ABI 6 and 7. dav1d 1.1+ uses 4 of the 20 reserved bytes
/// for `decode_frame_type` (default 0 = all frames), which dav1d_default_settings sets.
#[repr(C)]
pub(crate) struct Dav1dSettings {
    pub(crate) n_threads: c_int,
    pub(crate) max_frame_delay: c_int,
    pub(crate) apply_grain: c_int,
    pub(crate) operating_point: c_int,
    pub(crate) all_layers: c_int,
    pub(crate) frame_size_limit: c_uint,
    pub(crate) allocator: Dav1dPicAllocator,
    pub(crate) logger: Dav1dLogger,
    pub(crate) strict_std_compliance: c_int,
    pub(crate) output_invisible_frames: c_int,
    pub(crate) inloop_filters: c_uint, // enum Dav1dInloopFilterType
    pub(crate) reserved: [u8; 20],
}

/// Dav1dPictureParameters (picture.h): 16 bytes, same in ABI 6 and 7.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub(crate) struct Dav1dPictureParameters {
    pub(crate) w: c_int,
    pub(crate) h: c_int,
    pub(crate) layout: c_uint, // enum Dav1dPixelLayout: 0 I400, 1 I420, 2 I422, 3 I444
    pub(crate) bpc: c_int,     // 8, 10 or 12
}

/// Dav1dPicture (picture.h). The fields up to `itut_t35` (offset 136) are at the same offsets
/// in ABI 6 (size 264) and ABI 7 (size 272, `n_itut_t35` added at 144); the rest is only
/// passed back to dav1d_picture_unref, so it is opaque here and sized for the larger ABI.
#[repr(C)]
pub(crate) struct Dav1dPicture {
    pub(crate) seq_hdr: *const c_void, // Dav1dSequenceHeader *: see SeqHdr6 / SeqHdr7
    pub(crate) frame_hdr: *const c_void,
    pub(crate) data: [*mut c_void; 3],
    pub(crate) stride: [isize; 2], // bytes; [0] luma, [1] both chroma planes
    pub(crate) p: Dav1dPictureParameters,
    pub(crate) m: Dav1dDataProps,
    pub(crate) content_light: *mut c_void,
    pub(crate) mastering_display: *mut c_void,
    pub(crate) itut_t35: *mut c_void,
    /// ABI 6: reserved[4], 5 refs, reserved_ref[4], ref, allocator_data (120 bytes);
    /// ABI 7: n_itut_t35, reserved[4], 5 refs, reserved_ref[4], ref, allocator_data (128).
    pub(crate) opaque_tail: [usize; 16],
}

/// The first fields of Dav1dSequenceHeader (headers.h) in ABI 6 (dav1d 1.0–1.2: all `int`;
/// whole struct 1484 bytes, never allocated here: read through Dav1dPicture::seq_hdr).
#[repr(C)]
pub(crate) struct SeqHdr6 {
    pub(crate) profile: c_int,
    pub(crate) max_width: c_int,
    pub(crate) max_height: c_int,
    pub(crate) layout: c_uint,
    pub(crate) pri: c_uint,        // enum Dav1dColorPrimaries
    pub(crate) trc: c_uint,        // enum Dav1dTransferCharacteristics
    pub(crate) mtrx: c_uint,       // enum Dav1dMatrixCoefficients
    pub(crate) chr: c_uint,        // enum Dav1dChromaSamplePosition
    pub(crate) hbd: c_int,         // 0, 1, 2: 8, 10, 12 bits
    pub(crate) color_range: c_int, // 1: full ("JPEG") range
}

/// The same in ABI 7 (dav1d 1.3+: flags became uint8_t; whole struct 808 bytes).
#[repr(C)]
pub(crate) struct SeqHdr7 {
    pub(crate) profile: u8,
    pub(crate) max_width: c_int,
    pub(crate) max_height: c_int,
    pub(crate) layout: c_uint,
    pub(crate) pri: c_uint,
    pub(crate) trc: c_uint,
    pub(crate) mtrx: c_uint,
    pub(crate) chr: c_uint,
    pub(crate) hbd: u8,
    pub(crate) color_range: u8,
}

pub(crate) type Dav1dContext = c_void;
pub(crate) type VersionFn = unsafe extern "C" fn() -> *const c_char;
pub(crate) type DefaultSettingsFn = unsafe extern "C" fn(*mut Dav1dSettings);
pub(crate) type OpenFn =
    unsafe extern "C" fn(*mut *mut Dav1dContext, *const Dav1dSettings) -> c_int;
pub(crate) type DataCreateFn = unsafe extern "C" fn(*mut Dav1dData, usize) -> *mut u8;
pub(crate) type DataWrapFn = unsafe extern "C" fn(
    *mut Dav1dData,
    *const u8,
    usize,
    Option<unsafe extern "C" fn(*const u8, *mut c_void)>,
    *mut c_void,
) -> c_int;
pub(crate) type DataUnrefFn = unsafe extern "C" fn(*mut Dav1dData);
pub(crate) type SendDataFn = unsafe extern "C" fn(*mut Dav1dContext, *mut Dav1dData) -> c_int;
pub(crate) type GetPictureFn = unsafe extern "C" fn(*mut Dav1dContext, *mut Dav1dPicture) -> c_int;
pub(crate) type PictureUnrefFn = unsafe extern "C" fn(*mut Dav1dPicture);
pub(crate) type CloseFn = unsafe extern "C" fn(*mut *mut Dav1dContext);

/// DAV1D_ERR(EAGAIN) on Linux (and on Windows, where EAGAIN is also 11).
pub(crate) const DAV1D_EAGAIN: c_int = -11;

const _: () = {
    use std::mem::{offset_of, size_of};
    assert!(size_of::<Dav1dUserData>() == 16);
    assert!(size_of::<Dav1dDataProps>() == 48);
    assert!(size_of::<Dav1dData>() == 72);
    assert!(offset_of!(Dav1dData, m) == 24);
    assert!(size_of::<Dav1dPicAllocator>() == 24);
    assert!(size_of::<Dav1dLogger>() == 16);
    assert!(size_of::<Dav1dSettings>() == 96);
    assert!(offset_of!(Dav1dSettings, frame_size_limit) == 20);
    assert!(offset_of!(Dav1dSettings, allocator) == 24);
    assert!(offset_of!(Dav1dSettings, logger) == 48);
    assert!(offset_of!(Dav1dSettings, inloop_filters) == 72);
    assert!(size_of::<Dav1dPictureParameters>() == 16);
    assert!(offset_of!(Dav1dPicture, data) == 16);
    assert!(offset_of!(Dav1dPicture, stride) == 40);
    assert!(offset_of!(Dav1dPicture, p) == 56);
    assert!(offset_of!(Dav1dPicture, m) == 72);
    assert!(offset_of!(Dav1dPicture, itut_t35) == 136);
    assert!(size_of::<Dav1dPicture>() == 272);
    assert!(offset_of!(SeqHdr6, layout) == 12);
    assert!(offset_of!(SeqHdr6, mtrx) == 24);
    assert!(offset_of!(SeqHdr6, hbd) == 32);
    assert!(offset_of!(SeqHdr6, color_range) == 36);
    assert!(offset_of!(SeqHdr7, max_width) == 4);
    assert!(offset_of!(SeqHdr7, mtrx) == 24);
    assert!(offset_of!(SeqHdr7, hbd) == 32);
    assert!(offset_of!(SeqHdr7, color_range) == 33);
};
