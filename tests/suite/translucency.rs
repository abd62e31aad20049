//! Translucency as the second seed document draws it: only the nearest translucent layer
//! blends, independent of face order; inner layers never show; the background shows through
//! (glTF's BLEND), or with `--translucency nearest-masked` (the seed's globe) never does; the
//! CPU reference composites the same rule; logarithmic depth separates surfaces the standard
//! buffer cannot.
use crate::common;
use common::*;
use glview::image_out::Rgba;
use glview::image_out::RgbaFiles;
use std::fmt::Write;
use std::path::Path;

/// A UV sphere of radius `r` around the origin with outward normals, as OBJ lines; faces in
/// the order `order` gives (a permutation of the face list).
fn sphere(out: &mut String, base: &mut usize, r: f64, order: &dyn Fn(Vec<String>) -> Vec<String>) {
    let (seg, rings) = (96usize, 48usize);
    for j in 0..=rings {
        let t = std::f64::consts::PI * j as f64 / rings as f64;
        for i in 0..=seg {
            let p = std::f64::consts::TAU * i as f64 / seg as f64;
            let n = [t.sin() * p.cos(), t.cos(), t.sin() * p.sin()];
            writeln!(
                out,
                "v {} {} {}\nvn {} {} {}",
                n[0] * r,
                n[1] * r,
                n[2] * r,
                n[0],
                n[1],
                n[2]
            )
            .unwrap();
        }
    }
    let idx = |j: usize, i: usize| *base + j * (seg + 1) + i + 1;
    let mut faces = Vec::new();
    for j in 0..rings {
        for i in 0..seg {
            let (a, b, c, d) = (idx(j, i), idx(j, i + 1), idx(j + 1, i + 1), idx(j + 1, i));
            faces.push(format!("f {a}//{a} {c}//{c} {b}//{b}"));
            faces.push(format!("f {a}//{a} {d}//{d} {c}//{c}"));
        }
    }
    *base += (rings + 1) * (seg + 1);
    for f in order(faces) {
        out.push_str(&f);
        out.push('\n');
    }
}

const MTL: &str =
    "newmtl outer\nKa 0 0 1\nKd 0 0 0\nd 0.4\nnewmtl inner\nKa 1 1 0\nKd 0 0 0\nd 0.5\n\
                   newmtl core\nKa 1 0 0\nKd 0 0 0\n";

/// Outer shell (r 1, blue, α 0.4), inner shell (r 0.7, yellow, α 0.5), opaque core (r 0.4,
/// red); lit by ambient only, so every colour is Ka.
pub(crate) fn shells(dir: &Path, name: &str, order: &dyn Fn(Vec<String>) -> Vec<String>) -> String {
    let mut s = format!("mtllib {name}.mtl\n");
    let mut base = 0;
    for (obj, r) in [("outer", 1.0), ("inner", 0.7), ("core", 0.4)] {
        writeln!(s, "o {obj}\nusemtl {obj}").unwrap();
        sphere(&mut s, &mut base, r, order);
    }
    std::fs::write(dir.join(format!("{name}.mtl")), MTL).unwrap();
    let p = dir.join(format!("{name}.obj"));
    std::fs::write(&p, s).unwrap();
    p.to_str().unwrap().to_string()
}

const SIZE: u32 = 120;
const VIEW: &[&str] = &[
    "--size",
    "120x120",
    "--yaw",
    "0",
    "--pitch",
    "0",
    "--ortho",
    "2.4",
    "--light",
    "none",
    "--ambient",
    "1,1,1",
    "--background",
    "0.2,0.8,0.3",
    "--no-shadows",
];

/// The analytic picture: ortho height 2.4 over 120 pixels, looking down −Z at the origin.
/// None near a silhouette (within 2 px), where the tessellation decides. `masked`: the
/// background is drawn only where nothing was (`nearest-masked`), so the glass blends over
/// black where nothing opaque lies behind it.
fn expected(x: u32, y: u32, masked: bool) -> Option<[f64; 3]> {
    let px = 2.4 / SIZE as f64;
    let (wx, wy) = ((x as f64 + 0.5) * px - 1.2, 1.2 - (y as f64 + 0.5) * px);
    let d = (wx * wx + wy * wy).sqrt();
    if [1.0, 0.7, 0.4].iter().any(|r| (d - r).abs() < 2.0 * px) {
        return None;
    }
    let blue = [0.0, 0.0, 1.0];
    let mix = |a: f64, top: [f64; 3], under: [f64; 3]| {
        [0, 1, 2].map(|i| a * top[i] + (1.0 - a) * under[i])
    };
    Some(if d > 1.0 {
        [0.2, 0.8, 0.3] // the background
    } else if d < 0.4 {
        mix(0.4, blue, [1.0, 0.0, 0.0]) // glass over the core
    } else if masked {
        mix(0.4, blue, [0.0; 3]) // glass over nothing: the inner shell and background hidden
    } else {
        mix(0.4, blue, [0.2, 0.8, 0.3]) // glass over the background: the inner shell hidden
    })
}

fn check_analytic(dir: &Path, name: &str, img: &Rgba, masked: bool) {
    let mut worst = 0.0f64;
    let mut n = 0;
    for y in 0..SIZE {
        for x in 0..SIZE {
            if let Some(e) = expected(x, y, masked) {
                let p = img.pixel(x, y);
                for c in 0..3 {
                    worst = worst.max((f64::from(p[c]) - e[c] * 255.0).abs());
                }
                n += 1;
            }
        }
    }
    eprintln!("{name}: {n} pixels, worst {worst:.2}/255 from the analytic composite");
    if worst > 3.0 {
        img.save_png(&dir.join(format!("{name}-failed.png")), &[])
            .unwrap();
    }
    assert!(
        n > 9000 && worst <= 3.0,
        "{name}: worst {worst:.2}/255 (allowed 3)"
    );
}

#[test]
fn nearest_layer_is_order_independent_and_matches_the_composite() {
    let dir = out_dir("translucency-shells");
    let forward = shells(&dir, "forward", &|f| f);
    let reversed = shells(&dir, "reversed", &|mut f| {
        f.reverse();
        f
    });
    let shuffled = shells(&dir, "shuffled", &|mut f| {
        // A fixed pseudo-random permutation (xorshift), so the test is repeatable.
        let mut s = 0x9e3779b97f4a7c15u64;
        for i in (1..f.len()).rev() {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            f.swap(i, (s % (i as u64 + 1)) as usize);
        }
        f
    });
    let mut images = Vec::new();
    for (name, model) in [
        ("forward", &forward),
        ("reversed", &reversed),
        ("shuffled", &shuffled),
    ] {
        for (path, gl, vars) in [
            ("core", &["--gl", "core", "--backend", "egl"][..], &[][..]),
            (
                "gl21-osmesa",
                &["--gl", "2.1", "--backend", "osmesa"][..],
                GL21_NO_FBO,
            ),
        ] {
            let mut args = vec![model.as_str()];
            args.extend_from_slice(VIEW);
            args.extend_from_slice(gl);
            let img = render(&dir, &format!("{name}-{path}"), &args, vars);
            check_analytic(&dir, &format!("{name}-{path}"), &img, false);
            images.push(img);
            // The seed's globe frame: the background masked by the stencil.
            if name == "forward" {
                args.extend(["--translucency", "nearest-masked"]);
                let masked = render(&dir, &format!("masked-{path}"), &args, vars);
                check_analytic(&dir, &format!("masked-{path}"), &masked, true);
            }
        }
    }
    for (i, img) in images.iter().enumerate().skip(1) {
        assert_close(&dir, &format!("order-{i}"), &images[0], img, 2, 0, 2);
    }
    // The CPU reference composites the same rule, pixel for pixel (no pixel skipped).
    let mut args = vec![forward.as_str()];
    args.extend_from_slice(VIEW);
    let (settings, scene) = settings_for(&args);
    let reference = glview::reference::render(&scene, &settings, SIZE, SIZE);
    check_analytic(&dir, "reference", &reference, false);
    args.extend(["--translucency", "nearest-masked"]);
    let (settings, scene) = settings_for(&args);
    let masked = glview::reference::render(&scene, &settings, SIZE, SIZE);
    check_analytic(&dir, "reference-masked", &masked, true);
    let d = diff(&images[0], &reference, 8);
    eprintln!("GPU vs reference: {} pixels > 8/255, max {}", d.over, d.max);
    assert!(
        d.over <= 120,
        "GPU and reference differ on {} pixels",
        d.over
    );
}

/// The sorted (legacy) mode shows the inner shell through the outer one; the additive blend
/// adds the layer to what lies behind.
#[test]
fn sorted_mode_and_additive_blend_differ_as_the_formulas_say() {
    let dir = out_dir("translucency-modes");
    let model = shells(&dir, "m", &|f| f);
    let run_with = |name: &str, extra: &[&str]| {
        let mut args = vec![model.as_str()];
        args.extend_from_slice(VIEW);
        args.extend_from_slice(extra);
        render(&dir, name, &args, &[])
    };
    let sorted = run_with("sorted", &["--translucency", "sorted"]);
    // Between r 0.4 and 0.7 the sorted mode blends the inner (yellow) shell in: red > 0.
    let (x, y) = (60 + 33, 60); // world x ≈ 0.55
    assert!(sorted.pixel(x, y)[0] > 30, "{:?}", sorted.pixel(x, y));
    let add = run_with("add", &["--blend", "add"]);
    // Over the core: 0.4·blue + red = (1, 0, 0.4).
    let p = add.pixel(60, 60);
    assert!(
        p[0] >= 253 && p[1] <= 2 && (i32::from(p[2]) - 102).abs() <= 2,
        "{p:?}"
    );
    // --opacity overrides: α 1 hides the core entirely.
    let opaque = run_with("opacity1", &["--opacity", "1"]);
    assert!(
        opaque.pixel(60, 60)[..3] == [0, 0, 255],
        "{:?}",
        opaque.pixel(60, 60)
    );
}

/// `--xray NAME` makes a material or object translucent; an unknown name is an error that
/// lists the names there are.
#[test]
fn xray_by_name() {
    let dir = out_dir("translucency-xray");
    let plain = render(&dir, "plain", &["--size", "96x72"], &[]);
    let xray = render(&dir, "xray", &["--size", "96x72", "--xray", "metal"], &[]);
    assert!(
        diff(&plain, &xray, 8).over > 100,
        "--xray metal changed nothing"
    );
    let o = run(
        &[
            "--xray",
            "banana",
            "-o",
            dir.join("x.png").to_str().unwrap(),
        ],
        &[],
    );
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        !o.status.success() && err.contains("banana") && err.contains("saucer"),
        "{err}"
    );
}

/// Two quads 10 units apart (10⁻⁴ of the distance) at 10⁵ with the near plane at 0.01: in
/// the standard 24-bit buffer everything beyond ~1.6·10⁴ rounds to the cleared depth 1.0,
/// so the quads are lost (or fight, nearer); the logarithmic buffer (a step of ~0.07 there)
/// draws the front quad over its whole footprint and never the back one.
#[test]
fn logarithmic_depth_removes_z_fighting() {
    let dir = out_dir("translucency-logz");
    let obj = "mtllib q.mtl\nusemtl front\nv -20000 -20000 0\nv 20000 -20000 0\nv 20000 20000 0\nv -20000 20000 0\n\
               f 1 2 3\nf 1 3 4\nusemtl back\nv -20000 -20000 -10\nv 20000 -20000 -10\nv 20000 20000 -10\nv -20000 20000 -10\n\
               f 5 6 7\nf 5 7 8\n";
    std::fs::write(dir.join("q.obj"), obj).unwrap();
    std::fs::write(
        dir.join("q.mtl"),
        "newmtl front\nKa 1 0 0\nKd 0 0 0\nnewmtl back\nKa 0 1 0\nKd 0 0 0\n",
    )
    .unwrap();
    let q = dir.join("q.obj");
    let shot = |depth: &str| {
        let out = dir.join(format!("{depth}.png"));
        let o = run(
            &[
                q.to_str().unwrap(),
                "--size",
                "80x80",
                "--yaw",
                "0",
                "--pitch",
                "0",
                "--distance",
                "100000",
                "--fov",
                "30",
                "--near",
                "0.01",
                "--light",
                "none",
                "--ambient",
                "1,1,1",
                "--no-shadows",
                "--depth",
                depth,
                "-o",
                out.to_str().unwrap(),
            ],
            &[],
        );
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        Rgba::load_png(&out).unwrap()
    };
    let (standard, log) = (shot("standard"), shot("log"));
    let red = |p: &[u8]| p[0] > 200 && p[1] < 50;
    let footprint: Vec<bool> = log.data.chunks_exact(4).map(red).collect();
    let covered = footprint.iter().filter(|&&f| f).count();
    let green_log = log.data.chunks_exact(4).filter(|p| p[1] > 128).count();
    let wrong_standard = standard
        .data
        .chunks_exact(4)
        .zip(&footprint)
        .filter(|(p, &f)| f && !red(p))
        .count();
    eprintln!("front quad footprint {covered} px; wrong with the standard buffer {wrong_standard}, back quad showing with log depth {green_log}");
    assert!(
        covered > 3000,
        "the front quad covers only {covered} pixels with log depth"
    );
    assert_eq!(green_log, 0, "logarithmic depth still z-fights");
    assert!(
        wrong_standard > covered / 2,
        "the standard buffer got it right ({wrong_standard} wrong): the case proves nothing"
    );
}

/// From inside the outer shell the nearest translucent layer is the shell's inside (a back
/// face): nothing is culled in nearest mode, so the technique keeps working from inside and
/// the core still shows through the inner shell's nearest layer.
#[test]
fn camera_inside_the_shell() {
    let dir = out_dir("translucency-inside");
    let model = shells(&dir, "m", &|f| f);
    let args = [
        model.as_str(),
        "--size",
        "96x96",
        "--yaw",
        "0",
        "--pitch",
        "0",
        "--distance",
        "0.85",
        "--light",
        "none",
        "--ambient",
        "1,1,1",
        "--no-shadows",
    ];
    let img = render(&dir, "inside", &args, &[]);
    // The centre looks at the core through the inner shell (yellow, α 0.5), the camera being
    // between the outer and the inner shell: 0.5·yellow + 0.5·red = (1, 0.5, 0).
    let p = img.pixel(48, 48);
    assert!(
        p[0] >= 253 && (i32::from(p[1]) - 128).abs() <= 3 && p[2] <= 2,
        "{p:?}"
    );
    // Looking sideways, past the inner shell, the outer shell's inside blends over the
    // background.
    let (settings, scene) = settings_for(&args);
    let reference = glview::reference::render(&scene, &settings, 96, 96);
    let d = diff(&img, &reference, 8);
    assert!(
        d.over <= 60,
        "inside view differs from the reference on {} pixels",
        d.over
    );
}
