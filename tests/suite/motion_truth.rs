//! A moment of a Khronos sample with a skin and an animation (RiggedSimple, committed under
//! tests/data/khronos/motion/ with its licence), drawn by every context glview has, held to
//! the CPU reference renderer posing the same scene (issue #39, "Truth and measurement"),
//! and the same `--time` giving the same bytes, from a fresh session and a kept one.
use super::common::*;
use glview::image_out::Rgba;
use glview::image_out::RgbaFiles;

const MODEL: &str = "tests/data/khronos/motion/RiggedSimple.glb";
const SIZE: &str = "160x120";

/// The words of a picture of MODEL at `time` (None: the static pose), shadows off: the
/// GPU against the reference's formula, as `gpu_vs_reference::without_shadows_*`.
fn words(time: Option<&'static str>) -> Vec<&'static str> {
    let mut w = vec![MODEL, "--size", SIZE, "--no-shadows", "--yaw", "30"];
    if let Some(t) = time {
        w.extend(["--time", t]);
    }
    w
}

/// Mean max-channel error (/255) and pixels off by more than 8/255.
fn errors(a: &Rgba, b: &Rgba) -> (f64, usize) {
    let d = diff(a, b, 8);
    (d.mean, d.over)
}

/// The GPU at 1.25 s on GL 3.3, ES 3.0, GL 2.1 (Mesa pretending to be a GL 2.1 driver, with
/// and without VAOs and FBOs) and OSMesa equals the reference renderer at 1.25 s within the tolerance of
/// `gpu_vs_reference::without_shadows_the_gpu_is_the_formula`'s (mean < 0.05/255; silhouette
/// pixels where coverage differs: at most 0.1 % here, the picture being small); and that
/// moment is not the static pose (the bend shows) in either renderer. On each context the
/// mesh is skinned on the GPU (its two joints fit every budget) and the picture is the CPU
/// path's (`GLVIEW_SKINNING=cpu`) byte for byte (measured: identical on all five).
#[test]
fn a_moment_on_every_context_is_the_reference_posed() {
    let dir = out_dir("motion_truth");
    let mut reference = words(Some("1.25"));
    reference.push("--reference");
    let want = render(&dir, "reference", &reference, &[]);
    let mut still = words(None);
    still.push("--reference");
    let rest = render(&dir, "reference-static", &still, &[]);
    let (_, moved) = errors(&want, &rest);
    assert!(
        moved > 200,
        "the moment is not the static pose: {moved} pixels moved"
    );
    for (name, extra, env) in CONTEXTS {
        let mut w = words(Some("1.25"));
        w.extend_from_slice(extra);
        let got = render(&dir, name, &w, env);
        check_frame(&got, name);
        let cpu_env: Vec<(&str, &str)> = env
            .iter()
            .copied()
            .chain([("GLVIEW_SKINNING", "cpu")])
            .collect();
        let cpu = render(&dir, &format!("{name}-cpu"), &w, &cpu_env);
        assert!(
            got.data == cpu.data,
            "{name}: skinned on the GPU is not the CPU path's picture: {}",
            write_diff(&dir, name, &got, &cpu).display()
        );
        let (mean, over) = errors(&got, &want);
        eprintln!("{name}: mean {mean:.4}/255, {over} pixels > 8/255");
        if mean >= 0.05 || over * 1000 > pixels(&got) {
            let p = write_diff(&dir, name, &got, &want);
            panic!(
                "{name}: mean {mean:.4}, {over} pixels > 8/255: {}",
                p.display()
            );
        }
    }
}

/// A context's name, its options and its environment.
pub(crate) type Context = (
    &'static str,
    &'static [&'static str],
    &'static [(&'static str, &'static str)],
);

fn pixels(img: &Rgba) -> usize {
    (img.width * img.height) as usize
}

/// `--time` twice gives the same bytes: two fresh runs of the binary, and a kept session
/// drawing 1.25 s, then 0.5 s, then 1.25 s again (a renderer posed away and back), then no
/// `--time` (the static pose restored).
#[test]
fn the_same_time_twice_gives_the_same_bytes() {
    let dir = out_dir("motion_truth");
    let files: Vec<Vec<u8>> = ["twice-a", "twice-b"]
        .iter()
        .map(|name| {
            let out = dir.join(format!("{name}.png"));
            let mut w = words(Some("1.25"));
            w.extend(["-o", out.to_str().unwrap()]);
            let o = run(&w, &[]);
            assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
            std::fs::read(&out).unwrap()
        })
        .collect();
    assert_eq!(files[0], files[1], "two runs at --time 1.25");
    let first = Rgba::load_png(&dir.join("twice-a.png")).unwrap();
    let mut session = glview::session::Session::new();
    let mut draw = |t: Option<&'static str>| {
        let o = glview::Options::from_words(words(t)).unwrap();
        let mut profile = Default::default();
        let d = session.draw(&o, None, Default::default(), &mut profile);
        (d.unwrap().image, profile)
    };
    let (a, pa) = draw(Some("1.25"));
    let (b, _) = draw(Some("0.5"));
    let (c, pc) = draw(Some("1.25"));
    // Back to the static pose: the picture of a session that never posed.
    let (d, _) = draw(None);
    let still = run_still(&dir);
    assert_eq!(d.data, still.data, "the static pose after a moment");
    assert_eq!(a.data, first.data, "the session's picture is the binary's");
    assert_eq!(a.data, c.data, "posed away and back");
    assert_ne!(a.data, b.data, "another moment");
    assert_eq!((pa.scene_uploads, pc.scene_uploads), (1, 0), "loaded once");
    // RiggedSimple is skinned on the GPU: a pose sets its joints and uploads nothing.
    assert!(
        pc.pose
            .is_some_and(|p| p.skinned == 1 && p.meshes == 0 && p.bytes == 0),
        "posed again on the GPU: {pc:?}"
    );
}

/// The static pose drawn by the binary (a process that never posed).
fn run_still(dir: &std::path::Path) -> Rgba {
    let out = dir.join("still.png");
    let mut w = words(None);
    w.extend(["-o", out.to_str().unwrap()]);
    let o = run(&w, &[]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    Rgba::load_png(&out).unwrap()
}

/// Skinned on the GPU, the passes beyond the legacy lit one: the PBR tier over its shadow
/// map (the depth program's `SKINNED` variant) and the shadow map itself
/// (`--show shadow-map`, which shows the bend: not the static pose's map) are the CPU path's
/// byte for byte (measured: identical).
#[test]
fn shadows_and_pbr_skinned_on_the_gpu_are_the_cpu_paths() {
    let dir = out_dir("motion_truth");
    let base = [
        MODEL,
        "--size",
        "64x48",
        "--yaw",
        "30",
        "--shadow-size",
        "256",
    ];
    for (name, view) in [
        ("pbr-shadows", ["--shading", "pbr"]),
        ("shadow-map", ["--show", "shadow-map"]),
    ] {
        let mut w = base.to_vec();
        w.extend(view);
        let mut at = w.clone();
        at.extend(["--time", "1.25"]);
        let gpu = render(&dir, name, &at, &[]);
        assert!(!gpu.is_uniform(), "{name}: blank");
        let cpu = render(
            &dir,
            &format!("{name}-cpu"),
            &at,
            &[("GLVIEW_SKINNING", "cpu")],
        );
        assert!(
            gpu.data == cpu.data,
            "{name}: skinned on the GPU is not the CPU path's picture: {}",
            write_diff(&dir, name, &gpu, &cpu).display()
        );
        if name == "shadow-map" {
            let still = render(&dir, &format!("{name}-static"), &w, &[]);
            assert!(
                gpu.data != still.data,
                "the shadow map does not show the pose"
            );
        }
    }
}

const MORPH_CUBE: &str = "tests/data/khronos/motion/AnimatedMorphCube.glb";

/// The contexts glview has: GL 3.3, ES 3.0, GL 2.1 (Mesa overrides, with and without VAOs
/// and FBOs) and OSMesa.
pub(crate) const CONTEXTS: [Context; 5] = [
    ("gl33", &["--gl", "core"], &[]),
    ("es3", &["--gl", "es3"], &[]),
    ("gl21", &["--gl", "2.1"], GL21),
    ("osmesa", &["--backend", "osmesa"], &[]),
    // A GL 2.1 driver without VAOs or FBOs: attributes bound per draw.
    (
        "osmesa-gl21-bare",
        &["--backend", "osmesa", "--gl", "2.1"],
        GL21_NO_FBO,
    ),
];

/// `model` at `time` on a context through the binary (64×48, no shadows), written to
/// `name`.png: the picture and the programs `--stats` lists.
fn drawn(
    model: &str,
    dir: &std::path::Path,
    name: &str,
    time: &str,
    ctx: Context,
    cpu: bool,
) -> (Rgba, String) {
    let (ctx_name, extra, env) = ctx;
    let out = dir.join(format!("{name}.png"));
    let mut w = vec![model, "--size", "64x48", "--yaw", "30", "--no-shadows"];
    w.extend(["--time", time, "--stats", "-o", out.to_str().unwrap()]);
    w.extend_from_slice(extra);
    let mut env = env.to_vec();
    if cpu {
        env.push(("GLVIEW_SKINNING", "cpu"));
    }
    let o = run(&w, &env);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let img = Rgba::load_png(&out).unwrap();
    check_frame(&img, ctx_name);
    (img, String::from_utf8_lossy(&o.stdout).into_owned())
}

/// Morph targets on the GPU: AnimatedMorphCube (two targets, positions and normals: four
/// delta attributes, which fit every context's 16) at two moments of its weights animation
/// is drawn by the `morph` programs on every context, and the picture is the CPU path's
/// (`GLVIEW_SKINNING=cpu`) byte for byte (measured: identical on all five); the two moments
/// differ.
#[test]
fn morphed_on_the_gpu_every_context_is_the_cpu_paths() {
    let dir = out_dir("motion_truth");
    for ctx in CONTEXTS {
        let mut seen = Vec::new();
        for time in ["0.5", "1.5"] {
            let name = format!("morph-{}-{time}", ctx.0);
            let (gpu, stats) = drawn(MORPH_CUBE, &dir, &name, time, ctx, false);
            assert!(
                stats.contains(",morph,m4]"),
                "{}: not morphed on the GPU: {stats}",
                ctx.0
            );
            let (cpu, stats) = drawn(MORPH_CUBE, &dir, &format!("{name}-cpu"), time, ctx, true);
            assert!(!stats.contains(",morph,"), "{}: {stats}", ctx.0);
            assert!(
                gpu.data == cpu.data,
                "{} at {time} s: morphed on the GPU is not the CPU path's picture: {}",
                ctx.0,
                write_diff(&dir, &name, &gpu, &cpu).display()
            );
            seen.push(gpu.data);
        }
        assert_ne!(seen[0], seen[1], "{}: the two moments", ctx.0);
    }
}

/// A pose of a mesh morphed on the GPU, with or without a skin, sets its weights (and
/// joints) and uploads nothing (`PoseCost`).
#[test]
fn a_gpu_morphed_pose_uploads_nothing() {
    at_repo();
    for model in [MORPH_CUBE, SKINNED_MORPHED] {
        let mut session = glview::session::Session::new();
        let mut draw = |t: &str| {
            let words = [model, "--size", "64x48", "--no-shadows", "--time", t];
            let o = glview::Options::from_words(words).unwrap();
            let mut profile = Default::default();
            session
                .draw(&o, None, Default::default(), &mut profile)
                .unwrap();
            profile
        };
        draw("0.5");
        let p = draw("1.5");
        assert_eq!(p.scene_uploads, 0, "{model}: loaded once");
        assert!(
            p.pose
                .is_some_and(|p| p.skinned == 1 && p.meshes == 0 && p.bytes == 0),
            "{model}: posed again on the GPU: {p:?}"
        );
    }
}

const SKINNED_MORPHED: &str = "tests/data/motion/SkinnedMorphed.glb";
const SKINNED_MORPHED_MAPPED: &str = "tests/data/motion/SkinnedMorphedMapped.glb";

/// A mesh both skinned and morphed (tests/data/motion/SkinnedMorphed.glb, made by
/// scripts/make_skinned_morphed.py: two joints, two targets of positions and normals) at
/// 0.6 s, where the joint has turned 24° and the weights are [0.6, 0.3], is drawn on every
/// context (GL 3.3, ES 3.0, GL 2.1 with and without VAOs, OSMesa) by one program that skins
/// and morphs (`--stats`: `skin,j2,morph,m4`), and the picture is the CPU path's
/// (`GLVIEW_SKINNING=cpu`) byte for byte; that moment is not the picture at 0 s, and the CPU
/// reference renderer posing the same scene gives it within `errors`' tolerance (measured:
/// identical).
#[test]
fn skinned_and_morphed_on_the_gpu_is_the_cpu_paths() {
    let dir = out_dir("motion_truth");
    for ctx in &CONTEXTS {
        let gpu = gpu_is_cpu(&dir, SKINNED_MORPHED, ",skin,j2,morph,m4]", *ctx);
        if ctx.0 == "gl33" {
            let (rest, _) = drawn(SKINNED_MORPHED, &dir, "skinmorph-rest", "0", *ctx, false);
            assert_ne!(rest.data, gpu.data, "0.6 s is not the rest pose");
            let reference: Context = ("reference", &["--reference"], &[]);
            let (want, _) = drawn(
                SKINNED_MORPHED,
                &dir,
                "skinmorph-ref",
                "0.6",
                reference,
                false,
            );
            let (mean, over) = errors(&gpu, &want);
            assert!(
                mean < 0.05 && over * 1000 <= pixels(&gpu),
                "mean {mean:.4}, {over} pixels > 8/255: {}",
                write_diff(&dir, "skinmorph-ref", &gpu, &want).display()
            );
        }
    }
}

/// A skin with two joint sets (tests/data/motion/TwoJointSets.glb, made by
/// scripts/make_two_joint_sets.py: six joints, up to six per vertex split across JOINTS_0
/// and JOINTS_1) at 0.6 s is skinned on the GPU on every context by the two-set program
/// (`--stats`: `skin,j6,s2`), and the picture is the CPU path's byte for byte (the CPU pose
/// itself is held to the script's positions in `scene::motion::tests`); that moment is not
/// the rest pose.
#[test]
fn two_joint_sets_on_the_gpu_are_the_cpu_paths() {
    let dir = out_dir("motion_truth");
    for ctx in &CONTEXTS {
        let gpu = gpu_is_cpu(&dir, TWO_SETS, ",skin,j6,s2]", *ctx);
        if ctx.0 == "gl33" {
            let (rest, _) = drawn(TWO_SETS, &dir, "two-sets-rest", "0", *ctx, false);
            assert_ne!(rest.data, gpu.data, "0.6 s is not the rest pose");
        }
    }
}

const TWO_SETS: &str = "tests/data/motion/TwoJointSets.glb";

/// `model` at 0.6 s on `ctx` is drawn by a program whose `--stats` name ends in `program`
/// (skinned, and morphed, on the GPU) and equals the CPU path's picture byte for byte; the
/// GPU's picture.
fn gpu_is_cpu(dir: &std::path::Path, model: &str, program: &str, ctx: Context) -> Rgba {
    let stem = std::path::Path::new(model).file_stem().unwrap();
    let name = format!("{}-{}", stem.to_string_lossy(), ctx.0);
    let (gpu, stats) = drawn(model, dir, &name, "0.6", ctx, false);
    assert!(
        stats.contains(program),
        "{name}: not skinned (and morphed) on the GPU: {stats}"
    );
    let cpu_name = format!("{name}-cpu");
    let (cpu, stats) = drawn(model, dir, &cpu_name, "0.6", ctx, true);
    assert!(!stats.contains(",skin,"), "{name}: {stats}");
    assert!(
        gpu.data == cpu.data,
        "{name}: skinned (and morphed) on the GPU is not the CPU path's picture: {}",
        write_diff(dir, &name, &gpu, &cpu).display()
    );
    gpu
}

/// The same tube with a normal map (tests/data/motion/SkinnedMorphedMapped.glb, made by
/// `scripts/make_skinned_morphed.py --mapped`: UVs, the file's tangents, one target moving
/// positions, normals and tangents) skins and morphs its tangents on the GPU as the CPU pose
/// does: on every context a `nrm,skin,j2,morph,m3` program (three delta attributes, the
/// tangents' among them) gives the CPU path's picture byte for byte. (Without the tangent
/// deltas the CPU path's picture differs in 364 pixels, by up to 13/255: measured.)
#[test]
fn skinned_morphed_tangents_on_the_gpu_are_the_cpu_paths() {
    let dir = out_dir("motion_truth");
    for ctx in &CONTEXTS {
        gpu_is_cpu(&dir, SKINNED_MORPHED_MAPPED, "nrm,skin,j2,morph,m3]", *ctx);
    }
}
