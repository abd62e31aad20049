//! Level of detail (`scene::lod`): at error 0 it draws exactly what `--lod off` draws, and at
//! the default bound the silhouette of a finely tessellated unit sphere stays within the
//! bound (in pixels) of the exact sphere's, orthographic and perspective, while far fewer
//! triangles are sent.
use crate::common::*;
use crate::culling::sphere_obj;

/// 2·400·200 = 160,000 triangles: in a 160×160 picture most are smaller than a pixel.
fn fine_sphere(dir: &std::path::Path) -> String {
    // Written every run: a new modification time, so no mesh cache entry of an older build
    // (whose levels may differ) is hit.
    let p = dir.join("sphere.obj");
    std::fs::write(&p, sphere_obj(201, 400, false)).unwrap();
    p.to_str().unwrap().to_string()
}

const SIZE: u32 = 160;

fn stats(args: &[&str], out: &std::path::Path) -> serde_json::Value {
    let mut a = args.to_vec();
    a.extend(["-o", out.to_str().unwrap(), "--stats"]);
    let o = run(&a, &[]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    serde_json::from_str(String::from_utf8_lossy(&o.stdout).lines().last().unwrap()).unwrap()
}

/// Loads `model` once, so its mesh cache entry (with the levels) exists for the pictures
/// after: they then measure drawing, not building the levels (the pictures are the same).
fn warm(dir: &std::path::Path, model: &str) {
    let out = dir.join("warm.png");
    let o = run(
        &[model, "--size", "16x16", "-o", out.to_str().unwrap()],
        &[],
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}

#[test]
fn error_zero_draws_what_lod_off_draws() {
    let dir = out_dir("lod_zero");
    let sphere = fine_sphere(&dir);
    warm(&dir, &sphere);
    let base = [sphere.as_str(), "--size", "160x160", "--yaw", "30"];
    let off = render(&dir, "off", &[&base[..], &["--lod", "off"]].concat(), &[]);
    let zero = render(
        &dir,
        "zero",
        &[&base[..], &["--lod", "on", "--lod-error", "0"]].concat(),
        &[],
    );
    assert_eq!(diff(&zero, &off, 0).max, 0, "--lod-error 0 changed pixels");
}

/// Pixels whose coverage differs from the exact sphere's lie within `bound` pixels inside its
/// silhouette (the coarser levels keep the sphere's vertices, so their chords can only cut
/// inwards) and none outside it. `radius_px` is the exact silhouette's radius about the
/// picture's centre.
fn silhouette_within(img: &glview::image_out::Rgba, radius_px: f64, bound: f64, what: &str) {
    let bg = img.pixel(0, 0);
    let c = f64::from(SIZE) * 0.5;
    let (mut inside_missed, mut worst) = (0, 0.0f64);
    for y in 0..SIZE {
        for x in 0..SIZE {
            let d = (f64::from(x) + 0.5 - c).hypot(f64::from(y) + 0.5 - c);
            let covered = img.pixel(x, y) != bg;
            if covered == (d < radius_px) {
                continue;
            }
            // The tessellation itself: chords of 400 segments sag by r·(1 − cos(π/400)).
            let slack = radius_px * (1.0 - (std::f64::consts::PI / 400.0).cos()) + 1e-3;
            assert!(
                !covered || d <= radius_px + slack,
                "{what}: pixel {x},{y} covered {:.3} px outside the exact silhouette",
                d - radius_px
            );
            worst = worst.max(radius_px - d);
            inside_missed += 1;
        }
    }
    println!("{what}: {inside_missed} pixels inside the exact silhouette not covered, deepest {worst:.3} px");
    assert!(
        worst <= bound + 1e-3,
        "{what}: silhouette moved {worst:.3} px (bound {bound})"
    );
}

#[test]
fn default_bound_moves_the_silhouette_by_at_most_the_bound() {
    let dir = out_dir("lod_silhouette");
    let sphere = fine_sphere(&dir);
    warm(&dir, &sphere);
    let bound = f64::from(glview::options::DEFAULT_LOD_ERROR);
    // Orthographic, 2.2 units high: the silhouette is a circle of 160 / 2.2 pixels.
    let ortho = [
        sphere.as_str(),
        "--size",
        "160x160",
        "--ortho",
        "2.2",
        "--background",
        "1,0,1",
        "--yaw",
        "30",
        "--pitch",
        "20",
    ];
    let img = render(&dir, "ortho", &ortho, &[]);
    silhouette_within(&img, f64::from(SIZE) / 2.2, bound, "ortho");
    // Perspective from 3 units, fov 45°: the silhouette's angular radius is asin(1/3).
    let persp = [
        sphere.as_str(),
        "--size",
        "160x160",
        "--distance",
        "3",
        "--background",
        "1,0,1",
        "--yaw",
        "-50",
        "--pitch",
        "-10",
    ];
    let img = render(&dir, "persp", &persp, &[]);
    let focal = f64::from(SIZE) * 0.5 / (22.5f64).to_radians().tan();
    let radius = focal * (1.0f64 / 3.0).asin().tan();
    silhouette_within(&img, radius, bound, "perspective");
    // And it pays: far fewer triangles than with every one drawn.
    let out = dir.join("s.png");
    let on = stats(&persp, &out)["triangles"].as_u64().unwrap();
    let off = stats(&[&persp[..], &["--lod", "off"]].concat(), &out)["triangles"]
        .as_u64()
        .unwrap();
    assert!(on * 2 < off, "lod drew {on} triangles, off {off}");
}
