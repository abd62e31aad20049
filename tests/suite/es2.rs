//! OpenGL ES 2.0 / GLSL ES 1.00, the WebGL 1 path, drawn natively: `--gl es2` on Mesa's EGL
//! (an ES 3.2 context held to ES 2.0's rules, and with MESA_GLES_VERSION_OVERRIDE=2.0 an
//! honest ES 2.0 one) draws the legacy tier as GL 2.1 does — the same bodies, shadows
//! compared in the shader instead of by a shadow sampler — and the PBR tier as GL 2.1 draws
//! it (per-roughness cubes, RGBM8 maps).
use crate::common;
use common::*;
use glview::image_out::Rgba;

/// The parity test's picture (shadows, glass, the saucer's specular highlight), on EGL.
fn args() -> Vec<&'static str> {
    [super::parity::ARGS, &["--backend", "egl"]].concat()
}

/// An honest ES 2.0 context (GL_VERSION "OpenGL ES 2.0 Mesa", GLSL ES 1.0.16).
const ES2: &[(&str, &str)] = &[("MESA_GLES_VERSION_OVERRIDE", "2.0")];

/// Mean, 99th percentile and share over 8/255 of the per-pixel largest channel difference.
pub fn stats(a: &Rgba, b: &Rgba) -> (f64, u8, f64) {
    assert_eq!((a.width, a.height), (b.width, b.height));
    let mut d: Vec<u8> = a
        .data
        .chunks_exact(4)
        .zip(b.data.chunks_exact(4))
        .map(|(p, q)| (0..3).map(|i| p[i].abs_diff(q[i])).max().unwrap_or(0))
        .collect();
    let n = d.len().max(1) as f64;
    let mean = d.iter().map(|&v| f64::from(v)).sum::<f64>() / n;
    let over = d.iter().filter(|&&v| v > 8).count() as f64 / n;
    d.sort_unstable();
    let p99 = d[((d.len() as f64 * 0.99) as usize).min(d.len() - 1)];
    (mean, p99, over)
}

#[test]
fn es2_draws_the_legacy_tier_as_gl21_does() {
    let dir = out_dir("es2");
    let with = |gl: &'static str| [&args()[..], &["--gl", gl]].concat();
    let gl21 = render(&dir, "gl21", &with("2.1"), GL21);
    let held = render(&dir, "es2-held", &with("es2"), &[]);
    let honest = render(&dir, "es2", &with("es2"), ES2);
    let text = glview::image_out::png_text(&dir.join("es2.png")).unwrap();
    let get = |k: &str| {
        text.iter()
            .find(|(key, _)| key == k)
            .map(|(_, v)| v.clone())
            .unwrap_or_default()
    };
    assert_eq!(get("glview.dialect"), "GLSL ES 1.00", "{text:?}");
    assert!(
        get("glview.gl_version").starts_with("OpenGL ES 2.0"),
        "{text:?}"
    );
    // The held ES 3.2 context and the honest ES 2.0 one compile the same GLSL ES 1.00 on the
    // same rasteriser: the same picture.
    assert_close(&dir, "held-vs-honest", &held, &honest, 0, 0, 0);
    // Against GL 2.1 the formula and the rasteriser are the same; the shadow lookups differ:
    // GL 2.1's LINEAR comparing sampler weighs the four compared texels in llvmpipe's fixed
    // point, ES 2.0's shader weighs them in float (shadow.glsl, glviewShadowTap), which can
    // move a penumbra texel by a step. Measured (Mesa 22.3.6 llvmpipe): mean 0.0001, p99 0,
    // share > 8/255 0.0008 % (1 pixel of 120,000, max 10, on the shadow's edge). Held to
    // a bound a different llvmpipe can meet without hiding a wrong shadow (which moves
    // hundreds of pixels by tens of levels): mean < 0.02, p99 <= 1, at most 60 pixels
    // (0.05 %) over 8/255, none over 32/255.
    let (mean, p99, over) = stats(&gl21, &honest);
    eprintln!(
        "es2 vs gl21: mean {mean:.4}, p99 {p99}, share > 8/255 {:.4} %",
        over * 100.0
    );
    assert!(mean < 0.02 && p99 <= 1, "mean {mean}, p99 {p99}");
    assert_close(&dir, "gl21-vs-es2", &gl21, &honest, 8, 60, 32);
}

#[test]
fn es2_shadows_are_drawn_not_dropped() {
    // The shadow compared in the shader is a shadow: without it the saucer under the
    // holder is lit, and that is far from the picture with it.
    let dir = out_dir("es2-shadows");
    let on = render(&dir, "on", &[&args()[..], &["--gl", "es2"]].concat(), ES2);
    let off = render(
        &dir,
        "off",
        &[&args()[..], &["--gl", "es2", "--no-shadows"]].concat(),
        ES2,
    );
    let (mean, _, over) = stats(&on, &off);
    assert!(
        mean > 0.5 && over > 0.005,
        "shadows change too little: mean {mean}, share {over}"
    );
}

#[test]
fn es2_draws_the_pbr_tier_as_gl21_does() {
    // WebGL 1's PBR tier is GL 2.1's: no explicit-LOD lookups (one cube per roughness, mixed
    // in the shader), RGBM8 light maps and a byte-split BRDF table (no float textures), the
    // shadow compared in the shader. The same bodies on the same rasteriser: the built-in
    // scene (metal, glass, shadows) and a textured glTF (the Avocado: base colour, normal and
    // ORM maps) against the GL 2.1 override.
    let dir = out_dir("es2-pbr");
    let avocado = shared().join("gltf-samples/Avocado/Avocado.gltf");
    let scenes: [(&str, Vec<&str>); 2] = [
        ("builtin", vec![]),
        ("avocado", vec![avocado.to_str().unwrap()]),
    ];
    for (name, model) in scenes {
        let with =
            |gl: &'static str| [&model[..], &args(), &["--shading", "pbr", "--gl", gl]].concat();
        let gl21 = render(&dir, &format!("{name}-gl21"), &with("2.1"), GL21);
        let es2 = render(&dir, &format!("{name}-es2"), &with("es2"), ES2);
        let text = glview::image_out::png_text(&dir.join(format!("{name}-es2.png"))).unwrap();
        assert!(
            text.iter()
                .any(|(k, v)| k == "glview.dialect" && v == "GLSL ES 1.00"),
            "{text:?}"
        );
        // Measured (Mesa 22.3.6 llvmpipe): built-in mean 0.20, p99 1, none over 8/255;
        // Avocado mean 0.40, p99 2, 0.008 % over 8/255 (10 pixels), max 20: the shadow taps'
        // rounding as in the legacy tier, the RGBM maps' and the in-shader sRGB decode's
        // (the GL 2.1 override has float and sRGB textures, ES 2.0 neither). A wrong level,
        // a lost map or a lost shadow moves thousands of pixels by tens of levels.
        let (mean, p99, over) = stats(&gl21, &es2);
        eprintln!(
            "es2 pbr vs gl21 ({name}): mean {mean:.4}, p99 {p99}, share > 8/255 {:.4} %",
            over * 100.0
        );
        assert!(mean < 1.0 && p99 <= 3, "{name}: mean {mean}, p99 {p99}");
        assert_close(
            &dir,
            &format!("{name}-gl21-vs-es2"),
            &gl21,
            &es2,
            8,
            120,
            48,
        );
    }
}

#[test]
fn es2_point_light_atlas_as_gl21() {
    // A point light inside the model gets six faces in a 3x2 atlas whose depths crowd near 1.
    // ES 1.00's samplers default to lowp, which Mesa honours with half-float lookups (steps
    // of 2^-11 there): the saucer came out shadowed all over (2,849 pixels over 8/255 against
    // GL 2.1) until the ES 1.00 header made samplers highp. Measured since (Mesa 22.3.6
    // llvmpipe): mean 0.0006, 4 pixels over 8/255 (0.003 %), max 24, on the shadow's edges.
    let dir = out_dir("es2-point");
    let with = |gl: &'static str| [&args()[..], &["--light", "point:0,1.5,0", "--gl", gl]].concat();
    let gl21 = render(&dir, "gl21", &with("2.1"), GL21);
    let es2 = render(&dir, "es2", &with("es2"), ES2);
    let (mean, p99, over) = stats(&gl21, &es2);
    eprintln!(
        "es2 point atlas vs gl21: mean {mean:.4}, p99 {p99}, share > 8/255 {:.4} %",
        over * 100.0
    );
    assert!(mean < 0.02 && p99 <= 1, "mean {mean}, p99 {p99}");
    assert_close(&dir, "gl21-vs-es2", &gl21, &es2, 8, 60, 32);
}

/// ES 2.0 without OES_depth_texture (WebGL 1 without WEBGL_depth_texture). Mesa cannot hide
/// that one alone: disabling it turns off every extension Mesa always has (87 → 48 here),
/// EXT_frag_depth, OES_depth24 and OES_packed_depth_stencil among them, so this is an older
/// device still: 16-bit depth buffers and no written depth.
pub const ES2_NO_DEPTH_TEXTURES: &[(&str, &str)] = &[
    ("MESA_GLES_VERSION_OVERRIDE", "2.0"),
    ("MESA_EXTENSION_OVERRIDE", "-GL_OES_depth_texture"),
];

#[test]
fn es2_without_depth_textures_packs_depth_into_rgba8() {
    let o = run(
        &["--info", "--gl", "es2", "--backend", "egl"],
        ES2_NO_DEPTH_TEXTURES,
    );
    let info = String::from_utf8_lossy(&o.stdout);
    assert!(
        info.contains("depth textures: no")
            && info.contains("shadow maps: depth packed into RGBA8"),
        "{info}"
    );
    // The packed map holds the depth to about 2^-24, as a 24-bit depth texture: the same
    // shadows. Measured (Mesa 22.3.6 llvmpipe) against ES 2.0 with depth textures: the
    // directional key light 2 pixels over 8/255 (max 25), PBR 1 (max 40), a point light's
    // atlas 324 (0.27 %, max 226). The atlas's are a one-pixel ring where the holder stands
    // on the saucer: without EXT_frag_depth the map's depth test runs on the 16-bit buffer
    // with the rasteriser's offset, and the nearest caster there is not always a depth
    // texture's (with EXT_frag_depth, which WebGL 1 has, the shader writes the offset depth
    // it packs: test_viewer.py's WebGL 1 case, and equal to GL 2.1's atlas on llvmpipe). A
    // lost shadow moves over 900 pixels by more than 8/255 (the --no-shadows check below:
    // PBR's image-based light is not shadowed, so its key light's shadow moves least).
    let dir = out_dir("es2-packed");
    let cases: [(&str, &[&str], usize, u8); 3] = [
        ("directional", &[], 60, 64),
        ("pbr", &["--shading", "pbr"], 60, 64),
        ("point", &["--light", "point:0,1.5,0"], 720, 255),
    ];
    for (name, extra, max_over, hard_max) in cases {
        let with = |more: &[&'static str]| [&args()[..], &["--gl", "es2"], extra, more].concat();
        let depth = render(&dir, &format!("{name}-depth"), &with(&[]), ES2);
        let packed = render(
            &dir,
            &format!("{name}-packed"),
            &with(&[]),
            ES2_NO_DEPTH_TEXTURES,
        );
        let (mean, p99, over) = stats(&depth, &packed);
        eprintln!(
            "es2 packed vs depth textures ({name}): mean {mean:.4}, p99 {p99}, share > 8/255 {:.4} %",
            over * 100.0
        );
        assert!(mean < 0.6 && p99 <= 1, "{name}: mean {mean}, p99 {p99}");
        assert_close(
            &dir,
            &format!("{name}-depth-vs-packed"),
            &depth,
            &packed,
            8,
            max_over,
            hard_max,
        );
        let off = render(
            &dir,
            &format!("{name}-off"),
            &with(&["--no-shadows"]),
            ES2_NO_DEPTH_TEXTURES,
        );
        let (mean, _, over) = stats(&packed, &off);
        assert!(
            mean > 0.1 && over > 0.005,
            "{name}: packed shadows change too little: mean {mean}, share {over}"
        );
    }
}

#[test]
fn without_frag_depth_the_grid_is_refused_and_the_rest_compiles() {
    let png = out_dir("es2-no-frag-depth").join("grid.png");
    let o = run(
        &[
            "-o",
            png.to_str().unwrap(),
            "--grid",
            "--gl",
            "es2",
            "--backend",
            "egl",
        ],
        ES2_NO_DEPTH_TEXTURES,
    );
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success(), "{err}");
    assert!(
        err.lines()
            .any(|l| l.starts_with("error: --grid writes each fragment's depth")),
        "{err}"
    );
    let all = glview::render::programs::all_keys(glview::light::MAX_LIGHTS as u8).len();
    let o = run(
        &["--compile-shaders", "--gl", "es2", "--backend", "egl"],
        ES2_NO_DEPTH_TEXTURES,
    );
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    // "compiled and linked N programs … (M that write depth skipped: no EXT_frag_depth)"
    let words: Vec<&str> = out.split_whitespace().collect();
    let number = |i: usize| words[i].trim_start_matches('(').parse::<usize>().ok();
    let compiled = (1..words.len()).find(|&i| words[i - 1] == "linked");
    let skipped = (0..words.len().saturating_sub(1)).find(|&i| words[i + 1] == "that");
    let (compiled, skipped) = (
        compiled.and_then(number).unwrap_or_else(|| panic!("{out}")),
        skipped.and_then(number).unwrap_or_else(|| panic!("{out}")),
    );
    assert!(skipped > 0 && compiled + skipped == all, "{out}");
}

#[test]
fn every_permutation_compiles_in_glsl_es_100() {
    // Every program, the PBR tier's too.
    let expected = glview::render::programs::all_keys(glview::light::MAX_LIGHTS as u8).len();
    let o = run(
        &["--compile-shaders", "--gl", "es2", "--backend", "egl"],
        ES2,
    );
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(
        out.contains(&format!(
            "compiled and linked {expected} programs for GLSL ES 1.00 (OpenGL ES 2.0"
        )),
        "{out}"
    );
}
