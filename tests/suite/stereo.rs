//! Stereo 3D (docs/stereo.md): each eye is a plain picture through an off-axis camera this
//! file spells out itself; every composed mode is exactly its eyes' pixels; the anaglyph is
//! its matrix applied to the eyes' display values; the convergence plane has no parallax;
//! and the nearest-layer globe's stencil mask survives row interlacing on every context.
use crate::common;
use common::*;
use glview::image_out::Rgba;
use std::path::Path;

const W: u32 = 320;
const H: u32 = 240;

/// The view every test but the globe's looks through: explicit, so the test can spell the
/// eyes out without the fitted defaults.
const VIEW: &[&str] = &[
    "--size",
    "320x240",
    "--yaw",
    "30",
    "--pitch",
    "25",
    "--distance",
    "0.5",
    "--fov",
    "45",
    "--shadow-size",
    "512",
];
const YAW: f64 = 30.0;
const PITCH: f64 = 25.0;
const TARGET: [f64; 3] = [0.0, 0.05, 0.0];
const DISTANCE: f64 = 0.5;
const FOV: f64 = 45.0;

/// The contexts every picture of glview is drawn on: GL 3.3 core, ES 3.0, GL 2.1 (an old
/// driver emulated), OSMesa, and OSMesa's GL 2.1 without framebuffer objects (the eyes then
/// go through the copy path).
/// A context: its name, glview's arguments for it and the environment (Mesa's overrides).
type Context = (
    &'static str,
    &'static [&'static str],
    &'static [(&'static str, &'static str)],
);

const CONTEXTS: &[Context] = &[
    ("core", &["--gl", "core", "--backend", "egl"], &[]),
    ("es3", &["--gl", "es3", "--backend", "egl"], &[]),
    ("gl21", &["--gl", "2.1", "--backend", "egl"], GL21),
    ("osmesa", &["--gl", "2.1", "--backend", "osmesa"], GL21),
    (
        "osmesa-no-fbo",
        &["--gl", "2.1", "--backend", "osmesa"],
        GL21_NO_FBO,
    ),
];

fn args<'a>(base: &[&'a str], extra: &[&'a str]) -> Vec<&'a str> {
    [base, extra].concat()
}

/// The eye's camera written out from the mono one: moved by ∓s along the right axis with
/// its target, the frustum's window shifted by s/(2·c·tan(fov/2)·aspect) of the width.
fn spelled_out(left: bool, separation: f64, convergence: f64, aspect: f64) -> Vec<String> {
    let (y, p) = (YAW.to_radians(), PITCH.to_radians());
    let dir = [p.cos() * y.sin(), p.sin(), p.cos() * y.cos()];
    let up = [-p.sin() * y.sin(), p.cos(), -p.sin() * y.cos()];
    // right = up × dir
    let right = [
        up[1] * dir[2] - up[2] * dir[1],
        up[2] * dir[0] - up[0] * dir[2],
        up[0] * dir[1] - up[1] * dir[0],
    ];
    let len = right.iter().map(|c| c * c).sum::<f64>().sqrt();
    let s = if left { -0.5 } else { 0.5 } * separation;
    let t: Vec<String> = (0..3)
        .map(|i| format!("{:.9}", TARGET[i] + s * right[i] / len))
        .collect();
    let shift = -s / (2.0 * convergence * (FOV.to_radians() * 0.5).tan() * aspect);
    vec![
        "--target".into(),
        t.join(","),
        "--lens-shift".into(),
        format!("{shift:.9}"),
    ]
}

fn owned(v: &[String]) -> Vec<&str> {
    v.iter().map(String::as_str).collect()
}

/// `--eye left` / `--eye right` equal plain pictures through the spelled-out cameras, on
/// every context; without `--eye-separation` and `--convergence` the eyes are the orbit
/// distance / 30 apart and converge at the orbit distance.
#[test]
fn eyes_are_plain_pictures_through_the_spelled_out_off_axis_cameras() {
    let dir = out_dir("stereo-eyes");
    let aspect = f64::from(W) / f64::from(H);
    for (name, ctx, env) in CONTEXTS {
        for (left, eye) in [(true, "left"), (false, "right")] {
            let base = args(VIEW, ctx);
            let centred = args(&base, &["--target", "0,0.05,0"]);
            let stereo = render(
                &dir,
                &format!("{name}-{eye}"),
                &args(
                    &centred,
                    &[
                        "--eye",
                        eye,
                        "--eye-separation",
                        "0.04",
                        "--convergence",
                        "0.6",
                    ],
                ),
                env,
            );
            let spelled = spelled_out(left, 0.04, 0.6, aspect);
            let plain = render(
                &dir,
                &format!("{name}-{eye}-plain"),
                &args(&base, &owned(&spelled)),
                env,
            );
            // Same camera, the target moved in f32 by the renderer and in f64 here: equal.
            assert_close(&dir, &format!("{name}-{eye}"), &plain, &stereo, 0, 0, 0);
            if *name == "core" {
                // The default separation, rounded to f32 as glview holds it.
                let sep = f64::from(DISTANCE as f32 / 30.0);
                let spelled = spelled_out(left, sep, DISTANCE, aspect);
                let defaults = render(
                    &dir,
                    &format!("{name}-{eye}-defaults"),
                    &args(&centred, &["--eye", eye]),
                    env,
                );
                let plain = render(
                    &dir,
                    &format!("{name}-{eye}-defaults-plain"),
                    &args(&base, &owned(&spelled)),
                    env,
                );
                assert_close(&dir, &format!("{eye}-defaults"), &plain, &defaults, 0, 0, 0);
                let mono = render(&dir, "mono", &centred, env);
                assert!(
                    diff(&mono, &defaults, 0).over > 0,
                    "the eye is the mono view"
                );
            }
        }
    }
}

fn pixel(img: &Rgba, x: u32, y: u32) -> &[u8] {
    let i = ((y * img.width + x) * 4) as usize;
    &img.data[i..i + 4]
}

/// The composed picture of `mode` rebuilt from its eye pictures (top-left origin, file
/// pixels): the test's own layout, independent of the shader.
fn rebuilt(mode: &str, l: &Rgba, r: &Rgba, w: u32, h: u32) -> Rgba {
    let mut data = Vec::with_capacity((w * h * 4) as usize);
    for y in 0..h {
        for x in 0..w {
            let p = match mode {
                "side-by-side" | "side-by-side-full" => {
                    let half = w / 2;
                    if x < half {
                        pixel(l, x, y)
                    } else {
                        pixel(r, x - half, y)
                    }
                }
                "over-under" => {
                    let half = h / 2;
                    if y < half {
                        pixel(l, x, y)
                    } else {
                        pixel(r, x, y - half)
                    }
                }
                "rows" if y % 2 == 0 => pixel(l, x, y),
                "columns" if x % 2 == 0 => pixel(l, x, y),
                "checkerboard" if (x + y) % 2 == 0 => pixel(l, x, y),
                _ => pixel(r, x, y),
            };
            data.extend_from_slice(p);
        }
    }
    Rgba {
        width: w,
        height: h,
        data,
    }
}

/// Every composed mode is exactly its eyes (each `--eye` picture at its size in the mode:
/// the squeezed forms' eyes at half the width or height), byte for byte; `--swap-eyes`
/// swaps them.
#[test]
fn composed_modes_are_exactly_their_eyes() {
    let dir = out_dir("stereo-modes");
    for mode in [
        "side-by-side",
        "side-by-side-full",
        "over-under",
        "rows",
        "columns",
        "checkerboard",
    ] {
        let base = args(VIEW, &["--target", "0,0.05,0", "--stereo", mode]);
        let left = render(
            &dir,
            &format!("{mode}-left"),
            &args(&base, &["--eye", "left"]),
            &[],
        );
        let right = render(
            &dir,
            &format!("{mode}-right"),
            &args(&base, &["--eye", "right"]),
            &[],
        );
        // The squeezed forms' eyes are drawn at the squeezed size.
        let eye_size = match mode {
            "side-by-side" => (W / 2, H),
            "over-under" => (W, H / 2),
            _ => (W, H),
        };
        assert_eq!(
            (left.width, left.height),
            eye_size,
            "{mode}: the eye's size"
        );
        let composed = render(&dir, mode, &base, &[]);
        let (w, h) = (composed.width, composed.height);
        let want = if mode == "side-by-side-full" {
            (2 * W, H)
        } else {
            (W, H)
        };
        assert_eq!((w, h), want, "{mode}: the composed picture's size");
        let expected = rebuilt(mode, &left, &right, w, h);
        assert_close(&dir, mode, &expected, &composed, 0, 0, 0);
        assert!(diff(&left, &right, 0).over > 0, "{mode}: the eyes differ");
        let swapped = render(
            &dir,
            &format!("{mode}-swapped"),
            &args(&base, &["--swap-eyes"]),
            &[],
        );
        let expected = rebuilt(mode, &right, &left, w, h);
        assert_close(
            &dir,
            &format!("{mode}-swapped"),
            &expected,
            &swapped,
            0,
            0,
            0,
        );
    }
}

/// Each anaglyph pixel is the method's matrices applied to the eyes' display values and
/// clamped, to 1/255 (the shader's float rounding); Dubois's red-cyan matrices are the
/// values three.js's AnaglyphEffect uses.
#[test]
fn anaglyphs_are_their_matrices_on_display_values() {
    let dir = out_dir("stereo-anaglyph");
    let base = args(VIEW, &["--target", "0,0.05,0", "--stereo", "anaglyph"]);
    let left = render(&dir, "left", &args(&base, &["--eye", "left"]), &[]);
    let right = render(&dir, "right", &args(&base, &["--eye", "right"]), &[]);
    use glview::stereo::{anaglyph_matrices, AnaglyphMethod, Glasses};
    let (l, r) = anaglyph_matrices(AnaglyphMethod::Dubois, Glasses::RedCyan);
    // three.js's colorMatrixLeft/Right (column-major there, row = output channel here).
    assert!((l.x_axis.x - 0.456_100).abs() < 1e-6 && (l.y_axis.x - 0.500_484).abs() < 1e-6);
    assert!((r.y_axis.y - 0.733_64).abs() < 1e-6 && (r.z_axis.z - 1.2264).abs() < 1e-6);
    for (method, m) in AnaglyphMethod::ALL.iter().map(|(m, w, _)| (*m, *w)) {
        for (glasses, g) in Glasses::ALL.iter().map(|(g, w, _)| (*g, *w)) {
            let name = format!("{m}-{g}");
            let img = render(
                &dir,
                &name,
                &args(&base, &["--anaglyph", m, "--glasses", g]),
                &[],
            );
            let (ml, mr) = anaglyph_matrices(method, glasses);
            let mut worst = 0.0f32;
            for i in 0..(W * H) as usize {
                let at = |img: &Rgba| {
                    let p = &img.data[i * 4..i * 4 + 3];
                    glam::Vec3::new(p[0] as f32, p[1] as f32, p[2] as f32) / 255.0
                };
                let want =
                    (ml * at(&left) + mr * at(&right)).clamp(glam::Vec3::ZERO, glam::Vec3::ONE);
                let got = at(&img);
                worst = worst.max((want - got).abs().max_element());
            }
            assert!(
                worst <= 1.0 / 255.0 + 1e-6,
                "{name}: a pixel is {:.2}/255 from the matrices",
                worst * 255.0
            );
        }
    }
}

/// A model of three small squares facing the camera at depths `zs` along its axis (yaw 0,
/// pitch 0: the view looks down −Z at the origin from +Z at `DIST`).
fn squares(dir: &Path, name: &str, z: f64) -> String {
    let a = 0.02 * z;
    let wz = DIST - z;
    let obj = format!(
        "v {} {} {wz}\nv {a} {} {wz}\nv {a} {a} {wz}\nv {} {a} {wz}\nf 1 2 3 4\n\
         v -3 -3 -3\nv -2.99 -3 -3\nv -3 -2.99 -3\nf 5 6 7\n",
        -a, -a, -a, -a
    );
    let p = dir.join(format!("{name}.obj"));
    std::fs::write(&p, obj).unwrap();
    p.to_str().unwrap().to_string()
}

const DIST: f64 = 4.0;

/// The centroid's column (file pixels) of the square's pixels.
fn centroid_x(img: &Rgba) -> f64 {
    let (mut sum, mut n) = (0.0, 0.0);
    for y in 0..img.height {
        for x in 0..img.width {
            // The square is grey 0.2 (ambient 1 × the default Ka), the background blue.
            if pixel(img, x, y)[0] > 32 {
                sum += f64::from(x) + 0.5;
                n += 1.0;
            }
        }
    }
    assert!(n > 0.0, "the square is in the picture");
    sum / n
}

/// Zero parallax at the convergence distance: a square there lands on the same pixels in
/// both eyes; squares nearer and farther shift in opposite directions by the frustum
/// formula's ±(s/(t·a))·(1/z − 1/c) (in NDC; × W/2 in pixels), to half a pixel: the
/// square's edges snap to pixel centres, so its centroid moves in whole pixels.
#[test]
fn parallax_is_zero_on_the_screen_plane_and_follows_the_frustum() {
    let dir = out_dir("stereo-parallax");
    let (sep, conv) = (0.2, DIST);
    let t = (FOV.to_radians() * 0.5).tan();
    let aspect = f64::from(W) / f64::from(H);
    for z in [2.0, 3.0, DIST, 6.0, 9.0] {
        let model = squares(&dir, &format!("z{z}"), z);
        let view = [
            model.as_str(),
            "--size",
            "320x240",
            "--yaw",
            "0",
            "--pitch",
            "0",
            "--target",
            "0,0,0",
            "--distance",
            "4",
            "--fov",
            "45",
            "--light",
            "none",
            "--ambient",
            "1,1,1",
            "--background",
            "0.05,0.05,0.3",
            "--no-shadows",
            "--eye-separation",
            "0.2",
            "--convergence",
            "4",
        ];
        let l = render(
            &dir,
            &format!("z{z}-left"),
            &args(&view, &["--eye", "left"]),
            &[],
        );
        let r = render(
            &dir,
            &format!("z{z}-right"),
            &args(&view, &["--eye", "right"]),
            &[],
        );
        let (xl, xr) = (
            centroid_x(&l) - f64::from(W) / 2.0,
            centroid_x(&r) - f64::from(W) / 2.0,
        );
        let want = (sep * 0.5 / (t * aspect)) * (1.0 / z - 1.0 / conv) * f64::from(W) / 2.0;
        eprintln!("z {z}: left {xl:+.3} px, right {xr:+.3} px, formula ±{want:.3}");
        assert!((xl - want).abs() <= 0.5, "z {z}: left {xl}, formula {want}");
        assert!(
            (xr + want).abs() <= 0.5,
            "z {z}: right {xr}, formula {}",
            -want
        );
        if z == DIST {
            assert_close(&dir, "screen-plane", &l, &r, 0, 0, 0);
        }
    }
}

/// The thesis's conflict: the nearest-layer translucent globe, its background masked by
/// the stencil, in `rows` equals each eye's masked picture on its rows, byte for byte, on
/// every context (the eyes keep their own stencil; the composite uses none).
#[test]
fn the_masked_globe_survives_row_interlacing_on_every_context() {
    let dir = out_dir("stereo-globe");
    let globe = super::translucency::shells(&dir, "globe", &|f| f);
    let view = [
        globe.as_str(),
        "--size",
        "160x120",
        "--yaw",
        "20",
        "--pitch",
        "15",
        "--translucency",
        "nearest-masked",
        "--background",
        "0.2,0.8,0.3",
        "--stereo",
        "rows",
    ];
    for (name, ctx, env) in CONTEXTS {
        let base = args(&view, ctx);
        let left = render(
            &dir,
            &format!("{name}-left"),
            &args(&base, &["--eye", "left"]),
            env,
        );
        let right = render(
            &dir,
            &format!("{name}-right"),
            &args(&base, &["--eye", "right"]),
            env,
        );
        let rows = render(&dir, &format!("{name}-rows"), &base, env);
        let expected = rebuilt("rows", &left, &right, rows.width, rows.height);
        assert_close(&dir, &format!("{name}-rows"), &expected, &rows, 0, 0, 0);
        // The mask held: the eye shows glass over black inside the globe, not the green
        // background (the plain nearest mode lets it through).
        let centre = pixel(&left, 80, 60);
        assert!(
            centre[1] < 200,
            "{name}: the globe's centre shows the background"
        );
    }
}

/// What stereo refuses, in one line naming the option: orthographic views (no parallax),
/// quad buffers in a picture, multisampling, interlacing under SSAA, odd halves.
#[test]
fn stereo_refusals_are_one_line_errors() {
    for (extra, says) in [
        (&["--stereo", "anaglyph", "--ortho"][..], "perspective"),
        (&["--eye", "left", "--ortho"][..], "perspective"),
        (&["--stereo", "quad-buffer"][..], "GL_STEREO"),
        (&["--stereo", "rows", "--aa", "msaa"][..], "single-sampled"),
        (&["--stereo", "rows", "--aa", "ssaa"][..], "interlaced"),
        (
            &["--stereo", "side-by-side", "--size", "321x240"][..],
            "odd width",
        ),
        (
            &["--stereo", "over-under", "--size", "320x241"][..],
            "odd height",
        ),
        (&["--stereo", "sideways"][..], "possible values"),
    ] {
        let out = std::env::temp_dir().join("glview-stereo-refused.png");
        let mut a = vec!["-o", out.to_str().unwrap()];
        a.extend_from_slice(extra);
        let o = run(&a, &[]);
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success(), "{extra:?} was drawn");
        assert!(err.contains(says), "{extra:?}: {err}");
        // clap's own usage errors add its usage lines; glview's are one line.
        if !says.contains("possible") {
            assert_eq!(err.trim().lines().count(), 1, "{extra:?}: {err}");
        }
    }
}
