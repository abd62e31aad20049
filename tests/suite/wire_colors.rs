//! Lines and points (`l`, `p`) are drawn as lines and points where the camera projects them;
//! vertex colours (`v x y z r g b`) multiply the diffuse colour the same way on the GPU, in
//! every dialect, and in the reference.
use crate::common::*;
use glam::{Vec3, Vec4Swizzles};
use glview::image_out::Rgba;
use glview::image_out::RgbaFiles;
use std::path::Path;

const SIZE: (u32, u32) = (160, 120);
const VIEW: &[&str] = &["--size", "160x120", "--yaw", "20", "--pitch", "10"];

/// Pixel (x, y), y down, where the frame of `args` projects the file point `p`.
fn project(args: &[&str], p: Vec3) -> (f32, f32) {
    let (s, scene) = settings_for(args);
    let aspect = SIZE.0 as f32 / SIZE.1 as f32;
    let vp = s.camera.projection(&scene.bounds, aspect) * s.camera.view();
    let local = scene.to_local(p.as_dvec3());
    let c = vp * local.extend(1.0);
    let ndc = c.xyz() / c.w;
    (
        (ndc.x + 1.0) * 0.5 * SIZE.0 as f32,
        (1.0 - ndc.y) * 0.5 * SIZE.1 as f32,
    )
}

fn differs(img: &Rgba, x: i64, y: i64, bg: [u8; 4]) -> bool {
    (x >= 0 && y >= 0 && x < i64::from(img.width) && y < i64::from(img.height))
        && img.pixel(x as u32, y as u32)[..3] != bg[..3]
}

/// Whether a pixel within `r` of (x, y) differs from the background.
fn near(img: &Rgba, (x, y): (f32, f32), r: i64, bg: [u8; 4]) -> bool {
    let (x, y) = (x.floor() as i64, y.floor() as i64);
    (-r..=r).any(|dy| (-r..=r).any(|dx| differs(img, x + dx, y + dy, bg)))
}

fn write(dir: &Path, name: &str, text: &str) -> String {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p.to_str().unwrap().to_string()
}

/// A file of only lines and a point: it loads, and exactly the pixels along the projected
/// segments (within one pixel, the rasterisation rule's slack) and at the point are drawn;
/// no pixel farther than 2 px from them is. Also on GLSL 1.20.
#[test]
fn lines_and_points_are_drawn_where_they_project() {
    let dir = out_dir("wire");
    let (a, b, c, d, q) = (
        Vec3::new(-1.0, -1.0, 0.0),
        Vec3::new(1.0, 1.0, 0.0),
        Vec3::new(1.0, -1.0, 0.0),
        Vec3::new(-1.0, 1.0, 0.5),
        Vec3::new(0.0, 0.8, -0.3),
    );
    let obj = write(
        &dir,
        "lines.obj",
        &format!(
            "v {} {} {}\nv {} {} {}\nv {} {} {}\nv {} {} {}\nv {} {} {}\nl 1 2\nl 3 4\np 5\n",
            a.x, a.y, a.z, b.x, b.y, b.z, c.x, c.y, c.z, d.x, d.y, d.z, q.x, q.y, q.z
        ),
    );
    let mut args = vec![obj.as_str()];
    args.extend_from_slice(VIEW);
    for (name, env) in [("lines", &[][..]), ("lines-gl21", GL21)] {
        let mut all = args.clone();
        all.extend_from_slice(&["--gl", if env.is_empty() { "auto" } else { "2.1" }]);
        let img = render(&dir, name, &all, env);
        let bg = img.pixel(0, 0);
        let segs = [(a, b), (c, d)].map(|(p, q)| (project(&args, p), project(&args, q)));
        for (p, q) in segs {
            for i in 1..20 {
                let t = i as f32 / 20.0;
                let at = (p.0 + t * (q.0 - p.0), p.1 + t * (q.1 - p.1));
                assert!(near(&img, at, 1, bg), "{name}: no line pixel near {at:?}");
            }
        }
        assert!(near(&img, project(&args, q), 1, bg), "{name}: the point");
        // Nothing else: every drawn pixel is within 2 px of a segment or of the point's
        // disk (a lone point is drawn at the largest default size).
        let qp = project(&args, q);
        let radius = glview::frame::MAX_POINT_PX / 2.0;
        for y in 0..img.height {
            for x in 0..img.width {
                if !differs(&img, x.into(), y.into(), bg) {
                    continue;
                }
                let (px, py) = (x as f32 + 0.5, y as f32 + 0.5);
                let dist = segs
                    .iter()
                    .map(|&(p, q)| segment_distance((px, py), p, q))
                    .fold(
                        (((px - qp.0).powi(2) + (py - qp.1).powi(2)).sqrt() - radius).max(0.0),
                        f32::min,
                    );
                assert!(
                    dist <= 2.0,
                    "{name}: pixel ({x}, {y}) drawn {dist} px from any line"
                );
            }
        }
    }
    // Lines beside a cube: both are drawn, and `--check` counts the wire.
    let mut text = box_obj([-0.5; 3], [0.5; 3], 0);
    text += "v 0.9 -0.5 0\nv 0.9 0.5 0\nl 9 10\n";
    let both = write(&dir, "cube-line.obj", &text);
    let mut args = vec![both.as_str()];
    args.extend_from_slice(VIEW);
    let img = render(&dir, "cube-line", &args, &[]);
    let bg = img.pixel(0, 0);
    let mid = project(&args, Vec3::new(0.9, 0.0, 0.0));
    assert!(near(&img, mid, 1, bg), "the line beside the cube");
    assert!(near(&img, project(&args, Vec3::ZERO), 0, bg), "the cube");
    let o = run(&["--check", &both], &[]);
    let report = String::from_utf8_lossy(&o.stdout);
    assert!(report.contains("lines: 1 "), "{report}");
}

fn segment_distance(p: (f32, f32), a: (f32, f32), b: (f32, f32)) -> f32 {
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    let len2 = (dx * dx + dy * dy).max(1e-9);
    let t = (((p.0 - a.0) * dx + (p.1 - a.1) * dy) / len2).clamp(0.0, 1.0);
    ((p.0 - a.0 - t * dx).powi(2) + (p.1 - a.1 - t * dy).powi(2)).sqrt()
}

/// A quad with red corners on the left and green on the right: GPU against the reference
/// (barycentric interpolation in f64) in both tiers, GLSL 1.20 against 3.30, and the colour
/// half-way is half red, half green with no blue from the diffuse term.
#[test]
fn vertex_colours_multiply_the_diffuse_colour_everywhere() {
    let dir = out_dir("vertex-colours");
    let obj = write(
        &dir,
        "quad.obj",
        "v -1 -1 0 1 0 0\nv 1 -1 0 0 1 0\nv 1 1 0 0 1 0\nv -1 1 0 1 0 0\nf 1 2 3\nf 1 3 4\n",
    );
    let base = [
        obj.as_str(),
        "--size",
        "160x120",
        "--yaw",
        "15",
        "--pitch",
        "10",
        "--light",
        "dir:0.2,-0.3,-1",
        // A plain background in the PBR tier too (else the environment is drawn behind).
        "--background",
        "0.1,0.1,0.12",
    ];
    for shading in ["phong", "gouraud", "pbr"] {
        let mut args = base.to_vec();
        args.extend_from_slice(&["--shading", shading, "--no-shadows"]);
        if shading == "pbr" {
            // Direct light only: the reference integrates the environment by Monte Carlo,
            // whose noise and split-sum differences are measured elsewhere (tests/suite/pbr.rs).
            args.extend_from_slice(&["--terms", "direct-diffuse,direct-specular"]);
        }
        let gpu = render(&dir, shading, &args, &[]);
        let gl21 = render(&dir, &format!("{shading}-gl21"), &args, GL21);
        assert_close(&dir, &format!("{shading}-dialects"), &gpu, &gl21, 1, 0, 1);
        let mut r = args.clone();
        r.push("--reference");
        let out = dir.join(format!("{shading}-ref.png"));
        r.extend_from_slice(&["-o", out.to_str().unwrap()]);
        assert!(run(&r, &[]).status.success());
        let reference = Rgba::load_png(&out).unwrap();
        // Silhouette pixels are partly covered in one and not the other; inside, rounding.
        assert_close(
            &dir,
            &format!("{shading}-vs-ref"),
            &gpu,
            &reference,
            2,
            60,
            255,
        );
        let inside = diff_inside(&gpu, &reference);
        assert!(
            inside <= 2,
            "{shading}: inside the quad the GPU differs by {inside}"
        );
    }
    // Phong with a headlight, the quad square to the view: the two pixels either side of the
    // centre line mirror each other (red on one side is green on the other: the colours
    // interpolate linearly and Kd, Ka are grey), and no blue comes from the diffuse colour.
    let args = [
        obj.as_str(),
        "--size",
        "160x120",
        "--yaw",
        "0",
        "--pitch",
        "0",
        "--light",
        "head",
        "--no-shadows",
    ];
    let flat = render(&dir, "centre", &args, &[]);
    let (l, r) = (flat.pixel(79, 60), flat.pixel(80, 60));
    assert!(
        l[0].abs_diff(r[1]) <= 1 && l[1].abs_diff(r[0]) <= 1 && l[0] > 60 && r[1] > 60,
        "left {l:?} right {r:?}"
    );
    assert!(l[2] <= 1 && r[2] <= 1, "blue: {l:?} {r:?}");
}

/// Largest channel difference over pixels that are not next to the quad's silhouette (both
/// images and all eight neighbours non-background in both).
fn diff_inside(a: &Rgba, b: &Rgba) -> u8 {
    let bg = a.pixel(0, 0);
    let inside = |img: &Rgba, x: u32, y: u32| {
        (0..3).all(|dy| (0..3).all(|dx| img.pixel(x + dx - 1, y + dy - 1)[..3] != bg[..3]))
    };
    let mut max = 0;
    for y in 1..a.height - 1 {
        for x in 1..a.width - 1 {
            if inside(a, x, y) && inside(b, x, y) {
                let (p, q) = (a.pixel(x, y), b.pixel(x, y));
                max = max.max((0..3).map(|i| p[i].abs_diff(q[i])).max().unwrap());
            }
        }
    }
    max
}
