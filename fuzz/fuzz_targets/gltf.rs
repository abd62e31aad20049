//! glTF JSON or GLB bytes (external URIs resolve into an empty folder) in → `glview::scene::load::load_bytes` → a scene that passes
//! `glview_fuzz::check_scene`, or a one-line error naming the file. A panic, an OOM over
//! `-rss_limit_mb` or a hang over `-timeout` is a finding (see fuzz/README.md).
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Ok(mut scene) = glview_fuzz::run_format(glview_fuzz::gltf_name(data), data) else {
        return;
    };
    // Every animation posed at two moments (its middle and past its end), then the static
    // pose again: a pose is an error naming the file, or a scene that keeps the invariants.
    for animation in 0..scene.animations().len().min(4) {
        let d = scene.animations()[animation].duration;
        for seconds in [d * 0.5, d + 1.0] {
            let moment = glview::scene::motion::Moment { animation, seconds };
            glview_fuzz::check_pose(&mut scene, Some(moment));
        }
    }
    glview_fuzz::check_pose(&mut scene, None);
});
