//! One shader body, every dialect and backend: GLSL 3.30 (core), GLSL ES 3.00, GLSL 1.20 (an
//! old GL 2.1 driver emulated by Mesa's overrides) and OSMesa give the same picture.
use crate::common;
use common::*;
use glview::image_out::RgbaFiles;

pub(crate) const ARGS: &[&str] = &[
    "--size",
    "400x300",
    "--yaw",
    "25",
    "--pitch",
    "20",
    "--shadow-size",
    "1024",
];

#[test]
fn dialects_and_backends_agree_on_the_builtin_scene() {
    let dir = out_dir("parity");
    let with = |extra: &[&'static str]| [ARGS, extra].concat();
    let core = render(
        &dir,
        "core",
        &with(&["--gl", "core", "--backend", "egl"]),
        &[],
    );
    let es3 = render(
        &dir,
        "es3",
        &with(&["--gl", "es3", "--backend", "egl"]),
        &[],
    );
    let gl21 = render(
        &dir,
        "gl21",
        &with(&["--gl", "2.1", "--backend", "egl"]),
        GL21,
    );
    let osmesa = render(
        &dir,
        "osmesa",
        &with(&["--gl", "2.1", "--backend", "osmesa"]),
        GL21,
    );
    let osmesa_core = render(
        &dir,
        "osmesa-core",
        &with(&["--gl", "core", "--backend", "osmesa"]),
        &[],
    );
    // Same rasteriser (llvmpipe), same formula: the dialects differ only in how the compiler
    // orders float operations, which can move a value across a rounding boundary. Allow
    // 1/255 on any pixel, nothing more.
    for (name, img) in [
        ("es3", &es3),
        ("gl21", &gl21),
        ("osmesa", &osmesa),
        ("osmesa-core", &osmesa_core),
    ] {
        assert_close(
            &dir,
            &format!("core-vs-{name}"),
            &core,
            img,
            0,
            usize::MAX,
            1,
        );
    }
}

#[test]
fn text_chunks_describe_the_render() {
    let dir = out_dir("parity-text");
    render(
        &dir,
        "t",
        &["--size", "64x48", "--gl", "es3", "--yaw", "10"],
        &[],
    );
    let text = glview::image_out::png_text(&dir.join("t.png")).unwrap();
    let get = |k: &str| {
        text.iter()
            .find(|(key, _)| key == k)
            .map(|(_, v)| v.clone())
            .unwrap_or_default()
    };
    assert!(get("glview.renderer").contains("llvmpipe"), "{text:?}");
    assert_eq!(get("glview.dialect"), "GLSL ES 3.00");
    assert!(get("glview.gl_version").starts_with("OpenGL ES"));
    assert!(get("glview.camera").contains("--yaw 10"));
    assert_eq!(get("glview.tier"), "legacy");
}

#[test]
fn output_has_exactly_the_requested_size() {
    let dir = out_dir("parity-size");
    for (w, h) in [(1u32, 1u32), (3, 5), (333, 77)] {
        let out = dir.join(format!("{w}x{h}.png"));
        let size = format!("{w}x{h}");
        let o = run(&["--output", out.to_str().unwrap(), "--size", &size], &[]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let img = glview::image_out::Rgba::load_png(&out).unwrap();
        assert_eq!((img.width, img.height), (w, h));
    }
}
