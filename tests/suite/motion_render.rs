//! Posing on the render side (issue #39): a renderer whose meshes changed in place uploads
//! them again and draws what a fresh renderer of the changed scene draws, byte for byte
//! (buffers, bounding spheres, clusters, shadow maps and edge lines all follow); and the
//! session's `--time` and `--animation` reach the scene or say what the file has.
use super::common::*;
use glview::headless::Headless;
use glview::image_out::Rgba;
use glview::platform::{Backend, GlRequest};
use glview::render::Renderer;
use glview::scene::{Mesh, Scene, Vertex};

/// Every corner of every triangle its own vertex: the same surface with another vertex
/// count (a pose may change it: generated normals are generated again).
fn unweld(m: &mut Mesh) {
    let v: Vec<Vertex> = m.indices.iter().map(|&i| m.vertices[i as usize]).collect();
    m.indices = (0..v.len() as u32).collect();
    m.vertices = v;
    // Per-vertex streams went with the weld they followed.
    m.colors.clear();
    m.uv1.clear();
    m.tangents.clear();
    m.color_alpha.clear();
}

/// Moves the built-in scene's largest mesh (a clustered one) and unwelds and lifts its
/// smallest, in place; returns their indices.
fn change(scene: &mut Scene) -> Vec<usize> {
    let by_size: Vec<usize> = {
        let mut i: Vec<usize> = (0..scene.meshes.len()).collect();
        i.sort_by_key(|&i| scene.meshes[i].indices.len());
        i
    };
    let (small, large) = (by_size[0], by_size[by_size.len() - 1]);
    assert!(
        scene.meshes[large].indices.len() / 3 >= 1 << 14,
        "the largest mesh is large enough for clusters"
    );
    for v in &mut scene.meshes[large].vertices {
        v.position[1] = v.position[1] * 1.25 + 0.05 * v.position[0];
    }
    let m = &mut scene.meshes[small];
    unweld(m);
    for v in &mut m.vertices {
        v.position[1] += 0.1;
    }
    vec![small, large]
}

/// The built-in scene (small meshes) with the committed sphere (one mesh large enough for
/// clusters) beside it, and the settings of `--edges` for it.
fn scene_with_a_large_mesh() -> (glview::render::FrameSettings, Scene) {
    let (_, builtin) = settings_for(&[]);
    let (_, sphere) = settings_for(&["models/sphere.obj"]);
    let mut materials = builtin.materials.clone();
    let mut meshes = builtin.meshes.to_vec();
    let size = |s: &Scene| (s.bounds.max - s.bounds.min).length();
    let r = size(&builtin) / size(&sphere);
    for mut m in sphere.meshes.iter().cloned() {
        m.material += materials.len();
        for v in &mut m.vertices {
            v.position = v.position.map(|c| 0.4 * r * c);
            v.position[0] += 0.3 * size(&builtin);
        }
        meshes.push(m);
    }
    materials.extend(sphere.materials.iter().cloned());
    let scene = Scene::from_meshes("two", meshes, materials);
    let o = glview::Options::from_words(["--size", "64x48", "--edges"]).unwrap();
    let (settings, _) = glview::session::frame_settings(&o, &scene).unwrap();
    (settings, scene)
}

/// On `request`: draw, change two meshes in place, refresh them, draw again; the second
/// picture equals a fresh renderer's of the changed scene and differs from the first.
fn refresh_equals_fresh(request: GlRequest, name: &str) {
    let (settings, scene) = scene_with_a_large_mesh();
    let hl = Headless::new(Backend::Egl, request, 64, 48).expect("EGL context");
    let mut r = Renderer::new(&hl.gpu, scene).unwrap();
    r.render(&settings, &hl.target()).unwrap();
    let before = hl.read();
    let changed = change(r.scene_mut());
    r.refresh_meshes(&changed).unwrap();
    r.render(&settings, &hl.target()).unwrap();
    let refreshed = hl.read();
    let mut fresh = Renderer::new(&hl.gpu, r.scene().clone()).unwrap();
    fresh.render(&settings, &hl.target()).unwrap();
    let want = hl.read();
    // Not `check_frame`: the edge lines are black.
    assert!(!refreshed.is_uniform(), "{name}: blank frame");
    let dir = out_dir("motion_render");
    if refreshed.data != want.data {
        let p = write_diff(&dir, name, &refreshed, &want);
        panic!(
            "{name}: the refreshed renderer differs from a fresh one: {}",
            p.display()
        );
    }
    assert_ne!(before.data, refreshed.data, "{name}: the change shows");
}

#[test]
fn refreshed_meshes_draw_what_a_fresh_renderer_draws_gl33() {
    refresh_equals_fresh(GlRequest::Core, "gl33");
}

/// The GL 2.1 request (Mesa answers with its newest compatibility context: the GLSL 1.20
/// programs, the same buffers).
#[test]
fn refreshed_meshes_draw_what_a_fresh_renderer_draws_gl21() {
    refresh_equals_fresh(GlRequest::Gl21, "gl21");
}

/// A mesh that does not exist is an error, not a panic; no mesh is nothing to do.
#[test]
fn refreshing_no_mesh_or_a_missing_one() {
    let (_, scene) = settings_for(&["--size", "16x16"]);
    let n = scene.meshes.len();
    let hl = Headless::new(Backend::Egl, GlRequest::Core, 16, 16).expect("EGL context");
    let mut r = Renderer::new(&hl.gpu, scene).unwrap();
    r.refresh_meshes(&[]).unwrap();
    let e = r.refresh_meshes(&[n]).expect_err("no such mesh");
    assert!(e.to_string().contains("no such mesh"), "{e}");
}

/// `--time` or `--animation` on a model without animations: one line naming it.
#[test]
fn time_on_a_still_model_is_a_one_line_error() {
    let dir = out_dir("motion_render");
    let out = dir.join("still.png");
    for args in [
        vec!["--time", "0.5"],
        vec!["--animation", "Walk"],
        vec!["--time", "1", "--reference"],
    ] {
        let mut all = args.clone();
        all.extend(["--size", "16x16", "-o", out.to_str().unwrap()]);
        let o = run(&all, &[]);
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success(), "{args:?}");
        assert_eq!(err.trim().lines().count(), 1, "{args:?}: {err}");
        assert!(
            err.contains(&format!(
                "{} {}: glass_holder has no animations",
                args[0], args[1]
            )),
            "{args:?}: {err}"
        );
    }
}

/// The texels a shadow pass drew again where casters moved (its `--stats` entry), or None
/// when it drew the maps whole or reused them.
fn texels_updated(shadow: &str) -> Option<u64> {
    let rest = shadow.strip_prefix("updated where casters moved (")?;
    rest.split(' ').next()?.parse().ok()
}

/// `kept`'s frame (drawn by a renderer that posed or moved things) against `fresh`'s, byte
/// for byte.
fn assert_same(dir: &std::path::Path, name: &str, kept: &Rgba, fresh: &Rgba) {
    assert!(
        kept.data == fresh.data,
        "{name}: the kept renderer's frame differs from a fresh renderer's: {}",
        write_diff(dir, name, kept, fresh).display()
    );
}

/// Nudging the built-in scene's smallest mesh draws only its part of the shadow map again
/// (the box of its old and new places), and that map — shown at a texel a pixel by
/// `--show shadow-map` — and the lit picture are a fresh renderer's, byte for byte, on
/// GL 3.3, ES 3.0 and GL 2.1.
#[test]
fn a_moved_caster_redraws_only_its_part_of_the_shadow_map() {
    for (name, request) in [
        ("gl33", GlRequest::Core),
        ("es3", GlRequest::Es3),
        ("gl21", GlRequest::Gl21),
        ("es2", GlRequest::Es2),
    ] {
        moved_caster(name, request);
    }
}

/// The same on ES 2.0 without depth textures (WebGL 1 without WEBGL_depth_texture): the map
/// is packed RGBA8, its moved rectangles cleared to white (depth 1 and more). Run in a child
/// process: Mesa reads its overrides once, when the first context is made.
#[test]
fn a_moved_caster_redraws_only_its_part_of_a_packed_shadow_map() {
    run_child_test(
        "motion_render::moved_caster_packed_child",
        super::es2::ES2_NO_DEPTH_TEXTURES,
    );
}

#[test]
#[ignore = "run by a_moved_caster_redraws_only_its_part_of_a_packed_shadow_map"]
fn moved_caster_packed_child() {
    let hl = Headless::new(Backend::Egl, GlRequest::Es2, 16, 16).expect("EGL context");
    let info = hl.gpu.caps.report();
    assert!(info.contains("shadow maps: depth packed"), "{info}");
    drop(hl);
    moved_caster("es2-packed", GlRequest::Es2);
}

fn moved_caster(name: &str, request: GlRequest) {
    let dir = out_dir("motion_render");
    let hl = Headless::new(Backend::Egl, request, 128, 128).expect("EGL context");
    let size = ["--size", "128x128", "--shadow-size", "128"];
    let (lit, scene) = settings_for(&size);
    let (map, _) = settings_for(&[&size[..], &["--show", "shadow-map"]].concat());
    let small = (0..scene.meshes.len())
        .min_by_key(|&i| scene.meshes[i].indices.len())
        .unwrap();
    let step = 0.04 * (scene.bounds.max - scene.bounds.min).length();
    let mut r = Renderer::new(&hl.gpu, scene).unwrap();
    r.render(&map, &hl.target()).unwrap();
    let before = hl.read();
    for v in &mut r.scene_mut().meshes[small].vertices {
        v.position[0] += step;
        v.position[1] += step;
    }
    r.refresh_meshes(&[small]).unwrap();
    let stats = r.render(&map, &hl.target()).unwrap();
    let texels =
        texels_updated(&stats.shadow).unwrap_or_else(|| panic!("{name}: {}", stats.shadow));
    assert!(
        texels > 0 && texels < 128 * 128 / 4,
        "{name}: {texels} texels drawn again"
    );
    let kept_map = hl.read();
    assert!(
        before.data != kept_map.data,
        "{name}: the nudge does not show in the map"
    );
    let mut fresh = Renderer::new(&hl.gpu, r.scene().clone()).unwrap();
    fresh.render(&map, &hl.target()).unwrap();
    assert_same(&dir, &format!("moved-map-{name}"), &kept_map, &hl.read());
    // The lit picture from the kept map (reused: nothing moved since).
    let stats = r.render(&lit, &hl.target()).unwrap();
    assert!(
        stats.shadow.starts_with("reused"),
        "{name}: {}",
        stats.shadow
    );
    let kept = hl.read();
    fresh.render(&lit, &hl.target()).unwrap();
    assert_same(&dir, &format!("moved-lit-{name}"), &kept, &hl.read());
}

/// A skinned figure played on the GPU: from its second moment on, each pose marks its
/// animation's framing box, which covers the map, so the map is drawn whole; each map
/// equals a fresh renderer's posed at that moment.
#[test]
fn a_playing_figure_updates_its_shadow_map_as_a_fresh_renderer_draws_it() {
    use glview::scene::motion::Moment;
    let dir = out_dir("motion_render");
    let hl = Headless::new(Backend::Egl, GlRequest::Core, 96, 96).expect("EGL context");
    let (map, scene) = settings_for(&[
        "tests/data/khronos/motion/CesiumMan.glb",
        "--size",
        "96x96",
        "--shadow-size",
        "96",
        "--show",
        "shadow-map",
    ]);
    let mut kept = Renderer::new(&hl.gpu, scene.clone()).unwrap();
    let mut last: Option<Rgba> = None;
    for (k, seconds) in [0.1, 0.6, 1.1].into_iter().enumerate() {
        let moment = Some(Moment {
            animation: 0,
            seconds,
        });
        kept.pose(moment).unwrap();
        let stats = kept.render(&map, &hl.target()).unwrap();
        // The first pose leaves the static pose (its bounds change): drawn whole; then the
        // framing box covers the map (fitted to it), which is drawn whole too (a scissored
        // clear of all but the whole map is llvmpipe's slow path).
        assert!(texels_updated(&stats.shadow).is_none(), "{}", stats.shadow);
        if k > 0 {
            assert!(
                stats.shadow.contains("casters moved over half"),
                "{}",
                stats.shadow
            );
        }
        let got = hl.read();
        let mut fresh = Renderer::new(&hl.gpu, scene.clone()).unwrap();
        fresh.pose(moment).unwrap();
        fresh.render(&map, &hl.target()).unwrap();
        assert_same(&dir, &format!("figure-{k}"), &got, &hl.read());
        assert!(
            last.as_ref().is_none_or(|l| l.data != got.data),
            "moment {k} did not move"
        );
        last = Some(got);
    }
}

/// Khronos' milk truck turns its wheels under a still body: each frame draws the shadow
/// map again inside the wheels' rectangles only (under half the map), and the map and the
/// lit picture are a fresh renderer's at that moment, byte for byte.
#[test]
fn a_turning_wheel_redraws_only_its_part_of_the_shadow_map() {
    use glview::scene::motion::Moment;
    let dir = out_dir("motion_render");
    let hl = Headless::new(Backend::Egl, GlRequest::Core, 96, 96).expect("EGL context");
    let model = "tests/data/khronos/motion/CesiumMilkTruck.glb";
    let size = [model, "--size", "96x96", "--shadow-size", "96"];
    let (lit, scene) = settings_for(&size);
    let (map, _) = settings_for(&[&size[..], &["--show", "shadow-map"]].concat());
    let mut kept = Renderer::new(&hl.gpu, scene.clone()).unwrap();
    for (k, seconds) in [0.1, 0.3, 0.5].into_iter().enumerate() {
        let moment = Some(Moment {
            animation: 0,
            seconds,
        });
        kept.pose(moment).unwrap();
        let stats = kept.render(&map, &hl.target()).unwrap();
        if k > 0 {
            let texels =
                texels_updated(&stats.shadow).unwrap_or_else(|| panic!("{}", stats.shadow));
            assert!(texels < 96 * 96 / 2, "{texels} texels drawn again");
        }
        let got_map = hl.read();
        kept.render(&lit, &hl.target()).unwrap();
        let got = hl.read();
        let mut fresh = Renderer::new(&hl.gpu, scene.clone()).unwrap();
        fresh.pose(moment).unwrap();
        fresh.render(&map, &hl.target()).unwrap();
        assert_same(&dir, &format!("truck-map-{k}"), &got_map, &hl.read());
        fresh.render(&lit, &hl.target()).unwrap();
        assert_same(&dir, &format!("truck-{k}"), &got, &hl.read());
    }
}

/// The APNG frames of the milk truck's wheels on a GL 2.1 driver without framebuffer
/// objects (OSMesa), where a shadow map is drawn into the frame's depth and copied: frames
/// after the first update the map only where the wheels are (each rectangle drawn and
/// copied alone; copying the whole view instead fails this), and every frame's map — shown by `--show shadow-map` — is the still's of
/// its moment, drawn by a fresh renderer.
#[test]
fn without_framebuffer_objects_a_moving_caster_updates_its_rectangles() {
    let dir = out_dir("motion_render");
    let out = dir.join("truck-nofbo.apng");
    let base = [
        "tests/data/khronos/motion/CesiumMilkTruck.glb",
        "--size",
        "64x64",
        "--shadow-size",
        "64",
        "--show",
        "shadow-map",
        "--backend",
        "osmesa",
        "--gl",
        "2.1",
    ];
    let mut args = base.to_vec();
    args.extend([
        "--fps",
        "5",
        "--duration",
        "0.6",
        "-o",
        out.to_str().unwrap(),
    ]);
    let o = run(&args, GL21_NO_FBO);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let file = std::io::BufReader::new(std::fs::File::open(&out).unwrap());
    let mut reader = png::Decoder::new(file).read_info().unwrap();
    for k in 0..3 {
        let mut buf = vec![0; reader.output_buffer_size().unwrap()];
        let info = reader.next_frame(&mut buf).unwrap();
        let frame = Rgba {
            width: 64,
            height: 64,
            data: buf[..info.buffer_size()].to_vec(),
        };
        let time = format!("{}", k as f32 / 5.0);
        let mut at = base.to_vec();
        at.extend(["--time", &time]);
        let still = render(&dir, &format!("truck-nofbo-{k}"), &at, GL21_NO_FBO);
        assert_same(&dir, &format!("truck-nofbo-{k}"), &frame, &still);
    }
}

/// Lines, points and instances of moving nodes move with them (tests/data/motion/MovingWire.glb
/// from scripts/make_moving_wire.py: a node's lines and points carried by its animation, a
/// skinned rope of lines bent by a joint, still lines beside them, an instanced child node
/// whose three copies GL 3.3 would draw as instances of one): at 1 s (STEP keys: the
/// key values exactly) the picture is that of the still twin whose nodes hold those values,
/// byte for byte, on every context (GL 3.3, ES 3.0, GL 2.1 with and without VAOs and
/// FBOs, OSMesa; the camera fixed: the two files' bounds differ), and
/// not the static pose's; a kept renderer posed away and back, and on to a moment of an
/// animation that moves no line (the lines go back to rest), draws a fresh renderer's bytes.
#[test]
fn lines_points_and_instances_of_moving_nodes_are_the_still_twins() {
    use glview::scene::motion::Moment;
    let dir = out_dir("motion_render");
    let camera = [
        "--size",
        "160x120",
        "--no-shadows",
        "--target",
        "0.5,0.8,0",
        "--distance",
        "7",
        "--yaw",
        "20",
    ];
    let file = |f: &'static str, time: Option<&'static str>, ctx: &[&'static str]| {
        let mut w = vec![f];
        w.extend(ctx);
        w.extend(camera);
        if let Some(t) = time {
            // The first animation's moment (by default both would play: they drive
            // different nodes).
            w.extend(["--animation", "0", "--time", t]);
        }
        w
    };
    const MOVING: &str = "tests/data/motion/MovingWire.glb";
    for (gl, ctx, env) in super::motion_truth::CONTEXTS {
        let w = file(MOVING, Some("1"), ctx);
        let moved = render(&dir, &format!("wire-{gl}"), &w, env);
        let twin = file("tests/data/motion/MovingWireStill.glb", None, ctx);
        let want = render(&dir, &format!("wire-twin-{gl}"), &twin, env);
        assert!(
            moved.data == want.data,
            "{gl}: lines and points at 1 s are not the still twin's: {}",
            write_diff(&dir, &format!("wire-{gl}"), &moved, &want).display()
        );
        let rest = render(
            &dir,
            &format!("wire-rest-{gl}"),
            &file(MOVING, None, ctx),
            env,
        );
        let d = diff(&moved, &rest, 8);
        assert!(d.over > 200, "{gl}: 1 s is the static pose: {}", d.over);
    }
    let hl = Headless::new(Backend::Egl, GlRequest::Core, 160, 120).expect("EGL context");
    let (settings, scene) = settings_for(&file(MOVING, None, &["--gl", "core"]));
    let mut kept = Renderer::new(&hl.gpu, scene.clone()).unwrap();
    let at = |animation, seconds| Some(Moment { animation, seconds });
    let mut frames = Vec::new();
    // Animation 1 turns the instanced node alone: from animation 0's moment to its own, the
    // lines and points go back to where animation 1 leaves them (the static pose).
    let moments = [at(0, 1.0), None, at(0, 0.5), at(0, 1.0), at(1, 1.0)];
    for moment in moments {
        kept.pose(moment).unwrap();
        kept.render(&settings, &hl.target()).unwrap();
        frames.push(hl.read());
    }
    let fresh = |moment| {
        let mut r = Renderer::new(&hl.gpu, scene.clone()).unwrap();
        r.pose(moment).unwrap();
        r.render(&settings, &hl.target()).unwrap();
        hl.read()
    };
    let (moved, spun) = (fresh(at(0, 1.0)), fresh(at(1, 1.0)));
    assert_same(&dir, "wire-kept", &frames[0], &moved);
    assert_same(&dir, "wire-back", &frames[3], &moved);
    assert_same(&dir, "wire-other-animation", &frames[4], &spun);
    assert!(frames[1].data != moved.data && frames[2].data == frames[1].data);
    assert!(spun.data != frames[1].data, "animation 1 turns the copies");
}

/// `path` (a GLB) with its JSON chunk replaced by `json`, written to `out`.
fn glb_with_json(path: &str, json: &serde_json::Value, out: &std::path::Path) {
    let bytes = std::fs::read(path).unwrap();
    let len = u32::from_le_bytes(bytes[12..16].try_into().unwrap()) as usize;
    write_glb(json, &bytes[20 + len + 8..], out);
}

/// KHR_animation_pointer: Khronos' BoxAnimated with every channel written as the pointer to
/// its node's property (`/nodes/N/rotation`, `"path": "pointer"`, no `node`; before, such a
/// file was refused: "missing field `node`"), plus a channel pointing at a material's alpha
/// cutoff (not played), loads with one warning naming that pointer, and draws the original file's
/// picture byte for byte at the static pose and at two moments.
#[test]
fn pointer_channels_to_nodes_play_as_the_node_channels() {
    const BOX: &str = "tests/data/khronos/motion/BoxAnimated.glb";
    let dir = out_dir("motion_render");
    at_repo();
    let bytes = std::fs::read(BOX).unwrap();
    let len = u32::from_le_bytes(bytes[12..16].try_into().unwrap()) as usize;
    let mut json: serde_json::Value = serde_json::from_slice(&bytes[20..20 + len]).unwrap();
    const POINTER: &str = "KHR_animation_pointer";
    let channels = json["animations"][0]["channels"].as_array_mut().unwrap();
    let plain = channels.len();
    for c in channels.iter_mut() {
        let t = &c["target"];
        let pointer = format!("/nodes/{}/{}", t["node"], t["path"].as_str().unwrap());
        c["target"] =
            serde_json::json!({"path": "pointer", "extensions": {POINTER: {"pointer": pointer}}});
    }
    channels.push(
        serde_json::json!({"sampler": 0, "target": {"path": "pointer",
        "extensions": {POINTER: {"pointer": "/materials/0/alphaCutoff"}}}}),
    );
    json["extensionsUsed"] = serde_json::json!([POINTER]);
    let pointers = dir.join("BoxPointers.glb");
    glb_with_json(BOX, &json, &pointers);
    let file = pointers.to_str().unwrap();
    let o = run(&["--check", file], &[]);
    // `--check` reports the warnings with the rest, on standard output.
    let err = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let warned: Vec<&str> = err.lines().filter(|l| l.contains(POINTER)).collect();
    assert_eq!(warned.len(), 1, "{err}");
    assert!(
        warned[0].contains(file)
            && warned[0].contains(&format!(
                "channel {plain}: {POINTER} /materials/0/alphaCutoff is not played"
            )),
        "{}",
        warned[0]
    );
    let mut seen = Vec::new();
    for time in [None, Some("1.3"), Some("3.0")] {
        let mut w = vec!["--size", "96x72"];
        w.extend(time.map(|t| ["--time", t]).into_iter().flatten());
        let name = format!("box-{}", time.unwrap_or("static"));
        let want = render(&dir, &name, &[&[BOX][..], &w].concat(), &[]);
        let got = render(
            &dir,
            &format!("{name}-pointers"),
            &[&[file][..], &w].concat(),
            &[],
        );
        assert!(
            got.data == want.data,
            "{name}: the pointer channels do not draw the node channels' picture: {}",
            write_diff(&dir, &name, &got, &want).display()
        );
        seen.push(want.data);
    }
    assert!(
        seen[0] != seen[1] && seen[1] != seen[2],
        "the moments differ"
    );
}

/// BoxAnimated's JSON and binary chunk, with `floats` appended to the binary chunk as one
/// accessor of `kind` (`count` values); the accessor's index.
fn add_floats(
    json: &mut serde_json::Value,
    bin: &mut Vec<u8>,
    floats: &[f32],
    (kind, count): (&str, usize),
) -> usize {
    bin.resize(bin.len().div_ceil(4) * 4, 0);
    let views = json["bufferViews"].as_array_mut().unwrap();
    views.push(
        serde_json::json!({"buffer": 0, "byteOffset": bin.len(), "byteLength": floats.len() * 4}),
    );
    let view = views.len() - 1;
    bin.extend(floats.iter().flat_map(|f| f.to_le_bytes()));
    json["buffers"][0]["byteLength"] = bin.len().into();
    let accessors = json["accessors"].as_array_mut().unwrap();
    let mut a = serde_json::json!({"bufferView": view, "componentType": 5126, "count": count, "type": kind});
    if kind == "SCALAR" {
        a["min"] = serde_json::json!([floats[0]]);
        a["max"] = serde_json::json!([floats[count - 1]]);
    }
    accessors.push(a);
    accessors.len() - 1
}

fn strs(v: &[String]) -> Vec<&str> {
    v.iter().map(String::as_str).collect()
}

/// KHR_animation_pointer on materials: Khronos' BoxAnimated with pointer channels (STEP, keys
/// 0 / 1 / 2 s) on the inner material's base colour and roughness and the outer's emissive
/// factor and strength, beside its own node channels. At 1.3 s its picture is, byte for
/// byte, that of the same file with the 1 s keys written into the materials and no pointer
/// channels (posed at 1.3 s too: the lid moves alike), on GL 3.3 and GL 2.1; at the static
/// pose it is the original file's; and a kept renderer posed to 1.3 s, the static pose and
/// 1.3 s again draws a fresh renderer's bytes each time (nothing of a material is kept
/// stale).
#[test]
fn pointer_channels_to_materials_are_the_factors_written_in() {
    use glview::scene::motion::Moment;
    let dir = out_dir("motion_render");
    let (animated, twin_file) = box_with_material_pointers(&dir);
    let o = run(&["--check", animated.to_str().unwrap()], &[]);
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success() && !out.contains("warning"), "{out}");
    assert!(
        out.contains("animation 0 \"animation 0\": 6 channels"),
        "{out}"
    );
    let w = |f: &std::path::Path, time: Option<&'static str>, gl: &'static str| {
        let mut w = vec![
            f.to_str().unwrap().to_string(),
            "--size".into(),
            "96x72".into(),
            "--gl".into(),
            gl.into(),
        ];
        w.extend(
            time.map(|t| ["--time".to_string(), t.to_string()])
                .into_iter()
                .flatten(),
        );
        w
    };
    for (gl, env) in [("core", &[][..]), ("2.1", GL21)] {
        let words = |f, t| w(f, t, gl);
        let a = words(&animated, Some("1.3"));
        let got = render(&dir, &format!("matptr-{gl}"), &strs(&a), env);
        let t = words(&twin_file, Some("1.3"));
        let want = render(&dir, &format!("matptr-twin-{gl}"), &strs(&t), env);
        assert!(
            got.data == want.data,
            "{gl}: the animated materials at 1.3 s are not the twin's: {}",
            write_diff(&dir, &format!("matptr-{gl}"), &got, &want).display()
        );
        let s = words(&animated, None);
        let still = render(&dir, &format!("matptr-static-{gl}"), &strs(&s), env);
        let o = words(std::path::Path::new(BOX_ANIMATED), None);
        let original = render(&dir, &format!("matptr-original-{gl}"), &strs(&o), env);
        assert!(
            still.data == original.data,
            "{gl}: the static pose is not the file's"
        );
        assert!(got.data != still.data);
    }
    let hl = Headless::new(Backend::Egl, GlRequest::Core, 96, 72).expect("EGL context");
    let words = w(&animated, None, "core");
    let (settings, scene) = settings_for(&strs(&words));
    let mut kept = Renderer::new(&hl.gpu, scene.clone()).unwrap();
    let at = Some(Moment {
        animation: 0,
        seconds: 1.3,
    });
    let fresh = |moment| {
        let mut r = Renderer::new(&hl.gpu, scene.clone()).unwrap();
        r.pose(moment).unwrap();
        r.render(&settings, &hl.target()).unwrap();
        hl.read()
    };
    let (moved, rest) = (fresh(at), fresh(None));
    for (moment, want, name) in [
        (at, &moved, "kept"),
        (None, &rest, "kept-static"),
        (at, &moved, "kept-again"),
    ] {
        kept.pose(moment).unwrap();
        kept.render(&settings, &hl.target()).unwrap();
        assert_same(&dir, &format!("matptr-{name}"), &hl.read(), want);
    }
}

const BOX_ANIMATED: &str = "tests/data/khronos/motion/BoxAnimated.glb";

/// BoxAnimated with the material pointer channels of the test above, and its twin with
/// their 1 s keys written into the materials: the two files' paths in `dir`.
fn box_with_material_pointers(dir: &std::path::Path) -> (std::path::PathBuf, std::path::PathBuf) {
    const BOX: &str = BOX_ANIMATED;
    at_repo();
    let bytes = std::fs::read(BOX).unwrap();
    let len = u32::from_le_bytes(bytes[12..16].try_into().unwrap()) as usize;
    let base: serde_json::Value = serde_json::from_slice(&bytes[20..20 + len]).unwrap();
    let bin0 = bytes[20 + len + 8..].to_vec();
    let (mut json, mut bin) = (base.clone(), bin0.clone());
    let times = add_floats(&mut json, &mut bin, &[0.0, 1.0, 2.0], ("SCALAR", 3));
    // (material, pointer tail, kind, the three keys' values)
    let channels: [(usize, &str, &str, Vec<f32>); 4] = [
        (
            0,
            "pbrMetallicRoughness/baseColorFactor",
            "VEC4",
            vec![0.8, 0.4, 0.8, 1.0, 0.1, 0.9, 0.2, 1.0, 0.3, 0.3, 0.3, 1.0],
        ),
        (
            0,
            "pbrMetallicRoughness/roughnessFactor",
            "SCALAR",
            vec![1.0, 0.25, 0.5],
        ),
        (
            1,
            "emissiveFactor",
            "VEC3",
            vec![0.0, 0.0, 0.0, 0.6, 0.2, 0.0, 0.0, 0.0, 1.0],
        ),
        (
            1,
            "extensions/KHR_materials_emissive_strength/emissiveStrength",
            "SCALAR",
            vec![1.0, 1.5, 1.0],
        ),
    ];
    const POINTER: &str = "KHR_animation_pointer";
    for (material, tail, kind, values) in &channels {
        let output = add_floats(&mut json, &mut bin, values, (kind, 3));
        let samplers = json["animations"][0]["samplers"].as_array_mut().unwrap();
        samplers
            .push(serde_json::json!({"input": times, "output": output, "interpolation": "STEP"}));
        let sampler = samplers.len() - 1;
        let pointer = format!("/materials/{material}/{tail}");
        json["animations"][0]["channels"].as_array_mut().unwrap().push(serde_json::json!(
            {"sampler": sampler, "target": {"path": "pointer", "extensions": {POINTER: {"pointer": pointer}}}}));
    }
    json["extensionsUsed"] = serde_json::json!([POINTER, "KHR_materials_emissive_strength"]);
    let animated = dir.join("BoxMaterialPointers.glb");
    write_glb(&json, &bin, &animated);
    // The twin: the 1 s keys written into the materials.
    let mut twin = base.clone();
    let key1 = |v: &Vec<f32>| {
        let w = v.len() / 3;
        v[w..2 * w].to_vec()
    };
    twin["materials"][0]["pbrMetallicRoughness"]["baseColorFactor"] = key1(&channels[0].3).into();
    twin["materials"][0]["pbrMetallicRoughness"]["roughnessFactor"] =
        key1(&channels[1].3)[0].into();
    twin["materials"][1]["emissiveFactor"] = key1(&channels[2].3).into();
    twin["materials"][1]["extensions"] = serde_json::json!(
        {"KHR_materials_emissive_strength": {"emissiveStrength": key1(&channels[3].3)[0]}});
    twin["extensionsUsed"] = serde_json::json!(["KHR_materials_emissive_strength"]);
    let twin_file = dir.join("BoxMaterialTwin.glb");
    write_glb(&twin, &bin0, &twin_file);
    (animated, twin_file)
}
