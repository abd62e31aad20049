//! Every animation of a file on one clock (issue 50, `--animation all`): the picture at a
//! moment is, byte for byte, that of the same file with its animations merged into one by
//! hand; where none is named, files whose animations drive different nodes play them all
//! (Khronos' InterpolationTest: nine cubes, one animation each, as the glTF Sample Viewer
//! plays it) and files whose animations share a skeleton play the first (Fox); `--check`
//! lists the nodes each animation drives and warns where two drive the same ones.
use crate::common::*;
use glview::image_out::RgbaFiles;
use serde_json::Value;
use std::path::{Path, PathBuf};

const INTERPOLATION: &str = "tests/data/khronos/motion/InterpolationTest.glb";
const FOX: &str = "tests/data/khronos/motion/Fox.glb";

/// `path` with its animations merged into one by hand: every channel, in file order, with
/// its sampler renumbered into the one animation's list.
fn merged_by_hand(dir: &Path, path: &str) -> PathBuf {
    let mut g = Glb::read(&repo().join(path));
    let animations = g.json["animations"].as_array().unwrap().clone();
    let (mut channels, mut samplers) = (Vec::new(), Vec::new());
    for a in &animations {
        let base = samplers.len() as u64;
        samplers.extend(a["samplers"].as_array().unwrap().iter().cloned());
        for c in a["channels"].as_array().unwrap() {
            let mut c = c.clone();
            c["sampler"] = Value::from(c["sampler"].as_u64().unwrap() + base);
            channels.push(c);
        }
    }
    g.json["animations"] =
        serde_json::json!([{"name": "merged", "channels": channels, "samplers": samplers}]);
    let out = dir.join("merged-by-hand.glb");
    g.write(&out);
    out
}

fn shot(dir: &Path, name: &str, model: &str, args: &[&str]) -> Vec<u8> {
    let out = dir.join(format!("{name}.png"));
    let mut all = vec![model, "--size", "160x120", "-o", out.to_str().unwrap()];
    all.extend(args);
    let o = run(&all, &[]);
    assert!(
        o.status.success(),
        "{name}: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    glview::image_out::Rgba::load_png(&out).unwrap().data
}

#[test]
fn all_animations_at_a_moment_are_the_file_merged_by_hand() {
    let dir = out_dir("motion-together");
    let merged = merged_by_hand(&dir, INTERPOLATION);
    let merged = merged.to_str().unwrap();
    for t in ["0.4", "1.3", "2.9"] {
        let all = shot(
            &dir,
            &format!("all-{t}"),
            INTERPOLATION,
            &["--animation", "all", "--time", t],
        );
        let hand = shot(&dir, &format!("hand-{t}"), merged, &["--time", t]);
        assert!(
            all == hand,
            "--animation all at {t} s is not the merged file's picture"
        );
        // Disjoint animations: the default plays them all.
        let default = shot(&dir, &format!("default-{t}"), INTERPOLATION, &["--time", t]);
        assert!(
            default == all,
            "the default at {t} s is not every animation together"
        );
        let one = shot(
            &dir,
            &format!("one-{t}"),
            INTERPOLATION,
            &["--animation", "3", "--time", t],
        );
        assert!(one != all, "one cube moving is not nine at {t} s");
    }
}

#[test]
fn a_shared_skeleton_plays_its_first_animation_by_default_and_check_says_why() {
    let dir = out_dir("motion-together");
    let first = shot(&dir, "fox-0", FOX, &["--animation", "0", "--time", "0.5"]);
    let default = shot(&dir, "fox-default", FOX, &["--time", "0.5"]);
    assert!(first == default, "Fox's default is not its first animation");
    // Together, the later animations' channels win on the shared bones: Run's pose at 0.5 s
    // (seen from one camera: the merged animation's framing holds every animation's poses).
    let camera = ["--target", "0,40,0", "--distance", "260", "--time", "0.5"];
    let all = shot(
        &dir,
        "fox-all",
        FOX,
        &[&["--animation", "all"][..], &camera].concat(),
    );
    let run_ = shot(
        &dir,
        "fox-2",
        FOX,
        &[&["--animation", "2"][..], &camera].concat(),
    );
    assert!(
        all == run_,
        "Fox together is not its last animation on the shared skeleton"
    );
    let o = run(&["--check", FOX], &[]);
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(
        text.contains("animation 0 \"Survey\": drives 20 nodes"),
        "{text}"
    );
    assert!(
        text.contains("warning: animations 0 \"Survey\" and 1 \"Walk\" drive 20 of the same nodes"),
        "{text}"
    );
    assert!(text.contains("default animation: 0"), "{text}");
    assert!(
        text.contains("animation 3 \"all\": the file's animations together"),
        "{text}"
    );
    let o = run(&["--check", INTERPOLATION], &[]);
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(text.contains("default animation: all 9 together"), "{text}");
    assert!(!text.contains("warning: animations"), "{text}");
}
