//! Cluster culling (`scene::clusters`, `render/cull.rs`) changes no pixel: large meshes drawn
//! by their visible clusters against the same meshes sent whole (`--no-culling`), from views
//! where back faces are hidden (outside a closed sphere), where they are not (camera inside
//! it, the near plane cutting it open, an open bowl, x-rayed glass), and for every kind of
//! shadow map (directional, point light outside, point light inside: the six-face atlas).
//! With `--lod off`: coarser levels change pixels by design (tests/suite/lod.rs bounds them).
use crate::common::*;
use std::fmt::Write;
use std::path::Path;

/// A UV sphere (unit radius, outward winding, `vn` = position) with 2·segments·(rings − 1)
/// triangles; `bowl` keeps only the upper half (an open mesh).
pub(crate) fn sphere_obj(rings: u32, segments: u32, bowl: bool) -> String {
    let mut s = String::from("o sphere\n");
    let mut vertex = |p: [f64; 3]| {
        writeln!(
            s,
            "v {:.6} {:.6} {:.6}\nvn {0:.6} {1:.6} {2:.6}",
            p[0], p[1], p[2]
        )
        .unwrap();
    };
    vertex([0.0, 1.0, 0.0]);
    for j in 1..rings {
        let th = std::f64::consts::PI * f64::from(j) / f64::from(rings);
        for i in 0..segments {
            let ph = std::f64::consts::TAU * f64::from(i) / f64::from(segments);
            vertex([th.sin() * ph.sin(), th.cos(), th.sin() * ph.cos()]);
        }
    }
    vertex([0.0, -1.0, 0.0]);
    let at = |j: u32, i: u32| 2 + (j - 1) * segments + i % segments;
    let south = 2 + (rings - 1) * segments;
    let mut f = |a: u32, b: u32, c: u32| writeln!(s, "f {a}//{a} {b}//{b} {c}//{c}").unwrap();
    let last = if bowl { rings / 2 } else { rings - 1 };
    for i in 0..segments {
        f(1, at(1, i), at(1, i + 1));
        if !bowl {
            f(south, at(rings - 1, i + 1), at(rings - 1, i));
        }
    }
    for j in 1..last {
        for i in 0..segments {
            f(at(j, i), at(j + 1, i), at(j + 1, i + 1));
            f(at(j, i), at(j + 1, i + 1), at(j, i + 1));
        }
    }
    s
}

fn write(dir: &Path, name: &str, text: &str) -> String {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p.to_str().unwrap().to_string()
}

#[test]
fn culled_frames_equal_whole_meshes_from_every_view() {
    let dir = out_dir("culling");
    // 2·160·80 = 25,600 triangles: above clusters::MIN_TRIANGLES, so it is clustered.
    let sphere = write(&dir, "sphere.obj", &sphere_obj(81, 160, false));
    let bowl = write(&dir, "bowl.obj", &sphere_obj(161, 160, true));
    let cases: &[(&str, &str, &[&str])] = &[
        ("outside", &sphere, &[]),
        ("ortho", &sphere, &["--ortho"]),
        (
            "inside",
            &sphere,
            &["--target", "0,0,0", "--distance", "0.4"],
        ),
        (
            "near_cuts",
            &sphere,
            &["--distance", "1.1", "--near", "0.3"],
        ),
        ("point_outside", &sphere, &["--light", "point:2.5,3,2"]),
        (
            "point_inside",
            &sphere,
            &[
                "--light",
                "point:0,0.3,0.2",
                "--distance",
                "0.5",
                "--target",
                "0,0,0",
            ],
        ),
        ("bowl", &bowl, &["--pitch", "-60"]),
        ("xray", &sphere, &["--xray", "sphere"]),
    ];
    for (name, model, extra) in cases {
        let mut args = vec![*model, "--size", "160x120", "--yaw", "35", "--lod", "off"];
        if !extra.contains(&"--pitch") {
            args.extend(["--pitch", "20"]);
        }
        args.extend_from_slice(extra);
        let culled = render(&dir, &format!("{name}-culled"), &args, &[]);
        args.push("--no-culling");
        let whole = render(&dir, &format!("{name}-whole"), &args, &[]);
        let d = diff(&culled, &whole, 0);
        if d.max > 0 {
            let p = write_diff(&dir, name, &culled, &whole);
            panic!(
                "{name}: culling changed {} pixels (max {}/255); see {}",
                d.over,
                d.max,
                p.display()
            );
        }
    }
}

/// `--stats`: culling keeps triangles from the GPU where it may, and none where it may not.
#[test]
fn stats_count_the_triangles_kept_from_the_gpu() {
    let dir = out_dir("culling_stats");
    let sphere = write(&dir, "sphere.obj", &sphere_obj(81, 160, false));
    let out = dir.join("s.png");
    let stats_of = |model: &str, extra: &[&str]| -> serde_json::Value {
        let mut a = vec![
            model,
            "-o",
            out.to_str().unwrap(),
            "--size",
            "96x72",
            "--stats",
            "--lod",
            "off",
        ];
        a.extend_from_slice(extra);
        let o = run(&a, &[]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        serde_json::from_str(String::from_utf8_lossy(&o.stdout).lines().last().unwrap()).unwrap()
    };
    let stats = |extra: &[&str]| stats_of(&sphere, extra);
    let total = 25_600u64;
    // Outside, no shadows: from a perspective eye more than half the sphere faces away
    // (the visible cap is smaller than a hemisphere), less the clusters that straddle the
    // silhouette (each is 0.25 % of this small sphere; measured: 51 % of all triangles).
    let s = stats(&["--no-shadows"]);
    let (drawn, skipped) = (
        s["triangles"].as_u64().unwrap(),
        s["triangles_skipped"].as_u64().unwrap(),
    );
    assert_eq!(drawn + skipped, total, "{s}");
    assert!(
        skipped > total / 4 && skipped < total * 3 / 4,
        "skipped {skipped} of {total}"
    );
    // An open bowl seen from below (into its hollow) and framed whole: no cluster lies outside
    // the view, and its back faces show (it is not closed), so nothing is kept back.
    let bowl = write(&dir, "bowl.obj", &sphere_obj(161, 160, true));
    let s = stats_of(&bowl, &["--no-shadows", "--pitch", "-60"]);
    assert_eq!(s["triangles_skipped"], 0, "{s}");
    // 25,440 triangles: above MIN_TRIANGLES, so clustered.
    assert_eq!(s["triangles"], 160 + 79 * 320, "{s}");
    // Off: every triangle goes.
    let s = stats(&["--no-shadows", "--no-culling"]);
    assert_eq!(
        (s["triangles"].as_u64(), s["triangles_skipped"].as_u64()),
        (Some(total), Some(0))
    );
}

/// A UV sphere as exporters write it (Blender-like): a (rings + 1) × (segments + 1) grid of
/// f64 angles printed in full, so the seam column appears twice and differs by ~1e-16
/// (sin 2π ≠ 0), each pole is repeated once per segment (the south one off by ulps: sin π ≠
/// 0), and each pole quad leaves a degenerate triangle. 2·rings·segments triangles.
fn exported_sphere_obj(rings: u32, segments: u32) -> String {
    let mut s = String::from("o exported\n");
    for j in 0..=rings {
        let th = std::f64::consts::PI * f64::from(j) / f64::from(rings);
        for i in 0..=segments {
            let ph = std::f64::consts::TAU * f64::from(i) / f64::from(segments);
            let p = [th.sin() * ph.sin(), th.cos(), th.sin() * ph.cos()];
            writeln!(s, "v {} {} {}\nvn {0} {1} {2}", p[0], p[1], p[2]).unwrap();
        }
    }
    let at = |j: u32, i: u32| 1 + j * (segments + 1) + i;
    for j in 0..rings {
        for i in 0..segments {
            let (a, b, c, d) = (at(j, i), at(j + 1, i), at(j + 1, i + 1), at(j, i + 1));
            writeln!(
                s,
                "f {a}//{a} {b}//{b} {c}//{c}\nf {a}//{a} {c}//{c} {d}//{d}"
            )
            .unwrap();
        }
    }
    s
}

/// The exporter's sphere is closed despite its ulp seam and repeated poles: culling skips its
/// far side (it skipped nothing when closedness needed exactly equal corners), with the same
/// pixels as `--no-culling`, and `--check` and `--stats` say why back faces are drawn where
/// they are.
#[test]
fn an_exported_sphere_with_an_ulp_seam_is_culled_with_the_same_pixels() {
    let dir = out_dir("culling_seam");
    let sphere = write(&dir, "exported.obj", &exported_sphere_obj(80, 160));
    let text = std::fs::read_to_string(&sphere).unwrap();
    assert!(
        text.contains("0.0000000000000002"),
        "the seam is written off by ~1e-16"
    );
    let check = run(&[&sphere, "--check"], &[]);
    let report = String::from_utf8_lossy(&check.stdout);
    assert!(
        report.contains("triangles in clusters; back faces skipped when seen from outside"),
        "{report}"
    );
    for (name, extra) in [
        ("front", &["--yaw", "0", "--pitch", "0"][..]),
        ("seam", &["--yaw", "180", "--pitch", "10"]),
        ("pole", &["--yaw", "20", "--pitch", "85"]),
    ] {
        let mut args = vec![sphere.as_str(), "--size", "160x120", "--lod", "off"];
        args.extend_from_slice(extra);
        let culled = render(&dir, &format!("{name}-culled"), &args, &[]);
        args.push("--no-culling");
        let whole = render(&dir, &format!("{name}-whole"), &args, &[]);
        let d = diff(&culled, &whole, 0);
        assert_eq!(d.max, 0, "{name}: culling changed {} pixels", d.over);
    }
    let out = dir.join("s.png");
    let stats = |model: &str, extra: &[&str]| -> serde_json::Value {
        let mut a = vec![model, "-o", out.to_str().unwrap(), "--size", "96x72"];
        a.extend_from_slice(&["--stats", "--no-shadows", "--lod", "off"]);
        a.extend_from_slice(extra);
        let o = run(&a, &[]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        serde_json::from_str(String::from_utf8_lossy(&o.stdout).lines().last().unwrap()).unwrap()
    };
    let s = stats(&sphere, &[]);
    assert!(s["triangles_skipped"].as_u64().unwrap() > 25_600 / 4, "{s}");
    assert_eq!(s["back_faces_kept"], serde_json::json!([]), "{s}");
    let s = stats(&sphere, &["--target", "0,0,0", "--distance", "0.4"]);
    let kept = s["back_faces_kept"].to_string();
    assert!(kept.contains("mesh 0: the viewer"), "{s}");
    let bowl = write(&dir, "bowl.obj", &sphere_obj(161, 160, true));
    let s = stats(&bowl, &["--pitch", "-60"]);
    assert!(
        s["back_faces_kept"]
            .to_string()
            .contains("mesh 0: open edges at 160 corners"),
        "{s}"
    );
}

/// The shared scans are really open: `--check` says so with the number of corners on open
/// edges, and that number is the one an independent count finds — corners (welded by exact
/// position) where some neighbour is reached by a different number of edges out than in.
#[test]
fn scanned_models_report_the_open_corners_they_have() {
    use std::collections::HashMap;
    for rel in [
        "models/stanford-bunny/stanford-bunny.obj",
        "models/dragon-200k/dragon_vrip_res2.obj",
    ] {
        let path = shared().join(rel);
        let o = run(&[path.to_str().unwrap(), "--check", "--no-cache"], &[]);
        let out = String::from_utf8_lossy(&o.stdout);
        let said: usize = out
            .split("back faces drawn: open edges at ")
            .nth(1)
            .and_then(|r| r.split(' ').next()?.parse().ok())
            .unwrap_or_else(|| panic!("{rel}: no open-edge reason in --check:\n{out}"));
        let scene = glview::scene::load(&path, &Default::default()).unwrap();
        let mut exact = 0;
        for m in &scene.meshes {
            let mut id: HashMap<[u32; 3], u32> = HashMap::new();
            let weld: Vec<u32> = m
                .vertices
                .iter()
                .map(|v| {
                    let n = id.len() as u32;
                    *id.entry(v.position.map(f32::to_bits)).or_insert(n)
                })
                .collect();
            let mut edges: HashMap<(u32, u32), i64> = HashMap::new();
            for t in m.indices.chunks_exact(3) {
                for k in 0..3 {
                    let (a, b) = (weld[t[k] as usize], weld[t[(k + 1) % 3] as usize]);
                    *edges.entry((a, b)).or_default() += 1;
                }
            }
            let mut open = std::collections::HashSet::new();
            for (&(a, b), &n) in &edges {
                if edges.get(&(b, a)).copied().unwrap_or(0) != n {
                    open.extend([a, b]);
                }
            }
            exact += open.len();
        }
        assert!(said > 0, "{rel}");
        assert_eq!(
            said, exact,
            "{rel}: --check and the independent count differ"
        );
    }
}

/// `--single-sided` culls back faces, so clusters facing away are skipped even on an open
/// mesh and from inside its bounding sphere, with the same pixels as sending every triangle; the option
/// changes the picture only where back faces showed (the bowl's inside seen from above).
#[test]
fn single_sided_skips_back_facing_clusters_of_open_meshes_exactly() {
    let dir = out_dir("culling_single_sided");
    let bowl = write(&dir, "bowl.obj", &sphere_obj(161, 160, true));
    let out = dir.join("s.png");
    let skipped = |extra: &[&str]| -> u64 {
        let mut a = vec![
            bowl.as_str(),
            "-o",
            out.to_str().unwrap(),
            "--size",
            "96x72",
        ];
        a.extend_from_slice(&["--stats", "--single-sided", "--lod", "off"]);
        a.extend_from_slice(extra);
        let o = run(&a, &[]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let s: serde_json::Value =
            serde_json::from_str(String::from_utf8_lossy(&o.stdout).lines().last().unwrap())
                .unwrap();
        s["triangles_skipped"].as_u64().unwrap()
    };
    for (name, extra) in [
        ("below", &["--pitch", "-60"][..]),
        ("side", &["--yaw", "40", "--pitch", "5"]),
        ("above", &["--pitch", "70"]),
        // Inside the bowl's bounding sphere, just above its dome.
        (
            "near",
            &["--target", "0,1,0", "--distance", "0.3", "--pitch", "80"],
        ),
    ] {
        assert!(skipped(extra) > 0, "{name}: nothing skipped");
        let mut args = vec![
            bowl.as_str(),
            "--size",
            "160x120",
            "--single-sided",
            "--lod",
            "off",
        ];
        args.extend_from_slice(extra);
        let culled = render(&dir, &format!("{name}-culled"), &args, &[]);
        args.push("--no-culling");
        let whole = render(&dir, &format!("{name}-whole"), &args, &[]);
        let d = diff(&culled, &whole, 0);
        if d.max != 0 {
            write_diff(&dir, name, &culled, &whole);
        }
        assert_eq!(d.max, 0, "{name}: culling changed {} pixels", d.over);
    }
    // The bowl is a dome open at the bottom: from below, its inside is its back faces, which
    // single-sided draws leave out.
    let below = [bowl.as_str(), "--size", "160x120", "--pitch", "-25"];
    let two = render(&dir, "below-two-sided", &below, &[]);
    let one = render(
        &dir,
        "below-one-sided",
        &[&below[..], &["--single-sided"]].concat(),
        &[],
    );
    assert!(
        diff(&two, &one, 8).over > 100,
        "--single-sided changed nothing"
    );
}

/// Single-sided opaque draws use a program without the back-face normal flip (`FRONT_ONLY`:
/// culling lets no back face through). On a closed sphere seen from outside only front faces
/// show either way, so the single-sided picture is the two-sided one, Phong and Gouraud, with
/// a point light too; only silhouette pixels where a back face won a depth tie may differ.
#[test]
fn front_only_programs_draw_what_two_sided_ones_draw() {
    let dir = out_dir("culling_front_only");
    let sphere = write(&dir, "sphere.obj", &sphere_obj(60, 80, false));
    for shading in ["phong", "gouraud"] {
        for light in ["dir:-1,-2,-1.5", "point:2,3,4"] {
            let name = format!("{shading}-{}", &light[..3]);
            let args = [
                sphere.as_str(),
                "--size",
                "160x120",
                "--shading",
                shading,
                "--light",
                light,
                "--light",
                "head",
                "--no-culling",
            ];
            let two = render(&dir, &format!("{name}-two"), &args, &[]);
            let one = render(
                &dir,
                &format!("{name}-one"),
                &[&args[..], &["--single-sided"]].concat(),
                &[],
            );
            let d = diff(&one, &two, 2);
            if d.over > 0 {
                write_diff(&dir, &name, &one, &two);
            }
            // 160×120 = 19,200 pixels; the silhouette is ~300 of them.
            assert!(
                d.over <= 20,
                "{name}: {} pixels differ by more than 2/255",
                d.over
            );
        }
    }
}
