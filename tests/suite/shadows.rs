//! Shadow mapping against exact geometry: the test ray-casts which floor pixels a box shadows
//! and compares with glview's render, on the FBO path and the no-FBO copy path.
use crate::common;
use common::*;
use glam::DVec3;
use glview::image_out::RgbaFiles;
use glview::light::LightKind;

struct Classified {
    /// Floor pixels away from the exact shadow edge.
    compared: usize,
    wrong: usize,
    shadowed: usize,
}

/// Renders `model` with shadows and without, classifies every floor pixel of the shadowed
/// render as lit or shadowed (closer to the unshadowed colour or to the ambient-only
/// colour), and compares with a shadow ray cast from the exact floor point to the light.
/// Pixels within `edge` pixels of the exact shadow boundary are not counted: PCF blurs the
/// boundary over ±1.5 map texels by design, and the map's texels project to about a pixel.
fn classify(
    name: &str,
    model: &str,
    light: &str,
    env: &[(&str, &str)],
    extra: &[&str],
    edge: i32,
) -> Classified {
    let dir = out_dir("shadows");
    let (w, h) = (400u32, 300u32);
    let obj = models().join(model);
    let mut args = vec![
        obj.to_str().unwrap(),
        "--size",
        "400x300",
        "--pitch",
        "55",
        "--yaw",
        "20",
        "--light",
        light,
    ];
    args.extend_from_slice(extra);
    let lit = render(
        &dir,
        &format!("{name}-lit"),
        &[&args[..], &["--no-shadows"]].concat(),
        env,
    );
    let shadowed = render(&dir, &format!("{name}-shadow"), &args, env);
    let (s, scene) = settings_for(&args);
    let rays = PixelRays::new(&s, &scene, w, h);
    let o = scene.origin;
    let floor_y = 0.0 - o.y;
    let (box_lo, box_hi) = if model == "box_floor.obj" {
        (
            DVec3::new(-0.5, 1.0, -0.5) - o,
            DVec3::new(0.5, 2.0, 0.5) - o,
        )
    } else {
        (
            DVec3::new(-0.5, 0.0, -0.5) - o,
            DVec3::new(0.5, 1.0, 0.5) - o,
        )
    };
    let light = s.lights[0];
    // Exact: None = not a visible floor pixel; Some(true) = in shadow.
    let exact: Vec<Option<bool>> = (0..w * h)
        .map(|i| {
            let (ro, rd) = rays.ray(i % w, i / w);
            let t = (floor_y - ro.y) / rd.y;
            let p = ro + rd * t;
            if t <= 0.0 || p.x.abs() > 2.95 || p.z.abs() > 2.95 {
                return None;
            }
            if ray_box(ro, rd, box_lo, box_hi, 0.0, t).is_some() {
                return None; // the box hides the floor here
            }
            let (to_l, dist) = match light.kind {
                LightKind::Point(q) => {
                    let v = q.as_dvec3() - p;
                    (v.normalize(), v.length())
                }
                LightKind::Directional(d) => (-d.as_dvec3().normalize(), f64::INFINITY),
            };
            Some(ray_box(p, to_l, box_lo, box_hi, 1e-9, dist).is_some())
        })
        .collect();
    let ambient_only = [10u8, 10, 10]; // Ka 0.2 × ambient 0.2 = 0.04 → 10/255
    let mut c = Classified {
        compared: 0,
        wrong: 0,
        shadowed: 0,
    };
    let mut wrong_img = shadowed.clone();
    for y in edge..h as i32 - edge {
        for x in edge..w as i32 - edge {
            let Some(truth) = exact[(y as u32 * w + x as u32) as usize] else {
                continue;
            };
            let near_edge = (-edge..=edge).any(|dy| {
                (-edge..=edge).any(|dx| {
                    exact[((y + dy) as u32 * w + (x + dx) as u32) as usize]
                        .is_some_and(|t| t != truth)
                })
            });
            if near_edge {
                continue;
            }
            let px = shadowed.pixel(x as u32, y as u32);
            let full = lit.pixel(x as u32, y as u32);
            let dist =
                |a: [u8; 4], b: [u8; 3]| (0..3).map(|k| a[k].abs_diff(b[k]) as u32).sum::<u32>();
            let to_lit = dist(px, [full[0], full[1], full[2]]);
            let to_dark = dist(px, ambient_only);
            let rendered_shadow = to_dark < to_lit;
            c.compared += 1;
            c.shadowed += usize::from(truth);
            if rendered_shadow != truth {
                c.wrong += 1;
                let i = ((y as u32 * w + x as u32) * 4) as usize;
                wrong_img.data[i..i + 4].copy_from_slice(&[255, 0, 255, 255]);
            }
        }
    }
    eprintln!(
        "{name}: {} of {} floor pixels misclassified ({:.3} %), {} in shadow",
        c.wrong,
        c.compared,
        100.0 * c.wrong as f64 / c.compared.max(1) as f64,
        c.shadowed
    );
    if c.wrong > 0 {
        wrong_img
            .save_png(&dir.join(format!("{name}-wrong.png")), &[])
            .unwrap();
    }
    c
}

fn assert_exact(c: &Classified, name: &str) {
    assert!(
        c.compared > 20_000,
        "{name}: only {} floor pixels",
        c.compared
    );
    assert!(
        c.shadowed > 300,
        "{name}: only {} shadowed pixels: test scene broken",
        c.shadowed
    );
    // Away from the edge every pixel must be right; allow 0.05 % for pixels where the floor
    // is seen at a grazing angle and one map texel covers several pixels.
    assert!(
        c.wrong * 2000 <= c.compared,
        "{name}: {} misclassified",
        c.wrong
    );
}

#[test]
fn directional_light_shadow_is_exact() {
    let c = classify("dir", "box_floor.obj", "dir:0.3,-1,-0.2", &[], &[], 2);
    assert_exact(&c, "dir");
}

#[test]
fn point_light_outside_shadow_is_exact() {
    let c = classify("point", "box_floor.obj", "point:2,4,3", &[], &[], 2);
    assert_exact(&c, "point");
}

#[test]
fn point_light_inside_uses_six_faces_and_is_exact() {
    let c = classify("cube", "box_floor.obj", "point:1.2,2.5,0.8", &[], &[], 3);
    assert_exact(&c, "cube");
}

#[test]
fn point_light_just_outside_the_bounding_sphere_is_exact() {
    // box_floor.obj: bounds (-3, 0, -3)..(3, 2, 3), centre (0, 1, 0), radius 4.36; the light
    // is 1.03 radii from the centre, where one frustum would be 158° wide (at 1.0 r, past
    // 180°): the six-face atlas is used and must be as exact as inside the sphere.
    let c = classify(
        "cube-near",
        "box_floor.obj",
        "point:2.8,4.0,1.8",
        &[],
        &[],
        3,
    );
    assert_exact(&c, "cube-near");
}

#[test]
fn copy_path_without_fbo_is_exact_too() {
    // GL 2.1 without framebuffer objects: OSMesa, depth copied with glCopyTexSubImage2D. The
    // map is limited to the target's size (300²), so edges are wider: 4 pixels excluded.
    let c = classify(
        "copy",
        "box_floor.obj",
        "dir:0.3,-1,-0.2",
        GL21_NO_FBO,
        &["--gl", "2.1", "--backend", "osmesa"],
        4,
    );
    assert_exact(&c, "copy");
}

#[test]
fn resting_box_shadow_touches_its_base() {
    // Light from the side: the shadow of a box on the floor must start at the box's base
    // (no peter-panning), so the floor right beside the base on the far side is dark.
    let c = classify("contact", "box_on_floor.obj", "dir:1,-0.6,0.4", &[], &[], 2);
    assert_exact(&c, "contact");
    let (s, scene) = settings_for(&[
        models().join("box_on_floor.obj").to_str().unwrap(),
        "--size",
        "400x300",
        "--pitch",
        "55",
        "--yaw",
        "20",
        "--light",
        "dir:1,-0.6,0.4",
    ]);
    let img =
        glview::image_out::Rgba::load_png(&out_dir("shadows").join("contact-shadow.png")).unwrap();
    let view_proj = s.camera.projection(&scene.bounds, 400.0 / 300.0) * s.camera.view();
    // Floor points 0.02 (2 % of the box size) beyond the base, on the shadow side (+x face).
    for z in [-0.3, 0.0, 0.3] {
        let p = glam::Vec3::new(0.52, 0.0, z) - scene.origin.as_vec3();
        let q = view_proj.project_point3(p);
        let (x, y) = (((q.x + 1.0) * 200.0) as u32, ((1.0 - q.y) * 150.0) as u32);
        let px = img.pixel(x, y);
        assert!(
            px[0] < 40,
            "floor at the base (z {z}) is lit: {px:?} at ({x},{y})"
        );
    }
}

#[test]
fn grazing_light_gives_no_acne() {
    // Only the floor, lit at 5° above the horizon: every floor pixel must have the same
    // colour (N·L is constant; acne would show as dark speckles or stripes).
    let dir = out_dir("shadows-acne");
    let obj = dir.join("floor.obj");
    std::fs::write(
        &obj,
        "v -3 0 -3\nv 3 0 -3\nv 3 0 3\nv -3 0 3\nvn 0 1 0\nf 1//1 3//1 2//1\nf 1//1 4//1 3//1\n",
    )
    .unwrap();
    for pcf in ["1", "4"] {
        let img = render(
            &dir,
            &format!("floor-pcf{pcf}"),
            &[
                obj.to_str().unwrap(),
                "--size",
                "400x300",
                "--pitch",
                "40",
                "--light",
                "dir:1,-0.087,0.3",
                "--pcf",
                pcf,
                "--background",
                "0,0,1",
            ],
            &[],
        );
        let bg = img.pixel(0, 0);
        let floor: Vec<[u8; 4]> = img
            .data
            .chunks_exact(4)
            .map(|p| [p[0], p[1], p[2], p[3]])
            .filter(|p| *p != bg)
            .collect();
        assert!(floor.len() > 20_000, "{} floor pixels", floor.len());
        let (lo, hi) = floor
            .iter()
            .fold((255u8, 0u8), |(lo, hi), p| (lo.min(p[0]), hi.max(p[0])));
        assert!(
            hi - lo <= 1,
            "pcf {pcf}: floor varies from {lo} to {hi}: acne"
        );
    }
}

#[test]
fn fbo_and_copy_paths_give_the_same_image() {
    let dir = out_dir("shadows-paths");
    let args = ["--size", "512x512", "--shadow-size", "512", "--gl", "2.1"];
    let fbo = render(
        &dir,
        "fbo",
        &[&args[..], &["--backend", "egl"]].concat(),
        GL21,
    );
    let copy = render(
        &dir,
        "copy",
        &[&args[..], &["--backend", "osmesa"]].concat(),
        GL21_NO_FBO,
    );
    // Same map size, same matrices, same depth format: the only difference is whether depth
    // reaches the texture through an attachment or a copy of a 24-bit depth buffer. Allow
    // 1/255 anywhere and 0.1 % of pixels beyond it (shadow-edge texels).
    assert_close(&dir, "fbo-vs-copy", &fbo, &copy, 1, 262, 255);
}

#[test]
fn stats_show_skipped_and_reused_shadow_passes() {
    let o = run(
        &[
            "--output",
            out_dir("shadows-stats").join("s.png").to_str().unwrap(),
            "--size",
            "64x64",
            "--stats",
            "--frames",
            "2",
        ],
        &[],
    );
    assert!(o.status.success());
    let lines: Vec<serde_json::Value> = String::from_utf8_lossy(&o.stdout)
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    assert_eq!(lines.len(), 2);
    assert_eq!(lines[0]["shadow"], "rendered");
    assert!(lines[0]["passes"][0]
        .as_str()
        .unwrap()
        .starts_with("shadow("));
    assert!(lines[1]["shadow"].as_str().unwrap().starts_with("reused"));
    assert_eq!(lines[1]["passes"], serde_json::json!(["lit"]));
    for (flag, reason) in [
        ("--no-shadows", "off (--no-shadows)"),
        ("--light=none", "off (no lights)"),
    ] {
        let o = run(
            &[
                "--output",
                out_dir("shadows-stats").join("n.png").to_str().unwrap(),
                "--size",
                "64x64",
                "--stats",
                flag,
            ],
            &[],
        );
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let v: serde_json::Value =
            serde_json::from_str(String::from_utf8_lossy(&o.stdout).lines().next().unwrap())
                .unwrap();
        assert_eq!(v["shadow"], reason);
        assert_eq!(v["passes"], serde_json::json!(["lit"]));
        assert!(!v["programs"].to_string().contains("depth"));
    }
}

#[test]
fn shadow_map_teaching_view_is_grey() {
    let dir = out_dir("shadows-show");
    let img = render(
        &dir,
        "map",
        &["--size", "256x256", "--show", "shadow-map"],
        &[],
    );
    assert!(
        img.data
            .chunks_exact(4)
            .all(|p| p[0] == p[1] && p[1] == p[2]),
        "not grey"
    );
    // Cleared depth (nothing drawn) is 1.0 = white; the scene is nearer, so darker.
    let white = img.data.chunks_exact(4).filter(|p| p[0] == 255).count();
    assert!(white > 0 && white < 256 * 256, "{white} white pixels");
}
