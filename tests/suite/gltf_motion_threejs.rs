//! glview's poses against three.js's (issue 39): an implementation of glTF skins, morph
//! targets and animations written by others, pinned (tests/threejs), on Khronos sample files
//! (tests/data/khronos/motion). three.js poses each vertex on the CPU
//! (`Mesh.getVertexPosition`: morph targets, then the skin) at the same moment of the same
//! animation; every glview mesh must match one of three.js's, vertex for vertex, within 1e-5
//! of the model's size (f32 joint matrices on three.js's side, f32 positions on glview's).
use crate::common::{in_ci, repo};
use glview::scene::motion::Moment;
use glview::scene::{LoadOptions, Scene};
use std::path::{Path, PathBuf};
use std::process::Command;

/// (file, animation, moments): skins (CesiumMan, Fox, RiggedSimple, RiggedFigure), morph
/// weights (AnimatedMorphCube; AnimatedMorphSphere's with tangents; MorphStressTest's 8
/// targets, past the GPU's budget), node TRS (BoxAnimated, CesiumMilkTruck's wheels), every
/// interpolation (InterpolationTest).
const CASES: &[(&str, usize, &[f64])] = &[
    ("CesiumMan", 0, &[0.0, 0.77, 1.5]),
    ("Fox", 1, &[0.31]),
    ("Fox", 2, &[0.9]),
    ("RiggedSimple", 0, &[1.1]),
    ("AnimatedMorphCube", 0, &[0.5, 2.9]),
    ("BoxAnimated", 0, &[1.3, 3.0]),
    ("InterpolationTest", 0, &[0.8]),
    ("InterpolationTest", 2, &[0.8]),
    ("InterpolationTest", 4, &[0.37]),
    ("InterpolationTest", 5, &[0.8]),
    ("AnimatedMorphSphere", 0, &[2.5, 4.5]),
    ("MorphStressTest", 0, &[3.3]),
    ("MorphStressTest", 1, &[0.9]),
    ("RiggedFigure", 0, &[0.4, 1.0]),
    ("CesiumMilkTruck", 0, &[0.3]),
    // A real exporter's file (tests/data/real): FBX2glTF's skin weights summing to 1.755,
    // normalised as three.js normalises them; its Dance.
    ("real/RobotExpressive", 0, &[1.0]),
];

/// The pinned three.js with the pose script, or None (a failure under CI=true) when
/// scripts/prepare_tests.sh has not installed it.
fn threejs() -> Option<PathBuf> {
    let dir = repo().join("target/threejs");
    if !dir.join("node_modules/three/package.json").exists() {
        assert!(
            !in_ci(),
            "target/threejs has no three.js: scripts/prepare_tests.sh installs it"
        );
        eprintln!("skipped: no three.js in target/threejs (run scripts/prepare_tests.sh)");
        return None;
    }
    let script = dir.join("pose.mjs");
    std::fs::copy(repo().join("tests/threejs/pose.mjs"), &script).expect("copy pose.mjs");
    Some(script)
}

/// three.js's posed positions of every mesh primitive, in world coordinates.
fn three_pose(script: &Path, file: &Path, animation: Option<usize>, t: f64) -> Vec<Vec<f64>> {
    let out = Command::new("node")
        .arg(script)
        .arg(file)
        .arg(animation.map_or("-1".into(), |a| a.to_string()))
        .arg(t.to_string())
        .output()
        .expect("run node");
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "three.js failed on {}: {text}",
        file.display()
    );
    serde_json::from_str(&text).unwrap_or_else(|e| panic!("three.js output: {e}: {text}"))
}

/// The largest distance between glview's posed vertices of a mesh and those of the
/// three.js mesh with as many vertices that is nearest.
fn worst_match(scene: &Scene, three: &[Vec<f64>]) -> f64 {
    let mut worst = 0.0f64;
    for (i, m) in scene.meshes.iter().enumerate() {
        let ours: Vec<[f64; 3]> = m
            .vertices
            .iter()
            .map(|v| {
                let p = v.position;
                [
                    f64::from(p[0]) + scene.origin.x,
                    f64::from(p[1]) + scene.origin.y,
                    f64::from(p[2]) + scene.origin.z,
                ]
            })
            .collect();
        let best = three
            .iter()
            .filter(|t| t.len() == ours.len() * 3)
            .map(|t| {
                ours.iter()
                    .enumerate()
                    .map(|(k, q)| {
                        let d: f64 = (0..3).map(|c| (q[c] - t[k * 3 + c]).powi(2)).sum();
                        d.sqrt()
                    })
                    .fold(0.0, f64::max)
            })
            .fold(f64::INFINITY, f64::min);
        assert!(
            best.is_finite(),
            "mesh {i}: no three.js mesh of {} vertices",
            ours.len()
        );
        worst = worst.max(best);
    }
    worst
}

#[test]
fn poses_match_threejs_on_khronos_samples() {
    let Some(script) = threejs() else { return };
    let dir = repo().join("tests/data/khronos/motion");
    let mut report = Vec::new();
    let mut seen = Vec::new();
    for &(name, animation, times) in CASES {
        let file = match name.strip_prefix("real/") {
            Some(real) => repo().join("tests/data/real").join(format!("{real}.glb")),
            None => dir.join(format!("{name}.glb")),
        };
        let mut scene = glview::scene::load(&file, &LoadOptions::default()).expect("loads");
        let size = (scene.bounds.max - scene.bounds.min).length() as f64;
        // The static pose too (three.js: no mixer), once per file.
        let mut moments: Vec<Option<f64>> = Vec::new();
        if !seen.contains(&name) {
            seen.push(name);
            moments.push(None);
        }
        moments.extend(times.iter().map(|&t| Some(t)));
        for t in moments {
            scene
                .pose(t.map(|seconds| Moment { animation, seconds }))
                .expect("poses");
            let three = three_pose(&script, &file, t.map(|_| animation), t.unwrap_or(0.0));
            let worst = worst_match(&scene, &three);
            report.push(format!(
                "{name} {animation} {t:?}: {worst:.2e} of {size:.3}"
            ));
            assert!(
                worst <= 1e-5 * size,
                "{name} animation {animation} at {t:?}: a vertex is {worst:.3e} from three.js's \
                 (model size {size:.3})\n{}",
                report.join("\n")
            );
        }
    }
    eprintln!("{}", report.join("\n"));
}
