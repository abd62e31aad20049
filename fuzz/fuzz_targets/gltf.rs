//! glTF JSON or GLB bytes (external URIs resolve into an empty folder) in → `glview::scene::load::load_bytes` → a scene that passes
//! `glview_fuzz::check_scene`, or a one-line error naming the file. A panic, an OOM over
//! `-rss_limit_mb` or a hang over `-timeout` is a finding (see fuzz/README.md).
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let _ = glview_fuzz::run_format(glview_fuzz::gltf_name(data), data);
});
