//! Posing on the render side (issue #39): a renderer whose meshes changed in place uploads
//! them again and draws what a fresh renderer of the changed scene draws, byte for byte
//! (buffers, bounding spheres, clusters, shadow maps and edge lines all follow); and the
//! session's `--time` and `--animation` reach the scene or say what the file has.
use super::common::*;
use glview::headless::Headless;
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
