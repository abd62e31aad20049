//! A glTF file's cameras, scenes and material variants (issue 37) on a generated file: the
//! picture through a file camera equals the `--yaw/--pitch/--distance/--fov/--near` (or
//! `--ortho`) picture its node was built from, on GL 3.3, ES 3.0, GL 2.1 and OSMesa, and
//! orbiting from it is orbiting from those options; `--scene 1` and `--variant` draw what a
//! twin file holding only that scene or that material draws, pixel for pixel; unknown names
//! are a one-line error listing what the file has; `--check` lists them.
use crate::common::*;
use crate::gltf_materials::b64;
use glam::{DVec3, Mat3, Quat, Vec3};
use glview::image_out::RgbaFiles;
use serde_json::{json, Value};
use std::path::{Path, PathBuf};

/// Where the box's centre is in the file (not the origin: the re-centring is exercised).
const CENTRE: [f64; 3] = [3.0, 1.0, -2.0];
/// The perspective camera's orbit: yaw, pitch, distance (degrees, file units).
const ORBIT: (f32, f32, f32) = (35.0, 20.0, 4.0);
const YFOV_DEG: f32 = 40.0;
const ZNEAR: f32 = 0.5;
/// The orthographic camera: its orbit and ymag.
const ORTHO_ORBIT: (f32, f32, f32) = (-60.0, 30.0, 5.0);
const YMAG: f32 = 1.25;

/// The orbit camera's eye direction for (yaw, pitch), as `camera.rs` defines it.
fn direction(yaw: f32, pitch: f32) -> Vec3 {
    let (y, p) = (yaw.to_radians(), pitch.to_radians());
    Vec3::new(p.cos() * y.sin(), p.sin(), p.cos() * y.cos())
}

/// A camera node at the orbit (yaw, pitch, distance) around [`CENTRE`]: its -Z looks at the
/// centre and its +Y is the orbit camera's up (the derivative of the eye direction).
fn camera_node(camera: usize, (yaw, pitch, d): (f32, f32, f32)) -> Value {
    let back = direction(yaw, pitch);
    let (y, p) = (yaw.to_radians(), pitch.to_radians());
    let up = Vec3::new(-p.sin() * y.sin(), p.cos(), -p.sin() * y.cos());
    let right = up.cross(back);
    let q = Quat::from_mat3(&Mat3::from_cols(right, up, back)).normalize();
    let eye = DVec3::from(CENTRE) + back.as_dvec3() * f64::from(d);
    json!({"camera": camera, "translation": eye.to_array(), "rotation": q.to_array()})
}

/// The file: a unit box at [`CENTRE`] (scene 0, material 0 unless a variant maps it), a
/// flat wide box (scene 1), a perspective and an orthographic camera, variants Red and Blue.
fn document(box_material: usize, variants: bool) -> Value {
    let mut pos: Vec<f32> = Vec::new();
    let mut nrm: Vec<f32> = Vec::new();
    let mut idx: Vec<u32> = Vec::new();
    for axis in 0..3 {
        for s in [-1.0f32, 1.0] {
            let n = Vec3::from_array(std::array::from_fn(|k| if k == axis { s } else { 0.0 }));
            let (u, v) = (
                n.any_orthonormal_vector(),
                n.cross(n.any_orthonormal_vector()),
            );
            let base = (pos.len() / 3) as u32;
            for (a, b) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
                let p = (n + u * a + v * b) * 0.5;
                pos.extend(p.to_array());
                nrm.extend(n.to_array());
            }
            // Counter-clockwise seen from outside (u × v = n).
            idx.extend([base, base + 1, base + 2, base, base + 2, base + 3]);
        }
    }
    let mut bin: Vec<u8> = Vec::new();
    for x in pos.iter().chain(&nrm) {
        bin.extend(x.to_le_bytes());
    }
    for i in &idx {
        bin.extend(i.to_le_bytes());
    }
    let nv = pos.len() / 3;
    let mut primitive = json!({"attributes": {"POSITION": 0, "NORMAL": 1}, "indices": 2,
        "material": box_material});
    let mut doc = json!({
        "asset": {"version": "2.0"}, "scene": 0,
        "scenes": [{"name": "Cube", "nodes": [0, 2, 3]}, {"name": "Slab", "nodes": [1]}],
        "nodes": [
            {"mesh": 0, "translation": CENTRE},
            {"mesh": 1, "translation": CENTRE, "scale": [2.5, 0.3, 1.5]},
            camera_node(0, ORBIT),
            camera_node(1, ORTHO_ORBIT),
        ],
        "cameras": [
            {"name": "Front", "type": "perspective",
             "perspective": {"yfov": YFOV_DEG.to_radians(), "znear": ZNEAR, "zfar": 100.0}},
            {"name": "Plan", "type": "orthographic",
             "orthographic": {"xmag": YMAG, "ymag": YMAG, "znear": 0.1, "zfar": 100.0}},
        ],
        "materials": [
            {"pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.8, 0.8, 1.0], "metallicFactor": 0.0}},
            {"pbrMetallicRoughness": {"baseColorFactor": [0.9, 0.05, 0.05, 1.0], "metallicFactor": 0.0}},
            {"pbrMetallicRoughness": {"baseColorFactor": [0.05, 0.05, 0.9, 1.0], "metallicFactor": 0.0}},
        ],
        "meshes": [],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": nv, "type": "VEC3",
             "min": [-0.5, -0.5, -0.5], "max": [0.5, 0.5, 0.5]},
            {"bufferView": 0, "byteOffset": nv * 12, "componentType": 5126, "count": nv, "type": "VEC3"},
            {"bufferView": 1, "componentType": 5125, "count": idx.len(), "type": "SCALAR"},
        ],
        "bufferViews": [
            {"buffer": 0, "byteLength": nv * 24},
            {"buffer": 0, "byteOffset": nv * 24, "byteLength": idx.len() * 4},
        ],
        "buffers": [{"byteLength": bin.len(),
            "uri": format!("data:application/octet-stream;base64,{}", b64(&bin))}],
    });
    if variants {
        primitive["extensions"] = json!({"KHR_materials_variants": {"mappings": [
            {"material": 1, "variants": [0]}, {"material": 2, "variants": [1]}]}});
        doc["extensionsUsed"] = json!(["KHR_materials_variants"]);
        doc["extensions"] = json!({"KHR_materials_variants": {"variants": [
            {"name": "Red"}, {"name": "Blue"}]}});
    }
    let slab = json!({"attributes": {"POSITION": 0, "NORMAL": 1}, "indices": 2, "material": 2});
    doc["meshes"] = json!([{"primitives": [primitive]}, {"primitives": [slab]}]);
    doc
}

fn write(dir: &Path, name: &str, doc: &Value) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, serde_json::to_string(doc).unwrap()).unwrap();
    p
}

pub(crate) fn views_file(dir: &Path) -> PathBuf {
    write(dir, "views.gltf", &document(0, true))
}

/// The orbit options a camera node was built from.
fn orbit_args((yaw, pitch, d): (f32, f32, f32)) -> Vec<String> {
    let s = |x: f32| x.to_string();
    ["--yaw", &s(yaw), "--pitch", &s(pitch), "--distance", &s(d)]
        .map(String::from)
        .to_vec()
}

/// (name, environment, arguments) of the four contexts.
type Context<'a> = (&'a str, &'a [(&'a str, &'a str)], &'a [&'a str]);
const CONTEXTS: [Context; 4] = [
    ("gl33", &[], &[]),
    ("es3", &[], &["--gl", "es3", "--backend", "egl"]),
    ("gl21", GL21, &[]),
    ("osmesa", GL21_NO_FBO, &["--backend", "osmesa"]),
];

fn shot(
    dir: &Path,
    name: &str,
    model: &Path,
    args: &[String],
    ctx: &Context,
) -> glview::image_out::Rgba {
    let mut all = vec![model.to_str().unwrap(), "--size", "96x72"];
    all.extend(ctx.2.iter().copied());
    all.extend(args.iter().map(String::as_str));
    render(dir, &format!("{}-{name}", ctx.0), &all, ctx.1)
}

/// The pictures through the file's perspective and orthographic cameras equal those of
/// the orbit options their nodes were made from, on every context. Bound: 0 — the camera
/// becomes those options (yaw and pitch through asin/atan2, the target through the view
/// ray's point nearest the centre), and the rounding they add stays below what moves a
/// pixel at this size.
#[test]
fn file_cameras_equal_their_orbit_options_on_every_context() {
    let dir = out_dir("gltf-views-cameras");
    let model = views_file(&dir);
    let fov = ["--fov".to_string(), YFOV_DEG.to_string()];
    let near = ["--near".to_string(), ZNEAR.to_string()];
    for ctx in &CONTEXTS {
        let through = shot(
            &dir,
            "camera0",
            &model,
            &["--camera".into(), "Front".into()],
            ctx,
        );
        let mut want = orbit_args(ORBIT);
        want.extend(fov.clone());
        want.extend(near.clone());
        let orbit = shot(&dir, "orbit0", &model, &want, ctx);
        let d = diff(&through, &orbit, 0);
        eprintln!(
            "{} perspective: max {} over {} mean {}",
            ctx.0, d.max, d.over, d.mean
        );
        assert_eq!(d.max, 0, "{}: perspective camera", ctx.0);
        let through = shot(
            &dir,
            "camera1",
            &model,
            &["--camera".into(), "1".into()],
            ctx,
        );
        let mut want = orbit_args(ORTHO_ORBIT);
        want.extend(["--ortho".to_string(), (2.0 * YMAG).to_string()]);
        let orbit = shot(&dir, "orbit1", &model, &want, ctx);
        let d = diff(&through, &orbit, 0);
        eprintln!(
            "{} orthographic: max {} over {} mean {}",
            ctx.0, d.max, d.over, d.mean
        );
        assert_eq!(d.max, 0, "{}: orthographic camera", ctx.0);
    }
}

/// Orbiting from a file camera starts from it: `--camera 0 --keys Right` is the orbit
/// options with yaw + 5°, and K (the window's and the page's key) looks through camera 0.
#[test]
fn orbiting_from_a_file_camera_moves_its_options() {
    let dir = out_dir("gltf-views-orbit");
    let model = views_file(&dir);
    let ctx = &CONTEXTS[0];
    let moved = shot(
        &dir,
        "moved",
        &model,
        &["--camera", "0", "--keys", "Right"].map(String::from),
        ctx,
    );
    let mut want = orbit_args((ORBIT.0 + 5.0, ORBIT.1, ORBIT.2));
    want.extend(["--fov", &YFOV_DEG.to_string(), "--near", &ZNEAR.to_string()].map(String::from));
    let orbit = shot(&dir, "orbit-moved", &model, &want, ctx);
    assert_eq!(diff(&moved, &orbit, 0).max, 0, "orbit from the file camera");
    let k = shot(&dir, "key-k", &model, &["--keys".into(), "K".into()], ctx);
    let c0 = shot(
        &dir,
        "camera0",
        &model,
        &["--camera".into(), "0".into()],
        ctx,
    );
    assert_eq!(diff(&k, &c0, 0).max, 0, "K looks through camera 0");
}

/// `--scene 1` draws what a file whose only scene is scene 1 draws; `--variant` draws what
/// the file with the variant's material on the primitive draws (and the colours are the
/// variants': red, blue), by name or index.
#[test]
fn scenes_and_variants_equal_their_twin_files() {
    let dir = out_dir("gltf-views-scenes");
    let model = views_file(&dir);
    let ctx = &CONTEXTS[0];
    let mut slab_only = document(0, true);
    slab_only["scenes"] = json!([{"nodes": [1]}]);
    let slab_only = write(&dir, "slab-only.gltf", &slab_only);
    let scene1 = shot(&dir, "scene1", &model, &["--scene".into(), "1".into()], ctx);
    let twin = shot(&dir, "slab-only", &slab_only, &[], ctx);
    assert_eq!(diff(&scene1, &twin, 0).max, 0, "--scene 1");
    let by_name = shot(
        &dir,
        "scene-slab",
        &model,
        &["--scene".into(), "Slab".into()],
        ctx,
    );
    assert_eq!(diff(&by_name, &twin, 0).max, 0, "--scene Slab");
    let plain = shot(&dir, "scene0", &model, &[], ctx);
    assert!(diff(&scene1, &plain, 0).max > 0, "scene 1 is not scene 0");
    let centre = |img: &glview::image_out::Rgba| {
        let at = 4 * ((img.height / 2) * img.width + img.width / 2) as usize;
        [img.data[at], img.data[at + 1], img.data[at + 2]]
    };
    for (variant, material) in [("Red", 1), ("1", 2)] {
        let twin = write(
            &dir,
            &format!("material{material}.gltf"),
            &document(material, false),
        );
        let a = shot(
            &dir,
            &format!("variant-{variant}"),
            &model,
            &["--variant".into(), variant.into()],
            ctx,
        );
        let b = shot(&dir, &format!("material{material}"), &twin, &[], ctx);
        assert_eq!(diff(&a, &b, 0).max, 0, "--variant {variant}");
        let [r, _, bl] = centre(&a);
        assert!(
            if material == 1 {
                r > 2 * bl
            } else {
                bl > 2 * r
            },
            "{variant}: {:?}",
            centre(&a)
        );
    }
}

#[test]
fn unknown_names_are_one_line_errors_listing_the_file() {
    let dir = out_dir("gltf-views-errors");
    let model = views_file(&dir);
    let m = model.to_str().unwrap();
    let cases = [
        (
            vec!["--camera", "Side"],
            r#"no camera "Side": the file has 0 "Front", 1 "Plan""#,
        ),
        (
            vec!["--scene", "7"],
            r#"no scene "7": the file has 0 "Cube", 1 "Slab""#,
        ),
        (
            vec!["--variant", "Green"],
            r#"no variant "Green": the file has 0 "Red", 1 "Blue""#,
        ),
        (vec!["--keys", "V"], "use --variant"),
    ];
    for (args, expect) in cases {
        let out = dir.join("x.png");
        let mut all = vec![m, "--size", "32x32", "-o", out.to_str().unwrap()];
        all.extend(args.iter().copied());
        let o = run(&all, &[]);
        let e = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success(), "{args:?} succeeded");
        assert!(e.contains(expect), "{args:?}: {e}");
        assert_eq!(e.trim_end().lines().count(), 1, "{args:?}: {e}");
    }
}

#[test]
fn check_lists_cameras_scenes_and_variants() {
    let dir = out_dir("gltf-views-check");
    let model = views_file(&dir);
    let o = run(&["--check", model.to_str().unwrap()], &[]);
    let out = String::from_utf8_lossy(&o.stdout);
    for want in [
        r#"camera 0 "Front": perspective, yfov 40.00°"#,
        r#"camera 1 "Plan": orthographic, xmag 1.25 ymag 1.25"#,
        r#"scenes: 0 "Cube", 1 "Slab" (drawn: 0 "Cube""#,
        r#"variants: 0 "Red", 1 "Blue" (drawn: none"#,
    ] {
        assert!(out.contains(want), "{want}\n{out}");
    }
}

/// The mesh cache keeps the file's lists: on a hit `--check` lists the same cameras, scenes
/// and variants and `--camera` draws the same picture; `--variant` and `--scene` bypass the
/// entry (it holds the default scene and materials) and draw what an uncached load draws.
#[test]
fn cached_files_keep_their_cameras_and_bypass_for_choices() {
    let dir = out_dir("gltf-views-cache");
    let entries = dir.join("entries");
    let _ = std::fs::remove_dir_all(&entries);
    let env = [("GLVIEW_CACHE_DIR", entries.to_str().unwrap())];
    // Padded past cache::MIN_SIZE with bytes no accessor reads.
    let mut doc = document(0, true);
    let uri = doc["buffers"][0]["uri"].as_str().unwrap().to_string();
    let data = uri.split(',').nth(1).unwrap();
    let pad = (glview::scene::cache::MIN_SIZE as usize / 3 + 1) * 4;
    doc["buffers"][0]["uri"] = json!(format!(
        "data:application/octet-stream;base64,{data}{}",
        "A".repeat(pad)
    ));
    doc["buffers"][0]["byteLength"] = json!((data.len() + pad) / 4 * 3);
    let model = write(&dir, "big.gltf", &doc);
    let m = model.to_str().unwrap();
    let check = |extra: &[&str]| {
        let o = run(&[&[m, "--check"], extra].concat(), &env);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let out = String::from_utf8_lossy(&o.stdout).into_owned();
        let (load, rest): (Vec<&str>, Vec<&str>) =
            out.lines().partition(|l| l.starts_with("load: "));
        (load.join("\n"), rest.join("\n"))
    };
    let (_, uncached) = check(&["--no-cache"]);
    check(&[]);
    let (load, cached) = check(&[]);
    assert!(load.contains("(mesh cache)"), "not a hit: {load}");
    assert_eq!(uncached, cached, "--check from the entry");
    assert!(cached.contains(r#"camera 1 "Plan""#), "{cached}");
    for args in [
        &["--camera", "Front"][..],
        &["--variant", "Blue"],
        &["--scene", "1"],
    ] {
        let shot = |name: &str, extra: &[&str]| {
            let out = dir.join(format!("{name}.png"));
            let all = [
                &[m, "--size", "64x48", "-o", out.to_str().unwrap()],
                args,
                extra,
            ]
            .concat();
            let o = run(&all, &env);
            assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
            glview::image_out::Rgba::load_png(&out).unwrap()
        };
        let (a, b) = (shot("cached", &[]), shot("uncached", &["--no-cache"]));
        assert_eq!(
            diff(&a, &b, 0).max,
            0,
            "{args:?}: cached and uncached differ"
        );
    }
}

/// A camera no projection can be made of (zero field of view, non-finite near plane, zero
/// magnification) is left out with a warning naming it; the file still loads and the
/// variant mappings that name no material fall back to the default one.
#[test]
fn unusable_cameras_and_mappings_are_warnings() {
    let dir = out_dir("gltf-views-hostile");
    let mut doc = document(0, true);
    doc["cameras"][0]["perspective"]["yfov"] = json!(0.0);
    doc["cameras"][1]["orthographic"]["ymag"] = json!(0.0);
    doc["meshes"][0]["primitives"][0]["extensions"]["KHR_materials_variants"]["mappings"][0]
        ["material"] = json!(99);
    let model = write(&dir, "hostile.gltf", &doc);
    let opts = glview::scene::LoadOptions {
        variant: Some("Red".into()),
        ..Default::default()
    };
    let scene = glview::scene::load(&model, &opts).unwrap();
    assert!(scene.views.cameras.is_empty());
    let w: Vec<String> = scene.warnings.iter().map(|w| w.message.clone()).collect();
    assert!(
        w.iter()
            .any(|m| m.contains("camera 0 (node 2): yfov 0 is not a positive number")),
        "{w:?}"
    );
    assert!(
        w.iter().any(|m| m.contains("camera 1 (node 3): ymag 0")),
        "{w:?}"
    );
    let m = scene.meshes.iter().next().unwrap().material;
    assert_eq!(
        m,
        scene.materials.len() - 1,
        "material 99 is the default one"
    );
}
