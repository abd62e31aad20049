//! Shared by the fuzz target (`fuzz_targets/loader.rs`) and the regression tests
//! (`tests/fuzz_regressions.rs` includes this file with `#[path]`), so both split inputs and
//! check scenes in exactly the same way. Depends on nothing but glview and std.
#![allow(dead_code)]

use glview::scene::loaders::obj::fast::Parser;
use glview::scene::Scene;
use glview::scene::{loaders::obj::load_embedded_with, LoadOptions};
use std::path::Path;

/// Separates the OBJ part from the MTL part of one fuzz input.
pub const SEPARATOR: &[u8] = b"\xff\x00\xff";

/// Splits a fuzz input at the first [`SEPARATOR`] into (OBJ bytes, MTL bytes). Without a
/// separator the whole input is the OBJ and the MTL is empty.
pub fn split_input(data: &[u8]) -> (&[u8], &[u8]) {
    match data.windows(SEPARATOR.len()).position(|w| w == SEPARATOR) {
        Some(i) => (&data[..i], &data[i + SEPARATOR.len()..]),
        None => (data, &[]),
    }
}

/// Joins an OBJ and an MTL into one fuzz input (the seed script does the same in shell).
pub fn join_input(obj: &[u8], mtl: &[u8]) -> Vec<u8> {
    let mut v = Vec::with_capacity(obj.len() + SEPARATOR.len() + mtl.len());
    v.extend_from_slice(obj);
    v.extend_from_slice(SEPARATOR);
    v.extend_from_slice(mtl);
    v
}

/// What every `Ok` scene must satisfy. Returns the first violation as text.
pub fn check_scene(scene: &Scene) -> Result<(), String> {
    // A file with only lines or points loads (issue 13); nothing at all does not.
    if scene.triangle_count() == 0 && scene.wire.is_empty() {
        return Err("Ok scene without triangles, lines or points".into());
    }
    let wn = scene.wire.positions.len();
    if let Some(i) = scene
        .wire
        .segments
        .iter()
        .flatten()
        .chain(&scene.wire.points)
        .find(|&&i| i as usize >= wn)
    {
        return Err(format!("wire index {i} >= wire position count {wn}"));
    }
    for (mi, mesh) in scene.meshes.iter().enumerate() {
        let n = mesh.vertices.len();
        if !mesh.colors.is_empty() && mesh.colors.len() != n {
            return Err(format!(
                "mesh {mi}: {} colours for {n} vertices",
                mesh.colors.len()
            ));
        }
        if mesh.indices.len() % 3 != 0 {
            return Err(format!(
                "mesh {mi}: {} indices, not a multiple of 3",
                mesh.indices.len()
            ));
        }
        if let Some(&i) = mesh.indices.iter().find(|&&i| i as usize >= n) {
            return Err(format!("mesh {mi}: index {i} >= vertex count {n}"));
        }
        if mesh.material >= scene.materials.len() {
            return Err(format!(
                "mesh {mi}: material {} >= material count {}",
                mesh.material,
                scene.materials.len()
            ));
        }
        for (vi, v) in mesh.vertices.iter().enumerate() {
            if !v.position.iter().all(|x| x.is_finite()) {
                return Err(format!(
                    "mesh {mi} vertex {vi}: position {:?} not finite",
                    v.position
                ));
            }
            if !v.normal.iter().all(|x| x.is_finite()) {
                return Err(format!(
                    "mesh {mi} vertex {vi}: normal {:?} not finite",
                    v.normal
                ));
            }
            let len = v
                .normal
                .iter()
                .map(|&x| f64::from(x) * f64::from(x))
                .sum::<f64>()
                .sqrt();
            if (len - 1.0).abs() > 1e-3 {
                return Err(format!(
                    "mesh {mi} vertex {vi}: normal {:?} has length {len}, not 1",
                    v.normal
                ));
            }
        }
    }
    Ok(())
}

/// An empty folder for the fuzzed OBJ to "live" in: MTL bytes come from memory, and texture
/// paths resolve against this folder (empty, so they are not found, and anything outside it is
/// refused by the loader's path rule).
pub fn model_path() -> &'static std::path::Path {
    use std::sync::OnceLock;
    static PATH: OnceLock<std::path::PathBuf> = OnceLock::new();
    PATH.get_or_init(|| {
        // One fixed name: nothing is ever written into it, so concurrent jobs can share it.
        let dir = std::env::temp_dir().join("glview-fuzz-model");
        std::fs::create_dir_all(&dir).expect("create the fuzz model folder");
        dir.join("fuzz.obj")
    })
}

/// Whether an input (OBJ bytes, MTL bytes) would hit a known crash.
pub type Matcher = fn(&[u8], &[u8]) -> bool;

/// Crashes found by fuzzing whose fix has not landed in the loader yet, one per entry:
/// (what goes wrong, which inputs hit it). Each has a regression test in
/// `tests/fuzz_regressions.rs`. With `GLVIEW_FUZZ_SKIP_KNOWN=1` the fuzz target skips inputs
/// that match one, so a long run explores past them instead of stopping at the first; without
/// it (the default) every input is loaded. Remove an entry once its fix has landed.
pub const KNOWN_UNFIXED: &[(&str, Matcher)] = &[
    // Empty: the three crashes found so far (short MTL colours, positions beyond f32,
    // overflowing normals) are fixed; their regression tests are in tests/fuzz_regressions.rs.
];

/// Whether the fuzz target skips inputs that hit a [`KNOWN_UNFIXED`] crash.
pub fn skip_known() -> bool {
    use std::sync::OnceLock;
    static SKIP: OnceLock<bool> = OnceLock::new();
    *SKIP.get_or_init(|| std::env::var_os("GLVIEW_FUZZ_SKIP_KNOWN").is_some_and(|v| v == "1"))
}

/// The name of the known, unfixed crash this input would hit, if any.
pub fn known_unfixed(data: &[u8]) -> Option<&'static str> {
    let (obj, mtl) = split_input(data);
    KNOWN_UNFIXED
        .iter()
        .find(|(_, hit)| hit(obj, mtl))
        .map(|(name, _)| *name)
}

/// The fast OBJ parsers the differential check runs against the old path (repair pre-pass +
/// tobj, the reference): the default chunking (one chunk for a fuzz-sized input) and chunks of
/// about 64 bytes, so that relative indices, names and materials cross chunk boundaries.
pub const FAST_PARSERS: &[Parser] = &[Parser::Auto, Parser::Chunked(64)];

/// The outcome of a load as text: the Scene's Debug text (exact floats) or the error.
pub fn outcome_text(r: &Result<Scene, glview::scene::error::Error>) -> String {
    match r {
        Ok(s) => format!("{s:?}"),
        Err(e) => format!("error: {e}"),
    }
}

/// Where two outcome texts first differ, with some text either side (the texts of a fuzz input
/// can be megabytes long).
pub fn first_difference(a: &str, b: &str) -> String {
    let at = a
        .bytes()
        .zip(b.bytes())
        .position(|(x, y)| x != y)
        .unwrap_or(a.len().min(b.len()));
    let around = |s: &str| {
        let mut lo = at.saturating_sub(300).min(s.len());
        while !s.is_char_boundary(lo) {
            lo -= 1;
        }
        let mut hi = (at + 300).min(s.len());
        while !s.is_char_boundary(hi) {
            hi += 1;
        }
        s[lo..hi].to_string()
    };
    format!(
        "first difference at byte {at} of {} / {}:\n  old: …{}…\n  new: …{}…",
        a.len(),
        b.len(),
        around(a),
        around(b)
    )
}

/// Loads OBJ + MTL bytes as `path` with the old path and with every [`FAST_PARSERS`] entry
/// (`load_embedded_with`: the MTL bytes are what every `mtllib` gets, in both), and panics
/// when a fast parser's outcome differs from the old path's in any way: the scene (meshes,
/// vertex order, indices, materials, smoothing, warnings and their lines) or the error text.
/// The fast path either gives the old path's result or falls back to it, so any difference is
/// a bug in the fast path. Returns the old path's outcome.
pub fn load_compared(
    path: &Path,
    obj: &[u8],
    mtl: &[u8],
) -> Result<Scene, glview::scene::error::Error> {
    let opts = LoadOptions::default();
    let want = load_embedded_with(path, obj, mtl, &opts, Parser::Tobj);
    let want_text = outcome_text(&want);
    for &parser in FAST_PARSERS {
        let got = outcome_text(&load_embedded_with(path, obj, mtl, &opts, parser));
        if got != want_text {
            panic!(
                "differential: the fast OBJ path ({parser:?}) differs from the old path \
                 (repair + tobj); {}",
                first_difference(&want_text, &got)
            );
        }
    }
    want
}

/// Loads one fuzz input with the old and the fast OBJ paths and checks the outcome; panics (the
/// fuzzer's "crash") when the two differ ([`load_compared`]), on a violated invariant or on an
/// error that does not name the file.
pub fn run_one(data: &[u8]) -> Result<Scene, glview::scene::error::Error> {
    let (obj, mtl) = split_input(data);
    let path = model_path();
    let out = load_compared(path, obj, mtl);
    check_outcome(path, &out);
    out
}

/// Panics (the fuzzer's "crash") on a scene that breaks an invariant, or on an error that
/// does not name the file in one line.
fn check_outcome(path: &std::path::Path, out: &Result<Scene, glview::scene::error::Error>) {
    match out {
        Ok(scene) => {
            if let Err(e) = check_scene(scene) {
                panic!("invariant violated: {e}");
            }
        }
        Err(e) => {
            let msg = e.to_string();
            assert!(
                msg.contains(&*path.to_string_lossy()),
                "error does not name the file: {msg}"
            );
            assert!(!msg.contains('\n'), "error of more than one line: {msg}");
        }
    }
}

/// Poses `scene` at `moment` and checks the outcome as a load's: the scene's invariants, or
/// a one-line error naming the file.
pub fn check_pose(scene: &mut Scene, moment: Option<glview::scene::motion::Moment>) {
    let out = scene.pose(moment).map(|_| scene.clone());
    check_outcome(&format_path("fuzz.gltf").with_file_name(""), &out);
}

/// Where a fuzzed STL, PLY or glTF file "lives": the same empty folder as the OBJ, so URIs
/// resolve to nothing inside it and everything outside is refused by the loader's rule.
pub fn format_path(name: &str) -> std::path::PathBuf {
    model_path().with_file_name(name)
}

/// Loads one fuzz input as the file `name` (its extension picks the loader, `.gz` inflates
/// it first) and checks the outcome like [`run_one`]: a scene that keeps the invariants, or an
/// error naming the file. Used by the `stl`, `ply` and `gltf` targets.
pub fn run_format(name: &str, data: &[u8]) -> Result<Scene, glview::scene::error::Error> {
    let path = format_path(name);
    let out = glview::scene::load::load_bytes(&path, data, &LoadOptions::default());
    check_outcome(&path, &out);
    out
}

/// The glTF target's file name: binary glTF when the input starts with the GLB magic.
pub fn gltf_name(data: &[u8]) -> &'static str {
    if data.starts_with(b"glTF") {
        "fuzz.glb"
    } else {
        "fuzz.gltf"
    }
}
