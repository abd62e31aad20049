//! Point clouds and POINTS: a PLY (ASCII or binary) or OBJ with vertices and no faces loads as
//! a cloud; every point is a round disk of `--point-size` pixels centred where the camera
//! projects it, in its own colour (unlit without normals), on GL 2.1 and the default context,
//! and where the CPU reference draws it; glTF POINTS are dots of the default size.
use crate::common::*;
use glam::{Vec3, Vec4Swizzles};
use glview::image_out::Rgba;
use glview::image_out::RgbaFiles;
use std::path::Path;

pub(crate) const W: u32 = 200;
pub(crate) const H: u32 = 150;
const VIEW: &[&str] = &["--size", "200x150", "--yaw", "20", "--pitch", "10"];

/// Five points far apart (their disks never touch at the sizes used) and their colours.
const POINTS: [([f32; 3], [u8; 3]); 5] = [
    ([-1.0, -1.0, 0.0], [255, 0, 0]),
    ([1.0, -0.9, 0.3], [0, 255, 0]),
    ([0.1, 1.0, -0.2], [0, 0, 255]),
    ([-0.8, 0.5, 0.5], [255, 255, 0]),
    ([0.7, 0.4, -0.5], [0, 255, 255]),
];

/// Unit normals, for the lit variant.
fn normal(i: usize) -> [f32; 3] {
    let n = Vec3::new(0.3 * i as f32 - 0.5, 0.4, 1.0).normalize();
    n.to_array()
}

/// An ASCII PLY of the points with colours (uchar).
fn ascii_ply(colours: bool) -> String {
    let mut s = format!(
        "ply\nformat ascii 1.0\ncomment a cloud\nelement vertex {}\nproperty float x\n\
         property float y\nproperty float z\n",
        POINTS.len()
    );
    if colours {
        s += "property uchar red\nproperty uchar green\nproperty uchar blue\n";
    }
    s += "end_header\n";
    for (p, c) in POINTS {
        s += &format!("{} {} {}", p[0], p[1], p[2]);
        if colours {
            s += &format!(" {} {} {}", c[0], c[1], c[2]);
        }
        s += "\n";
    }
    s
}

/// A binary little-endian PLY of the points: float xyz, optional float normals and uchar
/// colours, and an empty face element (as MeshLab writes clouds).
fn binary_ply(normals: bool, colours: bool) -> Vec<u8> {
    let mut h = format!(
        "ply\nformat binary_little_endian 1.0\nelement vertex {}\nproperty float x\n\
         property float y\nproperty float z\n",
        POINTS.len()
    );
    if normals {
        h += "property float nx\nproperty float ny\nproperty float nz\n";
    }
    if colours {
        h += "property uchar red\nproperty uchar green\nproperty uchar blue\n";
    }
    h += "element face 0\nproperty list uchar int vertex_indices\nend_header\n";
    let mut b = h.into_bytes();
    for (i, (p, c)) in POINTS.iter().enumerate() {
        for v in p {
            b.extend(v.to_le_bytes());
        }
        if normals {
            for v in normal(i) {
                b.extend(v.to_le_bytes());
            }
        }
        if colours {
            b.extend(c);
        }
    }
    b
}

/// Pixel (x, y), y down, where the frame of `args` projects the file point `p`.
pub(crate) fn project(args: &[&str], p: [f32; 3]) -> (f64, f64) {
    let (s, scene) = settings_for(args);
    let vp = s.camera.projection(&scene.bounds, W as f32 / H as f32) * s.camera.view();
    let c = vp * scene.to_local(Vec3::from(p).as_dvec3()).extend(1.0);
    let ndc = c.xyz() / c.w;
    (
        f64::from(ndc.x + 1.0) * 0.5 * f64::from(W),
        f64::from(1.0 - ndc.y) * 0.5 * f64::from(H),
    )
}

/// The pixels within `reach` of `c` that `hit` accepts: their count and centroid.
fn disk(img: &Rgba, c: (f64, f64), reach: f64, hit: impl Fn([u8; 4]) -> bool) -> (usize, f64, f64) {
    let (mut n, mut sx, mut sy) = (0, 0.0, 0.0);
    for y in 0..img.height {
        for x in 0..img.width {
            let (px, py) = (f64::from(x) + 0.5, f64::from(y) + 0.5);
            if (px - c.0).hypot(py - c.1) <= reach && hit(img.pixel(x, y)) {
                n += 1;
                sx += px;
                sy += py;
            }
        }
    }
    (n, sx / n.max(1) as f64, sy / n.max(1) as f64)
}

/// Pixel centres within `r` of `c`: what an exact disk covers.
fn lattice(c: (f64, f64), r: f64) -> usize {
    let img = Rgba {
        width: W,
        height: H,
        data: vec![0; (W * H * 4) as usize],
    };
    disk(&img, c, r, |_| true).0
}

pub(crate) fn write(dir: &Path, name: &str, bytes: &[u8]) -> String {
    let p = dir.join(name);
    std::fs::write(&p, bytes).unwrap();
    p.to_str().unwrap().to_string()
}

/// Each point of `file` drawn in `img` is a disk of `size` px in its colour (`colour(i)`,
/// None: anything but the background), centred on its projection.
fn assert_disks(
    name: &str,
    img: &Rgba,
    args: &[&str],
    size: f64,
    colour: &dyn Fn(usize) -> Option<[u8; 3]>,
) {
    let bg = img.pixel(0, 0);
    let r = size / 2.0;
    for (i, (p, _)) in POINTS.iter().enumerate() {
        let c = project(args, *p);
        let want = colour(i);
        let (n, x, y) = disk(img, c, r + 2.0, |px| match want {
            Some(w) => px[..3].iter().zip(w).all(|(a, b)| a.abs_diff(b) <= 1),
            None => px[..3] != bg[..3],
        });
        // Pixel squares whose centres lie in a disk of radius r cover at least the disk of
        // radius r − √2/2 and at most that of r + √2/2: the count is π r² within
        // π(√2 r + 1/2). The exact lattice count is checked tighter: within 2 (centres on
        // the circle itself, f32 projection).
        let area = std::f64::consts::PI * r * r;
        let band = std::f64::consts::PI * (std::f64::consts::SQRT_2 * r + 0.5);
        let exact = lattice(c, r);
        assert!(
            (n as f64 - area).abs() <= band && n.abs_diff(exact) <= 2,
            "{name}: point {i} at {c:?}: {n} pixels, π r² = {area:.1}, exact disk {exact}"
        );
        assert!(
            (x - c.0).hypot(y - c.1) <= 0.5,
            "{name}: point {i}: disk centred at ({x:.2}, {y:.2}), projected {c:?}"
        );
    }
    // Nothing else is drawn: every non-background pixel lies within a disk.
    let centres: Vec<(f64, f64)> = POINTS.iter().map(|(p, _)| project(args, *p)).collect();
    for y in 0..img.height {
        for x in 0..img.width {
            if img.pixel(x, y)[..3] == bg[..3] {
                continue;
            }
            let (px, py) = (f64::from(x) + 0.5, f64::from(y) + 0.5);
            let d = centres
                .iter()
                .map(|c| (px - c.0).hypot(py - c.1))
                .fold(f64::INFINITY, f64::min);
            assert!(
                d <= r + 0.75,
                "{name}: pixel ({x}, {y}) drawn {d:.2} px from any point"
            );
        }
    }
}

/// The cloud as ASCII and binary PLY, with and without colours: every point a disk of the
/// asked size at its projection, in the file's colour (white without), on every context
/// ([`CONTEXTS`]; GL 2.1 needs `GL_VERTEX_PROGRAM_POINT_SIZE` and `GL_POINT_SPRITE`); the
/// CPU reference draws the same disks.
#[test]
fn cloud_points_are_disks_of_the_asked_size() {
    let dir = out_dir("points");
    let files = [
        (
            "ascii-rgb",
            write(&dir, "ascii-rgb.ply", ascii_ply(true).as_bytes()),
            true,
        ),
        (
            "ascii",
            write(&dir, "ascii.ply", ascii_ply(false).as_bytes()),
            false,
        ),
        (
            "binary-rgb",
            write(&dir, "binary-rgb.ply", &binary_ply(false, true)),
            true,
        ),
    ];
    for (name, file, colours) in &files {
        let o = run(&["--check", file], &[]);
        let report = String::from_utf8_lossy(&o.stdout);
        let want = format!(
            "point cloud: 5 points  colours: {}  normals: no",
            if *colours { "yes" } else { "no" }
        );
        assert!(report.contains(&want), "{name}: {report}");
        for size in ["9", "14"] {
            let mut args = vec![file.as_str(), "--point-size", size];
            args.extend_from_slice(VIEW);
            let colour = |i: usize| Some(if *colours { POINTS[i].1 } else { [255; 3] });
            for (ctx, extra, env) in CONTEXTS {
                let mut all = args.clone();
                all.extend_from_slice(extra);
                let tag = format!("{name}-{size}{ctx}");
                let img = render_bin(&dir, &tag, &all, env);
                assert_disks(&tag, &img, &args, size.parse().unwrap(), &colour);
            }
            let reference = reference(&dir, &format!("{name}-{size}"), &args);
            assert_disks(
                &format!("{name}-{size}-ref"),
                &reference,
                &args,
                size.parse().unwrap(),
                &colour,
            );
        }
    }
}

/// Every context kind: the default (in this process), GL 2.1 (Mesa told to be a GL 2.1
/// driver: GLSL 1.20), 3.3 core, ES 3.0, and OSMesa.
pub(crate) type Context = (
    &'static str,
    &'static [&'static str],
    &'static [(&'static str, &'static str)],
);
pub(crate) const CONTEXTS: [Context; 5] = [
    ("", &[], &[]),
    ("-gl21", &["--gl", "2.1"], GL21),
    ("-core", &["--gl", "core"], &[]),
    ("-es3", &["--gl", "es3"], &[]),
    ("-osmesa", &["--backend", "osmesa"], &[]),
];

/// [`render`], through the binary (a context of its own) for every context but the default.
pub(crate) fn render_bin(dir: &Path, name: &str, args: &[&str], env: &[(&str, &str)]) -> Rgba {
    if args.iter().all(|a| !["--gl", "--backend"].contains(a)) {
        return render(dir, name, args, env);
    }
    let out = dir.join(format!("{name}.png"));
    let mut all = args.to_vec();
    all.extend_from_slice(&["-o", out.to_str().unwrap()]);
    let o = run(&all, env);
    assert!(
        o.status.success(),
        "{name}: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    let img = Rgba::load_png(&out).unwrap();
    check_frame(&img, name);
    img
}

/// The reference renderer's picture for `args`.
pub(crate) fn reference(dir: &Path, name: &str, args: &[&str]) -> Rgba {
    let out = dir.join(format!("{name}-ref.png"));
    let mut r = args.to_vec();
    r.extend_from_slice(&["--reference", "-o", out.to_str().unwrap()]);
    let o = run(&r, &[]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    Rgba::load_png(&out).unwrap()
}

/// With normals the points are lit (the tier's formula at the point, one colour per disk):
/// the same disks, each within 2/255 of the reference's colour, on every context; in the PBR
/// tier (unlit and lit) the same coverage, and lit each within [`PBR_TOLERANCE`] of the
/// reference's colour (default context and GL 2.1).
#[test]
fn lit_cloud_points_match_the_reference() {
    let dir = out_dir("points-lit");
    let file = write(&dir, "lit.ply", &binary_ply(true, true));
    let o = run(&["--check", &file], &[]);
    let report = String::from_utf8_lossy(&o.stdout);
    assert!(
        report.contains("point cloud: 5 points  colours: yes  normals: yes"),
        "{report}"
    );
    let mut args = vec![file.as_str(), "--point-size", "11"];
    args.extend_from_slice(VIEW);
    let reference = reference(&dir, "lit", &args);
    assert_disks("lit-ref", &reference, &args, 11.0, &|_| None);
    for (ctx, extra, env) in CONTEXTS {
        let mut all = args.clone();
        all.extend_from_slice(extra);
        let img = render_bin(&dir, &format!("lit{ctx}"), &all, env);
        assert_disks(&format!("lit{ctx}"), &img, &args, 11.0, &|_| None);
        for (i, (p, _)) in POINTS.iter().enumerate() {
            let c = project(&args, *p);
            let (x, y) = (c.0 as u32, c.1 as u32);
            let (g, r) = (img.pixel(x, y), reference.pixel(x, y));
            let d = (0..3).map(|k| g[k].abs_diff(r[k])).max().unwrap();
            assert!(d <= 2, "lit{ctx}: point {i}: GPU {g:?}, reference {r:?}");
        }
    }
    for (name, file) in [
        ("pbr-lit", file.clone()),
        (
            "pbr-unlit",
            write(&dir, "unlit.ply", &binary_ply(false, true)),
        ),
    ] {
        let mut a = vec![file.as_str(), "--point-size", "11", "--shading", "pbr"];
        a.extend_from_slice(VIEW);
        a.extend_from_slice(&["--background", "0.1,0.1,0.12"]);
        let img = render(&dir, name, &a, &[]);
        assert_disks(name, &img, &a, 11.0, &|_| None);
        if name == "pbr-lit" {
            // Lit in the PBR tier: the reference's formula (Monte Carlo environment, exact
            // BRDF) at each centre, against the split sum.
            let truth = self::reference(&dir, name, &a);
            assert_disks("pbr-lit-ref", &truth, &a, 11.0, &|_| None);
            assert_centres_match(name, &img, &truth, &a, PBR_TOLERANCE);
            let (ctx, extra, env) = CONTEXTS[1];
            let gl21 = render_bin(&dir, &format!("{name}{ctx}"), &[&a, extra].concat(), env);
            assert_centres_match(&format!("{name}{ctx}"), &gl21, &truth, &a, PBR_TOLERANCE);
        }
    }
}

/// The largest channel difference of a lit point's centre between the PBR tier and the
/// reference: the split sum against the Monte Carlo environment (measured: up to 1/255).
pub(crate) const PBR_TOLERANCE: u8 = 3;

/// Each point's centre pixel within `tolerance` of the reference's.
fn assert_centres_match(name: &str, img: &Rgba, reference: &Rgba, args: &[&str], tolerance: u8) {
    for (i, (p, _)) in POINTS.iter().enumerate() {
        let c = project(args, *p);
        let (x, y) = (c.0 as u32, c.1 as u32);
        let (g, r) = (img.pixel(x, y), reference.pixel(x, y));
        let d = (0..3).map(|k| g[k].abs_diff(r[k])).max().unwrap();
        eprintln!("{name}: point {i}: GPU {g:?}, reference {r:?}");
        assert!(
            d <= tolerance,
            "{name}: point {i}: GPU {g:?}, reference {r:?}"
        );
    }
}

/// An OBJ of `v` lines only is a cloud: `--check` says so and every vertex is a disk.
#[test]
fn obj_of_vertices_only_is_a_cloud() {
    let dir = out_dir("points-obj");
    let text: String = POINTS
        .iter()
        .map(|(p, _)| format!("v {} {} {}\n", p[0], p[1], p[2]))
        .collect();
    let file = write(&dir, "cloud.obj", text.as_bytes());
    let o = run(&["--check", &file], &[]);
    let report = String::from_utf8_lossy(&o.stdout);
    assert!(
        report.contains("point cloud: 5 points  colours: no  normals: no"),
        "{report}"
    );
    let mut args = vec![file.as_str(), "--point-size", "9"];
    args.extend_from_slice(VIEW);
    let img = render(&dir, "obj", &args, &[]);
    assert_disks("obj", &img, &args, 9.0, &|_| None);
}

/// MeshPrimitiveModes' POINTS primitive (seven points on a hexagon and its centre, Khronos's
/// reference shows visible dots): drawn at the default size, which for points this sparse is
/// the largest default (8 px): every pixel centre within 3.5 px of each projected point is
/// drawn.
#[test]
fn gltf_points_are_visible_dots_of_the_default_size() {
    let dir = out_dir("points-gltf");
    let model = shared().join("gltf-samples/MeshPrimitiveModes/MeshPrimitiveModes.gltf");
    let model = model.to_str().unwrap();
    let mut args = vec![model];
    args.extend_from_slice(VIEW);
    let (s, scene) = settings_for(&args);
    assert_eq!(s.lighting.point_size, (glview::frame::MAX_POINT_PX, H));
    assert_eq!(scene.wire.points.len(), 7);
    let img = render(&dir, "modes", &args, &[]);
    let bg = img.pixel(0, 0);
    let vp = s.camera.projection(&scene.bounds, W as f32 / H as f32) * s.camera.view();
    for &i in &scene.wire.points {
        let c = vp * Vec3::from(scene.wire.positions[i as usize]).extend(1.0);
        let ndc = c.xyz() / c.w;
        let c = (
            f64::from(ndc.x + 1.0) * 0.5 * f64::from(W),
            f64::from(1.0 - ndc.y) * 0.5 * f64::from(H),
        );
        let (n, _, _) = disk(&img, c, 3.5, |p| p[..3] != bg[..3]);
        assert_eq!(n, lattice(c, 3.5), "point {i} at {c:?}: not a full dot");
    }
}

/// A million-point binary PLY with colours and normals loads and renders (run with
/// `--ignored`; prints the load and render times and the peak memory).
#[test]
#[ignore]
fn million_point_cloud_loads_and_renders() {
    let dir = out_dir("points-1m");
    let n = 1_000_000u32;
    let mut b = format!(
        "ply\nformat binary_little_endian 1.0\nelement vertex {n}\nproperty float x\n\
         property float y\nproperty float z\nproperty float nx\nproperty float ny\n\
         property float nz\nproperty uchar red\nproperty uchar green\nproperty uchar blue\n\
         end_header\n"
    )
    .into_bytes();
    // A noisy torus knot-free torus: points spread on a surface, as a scan's are.
    let mut seed = 12345u64;
    let mut rnd = || {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (seed >> 40) as f32 / (1u64 << 24) as f32
    };
    for _ in 0..n {
        let (u, v) = (rnd() * std::f32::consts::TAU, rnd() * std::f32::consts::TAU);
        let (big, small) = (1.0, 0.35);
        let nrm = Vec3::new(v.cos() * u.cos(), v.sin(), v.cos() * u.sin());
        let p = Vec3::new(big * u.cos(), 0.0, big * u.sin()) + small * nrm;
        for x in p.to_array().into_iter().chain(nrm.to_array()) {
            b.extend(x.to_le_bytes());
        }
        b.extend([(u * 40.0) as u8, (v * 40.0) as u8, 200]);
    }
    let file = write(&dir, "million.ply", &b);
    let out = dir.join("million.png");
    for args in [
        vec!["--check", file.as_str()],
        vec![
            file.as_str(),
            "-o",
            out.to_str().unwrap(),
            "--size",
            "640x480",
        ],
    ] {
        let rss = dir.join("rss");
        let script = format!(
            "exec /usr/bin/time -o '{}' -f '%e s, peak RSS %M KB' '{}' {}",
            rss.display(),
            bin(),
            args.iter()
                .map(|a| format!("'{a}'"))
                .collect::<Vec<_>>()
                .join(" ")
        );
        let o = std::process::Command::new("sh")
            .args(["-c", &script])
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let stdout = String::from_utf8_lossy(&o.stdout);
        if args[0] == "--check" {
            assert!(
                stdout.contains("point cloud: 1000000 points  colours: yes  normals: yes"),
                "{stdout}"
            );
        }
        eprintln!(
            "{:?}: {}",
            args[0],
            std::fs::read_to_string(&rss).unwrap().trim()
        );
    }
    let img = Rgba::load_png(&out).unwrap();
    check_frame(&img, "million");
}

/// The default size is 1.5 spacings as the fitted view shows them, within 2..8 px: a 100×100
/// lattice of pitch 0.03 (every nearest distance 0.03) seen face on.
#[test]
fn default_size_follows_the_spacing() {
    let dir = out_dir("points-default");
    let mut text = String::from(
        "ply\nformat ascii 1.0\nelement vertex 10000\nproperty float x\nproperty float y\n\
         property float z\nend_header\n",
    );
    for i in 0..100 {
        for j in 0..100 {
            text += &format!("{} {} 0\n", i as f32 * 0.03, j as f32 * 0.03);
        }
    }
    let file = write(&dir, "lattice.ply", text.as_bytes());
    for size in ["320x240", "640x480"] {
        let (s, _) = settings_for(&[&file, "--size", size, "--yaw", "0", "--pitch", "0"]);
        let h: f32 = size.split('x').nth(1).unwrap().parse().unwrap();
        let c = &s.camera;
        let view_height = 2.0 * c.distance * (c.fov_y_deg.to_radians() * 0.5).tan();
        let want = (1.5 * 0.03 * h / view_height).clamp(2.0, 8.0);
        let got = s.lighting.point_size.0;
        assert!(
            (got - want).abs() < 1e-3 * want,
            "{size}: {got} px, want {want}"
        );
        assert!(
            got > 2.0 && got < 8.0,
            "{size}: {got} px is clamped; pick another lattice"
        );
    }
}

/// OBJ clouds carry colours (`v x y z r g b`, 0–1 or 0–255) and one `vn` per `v` as
/// normals: `--check` says so, the disks take the colours (times the default Kd), and with normals they are lit as
/// the reference lights them (within 2/255 at each centre); glTF POINTS use COLOR_0 (linear,
/// shown encoded) and NORMAL the same way.
#[test]
fn obj_and_gltf_point_colours_and_normals() {
    let dir = out_dir("points-attrs");
    let v = |scale: f32| -> String {
        POINTS
            .iter()
            .map(|(p, c)| {
                let c = c.map(|x| f32::from(x) / 255.0 * scale);
                format!("v {} {} {} {} {} {}\n", p[0], p[1], p[2], c[0], c[1], c[2])
            })
            .collect()
    };
    let vn: String = (0..POINTS.len())
        .map(|i| {
            let n = normal(i);
            format!("vn {} {} {}\n", n[0], n[1], n[2])
        })
        .collect();
    let unit = write(&dir, "rgb.obj", v(1.0).as_bytes());
    let bytes = write(&dir, "rgb255.obj", v(255.0).as_bytes());
    let lit = write(&dir, "lit.obj", (v(1.0) + &vn).as_bytes());
    let gltf = write_gltf(&dir);
    for (file, normals) in [(&unit, "no"), (&bytes, "no"), (&lit, "yes"), (&gltf, "yes")] {
        let o = run(&["--check", file], &[]);
        let report = String::from_utf8_lossy(&o.stdout);
        let want = format!("point cloud: 5 points  colours: yes  normals: {normals}");
        assert!(report.contains(&want), "{file}: {report}");
    }
    for (name, file) in [("rgb", &unit), ("rgb255", &bytes)] {
        let mut args = vec![file.as_str(), "--point-size", "9"];
        args.extend_from_slice(VIEW);
        let img = render(&dir, name, &args, &[]);
        // OBJ's default material (Kd 0.8) multiplies vertex colours, as on its meshes.
        let kd = |i: usize| Some(POINTS[i].1.map(|c| (f32::from(c) * 0.8).round() as u8));
        assert_disks(name, &img, &args, 9.0, &kd);
    }
    for (name, file) in [("lit-obj", &lit), ("lit-gltf", &gltf)] {
        let mut args = vec![file.as_str(), "--point-size", "11"];
        args.extend_from_slice(VIEW);
        let img = render(&dir, name, &args, &[]);
        let reference = reference(&dir, name, &args);
        assert_disks(name, &img, &args, 11.0, &|_| None);
        let mut unlit = 0;
        for (i, (p, c)) in POINTS.iter().enumerate() {
            let (x, y) = project(&args, *p);
            let (g, r) = (
                img.pixel(x as u32, y as u32),
                reference.pixel(x as u32, y as u32),
            );
            let d = (0..3).map(|k| g[k].abs_diff(r[k])).max().unwrap();
            assert!(d <= 2, "{name}: point {i}: GPU {g:?}, reference {r:?}");
            unlit += usize::from(g[..3] == c[..]);
        }
        assert!(
            unlit < POINTS.len(),
            "{name}: every point in its plain colour: unlit"
        );
    }
}

/// A glTF of one POINTS primitive over [`POINTS`], with NORMAL and COLOR_0 (the colours are
/// 0 or 1 per channel, the same linear or encoded), its buffer beside it.
fn write_gltf(dir: &Path) -> String {
    let mut bin = Vec::new();
    for (p, _) in POINTS {
        p.iter().for_each(|x| bin.extend(x.to_le_bytes()));
    }
    for i in 0..POINTS.len() {
        normal(i).iter().for_each(|x| bin.extend(x.to_le_bytes()));
    }
    for (_, c) in POINTS {
        c.iter()
            .for_each(|&x| bin.extend((f32::from(x) / 255.0).to_le_bytes()));
    }
    std::fs::write(dir.join("points.bin"), &bin).unwrap();
    let n = POINTS.len();
    let view = |k: usize| {
        format!(
            r#"{{"buffer":0,"byteOffset":{},"byteLength":{}}}"#,
            k * n * 12,
            n * 12
        )
    };
    let acc = |k: usize, minmax: &str| {
        format!(r#"{{"bufferView":{k},"componentType":5126,"count":{n},"type":"VEC3"{minmax}}}"#)
    };
    let json = format!(
        r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[0]}}],"nodes":[{{"mesh":0}}],
"meshes":[{{"primitives":[{{"mode":0,"attributes":{{"POSITION":0,"NORMAL":1,"COLOR_0":2}}}}]}}],
"buffers":[{{"uri":"points.bin","byteLength":{}}}],"bufferViews":[{},{},{}],"accessors":[{},{},{}]}}"#,
        bin.len(),
        view(0),
        view(1),
        view(2),
        acc(0, r#","min":[-1,-1,-0.5],"max":[1,1,0.5]"#),
        acc(1, ""),
        acc(2, ""),
    );
    write(dir, "points.gltf", json.as_bytes())
}
