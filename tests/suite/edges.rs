//! `--edges` and `--wireframe` (`scene/edges.rs`, `render/edges.rs`) against the projected
//! segments: on a cube, every pixel in the line colour lies on a visible projected segment
//! and every visible segment is covered, from several views and on every context; the CPU
//! reference draws the same lines; `--keys E` is `--edges`.
use crate::common::*;
use glam::{DMat4, DVec2, DVec3, DVec4};
use glview::image_out::Rgba;
use std::path::Path;

const W: u32 = 240;
const H: u32 = 180;
/// The line colour, one no shaded pixel of the grey cube can have.
const MAGENTA: [u8; 3] = [255, 0, 255];

/// (yaw, pitch): oblique from above, face-on (the back face's edges project inside the
/// front face's and must not show), from below, from behind.
const VIEWS: &[(f32, f32)] = &[(30.0, 25.0), (0.0, 0.0), (-120.0, -40.0), (200.0, 10.0)];

/// The cube's OBJ, one file per test (tests run in parallel).
fn cube(dir: &Path, test: &str) -> String {
    let path = dir.join(format!("cube_{test}.obj"));
    std::fs::write(&path, box_obj([-1.0; 3], [1.0; 3], 0)).unwrap();
    path.to_str().unwrap().to_string()
}

fn args(model: &str, view: (f32, f32), extra: &[&str]) -> Vec<String> {
    let mut a: Vec<String> = [
        model,
        "--size",
        &format!("{W}x{H}"),
        "--yaw",
        &view.0.to_string(),
        "--pitch",
        &view.1.to_string(),
        "--edge-color",
        "1,0,1",
        "--no-shadows",
    ]
    .iter()
    .map(|s| s.to_string())
    .collect();
    a.extend(extra.iter().map(|s| s.to_string()));
    a
}

fn words(a: &[String]) -> Vec<&str> {
    a.iter().map(String::as_str).collect()
}

/// The segments a convex mesh shows in pixels (x right, y down): `edges` as corner pairs
/// (local positions) with the faces each bounds; an edge shows when one of its faces faces
/// the eye. Also the hidden ones.
struct Projected {
    visible: Vec<(DVec2, DVec2)>,
    hidden: Vec<(DVec2, DVec2)>,
}

fn project(a: &[String], edges: &[([DVec3; 2], Vec<[DVec3; 3]>)]) -> Projected {
    let (s, scene) = settings_for(&words(a));
    let vp: DMat4 =
        (s.camera.projection(&scene.bounds, W as f32 / H as f32) * s.camera.view()).as_dmat4();
    let eye = s.camera.eye().as_dvec3();
    let px = |p: DVec3| {
        let c = vp * DVec4::new(p.x, p.y, p.z, 1.0);
        DVec2::new(
            (c.x / c.w + 1.0) * 0.5 * f64::from(W),
            (1.0 - c.y / c.w) * 0.5 * f64::from(H),
        )
    };
    let mut out = Projected {
        visible: Vec::new(),
        hidden: Vec::new(),
    };
    for ([a, b], faces) in edges {
        let front = faces.iter().any(|[p, q, r]| {
            let n = (*q - *p).cross(*r - *p);
            (*p - eye).dot(n) < 0.0
        });
        let seg = (px(*a), px(*b));
        if front {
            out.visible.push(seg);
        } else {
            out.hidden.push(seg);
        }
    }
    out
}

/// The cube's corners as loaded (local coordinates) and its triangles.
fn triangles(a: &[String]) -> Vec<[DVec3; 3]> {
    let (_, scene) = settings_for(&words(a));
    let m = &scene.meshes[0];
    m.indices
        .chunks_exact(3)
        .map(|t| {
            let p = |k: usize| DVec3::from(m.vertices[t[k] as usize].position.map(f64::from));
            [p(0), p(1), p(2)]
        })
        .collect()
}

/// The 12 cube edges (corner pairs differing in one coordinate), or with `wire` every
/// triangle edge, each with the triangles that hold it.
fn cube_edges(a: &[String], wire: bool) -> Vec<([DVec3; 2], Vec<[DVec3; 3]>)> {
    let tris = triangles(a);
    let mut corners: Vec<DVec3> = tris.iter().flatten().copied().collect();
    corners.sort_by(|p, q| p.to_array().partial_cmp(&q.to_array()).unwrap());
    corners.dedup();
    assert_eq!(corners.len(), 8);
    let mut out = Vec::new();
    for (i, &p) in corners.iter().enumerate() {
        for &q in &corners[i + 1..] {
            let differ = (0..3).filter(|&k| p[k] != q[k]).count();
            let on = |t: &[DVec3; 3]| t.contains(&p) && t.contains(&q);
            let faces: Vec<[DVec3; 3]> = tris.iter().filter(|t| on(t)).copied().collect();
            if (differ == 1) || (wire && !faces.is_empty()) {
                out.push(([p, q], faces));
            }
        }
    }
    assert_eq!(out.len(), if wire { 18 } else { 12 });
    out
}

fn distance(p: DVec2, (a, b): (DVec2, DVec2)) -> f64 {
    let d = b - a;
    let t = ((p - a).dot(d) / d.length_squared()).clamp(0.0, 1.0);
    (a + d * t - p).length()
}

fn line_pixels(img: &Rgba) -> Vec<DVec2> {
    let mut v = Vec::new();
    for y in 0..img.height {
        for x in 0..img.width {
            let i = 4 * (y * img.width + x) as usize;
            if img.data[i..i + 3] == MAGENTA {
                v.push(DVec2::new(f64::from(x) + 0.5, f64::from(y) + 0.5));
            }
        }
    }
    v
}

/// Every line pixel within a pixel of a visible segment; every visible segment covered
/// (each point along it, its end pixels aside, has a line pixel within 1.5 px).
fn check_lines(name: &str, img: &Rgba, p: &Projected) {
    check_wide_lines(name, img, p, 1.0);
}

/// [`check_lines`] for lines `width` pixels wide: every line pixel within width/2 + ½ px
/// of a visible segment (its square cap reaching width/2 past the end).
fn check_wide_lines(name: &str, img: &Rgba, p: &Projected, width: f64) {
    let reach = if width > 1.0 { width / 2.0 + 0.75 } else { 1.0 };
    let pixels = line_pixels(img);
    assert!(!pixels.is_empty(), "{name}: no line pixels");
    for &q in &pixels {
        let d = p
            .visible
            .iter()
            .map(|&s| distance(q, s))
            .fold(f64::INFINITY, f64::min);
        assert!(
            d <= reach,
            "{name}: line pixel at {q} is {d:.2} px from every visible segment"
        );
    }
    for &(a, b) in &p.visible {
        let len = (b - a).length();
        let steps = len.floor() as usize;
        for k in 2..steps.saturating_sub(1) {
            let q = a + (b - a) * (k as f64 / len);
            let near = pixels.iter().any(|&x| (x - q).length() <= 1.5);
            assert!(near, "{name}: segment {a}–{b} not drawn near {q}");
        }
    }
}

fn render_view(dir: &Path, name: &str, a: &[String], env: &[(&str, &str)]) -> Rgba {
    render(dir, name, &words(a), env)
}

/// `--edges` on a cube: exactly its 12 edges, hidden ones not drawn, on `env`'s context.
fn cube_edges_on(tag: &str, env: &[(&str, &str)], extra: &[&str]) {
    let dir = out_dir("edges");
    let model = cube(&dir, tag);
    for &view in VIEWS {
        let mut e = vec!["--edges"];
        e.extend_from_slice(extra);
        let a = args(&model, view, &e);
        let name = format!("cube_edges_{tag}_{}_{}", view.0, view.1);
        let img = render_view(&dir, &name, &a, env);
        let p = project(&a, &cube_edges(&a, false));
        assert!(!p.visible.is_empty() && !p.hidden.is_empty());
        if extra.contains(&"log") {
            // Log depth's offset is fwidth of the written depth, a 2×2 quad's estimate: a
            // hidden edge may show a pixel at the corner where it leaves a visible one.
            check_wide_lines(&name, &img, &p, 1.5);
        } else {
            check_lines(&name, &img, &p);
        }
    }
}

#[test]
fn cube_edges_default_context() {
    cube_edges_on("default", &[], &[]);
    // Logarithmic depth writes gl_FragDepth, which the surface's offset does not reach.
    cube_edges_on("logz", &[], &["--depth", "log"]);
}

#[test]
fn cube_edges_gl21() {
    cube_edges_on("gl21", GL21, &[]);
}

#[test]
fn cube_edges_es3_core_and_osmesa() {
    // An environment entry sends the render to the binary, which makes the asked context.
    let env = &[("GLVIEW_TEST_CONTEXT", "1")];
    cube_edges_on("es3", env, &["--gl", "es3"]);
    cube_edges_on("core", env, &["--gl", "core"]);
    cube_edges_on("osmesa", env, &["--backend", "osmesa"]);
    // OSMesa's own buffer on GL 2.1 without framebuffer or vertex array objects.
    cube_edges_on("osmesa_nofbo", GL21_NO_FBO, &["--backend", "osmesa"]);
}

/// Wireframe: the 18 triangle edges, the face diagonals included, on the default context
/// and GL 2.1; without the surface (`--wireframe-only`) the same lines over the background.
#[test]
fn cube_wireframe_covers_the_triangle_edges() {
    let dir = out_dir("edges");
    let model = cube(&dir, "wire");
    for (tag, env) in [("default", &[][..]), ("gl21", GL21)] {
        for &view in &VIEWS[..2] {
            let a = args(&model, view, &["--wireframe"]);
            let name = format!("cube_wire_{tag}_{}_{}", view.0, view.1);
            let img = render_view(&dir, &name, &a, env);
            check_lines(&name, &img, &project(&a, &cube_edges(&a, true)));
        }
    }
    let a = args(&model, VIEWS[0], &["--wireframe-only"]);
    let img = render_view(&dir, "cube_wire_only", &a, &[]);
    check_lines("wire_only", &img, &project(&a, &cube_edges(&a, true)));
    let background = [26u8, 26, 31];
    let other = img
        .data
        .chunks_exact(4)
        .filter(|p| p[..3] != MAGENTA && p[..3] != background)
        .count();
    assert_eq!(other, 0, "--wireframe-only: only lines and background");
}

/// `--line-width 3`: quads widened in the vertex shader, on the default context and GL 2.1:
/// the line pixels within 2.25 px of the visible segments, every segment covered, about
/// three times the 1-pixel lines' count.
#[test]
fn wide_lines_keep_their_width() {
    let dir = out_dir("edges");
    let model = cube(&dir, "wide");
    for (tag, env) in [("default", &[][..]), ("gl21", GL21)] {
        for &view in &VIEWS[..2] {
            let a = args(&model, view, &["--edges", "--line-width", "3"]);
            let name = format!("cube_wide_{tag}_{}_{}", view.0, view.1);
            let img = render_view(&dir, &name, &a, env);
            let p = project(&a, &cube_edges(&a, false));
            check_wide_lines(&name, &img, &p, 3.0);
            let thin = render_view(
                &dir,
                &format!("{name}_thin"),
                &args(&model, view, &["--edges"]),
                env,
            );
            let ratio = line_pixels(&img).len() as f64 / line_pixels(&thin).len() as f64;
            assert!(
                (2.5..=3.6).contains(&ratio),
                "{name}: {ratio:.2} times the 1-pixel lines' pixels"
            );
        }
    }
}

/// `--edge-method barycentric`: the same 12 edges drawn on the triangles (2 pixels wide,
/// so a 1-pixel core is fully inside both faces), on the default context and GL 2.1.
#[test]
fn barycentric_edges_are_the_cube_edges() {
    let dir = out_dir("edges");
    let model = cube(&dir, "bary");
    for (tag, env) in [("default", &[][..]), ("gl21", GL21)] {
        for &view in &VIEWS[..3] {
            let extra = [
                "--edges",
                "--edge-method",
                "barycentric",
                "--line-width",
                "2",
            ];
            let a = args(&model, view, &extra);
            let name = format!("cube_bary_{tag}_{}_{}", view.0, view.1);
            let img = render_view(&dir, &name, &a, env);
            check_wide_lines(&name, &img, &project(&a, &cube_edges(&a, false)), 2.0);
        }
    }
}

/// The CPU reference draws the same lines: its line pixels and the GPU's each within a
/// pixel of the other's, in nearly the same number.
#[test]
fn reference_draws_the_same_edges() {
    let dir = out_dir("edges");
    let model = cube(&dir, "reference");
    for (i, &view) in VIEWS.iter().enumerate() {
        for mode in [
            &["--edges"][..],
            &["--wireframe"],
            &["--edges", "--line-width", "3"],
        ] {
            let a = args(&model, view, mode);
            let gpu = render_view(&dir, &format!("ref_gpu_{i}{}", mode.join("")), &a, &[]);
            let (s, scene) = settings_for(&words(&a));
            let cpu = glview::reference::render(&scene, &s, W, H);
            let (g, c) = (line_pixels(&gpu), line_pixels(&cpu));
            let near = |q: DVec2, set: &[DVec2]| set.iter().any(|&x| (x - q).length() <= 1.5);
            let g_off = g.iter().filter(|&&q| !near(q, &c)).count();
            let c_off = c.iter().filter(|&&q| !near(q, &g)).count();
            assert!(
                g_off == 0 && c_off == 0,
                "view {view:?} {mode:?}: {g_off} GPU line pixels away from the reference's, {c_off} the other way ({} / {})",
                g.len(),
                c.len()
            );
            let ratio = g.len() as f64 / c.len() as f64;
            assert!(
                (0.9..=1.1).contains(&ratio),
                "view {view:?} {mode:?}: {} GPU line pixels, {} reference",
                g.len(),
                c.len()
            );
        }
    }
}

/// The `E` key cycles off → edges → wireframe → off, and replays as the options do.
#[test]
fn key_e_replays_as_the_options() {
    let dir = out_dir("edges");
    let model = cube(&dir, "keys");
    let pic =
        |name: &str, extra: &[&str]| render_view(&dir, name, &args(&model, VIEWS[0], extra), &[]);
    let edges = pic("opt_edges", &["--edges"]);
    assert_eq!(pic("key_e", &["--keys", "E"]).data, edges.data);
    assert_eq!(
        pic("key_ee", &["--keys", "E E"]).data,
        pic("opt_wire", &["--wireframe"]).data
    );
    assert_eq!(
        pic("key_eee", &["--keys", "E E E"]).data,
        pic("opt_none", &[]).data
    );
}

/// `--check` counts the edges `--edges` and `--wireframe` draw: a cube's 12 creased edges
/// of 18 triangle edges at the default crease angle, none creased above 90°; an open mesh's
/// boundary.
#[test]
fn check_counts_the_edges() {
    let dir = out_dir("edges");
    let model = cube(&dir, "check");
    let check = |extra: &[&str]| {
        let mut a = vec!["--check", model.as_str()];
        a.extend_from_slice(extra);
        String::from_utf8_lossy(&run(&a, &[]).stdout).to_string()
    };
    let r = check(&[]);
    assert!(
        r.contains("edges: 12 feature at 60° (12 creased, 0 boundary, 0 non-manifold) of 18 triangle edges"),
        "{r}"
    );
    let r = check(&["--crease", "95"]);
    assert!(r.contains("edges: 0 feature at 95° (0 creased"), "{r}");
    let open = dir.join("open_box.obj");
    let text: String = box_obj([-1.0; 3], [1.0; 3], 0)
        .lines()
        .filter(|l| !l.starts_with('f'))
        .chain(
            box_obj([-1.0; 3], [1.0; 3], 0)
                .lines()
                .filter(|l| l.starts_with('f'))
                .take(10),
        )
        .map(|l| format!("{l}\n"))
        .collect();
    std::fs::write(&open, text).unwrap();
    let r =
        String::from_utf8_lossy(&run(&["--check", open.to_str().unwrap()], &[]).stdout).to_string();
    assert!(r.contains("4 boundary"), "{r}");
}
