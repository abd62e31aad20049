//! Regression tests for what the `loader` fuzz target found (see fuzz/README.md). Each test
//! feeds the loader the input the fuzzer found (minimised) or the smallest equivalent, and
//! asserts the outcome issue 5 asks for: a clean `Err` naming the file (and line), or `Ok` with
//! the scene invariants the fuzz target checks (`check_scene` below is the same code: this file
//! includes fuzz/src/lib.rs).
//!
//! Tests marked `Regression (finding n, fixed)` reproduce a crash described in
//! fuzz/README.md ("Findings"); its fix is in the loader, and the test keeps it there.
#[path = "../../fuzz/src/lib.rs"]
pub(crate) mod fuzz_support;

use fuzz_support::{check_scene, load_compared, split_input};
use glview::scene::Scene;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::{Path, PathBuf};

/// An empty folder per test for the model to "live" in (MTL bytes come from memory).
fn model_path(test: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("fuzz_regressions")
        .join(test);
    std::fs::create_dir_all(&dir).expect("create the test folder");
    dir.join("fuzz.obj")
}

/// Loads OBJ + MTL bytes like the fuzz target does (old path, and the fast path compared with
/// it: `load_compared`), turning a panic into a test failure that names the fix that has not
/// landed.
fn load(test: &str, obj: &[u8], mtl: &[u8], fix: &str) -> (PathBuf, glview::Result<Scene>) {
    let path = model_path(test);
    let out = catch_unwind(AssertUnwindSafe(|| load_compared(&path, obj, mtl)));
    match out {
        Ok(r) => (path, r.map_err(glview::Error::from)),
        Err(p) => {
            let msg = p
                .downcast_ref::<String>()
                .cloned()
                .or_else(|| p.downcast_ref::<&str>().map(|s| s.to_string()))
                .unwrap_or_default();
            panic!("the loader panicked ({fix} has not landed?): {msg}")
        }
    }
}

/// A fuzz input in the target's format: OBJ, 0xFF 0x00 0xFF, MTL.
fn load_input(test: &str, data: &[u8], fix: &str) -> (PathBuf, glview::Result<Scene>) {
    let (obj, mtl) = split_input(data);
    load(test, obj, mtl, fix)
}

fn assert_ok(path: &Path, r: glview::Result<Scene>) -> Scene {
    let scene = r.unwrap_or_else(|e| panic!("{}: expected a scene, got: {e}", path.display()));
    if let Err(v) = check_scene(&scene) {
        panic!("{}: invariant violated: {v}", path.display());
    }
    scene
}

/// A clean error whose message starts with `FILE:LINE: ` (or `FILE: ` without a line).
fn assert_err(path: &Path, line: Option<usize>, r: glview::Result<Scene>) -> String {
    let e = match r {
        Ok(s) => panic!(
            "{}: expected an error, got a scene with {} triangles",
            path.display(),
            s.triangle_count()
        ),
        Err(e) => e.to_string(),
    };
    let prefix = match line {
        Some(l) => format!("{}:{l}: ", path.display()),
        None => format!("{}: ", path.display()),
    };
    assert!(
        e.starts_with(&prefix),
        "error {e:?} does not start with {prefix:?}"
    );
    assert!(!e.contains('\n'), "error is not one line: {e:?}");
    e
}

const TRIANGLE_WITH_MATERIAL: &[u8] =
    b"mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl a\nf 1 2 3\n";

// --- Finding 1: tobj 4.0.5 panics on an MTL colour with fewer than 3 numbers ---------------
// `parse_float3` collects up to 3 numbers into a Vec and unwraps its conversion to [f64; 3]:
// `Kd`, `Kd 1` or `Ka 0 0` in any MTL the OBJ references aborts the whole program.

const FIX1: &str = "fix 1 (MTL colour pre-pass, fuzz/README.md)";

/// Regression (finding 1, fixed). The fuzzer's minimised input, byte for byte: an OBJ that is only
/// `mtllib ` and an MTL that is only `Kd`. Expected: no panic; no triangles, so a clean error.
#[test]
fn fuzz_crash_mtl_bare_kd() {
    let (path, r) = load_input("bare_kd", b"mtllib \xff\x00\xffKd", FIX1);
    let e = assert_err(&path, None, r);
    assert!(e.contains("no triangles"), "{e}");
}

/// Regression (finding 1, fixed). Every colour statement tobj parses as three numbers, with 0 and 2
/// numbers: the model renders with the default colour and one warning naming the MTL and line.
#[test]
fn fuzz_crash_mtl_colour_missing_numbers() {
    for (i, kw) in ["Ka", "Kd", "Ks", "Ke"].iter().enumerate() {
        for args in ["", " 0.5 0.5"] {
            let test = format!("short_colour_{i}_{}", args.len());
            let mtl = format!("newmtl a\n{kw}{args}\nNs 10\n");
            let (path, r) = load(&test, TRIANGLE_WITH_MATERIAL, mtl.as_bytes(), FIX1);
            let s = assert_ok(&path, r);
            let m = &s.materials[s.meshes[0].material];
            assert_eq!(m.name, "a", "{kw}{args}: the rest of the material is kept");
            assert_eq!(
                m.phong_terms().shininess,
                10.0,
                "{kw}{args}: later lines are still read"
            );
            let w = s
                .warnings
                .iter()
                .find(|w| w.message.contains(kw))
                .unwrap_or_else(|| panic!("{kw}{args}: no warning names {kw}: {:?}", s.warnings));
            assert!(
                w.file.ends_with("m.mtl") && w.line == Some(2),
                "{kw}{args}: warning should name m.mtl line 2: {w}"
            );
        }
    }
}

/// Regression (finding 1, fixed). One number is valid MTL (`Kd r`: g and b default to r).
#[test]
fn fuzz_crash_mtl_colour_one_number_is_grey() {
    let (path, r) = load(
        "one_number",
        TRIANGLE_WITH_MATERIAL,
        b"newmtl a\nKd 0.5\n",
        FIX1,
    );
    let s = assert_ok(&path, r);
    assert_eq!(s.materials[s.meshes[0].material].base_color, [0.5; 3]);
}

// --- Finding 2: positions beyond f32 range become inf --------------------------------------
// A coordinate such as 6.4e39 is finite as f64, so the repair pass accepts it; re-centred and
// rounded to f32 it is ±inf.

const FIX2: &str = "fix 2 (positions beyond f32 range refused)";

/// Regression (finding 2, fixed). Expected: the error of a non-finite position, with its line.
#[test]
fn fuzz_crash_position_beyond_f32() {
    let obj = b"v 0 0 0\nv 1e39 0 0\nv 0 1 0\nf 1 2 3\n";
    let (path, r) = load("position_1e39", obj, b"", FIX2);
    let e = assert_err(&path, Some(2), r);
    assert!(e.contains("1e39"), "{e}");
    // The fuzzer's input after `cargo fuzz tmin` (130 bytes; y = 6.4e39 on line 2).
    let data = b"c\nv 08 6406333333333333333333333333333333333333 0\nv 2 6 90\nv 2 3 0\n\
                 v 6 6 90\nv 2 6 0\nv 80 60 0\nv 4 6 48\nv 0 6 5\nv 595 7 585\nf 1 9 6";
    assert_eq!(data.len(), 130);
    let (path, r) = load_input("position_fuzzer", data, FIX2);
    assert_err(&path, Some(2), r);
}

/// Passes today and must keep passing with fix 2: large but representable coordinates on both
/// sides of the origin still load, with finite local positions.
#[test]
fn fuzz_large_positions_in_f32_range_load() {
    let obj = b"v 0 0 0\nv 3e38 0 0\nv -3e38 1 0\nf 1 2 3\n";
    let (path, r) = load("position_3e38", obj, b"", FIX2);
    assert_ok(&path, r);
}

// --- Finding 3: huge normals are "normalised" to zero ----------------------------------------
// `vn 1e20 0 0` is finite in f32, so `normals::usable` keeps it, and `Vec3::normalize` squares
// it to inf and returns (0, 0, 0): a black, unlit vertex. (Found by reading the code during the
// fuzz runs; the target's unit-length invariant reports this input as a crash.)

const FIX3: &str = "fix 3 (normals normalised in f64)";

/// Regression (finding 3, fixed). Expected: the normal is kept and normalised to unit length.
#[test]
fn fuzz_crash_normal_length_overflows_f32() {
    let obj = b"v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1e20\nvn 0 0 3e38\nf 1//1 2//2 3//1\n";
    let (path, r) = load("normal_1e20", obj, b"", FIX3);
    let s = assert_ok(&path, r);
    for v in &s.meshes[0].vertices {
        assert_eq!(v.normal, [0.0, 0.0, 1.0]);
    }
}

/// Passes today: tiny, zero and NaN normals are replaced by generated ones (unit length).
#[test]
fn fuzz_tiny_and_nan_normals_are_regenerated() {
    for vn in ["1e-19 1e-19 1e-19", "0 0 0", "nan 0 0", "1e-45 0 0"] {
        let obj = format!("v 0 0 0\nv 1 0 0\nv 0 1 0\nvn {vn}\nf 1//1 2//1 3//1\n");
        let (path, r) = load("normal_tiny", obj.as_bytes(), b"", FIX3);
        let s = assert_ok(&path, r);
        assert_eq!(s.meshes[0].vertices[0].normal, [0.0, 0.0, 1.0], "vn {vn}");
    }
}

// --- Finding 5: one key in two spellings made the same file load differently each time ------
// `map_pm a.tex` and `map_Pm b.tex` in one material are two keys of tobj's `unknown_param`
// HashMap; the PBR reader took the first case-insensitive match in the map's (per-load random)
// order. Found by the differential check (fast path vs old path differed, as did two old-path
// loads).

const FIX5: &str = "fix 5 (PBR keys looked up deterministically)";

/// Regression (finding 5, fixed). The exact spelling wins, else the smallest spelling; every
/// load gives the same scene (each `load` also compares the fast path with the old path).
#[test]
fn fuzz_pbr_key_in_two_spellings_is_deterministic() {
    let mtl = b"newmtl a\nmap_pm low.tex\nmap_Pm exact.tex\nmap_pr r1.tex\nmap_PR r2.tex\n";
    let mut first = None;
    for _ in 0..16 {
        let (path, r) = load("two_spellings", TRIANGLE_WITH_MATERIAL, mtl, FIX5);
        let s = assert_ok(&path, r);
        let maps = &s.materials[s.meshes[0].material].check.maps;
        let names: Vec<_> = maps.iter().map(|(k, v, _)| format!("{k} {v}")).collect();
        assert_eq!(names, ["map_Pm exact.tex", "map_Pr r2.tex"]);
        let text = format!("{s:?}");
        assert_eq!(first.get_or_insert_with(|| text.clone()), &text);
    }
}
