//! Every shader permutation compiles and links in every dialect the machine offers: GLSL 3.30
//! (core), GLSL ES 3.00, GLSL 1.20 (Mesa emulating a GL 2.1 driver) and GLSL 1.20 on OSMesa
//! without framebuffer or vertex-array objects. A broken shader reports the driver's log and
//! the numbered source.
use crate::common;
use common::*;

#[test]
fn every_permutation_compiles_in_every_dialect() {
    let expected = glview::render::programs::all_keys(glview::light::MAX_LIGHTS as u8).len();
    for (name, args, env) in [
        (
            "GLSL 3.30",
            vec!["--gl", "core", "--backend", "egl"],
            &[][..],
        ),
        (
            "GLSL ES 3.00",
            vec!["--gl", "es3", "--backend", "egl"],
            &[][..],
        ),
        ("GLSL 1.20", vec!["--gl", "2.1", "--backend", "egl"], GL21),
        (
            "GLSL 1.20",
            vec!["--gl", "2.1", "--backend", "osmesa"],
            GL21_NO_FBO,
        ),
    ] {
        let mut a = vec!["--compile-shaders"];
        a.extend_from_slice(&args);
        let o = run(&a, env);
        let out = String::from_utf8_lossy(&o.stdout);
        assert!(
            o.status.success(),
            "{args:?}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
        assert!(
            out.contains(&format!(
                "compiled and linked {expected} programs for {name}"
            )),
            "{args:?}: {out}"
        );
        eprint!("{out}");
    }
}

#[test]
fn a_broken_shader_shows_the_log_and_numbered_source() {
    use glview::headless::Headless;
    use glview::platform::{Backend, GlRequest};
    let hl = Headless::new(Backend::Egl, GlRequest::Core, 8, 8).expect("EGL context");
    let vs = "#version 330 core\nin vec3 aPosition;\nvoid main() { gl_Position = vec4(aPosition, 1.0); }\n";
    let fs = "#version 330 core\nout vec4 c;\nvoid main() {\n    c = vec4(undefined_thing);\n}\n";
    let before = hl.gpu.live_objects();
    let err = match glview::gpu::program::Program::new(&hl.gpu, "broken", vs, fs) {
        Ok(_) => panic!("a broken shader linked"),
        Err(e) => e.to_string(),
    };
    assert!(
        err.contains("shader broken (GLSL 3.30) failed to compile the fragment shader"),
        "{err}"
    );
    assert!(err.contains("undefined_thing"), "no driver log: {err}");
    assert!(
        err.contains("   4     c = vec4(undefined_thing);"),
        "no numbered source: {err}"
    );
    assert_eq!(
        hl.gpu.live_objects(),
        before,
        "a failed compile leaked objects"
    );
}
