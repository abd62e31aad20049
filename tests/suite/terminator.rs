//! The shadow terminator: a convex object casts no shadow on itself, so with smooth normals on
//! a coarse mesh, shadows on or off must give the same picture wherever the surface is lit.
//! Without the terminator rule (shadow.glsl, reference/surface.rs) the facets that face away
//! from the light while their smooth normals face it were shadowed by their own neighbours:
//! dark triangles inside the lit side, on the GPU and in the reference alike.
use crate::common::*;
use glview::image_out::Rgba;
use glview::image_out::RgbaFiles;
use std::f64::consts::PI;

/// A UV sphere of `rings` × `segments` quads with exact smooth normals (unit positions).
fn coarse_sphere(rings: usize, segments: usize) -> String {
    let mut s = String::new();
    for r in 0..=rings {
        let t = PI * r as f64 / rings as f64;
        for k in 0..segments {
            let p = 2.0 * PI * k as f64 / segments as f64;
            let (x, y, z) = (t.sin() * p.cos(), t.cos(), t.sin() * p.sin());
            s += &format!("v {x} {y} {z}\nvn {x} {y} {z}\n");
        }
    }
    let id = |r: usize, k: usize| r * segments + k % segments + 1;
    for r in 0..rings {
        for k in 0..segments {
            let (a, b, c, d) = (id(r, k), id(r, k + 1), id(r + 1, k + 1), id(r + 1, k));
            if r > 0 {
                s += &format!("f {a}//{a} {b}//{b} {c}//{c}\n");
            }
            if r + 1 < rings {
                s += &format!("f {a}//{a} {c}//{c} {d}//{d}\n");
            }
        }
    }
    s
}

/// Pixels whose largest channel differs by more than 8/255 between the two pictures.
fn changed(a: &Rgba, b: &Rgba) -> usize {
    diff(a, b, 8).over
}

#[test]
fn a_coarse_convex_mesh_does_not_shadow_its_lit_side() {
    let dir = out_dir("terminator");
    let obj = dir.join("coarse-sphere.obj");
    std::fs::write(&obj, coarse_sphere(8, 12)).unwrap();
    let base = [
        obj.to_str().unwrap(),
        "--size",
        "200x200",
        // Looking across the light: the terminator runs down the middle of the picture.
        "--yaw",
        "0",
        "--pitch",
        "15",
        "--light",
        "dir:-1,-0.2,-0.3",
        "--ambient",
        "0.3,0.3,0.3",
    ];
    let mut counts = Vec::new();
    for reference in [false, true] {
        let pic = |name: &str, extra: &[&str]| {
            let mut args = base.to_vec();
            args.extend_from_slice(extra);
            if reference {
                let out = dir.join(format!("{name}.png"));
                args.extend_from_slice(&["--reference", "-o", out.to_str().unwrap()]);
                let o = run(&args, &[]);
                assert!(o.status.success(), "{o:?}");
                Rgba::load_png(&out).unwrap()
            } else {
                render(&dir, name, &args, &[])
            }
        };
        let tag = if reference { "ref" } else { "gpu" };
        let with = pic(&format!("{tag}-shadows"), &[]);
        let without = pic(&format!("{tag}-no-shadows"), &["--no-shadows"]);
        let n = changed(&with, &without);
        if n > 10 {
            write_diff(&dir, &format!("{tag}-terminator"), &with, &without);
        }
        counts.push((tag, n));
    }
    eprintln!("pixels shadows changed (> 8/255): {counts:?}");
    // Measured: GPU 0, reference 0 of the sphere's 9,002 pixels; without the rule GPU 46
    // (its normal offset already hides part of it) and reference 352. Allowed: a few pixels
    // where the band meets grazing light and the map's resolution decides.
    for (tag, n) in counts {
        assert!(
            n <= 10,
            "{tag}: shadows darken {n} lit pixels of a convex mesh"
        );
    }
}
