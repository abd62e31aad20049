//! The fast OBJ path (`scene::fast`) against the old one (repair pre-pass + tobj), which is
//! the reference: the same Scene (meshes, vertex order, indices, materials, smoothing, warnings
//! with their lines) or the same error, on every shared OBJ file and on generated files. Small
//! files are also parsed in chunks of a few dozen bytes so that relative indices cross chunks.
use crate::common::shared;
use glview::scene::loaders::obj::fast::Parser;
use glview::scene::profile;
use glview::scene::{loaders::obj::load_bytes_with, LoadOptions};
use std::path::{Path, PathBuf};

/// Loads with `parser`; the Scene as Debug text (exact floats) or the error, and whether the
/// fast path ran.
fn load(path: &Path, bytes: &[u8], parser: Parser) -> (String, bool) {
    profile::begin(0);
    match load_bytes_with(path, bytes, &LoadOptions::default(), parser) {
        Ok(s) => (
            format!("{s:?}"),
            profile::last().is_some_and(|p| p.fast_path),
        ),
        Err(e) => (format!("error: {e}"), false),
    }
}

/// Compares every fast variant with the old path; returns whether the fast path was taken.
fn same(path: &Path, bytes: &[u8], chunks: &[usize]) -> bool {
    let (want, _) = load(path, bytes, Parser::Tobj);
    let (got, fast) = load(path, bytes, Parser::Auto);
    let shown = || String::from_utf8_lossy(&bytes[..bytes.len().min(4000)]).into_owned();
    assert!(
        got == want,
        "{}: fast path differs\n{}",
        path.display(),
        shown()
    );
    for &n in chunks {
        let (got, f) = load(path, bytes, Parser::Chunked(n));
        assert_eq!(f, fast, "{}: chunks of {n}", path.display());
        assert!(
            got == want,
            "{}: fast path in chunks of {n} differs\n{}",
            path.display(),
            shown()
        );
    }
    fast
}

fn obj_files(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for e in entries.flatten() {
        let p = e.path();
        if p.is_dir() {
            obj_files(&p, out);
        } else if p.extension().is_some_and(|x| x.eq_ignore_ascii_case("obj")) {
            out.push(p);
        }
    }
}

#[test]
fn shared_files_load_the_same() {
    let shared = shared();
    let mut files = Vec::new();
    for d in ["models", "conformance", "tricky"] {
        obj_files(&shared.join(d), &mut files);
    }
    files.sort();
    assert!(files.len() > 50, "{} OBJ files", files.len());
    let mut fast = Vec::new();
    for f in &files {
        let bytes = std::fs::read(f).unwrap();
        // Tiny chunks for small files only (the dragon in 61-byte chunks would be slow).
        let chunks: &[usize] = if bytes.len() < 200_000 {
            &[61, 997]
        } else {
            &[]
        };
        if same(f, &bytes, chunks) {
            fast.push(f.file_name().unwrap().to_string_lossy().into_owned());
        }
    }
    eprintln!(
        "fast path on {} of {} files: {fast:?}",
        fast.len(),
        files.len()
    );
    for must in ["dragon_vrip_res2.obj", "stanford-bunny.obj", "bunny.obj"] {
        assert!(fast.iter().any(|f| f == must), "{must} fell back");
    }
}

/// A small deterministic generator (xorshift64*).
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }
    fn below(&mut self, n: u64) -> u64 {
        self.next() % n
    }
    fn pick<'a>(&mut self, xs: &[&'a str]) -> &'a str {
        xs[self.below(xs.len() as u64) as usize]
    }
    fn float(&mut self) -> String {
        let x = (self.next() % 2_000_001) as f64 / 1000.0 - 1000.0;
        match self.below(6) {
            0 => format!("{}", x.round()),
            1 => format!("{x:.6}"),
            2 => format!("{:e}", x * 1e-7),
            3 => format!("{x}"),
            4 => format!("{:.17}", x / 7.0),
            _ => format!("{x:.3}"),
        }
    }
}

const MTL: &str = "newmtl red\nKd 1 0 0\nnewmtl blue\nKd 0 0 1\nNs 0\n";

/// A random OBJ: mostly statements the fast path takes, with `quirks` the odd one it must
/// leave to the old path (continuations, `l`/`p`, unknown statements, bad indices...).
fn generate(rng: &mut Rng, quirks: bool) -> String {
    let eol = if rng.below(4) == 0 { "\r\n" } else { "\n" };
    let (mut v, mut vt, mut vn) = (0i64, 0i64, 0i64);
    let mut out = String::new();
    let style = rng.below(4);
    for _ in 0..rng.below(120) + 5 {
        let line = match rng.below(22) {
            0..=5 => {
                v += 1;
                format!("v {} {} {}", rng.float(), rng.float(), rng.float())
            }
            6 if style & 1 == 1 => {
                vn += 1;
                format!("vn {} {} {}", rng.float(), rng.float(), rng.float())
            }
            7 if style & 2 == 2 => {
                vt += 1;
                match rng.below(2) {
                    0 => format!("vt {} {}", rng.float(), rng.float()),
                    _ => format!("vt {}\t{} 0", rng.float(), rng.float()),
                }
            }
            8..=13 if v >= 3 => {
                let n = (3 + rng.below(3) * rng.below(2)).min(v as u64);
                let mut f = String::from("f");
                // Distinct positions (with quirks, mostly: a repeat makes a degenerate face).
                let mut used: Vec<i64> = Vec::new();
                for _ in 0..n {
                    let idx = |rng: &mut Rng, count: i64| -> String {
                        let i = rng.below(count as u64) as i64;
                        if rng.below(3) == 0 {
                            format!("{}", i - count)
                        } else {
                            format!("{}", i + 1)
                        }
                    };
                    let mut i = rng.below(v as u64) as i64;
                    while used.contains(&i) && (!quirks || rng.below(50) != 0) {
                        i = rng.below(v as u64) as i64;
                    }
                    used.push(i);
                    let c = if rng.below(3) == 0 {
                        format!("{}", i - v)
                    } else {
                        format!("{}", i + 1)
                    };
                    let t = (vt > 0).then(|| idx(rng, vt));
                    let m = (vn > 0).then(|| idx(rng, vn));
                    f.push_str(&match (t, m) {
                        (None, None) => format!(" {c}"),
                        (Some(t), None) => format!(" {c}/{t}"),
                        (None, Some(m)) => format!(" {c}//{m}"),
                        (Some(t), Some(m)) => format!(" {c}/{t}/{m}"),
                    });
                }
                f
            }
            14 => format!("{} part{}", rng.pick(&["o", "g", "g"]), rng.below(3)),
            15 => format!("usemtl {}", rng.pick(&["red", "blue", "green"])),
            16 => format!("s {}", rng.pick(&["off", "1", "2", "0"])),
            17 => rng
                .pick(&["# comment", "", "#", "  ", "mtllib m.mtl"])
                .into(),
            18 if quirks => rng
                .pick(&[
                    "l 1 2",
                    "p 1",
                    "vp 0.5",
                    "curv 1 2",
                    "v 1 2 \\",
                    "usemtl",
                    "f 1 1 2",
                    "f 1/9/9 2 3",
                    "f 0 1 2",
                    "v 1 2 3 1 0 0",
                    "v nan 0 0",
                    "# caf\u{e9}",
                    "f 99 1 2",
                    "\tv 1 2 3",
                    "v 1 2 3 2",
                    "vt 1",
                    "s",
                    "g",
                    "f 1 2 -99",
                    "f 1//1 2//1 3//1",
                ])
                .into(),
            _ => continue,
        };
        out.push_str(&line);
        if rng.below(10) == 0 {
            out.push(' ');
        }
        out.push_str(eol);
    }
    if rng.below(5) == 0 {
        out.insert_str(0, &format!("usemtl red{eol}mtllib m.mtl{eol}"));
    }
    out
}

fn fuzz(seed: u64, quirks: bool) -> (usize, usize) {
    let dir = std::env::temp_dir().join(format!("glview-fast-{}-{seed}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("m.mtl"), MTL).unwrap();
    let path = dir.join("gen.obj");
    let mut rng = Rng(seed);
    let (mut fast, n) = (0, 400);
    for _ in 0..n {
        let text = generate(&mut rng, quirks);
        fast += usize::from(same(&path, text.as_bytes(), &[1, 23, 64]));
    }
    std::fs::remove_dir_all(&dir).ok();
    (fast, n)
}

#[test]
fn generated_files_load_the_same() {
    let (fast, n) = fuzz(0x9E37_79B9_7F4A_7C15, false);
    eprintln!("fast path on {fast} of {n} clean files");
    assert!(fast * 2 > n, "fast path on only {fast} of {n} clean files");
}

#[test]
fn generated_files_with_quirks_load_the_same() {
    let (fast, n) = fuzz(0xD1B5_4A32_D192_ED03, true);
    eprintln!("fast path on {fast} of {n} files with quirks");
}

/// Generated statements in one 3 MB file: the default chunk size, so relative indices and
/// `o`/`g`/`usemtl`/`s` cross the real chunk boundaries, and large models take the same
/// ordered pass.
#[test]
fn large_generated_file_in_default_chunks() {
    let dir = std::env::temp_dir().join(format!("glview-fast-large-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("m.mtl"), MTL).unwrap();
    let mut rng = Rng(7);
    let mut text = String::new();
    while text.len() < 3 << 20 {
        text.push_str(&generate(&mut rng, false));
    }
    let fast = same(&dir.join("large.obj"), text.as_bytes(), &[]);
    std::fs::remove_dir_all(&dir).ok();
    assert!(fast, "a file of clean statements fell back to the old path");
}

/// Number words at the edges of what `str::parse::<f64>` takes (the old path's reader; the
/// fast path reads decimals with fast-float2 and must accept, refuse and round exactly as it
/// does) in every numeric statement: the same scene or error, or a fall back.
#[test]
fn awkward_number_words_load_the_same() {
    let dir = std::env::temp_dir().join(format!("glview-fast-words-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("words.obj");
    let words = [
        "0.5",
        "+.5",
        "-.5",
        "5.",
        "+5",
        "-0",
        ".",
        "1e",
        "1e+",
        "1E-3",
        "1.e2",
        "1e400",
        "-1e400",
        "1e-400",
        "6.4e39",
        "3.4028235e38",
        "inf",
        "-inf",
        "infinity",
        "INF",
        "nan",
        "-nan",
        "nan(1)",
        "infx",
        "0x10",
        "1_0",
        "1,5",
        "1.2.3",
        "--1",
        "+-1",
        "0.1000000000000000055511151231257827",
        "9007199254740993",
        "2.4703282292062328e-324",
        "1.7976931348623159e308",
        "0.30000000000000004",
        "1\u{a0}",
        "١",
    ];
    let (mut fast, mut n) = (0, 0);
    for w in words {
        for text in [
            format!("v {w} 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"),
            format!("v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 {w} 1\nf 1//1 2//1 3//1\n"),
            format!("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt {w} 0\nvt 0 1 {w}\nf 1/1 2/2 3/1\n"),
        ] {
            fast += usize::from(same(&path, text.as_bytes(), &[1, 8]));
            n += 1;
        }
    }
    std::fs::remove_dir_all(&dir).ok();
    eprintln!("fast path on {fast} of {n} files with awkward number words");
}

/// Fuzz finding (differential run, fuzz/README.md): a face index of 19 or more digits
/// overflowed the fast path's i64 while being read (a panic where overflow checks are on; in
/// release it wrapped and the index was then refused as too long). The fuzzer's input had
/// `1/2/19223372036854775807` as a corner. Such an index must reach the old path, whose error
/// or warning is the reference.
#[test]
fn face_index_of_many_digits_falls_back() {
    let dir = std::env::temp_dir().join(format!("glview-fast-index-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("index.obj");
    for idx in [
        "9223372036854775807",
        "19223372036854775807",
        "-99999999999999999999999",
        "1/2/19223372036854775807",
        "1//99999999999999999999",
        "1/99999999999999999999/1",
        "000000000000000000000000001",
    ] {
        let text = format!("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\nf 1/1/1 2/1/1 {idx}\n");
        let fast = same(&path, text.as_bytes(), &[1, 8]);
        assert!(!fast, "{idx}: taken by the fast path");
    }
    std::fs::remove_dir_all(&dir).ok();
}
