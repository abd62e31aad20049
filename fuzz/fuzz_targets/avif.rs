//! AVIF bytes in → `glview::scene::decode_image` (avif-parse, libdav1d loaded at run time,
//! the YUV-to-RGBA conversion) → an image of exactly width × height × 4 bytes within the
//! texture bounds, or an error. A panic, an OOM over `-rss_limit_mb` or a hang over
//! `-timeout` is a finding (see fuzz/README.md). Needs libdav1d (Debian: libdav1d6): without
//! it every input is the same "no AV1 decoder" error and the run explores nothing past the
//! container.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if let Ok((w, h, rgba)) = glview::scene::decode_image(data) {
        assert_eq!(rgba.len(), w as usize * h as usize * 4, "{w}x{h}");
        assert!(w > 0 && h > 0 && u64::from(w) * u64::from(h) <= 1 << 26);
    }
});
