//! The library API (`glview::api`): its pictures are the command line's, its depth is the
//! exact sphere's, its ids cover exactly the drawn pixels, arrays equal the same file, and a
//! renderer refuses bad options and files with the command line's messages.
use crate::common::*;
use glview::api::{self, Arrays, Model, Outputs, Renderer};
use glview::image_out::Rgba;
use glview::image_out::RgbaFiles;
use glview::Options;

fn opts(words: &[&str]) -> Options {
    Options::from_words(words.iter().copied()).expect("valid options")
}

#[test]
fn colour_equals_the_cli_png() {
    let dir = out_dir("api_cli");
    let bunny = shared().join("models/bunny-small/bunny.obj");
    let words = [bunny.to_str().unwrap(), "--size", "200x150", "--yaw", "-40"];
    let out = dir.join("cli.png");
    let mut argv = words.to_vec();
    argv.extend(["-o", out.to_str().unwrap()]);
    let o = run(&argv, &[]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let cli = Rgba::load_png(&out).unwrap();
    let frame = api::render(&opts(&words), Outputs::default()).unwrap();
    assert_eq!((frame.color.width, frame.color.height), (200, 150));
    assert!(
        frame.color.data == cli.data,
        "API picture differs from the CLI's"
    );
    // The in-memory PNG holds the same pixels, and the same text: made on demand from what
    // the draw kept, it is the text the CLI wrote while drawing.
    let png = dir.join("api.png");
    std::fs::write(&png, frame.png()).unwrap();
    assert!(Rgba::load_png(&png).unwrap().data == cli.data);
    let cli_text = glview::image_out::png_text(&out).unwrap();
    assert_eq!(glview::image_out::png_text(&png).unwrap(), cli_text);
    assert_eq!(frame.text(), cli_text);
}

/// The kept scene is keyed by the typed load options and the model file's size and time: a
/// file rewritten between two pictures of one renderer is read again (its picture is a fresh
/// renderer's), and the same file is not.
#[test]
fn a_model_file_rewritten_between_pictures_is_read_again() {
    let dir = out_dir("api_rewritten");
    let model = dir.join("box.obj");
    std::fs::write(&model, box_obj([-1.0, -0.5, -1.0], [1.0, 0.5, 1.0], 0)).unwrap();
    let words = [model.to_str().unwrap(), "--size", "96x72", "--no-shadows"];
    let r = Renderer::new(opts(&words)).unwrap();
    let uploads = |f: &api::Frame| f.stats["profile"]["scene_uploads"].as_u64().unwrap();
    let first = r.render(&opts(&words), Outputs::default()).unwrap();
    let again = r.render(&opts(&words), Outputs::default()).unwrap();
    assert_eq!((uploads(&first), uploads(&again)), (1, 0));
    // A taller box: another size, so the stat tells it apart whatever the clock's grain.
    std::fs::write(&model, box_obj([-1.0, -1.25, -1.0], [1.0, 1.25, 1.0], 0)).unwrap();
    let rewritten = r.render(&opts(&words), Outputs::default()).unwrap();
    assert_eq!(uploads(&rewritten), 1, "the rewritten file is uploaded");
    let fresh = Renderer::new(opts(&words))
        .unwrap()
        .render(&opts(&words), Outputs::default())
        .unwrap();
    assert!(rewritten.color.data == fresh.color.data);
    assert!(rewritten.color.data != first.color.data);
}

#[test]
fn depth_is_the_exact_spheres_and_ids_cover_exactly_the_picture() {
    let dir = out_dir("api_sphere");
    let obj = crate::analytic::write_sphere(&dir, 256, "newmtl m\nKd 0.7 0.5 0.3\n");
    let words = [
        obj.to_str().unwrap(),
        "--size",
        "160x120",
        "--no-shadows",
        "--transparent",
        // Depth to 1e-3 of the exact sphere: coarser levels would be up to a pixel off.
        "--lod",
        "off",
    ];
    let r = Renderer::new(opts(&words)).unwrap();
    let f = r
        .render(
            &opts(&words),
            Outputs {
                depth: true,
                normals: true,
                ids: true,
                ..Outputs::default()
            },
        )
        .unwrap();
    let a = f.attributes.expect("asked for");
    let (settings, scene) = settings_for(&words);
    let rays = PixelRays::new(&settings, &scene, 160, 120);
    let eye = settings.camera.eye().as_dvec3();
    let forward = (settings.camera.target.as_dvec3() - eye).normalize();
    let (mut compared, mut worst) = (0, 0.0f64);
    for y in 0..120 {
        for x in 0..160 {
            let i = (y * 160 + x) as usize;
            // Coverage: the picture's alpha is coverage with --transparent.
            let drawn = f.color.data[i * 4 + 3] > 0;
            assert_eq!(a.object_ids[i] >= 0, drawn, "pixel {x},{y}");
            assert_eq!(a.material_ids[i] >= 0, drawn, "pixel {x},{y}");
            let (o, d) = rays.ray(x, y);
            let o = o + scene.origin;
            let (b, c) = (o.dot(d), o.length_squared() - 1.0);
            let disc = b * b - c;
            // Near the silhouette the tessellated outline differs from the circle.
            if disc.abs() < 0.02 {
                continue;
            }
            if disc < 0.0 {
                assert!(a.depth[i].is_infinite(), "pixel {x},{y}: {}", a.depth[i]);
                continue;
            }
            let hit = o + d * (-b - disc.sqrt());
            let z = (hit - scene.origin - eye).dot(forward);
            worst = worst.max((f64::from(a.depth[i]) - z).abs());
            let n = glam::Vec3::from(a.normals[i]);
            assert!((n.length() - 1.0).abs() < 1e-3, "pixel {x},{y}: {n}");
            assert!(n.z > 0.0, "pixel {x},{y}: normal {n} faces away");
            compared += 1;
        }
    }
    assert!(compared > 2000, "{compared}");
    // The 256×128 tessellation lies within 1 − cos(π/128) ≈ 3e-4 of the unit sphere.
    assert!(worst < 1e-3, "depth off by {worst}");
    assert!(a.object_ids.iter().all(|&i| i == -1 || i == 0));
}

/// Depth alone comes from the frame's own depth buffer (no second draw): on every context
/// that can read depth back, in both tiers, perspective and orthographic, it covers exactly
/// the pixels the attribute pass covers and agrees with its distances to 24-bit depth
/// precision. Where the frame does not draw straight into the target (MSAA) the attribute
/// pass answers, so both ways of asking give the same numbers there.
#[test]
fn depth_alone_equals_the_attribute_pass() {
    let model = shared().join("gltf-samples/Duck/Duck.glb");
    let model = model.to_str().unwrap();
    let only_depth = Outputs {
        depth: true,
        ..Outputs::default()
    };
    let with_ids = Outputs {
        depth: true,
        ids: true,
        ..Outputs::default()
    };
    for extra in [
        &["--backend", "egl"][..],
        &["--backend", "egl", "--shading", "pbr"],
        &["--backend", "egl", "--ortho"],
        &["--backend", "egl", "--aa", "msaa"],
        &["--backend", "osmesa"],
    ] {
        let mut words = vec![model, "--size", "160x120", "--yaw", "30"];
        words.extend_from_slice(extra);
        let o = opts(&words);
        let r = Renderer::new(o.clone()).unwrap();
        let fast = r.render(&o, only_depth).unwrap();
        let slow = r.render(&o, with_ids).unwrap();
        assert_eq!(
            fast.color.data, slow.color.data,
            "{extra:?}: colour changed"
        );
        let (a, b) = (fast.attributes.unwrap(), slow.attributes.unwrap());
        // The attribute pass (MSAA) fills ids too; the frame's depth buffer gives depth only.
        let direct = !extra.contains(&"msaa");
        assert_eq!(a.object_ids.is_empty(), direct, "{extra:?}");
        let (mut covered, mut worst) = (0, 0.0f32);
        for (i, (&d, &e)) in a.depth.iter().zip(&b.depth).enumerate() {
            assert_eq!(
                d.is_finite(),
                b.object_ids[i] >= 0,
                "{extra:?}: pixel {i}: depth {d}, attribute pass {e}"
            );
            if d.is_finite() {
                covered += 1;
                worst = worst.max((d - e).abs() / e);
            }
        }
        eprintln!("{extra:?}: {covered} pixels, worst relative difference {worst:e}");
        assert!(covered > 2000, "{extra:?}: {covered}");
        // Measured: at most 2.7e-6 relative (24-bit depth over the fitted near/far range).
        assert!(
            worst < 1e-5,
            "{extra:?}: depth differs by {worst} (relative)"
        );
    }
}

#[test]
fn arrays_equal_the_same_file_and_bad_input_is_refused() {
    let dir = out_dir("api_arrays");
    let v: [f64; 12] = [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0];
    let faces = [0i64, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3];
    let file = dir.join("tetra.obj");
    std::fs::write(
        &file,
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n",
    )
    .unwrap();
    let o = opts(&["--size", "96x64"]);
    let mut r = Renderer::new(o.clone()).unwrap();
    r.load(Model::load(&file, &o).unwrap());
    let from_file = r.render(&o, Outputs::default()).unwrap();
    let arrays = Arrays {
        vertices: &v,
        faces: &faces,
        ..Default::default()
    };
    r.load(Model::from_arrays(&arrays, &o).unwrap());
    let from_arrays = r.render(&o, Outputs::default()).unwrap();
    assert!(from_file.color.data == from_arrays.color.data);
    assert!(!from_file.color.is_uniform());

    let bad = Arrays {
        faces: &[0, 1, 9],
        ..arrays
    };
    let e = Model::from_arrays(&bad, &o).unwrap_err().to_string();
    assert_eq!(
        e,
        "<arrays>: face 0 refers to vertex 9, but there are 4 vertices"
    );
    let e = Model::load(&dir.join("missing.obj"), &o)
        .unwrap_err()
        .to_string();
    assert!(e.contains("missing.obj"), "{e}");
    let e = Options::from_words(["--pcf", "3"]).unwrap_err().to_string();
    assert!(e.contains("PCF taps must be 1, 4, 9 or 16"), "{e}");
}

/// While one caller holds the renderer every other is refused with the Busy error, whichever
/// thread it is on; afterwards the renderer draws again. No timing involved.
#[test]
fn a_reserved_renderer_refuses_other_callers() {
    let o = opts(&["--size", "32x24"]);
    let r = Renderer::new(o.clone()).unwrap();
    {
        let _held = r.reserve().unwrap();
        let refused = std::thread::scope(|s| s.spawn(|| r.render(&o, Outputs::default())).join());
        let err = refused.unwrap().unwrap_err();
        assert!(matches!(err, glview::Error::Busy), "{err}");
        assert!(err.to_string().contains("another thread"), "{err}");
        assert!(matches!(r.reserve(), Err(glview::Error::Busy)));
    }
    assert_eq!(r.render(&o, Outputs::default()).unwrap().color.width, 32);
}

/// The float linear colour is the frame before its output step: put through the CPU twin of
/// that step (`OutputParams::apply`: exposure, tone mapping, sRGB) it is the 8-bit picture,
/// and it is unclamped where the light is bright.
#[test]
fn linear_colour_is_the_picture_before_its_output_step() {
    let model = shared().join("gltf-samples/Duck/Duck.glb");
    let model = model.to_str().unwrap();
    let want = Outputs {
        linear: true,
        ..Outputs::default()
    };
    for extra in [
        &["--tonemap", "none", "--exposure", "0"][..],
        &["--exposure", "0.5"],
        &["--ibl-intensity", "4"],
    ] {
        let mut words = vec![model, "--size", "96x72", "--shading", "pbr", "--no-bloom"];
        words.extend_from_slice(extra);
        let o = opts(&words);
        let f = api::render(&o, want).unwrap();
        let linear = f.linear.expect("asked for");
        assert_eq!(linear.len(), 96 * 72);
        let (settings, _) = settings_for(&words);
        let output = settings.lighting.output;
        let mut worst = 0u8;
        for (i, c) in linear.iter().enumerate() {
            let shown = output.apply(c.map(f64::from));
            for (k, x) in shown.iter().enumerate() {
                let v = (x.clamp(0.0, 1.0) * 255.0).round() as u8;
                worst = worst.max(v.abs_diff(f.color.data[i * 4 + k]));
            }
        }
        let brightest = linear.iter().flatten().fold(0.0f32, |a, &b| a.max(b));
        eprintln!("{extra:?}: worst {worst}/255, brightest linear value {brightest}");
        // f32 on the GPU against f64 here: one step of rounding.
        assert!(worst <= 1, "{extra:?}: {worst}/255");
        if extra.contains(&"4") {
            assert!(brightest > 1.0, "unclamped: {brightest}");
        }
    }
}
