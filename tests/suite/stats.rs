//! Nothing a scene does not need is computed, and `--stats` says what ran: programs without
//! texture lookups for untextured models, no depth pass without lights or shadows, reused
//! shadow maps, off-screen meshes culled (without changing the picture).
use crate::common;
use common::*;
use serde_json::Value;

fn stats(args: &[&str]) -> Vec<Value> {
    let out = out_dir("stats").join("s.png");
    let mut a = vec![
        "--output",
        out.to_str().unwrap(),
        "--size",
        "96x72",
        "--stats",
    ];
    a.extend_from_slice(args);
    let o = run(&a, &[]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    String::from_utf8_lossy(&o.stdout)
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect()
}

#[test]
fn programs_carry_only_the_features_a_model_needs() {
    let plain = stats(&[shared()
        .join("models/suzanne/suzanne.obj")
        .to_str()
        .unwrap()]);
    let progs = plain[0]["programs"].to_string();
    assert!(progs.contains("lit[l3,s1,pcf1]"), "{progs}"); // the default kit: 3 lights, 1 caster
    assert!(
        !progs.contains("tex"),
        "untextured model uses a texture program: {progs}"
    );
    assert_eq!(plain[0]["textures_bound"], 1, "only the shadow map"); // shadow map only

    let tex = stats(&[models().join("textured_quad.obj").to_str().unwrap()]);
    assert!(
        tex[0]["programs"].to_string().contains(",tex]"),
        "{}",
        tex[0]["programs"]
    );
    assert_eq!(tex[0]["textures_bound"], 2, "diffuse map and shadow map");

    let dark = stats(&["--light", "none"]);
    assert!(
        dark[0]["programs"].to_string().contains("lit[l0,s0"),
        "{}",
        dark[0]["programs"]
    );

    let gouraud = stats(&["--shading", "gouraud", "--pcf", "9"]);
    assert!(
        gouraud[0]["programs"].to_string().contains("pcf9,gouraud"),
        "{}",
        gouraud[0]["programs"]
    );
}

#[test]
fn off_screen_meshes_are_culled_without_changing_the_picture() {
    let dir = out_dir("stats-cull");
    let cube = |x: f64, before| box_obj([x, 0.0, 0.0], [x + 1.0, 1.0, 1.0], before);
    let both = dir.join("both.obj");
    std::fs::write(
        &both,
        format!("o left\n{}o right\n{}", cube(-10.0, 0), cube(10.0, 8)),
    )
    .unwrap();
    let right = dir.join("right.obj");
    std::fs::write(&right, format!("o right\n{}", cube(10.0, 0))).unwrap();
    let view = [
        "--target",
        "10.5,0.5,0.5",
        "--distance",
        "4",
        "--no-shadows",
    ];
    let s = stats(&[&[both.to_str().unwrap()][..], &view].concat());
    assert_eq!(s[0]["culled"], 1);
    assert_eq!(s[0]["draw_calls"], 1);
    let a = render(
        &dir,
        "both",
        &[&[both.to_str().unwrap()][..], &view].concat(),
        &[],
    );
    let b = render(
        &dir,
        "right",
        &[&[right.to_str().unwrap()][..], &view].concat(),
        &[],
    );
    // The two files have different bounds, so a different re-centring origin and near/far
    // planes: positions and depths round differently, by at most one step.
    assert_close(&dir, "cull", &a, &b, 1, 0, 1);
    // Looking at both, nothing is culled.
    let s = stats(&[both.to_str().unwrap(), "--no-shadows"]);
    assert_eq!(s[0]["culled"], 0);
    assert_eq!(s[0]["draw_calls"], 2);
}

#[test]
fn gpu_time_comes_from_timer_queries_where_the_driver_has_them() {
    // GL 3.3 core has GL_TIME_ELAPSED; GL ES 3.0 does not (the field is then null). Frame
    // 1 too: llvmpipe's nonsense first query is spent when the renderer is made.
    let core = stats(&["--gl", "core", "--frames", "3"]);
    for f in &core {
        let (gpu, wall) = (
            f["gpu_ms"].as_f64().expect("gpu_ms on GL 3.3"),
            f["ms"].as_f64().unwrap(),
        );
        assert!(
            gpu > 0.0 && gpu <= wall + 1.0,
            "gpu {gpu} ms, wall {wall} ms"
        );
    }
    let es = stats(&["--gl", "es3", "--frames", "2"]);
    assert!(es.iter().all(|f| f["gpu_ms"].is_null()));
}

#[test]
fn info_reports_uniform_limits_at_least_the_spec_minimum() {
    // GL 2.0/2.1 promise 512 vertex and 64 fragment uniform components; GL 3.3 and ES 3.0
    // promise 1024 and 896 (ES) / 1024 (GL). The probe must read them from the driver on
    // every context glview can make here.
    for (args, env, min_v, min_f) in [
        (vec!["--info"], &[][..], 1024, 896),
        (vec!["--info", "--gl", "2.1"], GL21, 512, 64),
        (vec!["--info", "--gl", "es3"], &[][..], 1024, 896),
    ] {
        let o = run(&args, env);
        let out = String::from_utf8_lossy(&o.stdout);
        assert!(
            o.status.success(),
            "{args:?}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
        let value = |key: &str| -> u32 {
            out.lines()
                .find_map(|l| l.strip_prefix(key))
                .and_then(|v| v.trim().parse().ok())
                .unwrap_or_else(|| panic!("{args:?}: no {key:?} in:\n{out}"))
        };
        let v = value("max vertex uniform components:");
        let f = value("max fragment uniform components:");
        assert!(
            v >= min_v && f >= min_f,
            "{args:?}: vertex {v}, fragment {f}"
        );
    }
}

/// `--stats`: the last frame's line carries the picture's profile (where the time went from
/// arguments to PNG), with every stage that ran measured and the load's own stages.
#[test]
fn stats_profile_covers_every_stage_of_a_picture() {
    let model = shared().join("models/teapot-small");
    let obj = std::fs::read_dir(&model)
        .unwrap()
        .map(|e| e.unwrap().path())
        .find(|p| p.extension().is_some_and(|e| e == "obj"))
        .expect("the teapot OBJ");
    let lines = stats(&[obj.to_str().unwrap(), "--frames", "2", "--no-cache"]);
    assert_eq!(lines.len(), 2, "one line per frame");
    assert!(lines[0].get("profile").is_none());
    let p = &lines[1]["profile"];
    for stage in [
        "load_ms",
        "context_ms",
        "upload_ms",
        "readback_ms",
        "encode_ms",
    ] {
        let v = p[stage].as_f64().unwrap_or(-1.0);
        assert!(v > 0.0, "{stage}: {v} in {p}");
    }
    assert_eq!(p["frames_ms"].as_array().unwrap().len(), 2);
    assert!(p["programs_compiled"].as_u64().unwrap() >= 1, "{p}");
    let load = &p["load"];
    assert_eq!(
        load["bytes"].as_u64().unwrap(),
        std::fs::metadata(&obj).unwrap().len()
    );
    assert!(load["parse_ms"].as_f64().unwrap() > 0.0, "{load}");
    // Loading runs beside context creation, so the whole is at least the longer of the two
    // plus everything after them, and less than all parts in a row when both took time.
    let f = |k: &str| p[k].as_f64().unwrap();
    let after: f64 = ["upload_ms", "readback_ms", "encode_ms"]
        .iter()
        .map(|k| f(k))
        .sum::<f64>()
        + p["frames_ms"]
            .as_array()
            .unwrap()
            .iter()
            .map(|v| v.as_f64().unwrap())
            .sum::<f64>();
    let total = f("total_ms");
    assert!(
        f("load_ms").max(f("context_ms")) + after <= total + 0.5,
        "{p}"
    );
    eprintln!(
        "load {:.1} ms ‖ context {:.1} ms, then {after:.1} ms: total {total:.1} ms",
        f("load_ms"),
        f("context_ms")
    );
}

/// `--stats` lists each image texture with its size and cost: none for an untextured model,
/// the one image of BoxTextured in the legacy tier, and in the PBR tier its sRGB copy too.
#[test]
fn stats_list_each_texture_upload() {
    let boxed = shared().join("gltf-samples/BoxTextured/BoxTextured.glb");
    let boxed = boxed.to_str().unwrap();
    let textures = |args: &[&str]| {
        let lines = stats(args);
        lines.last().unwrap()["profile"]["textures"]
            .as_array()
            .unwrap()
            .clone()
    };
    assert!(textures(&[]).is_empty());
    // Each tier uploads the image it reads once, on first use: the legacy tier a plain copy,
    // PBR an sRGB one (before, a PBR frame uploaded both).
    for (shading, count) in [("phong", 1), ("pbr", 1)] {
        let t = textures(&[boxed, "--shading", shading]);
        assert_eq!(t.len(), count, "{shading}: {t:?}");
        for t in t {
            assert!(t["name"].as_str().unwrap().contains("BoxTextured"), "{t}");
            assert_eq!(
                (t["width"].as_u64(), t["height"].as_u64()),
                (Some(256), Some(256))
            );
            assert!(t["ms"].as_f64().unwrap() > 0.0, "{t}");
        }
    }
}
