//! The scenes in `models/` are generated; this keeps the committed copies in sync with
//! `src/scene/generate.rs`.

use glview::scene::generate;
use std::fs::File;
use std::io::BufReader;
use std::path::PathBuf;

const REGENERATE: &str = "run `cargo run --bin gen_models` and commit models/";

fn models_dir() -> PathBuf {
    crate::common::repo().join("models")
}

/// 1-based number of the first line where the two texts differ, to make a failure actionable
/// without dumping megabytes of OBJ.
fn first_difference(a: &str, b: &str) -> usize {
    let mut lines = a.lines().zip(b.lines());
    lines
        .position(|(x, y)| x != y)
        .unwrap_or(a.lines().count().min(b.lines().count()))
        + 1
}

#[test]
fn committed_models_match_the_generator() {
    for model in generate::all() {
        for (ext, want) in [("obj", &model.obj), ("mtl", &model.mtl)] {
            let path = models_dir().join(format!("{}.{ext}", model.name));
            let got = std::fs::read_to_string(&path)
                .unwrap_or_else(|e| panic!("cannot read {}: {e}; {REGENERATE}", path.display()));
            assert!(
                got == *want,
                "{} differs from the generator output (first at line {}); {REGENERATE}",
                path.display(),
                first_difference(&got, want)
            );
        }
    }
}

#[test]
fn committed_checker_png_matches_the_generator() {
    let path = models_dir().join("checker.png");
    let file = File::open(&path)
        .unwrap_or_else(|e| panic!("cannot open {}: {e}; {REGENERATE}", path.display()));
    let mut reader = png::Decoder::new(BufReader::new(file)).read_info().unwrap();
    let mut pixels = vec![0; reader.output_buffer_size().unwrap()];
    let info = reader.next_frame(&mut pixels).unwrap();
    let (width, height, rgba) = generate::checker_png_rgba();
    assert_eq!(
        (info.width, info.height, info.color_type, info.bit_depth),
        (width, height, png::ColorType::Rgba, png::BitDepth::Eight),
        "{}: {REGENERATE}",
        path.display()
    );
    assert!(
        pixels[..info.buffer_size()] == rgba[..],
        "{} pixels differ; {REGENERATE}",
        path.display()
    );
}
