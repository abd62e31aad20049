//! Numerical-stability stress suite: conditions that break naive code. Each case says what it
//! protects against; every render is checked for NaN/Inf (black) pixels and blank frames by
//! `common::render`. Far-from-origin and extreme-scale models are in tests/precision.rs.
use crate::common;
use common::*;
use glview::image_out::Rgba;
use glview::image_out::RgbaFiles;

fn rotate_180(img: &Rgba) -> Rgba {
    let mut out = img.clone();
    let n = (img.width * img.height) as usize;
    for i in 0..n {
        out.data[i * 4..i * 4 + 4].copy_from_slice(&img.data[(n - 1 - i) * 4..(n - i) * 4]);
    }
    out
}

/// Pitch past ±90° rolls the camera over the pole (see src/camera.rs): pitch 90 + a at yaw y
/// sees exactly what pitch 90 − a at yaw y + 180 sees, turned upside down. Rotating a pixel
/// grid of even size by 180° maps pixel centres onto pixel centres, so the images must match
/// to rounding. Protects against: NaN from a look-at whose up vector is parallel to the view,
/// and sudden flips at the pole.
#[test]
fn pitch_past_the_pole_is_a_rotated_view() {
    let dir = out_dir("stress-pole");
    let common = ["--size", "200x150", "--no-shadows"];
    for (a, b) in [(100.0, 80.0), (135.0, 45.0), (-120.0, -60.0)] {
        let over = render(
            &dir,
            &format!("over{a}"),
            &[&common[..], &["--pitch", &a.to_string(), "--yaw", "30"]].concat(),
            &[],
        );
        let under = render(
            &dir,
            &format!("under{b}"),
            &[&common[..], &["--pitch", &b.to_string(), "--yaw", "210"]].concat(),
            &[],
        );
        assert_close(
            &dir,
            &format!("pole{a}"),
            &over,
            &rotate_180(&under),
            2,
            20,
            255,
        );
    }
    for p in ["90", "-90", "270", "450"] {
        render(
            &dir,
            &format!("pitch{p}"),
            &[&common[..], &["--pitch", p]].concat(),
            &[],
        );
    }
}

/// Protects against: a near plane at or behind the eye when the camera is inside the model
/// (division by zero in the projection, everything clipped).
#[test]
fn camera_inside_the_model() {
    let dir = out_dir("stress-inside");
    let img = render(
        &dir,
        "inside",
        &["--size", "160x120", "--distance", "0.05", "--pitch", "10"],
        &[],
    );
    let bg = img.pixel(0, 0);
    let drawn = img
        .data
        .chunks_exact(4)
        .filter(|p| p[..3] != bg[..3])
        .count();
    eprintln!("inside the glass holder: {drawn} pixels of geometry");
}

/// A 20,000-unit floor with a 1 cm box at its centre, looked at from 5 cm: the depth range
/// needs near/far beyond 10⁶. Protects against: the detail being clipped by a near plane
/// derived from the whole scene, and NaN from extreme projection ratios.
#[test]
fn near_far_ratio_beyond_a_million() {
    let dir = out_dir("stress-depth");
    let obj = dir.join("huge.obj");
    let mut s = String::from("v -10000 0 -10000\nv 10000 0 -10000\nv 10000 0 10000\nv -10000 0 10000\nf 1 3 2\nf 1 4 3\n");
    s += &box_obj([-0.005, 0.0, -0.005], [0.005, 0.01, 0.005], 4);
    std::fs::write(&obj, s).unwrap();
    let view = [
        obj.to_str().unwrap(),
        "--target",
        "0,0.005,0",
        "--distance",
        "0.05",
        "--pitch",
        "20",
        "--size",
        "200x150",
    ];
    let (settings, scene) = settings_for(&view);
    let (near, far) = settings.camera.near_far(&scene.bounds);
    assert!(far / near > 1e6, "ratio {}", far / near);
    let img = render(
        &dir,
        "huge",
        &[&view[..], &["--no-shadows", "--light", "dir:0.3,-1,-0.5"]].concat(),
        &[],
    );
    // The box (Kd 0.8 under a light from above) fills the middle of the view.
    let centre = img.pixel(100, 75);
    let floor = img.pixel(100, 5);
    assert_ne!(centre[..3], floor[..3], "box clipped away or hidden");
}

/// Degenerate input that must not poison the frame. Protects against: NaN normals from
/// zero-area faces and from zero or non-finite normals in the file.
#[test]
fn zero_area_triangles_and_broken_normals() {
    let dir = out_dir("stress-normals");
    let obj = dir.join("broken.obj");
    std::fs::write(
        &obj,
        "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\nv 0.5 0.5 0\n\
         vn 0 0 0\nvn nan 0 1\nvn 0 0 1\nvn 1e-30 0 0\n\
         f 1//1 2//2 3//3\nf 1//4 3//3 4//1\nf 1//3 2//3 5//3\nf 1//3 6//3 3//3\n",
    )
    .unwrap();
    let img = render(
        &dir,
        "broken",
        &[
            obj.to_str().unwrap(),
            "--size",
            "120x90",
            "--pitch",
            "0",
            "--yaw",
            "0",
        ],
        &[],
    );
    assert!(img.data.chunks_exact(4).all(|p| p[3] == 255));
}

/// Protects against: normalize(0) = NaN when a point light sits exactly on the surface, and
/// pow(0, 0) for Ns = 0.
#[test]
fn light_at_the_surface_and_extreme_exponents() {
    let dir = out_dir("stress-light");
    for (name, mtl) in [("ns0", "Ns 0"), ("ns10000", "Ns 10000")] {
        std::fs::write(
            dir.join(format!("{name}.mtl")),
            format!("newmtl m\nKa 0.2 0.2 0.2\nKd 0.5 0.5 0.5\nKs 1 1 1\n{mtl}\n"),
        )
        .unwrap();
        let obj = dir.join(format!("{name}.obj"));
        std::fs::write(&obj, format!("mtllib {name}.mtl\nusemtl m\nv -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nvn 0 0 1\nf 1//1 2//1 3//1\nf 1//1 3//1 4//1\n")).unwrap();
        for light in [
            "point:0,0,0",
            "point:0.5,0.5,0",
            "point:0,0,1",
            "dir:0,0,-1",
        ] {
            render(
                &dir,
                &format!("{name}-{}", light.replace([':', ','], "_")),
                &[
                    obj.to_str().unwrap(),
                    "--size",
                    "63x63",
                    "--pitch",
                    "0",
                    "--yaw",
                    "0",
                    "--light",
                    light,
                ],
                &[],
            );
        }
        // Per vertex, a light placed exactly on a vertex gives a zero light vector there.
        render(
            &dir,
            &format!("{name}-vertex"),
            &[
                obj.to_str().unwrap(),
                "--size",
                "63x63",
                "--pitch",
                "0",
                "--yaw",
                "0",
                "--light",
                "point:1,1,0",
                "--shading",
                "gouraud",
            ],
            &[],
        );
    }
}

/// Protects against: zero-size viewports and division by zero at 1×1, and buffer-size
/// overflows at the largest size the driver allows (8192² here; llvmpipe's limit is 16384).
#[test]
fn tiny_and_huge_outputs() {
    let dir = out_dir("stress-size");
    let o = run(
        &[
            "--output",
            dir.join("one.png").to_str().unwrap(),
            "--size",
            "1x1",
        ],
        &[],
    );
    assert!(o.status.success());
    let one = Rgba::load_png(&dir.join("one.png")).unwrap();
    assert_eq!((one.width, one.height), (1, 1));
    let small = render(&dir, "small", &["--size", "256x256", "--no-shadows"], &[]);
    let big = render(&dir, "big", &["--size", "8192x8192", "--no-shadows"], &[]);
    let covered = |img: &Rgba| {
        let bg = img.pixel(0, 0);
        img.data
            .chunks_exact(4)
            .filter(|p| p[..3] != bg[..3])
            .count() as f64
            / (img.width * img.height) as f64
    };
    let (a, b) = (covered(&small), covered(&big));
    eprintln!("coverage 256²: {a:.4}, 8192²: {b:.4}");
    assert!(
        (a - b).abs() < 0.01,
        "the 8192² frame covers {b:.4} of the image, the 256² one {a:.4}"
    );
}
