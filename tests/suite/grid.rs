//! `--grid` and `--axes`: the GPU's grid lines lie where the CPU reference's ray-cast plane
//! puts them (the same line rule, GridPlane::alpha) and its shadow where the reference's
//! shadow rays say, on every context; the axes triad in the corner points where the
//! camera's view matrix turns the world axes.
use crate::common::*;
use crate::points::{render_bin, Context, CONTEXTS};
use glam::Vec3;
use glview::image_out::Rgba;
use glview::image_out::RgbaFiles;
use std::path::Path;

const W: u32 = 160;
const H: u32 = 120;
/// The grid's label is drawn over the bottom rows (not by the reference).
const LABEL_ROWS: u32 = 16;

/// A box standing on y = 0 (the grid's plane), taller than wide so its shadow falls on it.
fn model(dir: &Path) -> String {
    let p = dir.join("box.obj");
    std::fs::write(&p, box_obj([-0.6, 0.0, -0.6], [0.6, 1.6, 0.6], 0)).unwrap();
    p.to_str().unwrap().to_string()
}

/// `args` rendered on context `c`: through the binary but for the default context.
fn render_on(dir: &Path, name: &str, args: &[&str], c: &Context) -> Rgba {
    let mut all = args.to_vec();
    all.extend_from_slice(c.1);
    render_bin(dir, name, &all, c.2)
}

fn far(a: [u8; 4], b: [u8; 4], t: u8) -> bool {
    (0..3).any(|k| a[k].abs_diff(b[k]) > t)
}

/// Pixels off the model (the reference's info) and above the label rows where `pick` says
/// so, as a mask.
fn mask(img: &Rgba, off_model: &[bool], pick: impl Fn([u8; 4]) -> bool) -> Vec<bool> {
    (0..W * H)
        .map(|i| {
            let (x, y) = (i % W, i / W);
            y < H - LABEL_ROWS && off_model[i as usize] && pick(img.pixel(x, y))
        })
        .collect()
}

/// |a ∩ b| / |a ∪ b| and |a ∪ b|.
fn agreement(a: &[bool], b: &[bool]) -> (f64, usize) {
    let both = a.iter().zip(b).filter(|(x, y)| **x && **y).count();
    let either = a.iter().zip(b).filter(|(x, y)| **x || **y).count();
    (both as f64 / either.max(1) as f64, either)
}

/// Without shadows every pixel off the model that is not the background is a grid line:
/// the GPU's line pixels and the reference's are the same pixels (intersection over union
/// ≥ 0.9: the GPU's fwidth comes from its 2×2 quads, the reference's from the same
/// neighbours in f64, so only pixels at the coverage threshold differ), and their colours
/// agree (98 % within 12/255), on every context.
#[test]
fn grid_lines_lie_where_the_ray_cast_plane_says() {
    let dir = out_dir("grid-lines");
    let file = model(&dir);
    let args = [
        file.as_str(),
        "--grid",
        "--no-shadows",
        "--size",
        "160x120",
        "--yaw",
        "25",
        "--pitch",
        "30",
        "--background",
        "0.2,0.25,0.3",
    ];
    let (s, scene) = settings_for(&args);
    let (reference, info) = glview::reference::render_with_info(&scene, &s, W, H);
    reference.save_png(&dir.join("reference.png"), &[]).unwrap();
    let off: Vec<bool> = info.iter().map(|i| !i.hit()).collect();
    let bg = [51, 64, 77, 255];
    let want = mask(&reference, &off, |p| far(p, bg, 8));
    let lines = want.iter().filter(|b| **b).count();
    assert!(lines > (W * H / 20) as usize, "only {lines} line pixels");
    for c in &CONTEXTS {
        let name = format!("grid{}", c.0);
        let img = render_on(&dir, &name, &args, c);
        let got = mask(&img, &off, |p| far(p, bg, 8));
        let (iou, n) = agreement(&got, &want);
        let close = (0..W * (H - LABEL_ROWS))
            .filter(|i| !far(img.pixel(i % W, i / W), reference.pixel(i % W, i / W), 12))
            .count() as f64
            / f64::from(W * (H - LABEL_ROWS));
        eprintln!("{name}: line pixels agree {iou:.3} of {n}; {close:.4} within 12/255");
        assert!(iou >= 0.9, "{name}: line pixels agree {iou:.3} of {n}");
        assert!(close >= 0.98, "{name}: {close:.4} of pixels within 12/255");
    }
}

/// With the key light's shadow: the pixels the grid darkens (off lines and off the model)
/// are those whose plane point the reference's shadow ray finds blocked (intersection over
/// union ≥ 0.8: the shadow map's filtered edge against the exact one), on GL 2.1, ES 3.0 and
/// the default context, in both tiers (the PBR tier on the default context).
#[test]
fn grid_receives_the_models_shadow() {
    let dir = out_dir("grid-shadow");
    let file = model(&dir);
    let base = [
        file.as_str(),
        "--grid",
        "--size",
        "160x120",
        "--yaw",
        "-30",
        "--pitch",
        "35",
        "--background",
        "0.6,0.6,0.6",
        "--light",
        "dir:-1,-2,-0.5",
    ];
    let pbr: Vec<&str> = base.iter().copied().chain(["--shading", "pbr"]).collect();
    let runs: [(&str, &[&str], Context); 4] = [
        ("phong", &base, CONTEXTS[0]),
        ("phong-gl21", &base, CONTEXTS[1]),
        ("phong-es3", &base, CONTEXTS[3]),
        ("pbr", &pbr, CONTEXTS[0]),
    ];
    for (name, args, c) in runs {
        let (s, scene) = settings_for(args);
        let (reference, info) = glview::reference::render_with_info(&scene, &s, W, H);
        let bg = reference.pixel(0, 0);
        let off: Vec<bool> = info.iter().map(|i| !i.hit()).collect();
        // Darker than the background by more than lines alone make it: the grid's light
        // lines over the light background only brighten or keep it.
        let dark = |p: [u8; 4]| (0..3).all(|k| u16::from(p[k]) + 25 < u16::from(bg[k]));
        let want = mask(&reference, &off, dark);
        let shadow = want.iter().filter(|b| **b).count();
        assert!(
            shadow > 150,
            "{name}: the reference has {shadow} shadow pixels"
        );
        let img = render_on(&dir, name, args, &c);
        let got = mask(&img, &off, dark);
        let (iou, n) = agreement(&got, &want);
        eprintln!("{name}: shadow pixels agree {iou:.3} of {n}");
        assert!(iou >= 0.8, "{name}: shadow pixels agree {iou:.3} of {n}");
    }
}

/// The triad's axes point where the view matrix turns X, Y and Z (the centroid of each
/// axis's colour within its projected length from the triad's centre, against the projected unit
/// vector: within 8°, and none drawn for an axis pointing at the viewer), on every context;
/// after yaw 90° the eye is on +X, so Z points left.
#[test]
fn axes_triad_turns_with_the_camera() {
    let dir = out_dir("axes");
    let file = model(&dir);
    let len = glview::render::guides::AXIS_SHARE * 0.5 * glview::render::guides::TRIAD_PX - 9.0;
    let (cx, cy) = glview::render::guides::triad_centre(180, 1.0);
    for (i, (yaw, pitch)) in [("90", "0"), ("35", "25"), ("-120", "-40")]
        .iter()
        .enumerate()
    {
        let args = [
            file.as_str(),
            "--axes",
            "--size",
            "240x180",
            "--yaw",
            yaw,
            "--pitch",
            pitch,
            "--background",
            "0.1,0.1,0.1",
        ];
        let (s, _) = settings_for(&args);
        let view = s.camera.view();
        let contexts: &[Context] = if i == 0 { &CONTEXTS } else { &CONTEXTS[..1] };
        for c in contexts {
            let name = format!("axes-{yaw}-{pitch}{}", c.0);
            let img = render_on(&dir, &name, &args, c);
            for (axis, rgb, label) in glview::grid::AXES {
                let (dx, dy, _) = glview::grid::triad_direction(&view, Default::default(), axis);
                // The segment's pixels, not its letter just past the tip.
                let reach = len * dx.hypot(dy) + 1.5;
                let (mut n, mut sx, mut sy) = (0.0, 0.0, 0.0);
                for y in 0..img.height {
                    for x in 0..img.width {
                        let (px, py) = (x as f32 + 0.5 - cx, y as f32 + 0.5 - cy);
                        let p = img.pixel(x, y);
                        if px.hypot(py) <= reach && (0..3).all(|k| p[k].abs_diff(rgb[k]) <= 10) {
                            n += 1.0;
                            sx += px;
                            sy += py;
                        }
                    }
                }
                let shown = dx.hypot(dy);
                if shown < 0.2 {
                    // Pointing at (or away from) the viewer: a dot at most.
                    assert!(n < 40.0, "{name}: {label} seen end-on drew {n} pixels");
                    continue;
                }
                assert!(n >= 10.0, "{name}: {label}: {n} pixels");
                let (mx, my) = (sx / n, sy / n);
                let angle = (mx * dy - my * dx).atan2(mx * dx + my * dy).to_degrees();
                eprintln!("{name}: {label} centroid ({mx:.1}, {my:.1}), {angle:.1}° off");
                assert!(angle.abs() < 8.0, "{name}: {label} is {angle:.1}° off");
                // The centroid of a segment from the centre lies at half its length.
                let half = 0.5 * len * shown;
                assert!(
                    (mx.hypot(my) - half).abs() <= 0.25 * half + 2.0,
                    "{name}: {label} centroid at {:.1} px, expected {half:.1}",
                    mx.hypot(my)
                );
            }
            if i == 0 {
                let (zx, _, _) = glview::grid::triad_direction(&view, Default::default(), Vec3::Z);
                assert!(zx < -0.99, "yaw 90: Z points left ({zx})");
            }
        }
    }
}

/// The `Z` and `X` keys toggle the grid and the triad, and replay as the options do
/// (`--keys`, the window and the web page share the key table).
#[test]
fn keys_z_and_x_replay_as_the_options() {
    let dir = out_dir("grid-keys");
    let file = model(&dir);
    let pic = |name: &str, extra: &[&str]| {
        let mut a = vec![file.as_str(), "--size", "160x120", "--pitch", "20"];
        a.extend_from_slice(extra);
        render(&dir, name, &a, &[])
    };
    let both = pic("options", &["--grid", "--axes"]);
    assert_eq!(pic("keys", &["--keys", "Z X"]).data, both.data);
    assert_eq!(
        pic("grid", &["--grid"]).data,
        pic("key_z", &["--keys", "Z"]).data
    );
    assert_eq!(
        pic("none", &[]).data,
        pic("key_zz", &["--keys", "X Z X Z"]).data
    );
    assert_ne!(pic("none", &[]).data, both.data);
}

/// Bloom without float render targets (GL 2.1 on OSMesa without framebuffer objects) keeps
/// the frame RGBM-encoded in the 8-bit target, which fixed-function blending cannot blend:
/// the grid blends in its shader over a copy of the frame. With a negligible bloom the
/// picture is the one without bloom (99 % of pixels within 3/255: RGBM's rounding).
#[test]
fn grid_on_the_rgbm_copy_path() {
    let dir = out_dir("grid-rgbm");
    let file = model(&dir);
    let args = [
        file.as_str(),
        "--grid",
        "--size",
        "160x120",
        "--pitch",
        "30",
        "--backend",
        "osmesa",
    ];
    let c: Context = ("-nofbo", &[], GL21_NO_FBO);
    let plain = render_on(&dir, "plain", &args, &c);
    let out = dir.join("rgbm.png");
    let mut bloom = args.to_vec();
    bloom.extend_from_slice(&["--bloom", "0.0001", "--stats", "-o", out.to_str().unwrap()]);
    let o = run(&bloom, GL21_NO_FBO);
    let stats = String::from_utf8_lossy(&o.stdout);
    assert!(
        stats.contains("copy-to-texture path") && stats.contains("grid: ran"),
        "{stats}"
    );
    let rgbm = Rgba::load_png(&out).unwrap();
    let close = (0..W * H)
        .filter(|i| !far(plain.pixel(i % W, i / W), rgbm.pixel(i % W, i / W), 3))
        .count() as f64
        / f64::from(W * H);
    assert!(close >= 0.99, "{close:.4} of pixels within 3/255");
}
