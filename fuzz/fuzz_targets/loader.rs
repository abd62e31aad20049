//! OBJ + MTL bytes in (split at the first 0xFF 0x00 0xFF) → `load_embedded_with` on the old
//! path (repair + tobj) → a scene that passes `glview_fuzz::check_scene`, or a clean error
//! naming the file; the fast OBJ path (`Parser::Auto`, `Parser::Chunked(64)`) must give the
//! same scene or error text (`glview_fuzz::load_compared`). A panic anywhere (the loader, tobj,
//! a violated invariant or a fast/old difference), an OOM over `-rss_limit_mb` or a hang over
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
