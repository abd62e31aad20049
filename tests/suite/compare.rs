//! Comparisons: side-by-side panes are the separate renders, a difference with itself is
//! zero, stored-picture regression passes and fails as it should, contact sheets have their
//! grid, and the PBR terms switch off to the emissive-only picture.
use crate::common;
use common::*;
use glview::image_out::Rgba;
use glview::image_out::RgbaFiles;

const STRIP: u32 = glview::compare::canvas::STRIP;

fn crop(img: &Rgba, x0: u32, y0: u32, w: u32, h: u32) -> Rgba {
    let mut data = Vec::new();
    for y in y0..y0 + h {
        let s = ((y * img.width + x0) * 4) as usize;
        data.extend_from_slice(&img.data[s..s + (w * 4) as usize]);
    }
    Rgba {
        width: w,
        height: h,
        data,
    }
}

#[test]
fn panes_equal_separate_renders() {
    let dir = out_dir("compare-panes");
    let out = dir.join("cmp.png");
    let o = run(
        &[
            "--compare",
            "phong,pbr,reference",
            "--size",
            "96x72",
            "-o",
            out.to_str().unwrap(),
        ],
        &[],
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let cmp = Rgba::load_png(&out).unwrap();
    // One label size: the labels wrap onto as many lines as the longest needs, in every pane.
    let (settings, _) = settings_for(&["--size", "96x72"]);
    let labels: Vec<String> = glview::compare::parse_tiers("phong,pbr,reference", "t")
        .unwrap()
        .into_iter()
        .map(|t| glview::compare::label(t, &settings))
        .collect();
    assert!(
        labels[0].contains("3 lights"),
        "the default kit: {labels:?}"
    );
    let labels: Vec<&str> = labels.iter().map(String::as_str).collect();
    let strip = glview::compare::canvas::strip_height(96, &labels);
    assert!(strip > STRIP, "96-pixel panes wrap these labels");
    assert_eq!((cmp.width, cmp.height), (3 * 96, 72 + strip));
    for (i, (name, args)) in [
        ("phong", vec!["--shading", "phong"]),
        ("pbr", vec!["--shading", "pbr"]),
    ]
    .into_iter()
    .enumerate()
    {
        let mut a = vec!["--size", "96x72"];
        a.extend(args);
        let alone = render(&dir, name, &a, &[]);
        let pane = crop(&cmp, i as u32 * 96, strip, 96, 72);
        // The viewport's offset changes the float rounding of window coordinates: a varying
        // may land one 8-bit step apart on a handful of pixels (measured: 1 pixel by 1/255).
        assert_close(&dir, &format!("pane-{name}"), &pane, &alone, 0, 7, 1);
    }
    let reference = dir.join("reference.png");
    let o = run(
        &[
            "--reference",
            "--size",
            "96x72",
            "-o",
            reference.to_str().unwrap(),
        ],
        &[],
    );
    assert!(o.status.success());
    let pane = crop(&cmp, 2 * 96, strip, 96, 72);
    assert_close(
        &dir,
        "pane-reference",
        &pane,
        &Rgba::load_png(&reference).unwrap(),
        0,
        0,
        0,
    );
}

#[test]
fn a_difference_with_itself_is_zero() {
    let dir = out_dir("compare-diff");
    let out = dir.join("d.png");
    let o = run(
        &[
            "--diff",
            "phong,phong",
            "--size",
            "64x48",
            "-o",
            out.to_str().unwrap(),
        ],
        &[],
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("d.json")).unwrap()).unwrap();
    for k in ["mean", "max", "p99", "over_8", "one_minus_ssim"] {
        assert_eq!(json["numbers"][k].as_f64(), Some(0.0), "{k}: {json}");
    }
    let d = Rgba::load_png(&out).unwrap();
    assert!(crop(&d, 0, 0, 64, 48)
        .data
        .chunks_exact(4)
        .all(|p| p[..3] == [0, 0, 0]));
    assert!(dir.join("d-phong.png").exists());
    // Phong against PBR differs, and says by how much.
    let o = run(
        &[
            "--diff",
            "phong,pbr",
            "--size",
            "64x48",
            "-o",
            out.to_str().unwrap(),
        ],
        &[],
    );
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success() && text.contains("1 - SSIM"), "{text}");
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("d.json")).unwrap()).unwrap();
    assert!(json["numbers"]["mean"].as_f64().unwrap() > 1.0);
}

#[test]
fn stored_picture_regression() {
    let dir = out_dir("compare-stored");
    let stored = dir.join("stored.png");
    let _ = std::fs::remove_file(&stored);
    let args = |extra: &[&str]| {
        let mut a = vec![
            "--size",
            "64x48",
            "--diff-against",
            stored.to_str().unwrap(),
        ];
        a.extend_from_slice(extra);
        a.iter().map(|s| s.to_string()).collect::<Vec<_>>()
    };
    let go = |extra: &[&str]| {
        let a = args(extra);
        run(&a.iter().map(String::as_str).collect::<Vec<_>>(), &[])
    };
    let first = go(&[]);
    let err = String::from_utf8_lossy(&first.stderr);
    assert!(
        !first.status.success() && err.contains("no stored picture"),
        "{err}"
    );
    assert!(
        stored.exists(),
        "the render was not written as the stored picture"
    );
    let same = go(&[]);
    assert!(
        same.status.success(),
        "{}",
        String::from_utf8_lossy(&same.stderr)
    );
    let changed = go(&["--yaw", "80"]);
    let err = String::from_utf8_lossy(&changed.stderr);
    assert!(
        !changed.status.success() && err.contains("differs"),
        "{err}"
    );
    assert!(dir.join("stored-render.png").exists() && dir.join("stored-render-diff.png").exists());
}

#[test]
fn contact_sheet_grid() {
    let dir = out_dir("compare-sheet");
    let out = dir.join("sheet.png");
    let o = run(
        &[
            "sheet",
            "--views",
            "3",
            "--tiers",
            "phong,pbr",
            "--size",
            "80x60",
            "-o",
            out.to_str().unwrap(),
        ],
        &[],
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let s = Rgba::load_png(&out).unwrap();
    // Two rows of cells, each a label strip of whole 18-pixel lines over a 60-pixel render.
    let strip = s.height / 2 - 60;
    assert_eq!((s.width, s.height % 2, (strip - 2) % 18), (3 * 80, 0, 0));
    assert!(strip >= STRIP);
    // Each cell is a render: the cells differ from each other (views and tiers).
    let cell = |c: u32, r: u32| crop(&s, c * 80, r * (60 + strip) + strip, 80, 60);
    assert!(diff(&cell(0, 0), &cell(1, 0), 8).over > 50);
    assert!(diff(&cell(0, 0), &cell(0, 1), 8).over > 50);
    // The same cell as a separate render with the sheet's first angle.
    let alone = render(&dir, "alone", &["--size", "80x60", "--yaw", "0"], &[]);
    assert_close(&dir, "sheet-cell", &cell(0, 0), &alone, 0, 0, 0);
}

/// With every lighting term of the PBR tier off (`--terms emissive`), only emissive light
/// remains: exactly sRGB(Ke) with no tone mapping; with `none` even that goes.
#[test]
fn all_terms_off_leaves_the_emissive_image() {
    let dir = out_dir("compare-terms");
    std::fs::write(
        dir.join("e.mtl"),
        "newmtl e\nKd 0.8 0.8 0.8\nKe 0.5 0.25 0\n",
    )
    .unwrap();
    std::fs::write(
        dir.join("e.obj"),
        "mtllib e.mtl\nusemtl e\nv -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nf 1 2 3\nf 1 3 4\n",
    )
    .unwrap();
    let out = dir.join("e.png");
    let o = run(
        &[
            dir.join("e.obj").to_str().unwrap(),
            "--shading",
            "pbr",
            "--terms",
            "emissive",
            "--tonemap",
            "none",
            "--yaw",
            "0",
            "--pitch",
            "0",
            "--size",
            "32x32",
            "-o",
            out.to_str().unwrap(),
        ],
        &[],
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let img = Rgba::load_png(&out).unwrap();
    assert_eq!(img.pixel(16, 16)[..3], [188, 137, 0]);
}

/// Every teaching view is a picture (not blank, no NaN-black where a surface is) on every
/// path; the point-light atlas is no longer a white page; the reference refuses views.
#[test]
fn teaching_views_on_every_path() {
    let dir = out_dir("compare-views");
    let quad = models().join("textured_quad.obj");
    for (path, gl, vars) in [
        ("core", &["--gl", "core", "--backend", "egl"][..], &[][..]),
        ("es3", &["--gl", "es3", "--backend", "egl"][..], &[][..]),
        ("gl21", &["--gl", "2.1", "--backend", "egl"][..], GL21),
        (
            "gl21-osmesa",
            &["--gl", "2.1", "--backend", "osmesa"][..],
            GL21_NO_FBO,
        ),
    ] {
        for view in ["normals", "uvs", "roughness", "metallic"] {
            let mut a = vec![
                quad.to_str().unwrap(),
                "--size",
                "64x48",
                "--show",
                view,
                "--pitch",
                "10",
                "--metallic",
                "0.5",
            ];
            a.extend_from_slice(gl);
            render(&dir, &format!("{view}-{path}"), &a, vars);
        }
        let mut a = vec![
            "--size",
            "96x64",
            "--show",
            "shadow-map",
            "--light",
            "point:0,0.5,0",
        ];
        a.extend_from_slice(gl);
        let atlas = render(&dir, &format!("atlas-{path}"), &a, vars);
        let (lo, hi) = atlas
            .data
            .chunks_exact(4)
            .fold((255u8, 0u8), |(lo, hi), p| (lo.min(p[0]), hi.max(p[0])));
        assert!(
            hi - lo > 100,
            "{path}: the point-light atlas spans only {lo}..{hi}"
        );
    }
    // The map views are composed on the CPU from the precomputed data: one run covers every
    // path.
    for view in ["irradiance", "specular", "lut"] {
        render(&dir, view, &["--show", view, "--show-level", "2"], &[]);
    }
    let o = run(
        &[
            "--reference",
            "--show",
            "normals",
            "-o",
            dir.join("r.png").to_str().unwrap(),
        ],
        &[],
    );
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        !o.status.success() && err.contains("reference renderer draws only the scene"),
        "{err}"
    );
}

/// `--diff phong,pbr` on a model: the two tiers draw different backgrounds, so the whole
/// picture differs almost everywhere; the model numbers cover exactly the pixels either tier's
/// model covers (the union of their transparent renders' alpha), the difference picture is 0
/// everywhere else, and a tier against itself is zero there too.
#[test]
fn diff_reports_the_models_pixels() {
    let dir = out_dir("compare-diff-model");
    let duck = shared().join("gltf-samples/Duck/Duck.glb");
    let duck = duck.to_str().unwrap();
    let out = dir.join("d.png");
    let diff = |tiers: &str| {
        let o = run(
            &[
                duck,
                "--diff",
                tiers,
                "--size",
                "96x72",
                "-o",
                out.to_str().unwrap(),
            ],
            &[],
        );
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let text = std::fs::read_to_string(dir.join("d.json")).unwrap();
        serde_json::from_str::<serde_json::Value>(&text).unwrap()
    };
    let json = diff("phong,pbr");
    let mut union = vec![false; 96 * 72];
    for shading in ["phong", "pbr"] {
        let t = dir.join(format!("{shading}-alpha.png"));
        let o = run(
            &[
                duck,
                "--shading",
                shading,
                "--transparent",
                "--size",
                "96x72",
                "-o",
                t.to_str().unwrap(),
            ],
            &[],
        );
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let img = Rgba::load_png(&t).unwrap();
        for (u, p) in union.iter_mut().zip(img.data.chunks_exact(4)) {
            *u |= p[3] > 0;
        }
    }
    let covered = union.iter().filter(|&&c| c).count() as u64;
    assert!(covered > 500 && covered < 96 * 72 / 2, "{covered}");
    assert_eq!(json["model_pixels"].as_u64(), Some(covered), "{json}");
    // The difference picture shows the model only: every background pixel is 0.
    let d = Rgba::load_png(&out).unwrap();
    let background = crop(&d, 0, 0, 96, 72)
        .data
        .chunks_exact(4)
        .zip(&union)
        .filter(|(p, &u)| !u && p[..3] != [0, 0, 0])
        .count();
    assert_eq!(background, 0, "background pixels drawn into the difference");
    let n = |part: &str, k: &str| json[part][k].as_f64().unwrap();
    assert!(
        n("numbers", "over_8") > 0.9,
        "the backgrounds differ: {json}"
    );
    // A subset's worst pixel is no worse than the whole picture's.
    assert!(n("model", "max") <= n("numbers", "max"), "{json}");
    assert!(
        n("model", "mean") > 1.0,
        "the tiers shade differently: {json}"
    );
    let json = diff("pbr,pbr");
    for k in ["mean", "max", "p99", "over_8", "one_minus_ssim"] {
        assert_eq!(json["model"][k].as_f64(), Some(0.0), "{k}: {json}");
    }
}

/// The window's split view (`C`) frames each half for its own aspect: in a 4:3 window each
/// half is portrait, and the whole window's framing cut the model off at the halves' sides.
/// Each pane's model coverage (alpha of a transparent frame) must lie inside the pane, and
/// the old framing must not (so this test sees the difference).
#[test]
fn split_view_panes_frame_the_model() {
    use glview::headless::Headless;
    use glview::platform::{Backend, GlRequest};
    use glview::render::Renderer;
    let duck = shared().join("gltf-samples/Duck/Duck.glb");
    let (w, h) = (240u32, 180u32);
    let size = format!("{w}x{h}");
    let (mut settings, scene) = settings_for(&[duck.to_str().unwrap(), "--size", &size]);
    settings.lighting.post.transparent = true;
    let hl = Headless::new(Backend::Egl, GlRequest::Core, w, h).expect("EGL context");
    let mut renderer = Renderer::new(&hl.gpu, scene).unwrap();
    // Columns and rows the model covers in pane `i` (x relative to the pane).
    let extent = |img: &Rgba, i: u32| {
        let half = w / 2;
        let (mut x0, mut x1, mut y0, mut y1) = (u32::MAX, 0, u32::MAX, 0);
        for y in 0..h {
            for x in 0..half {
                if img.pixel(i * half + x, y)[3] > 0 {
                    (x0, x1, y0, y1) = (x0.min(x), x1.max(x), y0.min(y), y1.max(y));
                }
            }
        }
        assert!(x0 <= x1, "pane {i} is empty");
        (x0, x1, y0, y1)
    };
    glview::compare::split::draw(&mut renderer, &settings, &hl.target(), w, h).unwrap();
    let framed = hl.read();
    let dir = out_dir("compare-split");
    framed.save_png(&dir.join("framed.png"), &[]).unwrap();
    for i in 0..2 {
        let (x0, x1, y0, y1) = extent(&framed, i);
        assert!(
            x0 > 0 && x1 < w / 2 - 1 && y0 > 0 && y1 < h - 1,
            "pane {i}: the model spans x {x0}..{x1}, y {y0}..{y1} of {}x{h}",
            w / 2
        );
    }
    // The whole window's framing in each half: the duck touches the sides.
    for (i, shading) in glview::compare::split::TIERS.into_iter().enumerate() {
        let s = glview::render::FrameSettings {
            shading,
            ..settings.clone()
        };
        let vp = [i as u32 * w / 2, 0, w / 2, h];
        renderer.render_viewport(&s, &hl.target(), vp).unwrap();
    }
    let cut = hl.read();
    cut.save_png(&dir.join("whole-window-framing.png"), &[])
        .unwrap();
    let (x0, x1, _, _) = extent(&cut, 0);
    assert!(
        x0 == 0 || x1 == w / 2 - 1,
        "the old framing was not cut off"
    );
}

/// `--compare` in stereo: each pane is its tier's stereo picture (anaglyph here; the eyes
/// are drawn into targets of their own, so only the composite's viewport offset can move a
/// value by one step, as for mono panes).
#[test]
fn stereo_panes_equal_the_stereo_pictures() {
    let dir = out_dir("compare-stereo");
    let out = dir.join("cmp.png");
    let base = ["--size", "96x72", "--stereo", "anaglyph"];
    let mut args = vec!["--compare", "phong,pbr", "-o", out.to_str().unwrap()];
    args.extend_from_slice(&base);
    let o = run(&args, &[]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let cmp = Rgba::load_png(&out).unwrap();
    let strip = cmp.height - 72;
    for (i, tier) in ["phong", "pbr"].into_iter().enumerate() {
        let mut a = base.to_vec();
        a.extend(["--shading", tier]);
        let alone = render(&dir, tier, &a, &[]);
        let pane = crop(&cmp, i as u32 * 96, strip, 96, 72);
        assert_close(&dir, &format!("pane-{tier}"), &pane, &alone, 0, 7, 1);
        let mono = render(
            &dir,
            &format!("{tier}-mono"),
            &["--size", "96x72", "--shading", tier],
            &[],
        );
        assert!(
            diff(&pane, &mono, 8).over > 20,
            "{tier}: the pane is in stereo"
        );
    }
}
