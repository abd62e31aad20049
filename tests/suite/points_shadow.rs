//! Lit points receive the meshes' shadows: a row of points under a quad that hides half of
//! them from a light straight above is drawn as the reference draws it (exact shadow rays
//! from each point), the hidden half darker, in both tiers, on every context
//! (docs/guide.md, Point clouds).
use crate::common::*;
use crate::points::{project, reference, render_bin, write, CONTEXTS, PBR_TOLERANCE};

/// The row of points (y = 0, z = 0); those with x < 0 lie under the quad.
const XS: [f32; 6] = [-1.2, -0.8, -0.4, 0.4, 0.8, 1.2];

/// The normal of point `i`: up, leaning a little so no two are shaded alike.
fn normal(i: usize) -> [f32; 3] {
    let n = glam::Vec3::new(0.1 * i as f32 - 0.25, 1.0, 0.2).normalize();
    n.to_array()
}

/// A glTF of a quad at y = 0.6 over x in [-1.5, 0], z in [-0.3, 0.3] (two triangles facing
/// up) and the row of points (a POINTS primitive with NORMAL), its buffer beside it. (An OBJ
/// gives points normals only where it has no faces.)
fn scene_gltf(dir: &std::path::Path) -> String {
    let (x0, x1, z0, z1) = (-1.5f32, 0.0, -0.3, 0.3);
    let quad = [
        [x0, 0.6, z0],
        [x0, 0.6, z1],
        [x1, 0.6, z1],
        [x0, 0.6, z0],
        [x1, 0.6, z1],
        [x1, 0.6, z0],
    ];
    let points: Vec<[f32; 3]> = XS.iter().map(|&x| [x, 0.0, 0.0]).collect();
    let normals: Vec<[f32; 3]> = (0..XS.len()).map(normal).collect();
    let streams: [&[[f32; 3]]; 4] = [&quad, &[[0.0, 1.0, 0.0]; 6], &points, &normals];
    let mut bin = Vec::new();
    let (mut views, mut accessors) = (Vec::new(), Vec::new());
    for (k, s) in streams.iter().enumerate() {
        views.push(format!(
            r#"{{"buffer":0,"byteOffset":{},"byteLength":{}}}"#,
            bin.len(),
            s.len() * 12
        ));
        let minmax = match k {
            0 => r#","min":[-1.5,0.6,-0.3],"max":[0,0.6,0.3]"#,
            2 => r#","min":[-1.2,0,0],"max":[1.2,0,0]"#,
            _ => "",
        };
        accessors.push(format!(
            r#"{{"bufferView":{k},"componentType":5126,"count":{},"type":"VEC3"{minmax}}}"#,
            s.len()
        ));
        s.iter().flatten().for_each(|x| bin.extend(x.to_le_bytes()));
    }
    std::fs::write(dir.join("shadowed.bin"), &bin).unwrap();
    let json = format!(
        r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[0]}}],"nodes":[{{"mesh":0}}],
"meshes":[{{"primitives":[{{"attributes":{{"POSITION":0,"NORMAL":1}}}},
{{"mode":0,"attributes":{{"POSITION":2,"NORMAL":3}}}}]}}],
"buffers":[{{"uri":"shadowed.bin","byteLength":{}}}],"bufferViews":[{}],"accessors":[{}]}}"#,
        bin.len(),
        views.join(","),
        accessors.join(","),
    );
    write(dir, "shadowed.gltf", json.as_bytes())
}

/// The brightness (sum of the channels) of a pixel.
fn sum(p: [u8; 4]) -> u32 {
    p[..3].iter().map(|&c| u32::from(c)).sum()
}

#[test]
fn points_in_a_mesh_shadow_match_the_reference() {
    let dir = out_dir("points-shadow");
    let file = scene_gltf(&dir);
    for (tier, tolerance) in [("phong", 2), ("pbr", PBR_TOLERANCE)] {
        let args = [
            file.as_str(),
            "--point-size",
            "9",
            "--size",
            "200x150",
            "--yaw",
            "15",
            "--pitch",
            "25",
            "--light",
            "dir:0,-1,0",
            "--shading",
            tier,
            "--background",
            "0.1,0.1,0.12",
        ];
        let truth = reference(&dir, tier, &args);
        for (ctx, extra, env) in &CONTEXTS {
            let mut all = args.to_vec();
            all.extend_from_slice(extra);
            let img = render_bin(&dir, &format!("{tier}{ctx}"), &all, env);
            let mut worst = 0;
            let (mut dark, mut bright) = (0, u32::MAX);
            for (i, &x) in XS.iter().enumerate() {
                let c = project(&args, [x, 0.0, 0.0]);
                let (px, py) = (c.0 as u32, c.1 as u32);
                let (g, r) = (img.pixel(px, py), truth.pixel(px, py));
                let d = (0..3).map(|k| g[k].abs_diff(r[k])).max().unwrap();
                worst = worst.max(d);
                assert!(
                    d <= tolerance,
                    "{tier}{ctx}: point {i}: GPU {g:?}, reference {r:?}"
                );
                if x < 0.0 {
                    dark = dark.max(sum(g).max(sum(r)));
                } else {
                    bright = bright.min(sum(g).min(sum(r)));
                }
            }
            eprintln!("{tier}{ctx}: worst {worst}/255; shadowed ≤ {dark}, lit ≥ {bright} (R+G+B)");
            // Measured: Phong 30 against 612 (ambient only), PBR 582 against 695 (the sky's
            // light remains).
            assert!(
                dark * 10 < bright * 9,
                "{tier}{ctx}: shadowed points up to {dark}, lit from {bright} (R+G+B)"
            );
        }
    }
}
