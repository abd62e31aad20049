//! OBJ + MTL bytes in (split at the first 0xFF 0x00 0xFF) → `load_embedded` → a scene that
//! passes `glview_fuzz::check_scene`, or a clean error naming the file. A panic anywhere (the
//! loader, tobj, or a violated invariant), an OOM over `-rss_limit_mb` or a hang over
//! `-timeout` is a finding. `GLVIEW_FUZZ_SKIP_KNOWN=1` skips inputs that hit a crash already
//! recorded in `glview_fuzz::KNOWN_UNFIXED` (see fuzz/README.md).
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if glview_fuzz::skip_known() && glview_fuzz::known_unfixed(data).is_some() {
        return;
    }
    let _ = glview_fuzz::run_one(data);
});
