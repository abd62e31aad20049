//! Shared helpers for the integration tests: run the binary, read and compare images, and
//! write the output plus a diff image when a comparison fails.
#![allow(dead_code)]
use glview::image_out::Rgba;
use glview::image_out::RgbaFiles;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

pub fn bin() -> &'static str {
    at_repo();
    env!("CARGO_BIN_EXE_glview")
}

/// The tests name files relative to the repository's root (`models/sphere.obj`), as a user
/// there would, but cargo runs them in the package's folder (cli/): every helper moves the
/// process there first (the same folder from every thread, so the order does not matter).
pub fn at_repo() {
    static DONE: std::sync::Once = std::sync::Once::new();
    DONE.call_once(|| {
        std::env::set_current_dir(Path::new(env!("CARGO_MANIFEST_DIR")).join(".."))
            .expect("the repository's root");
    });
}

pub fn in_ci() -> bool {
    std::env::var("CI").is_ok_and(|v| v == "true")
}

/// Where failing tests leave their images.
pub fn out_dir(test: &str) -> PathBuf {
    at_repo();
    let d = Path::new(env!("CARGO_TARGET_TMPDIR")).join(test);
    std::fs::create_dir_all(&d).expect("create test output dir");
    d
}

/// The repository's root (the tests are the cli package's, in cli/).
pub fn repo() -> PathBuf {
    at_repo();
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// The shared test data folder (../shared beside the repository).
pub fn shared() -> PathBuf {
    at_repo();
    let p = repo().join("../shared");
    assert!(
        p.join("MANIFEST.md").exists(),
        "../shared is missing: the tests need the shared models and conformance files at {}",
        p.display()
    );
    p
}

pub fn models() -> PathBuf {
    at_repo();
    repo().join("models")
}

/// Runs glview with arguments and extra environment variables.
pub fn run(args: &[&str], env: &[(&str, &str)]) -> Output {
    at_repo();
    let mut c = Command::new(bin());
    c.args(args);
    for (k, v) in env {
        c.env(k, v);
    }
    c.output().expect("run glview")
}

/// Renders to `dir/name.png` and reads it back; panics with glview's error on failure.
/// A plain picture with no special environment is rendered in this process by the shared
/// fixture (one context, one program cache); anything else runs the binary.
/// `glview --repro PNG -o OUT`: the picture drawn again from its PNG text.
/// Runs the ignored test `name` (`module::test`) of this test binary in a child process
/// with `env` (Mesa reads its overrides once, when a process makes its first context) and
/// fails unless it passed.
pub fn run_child_test(name: &str, env: &[(&str, &str)]) {
    let o = std::process::Command::new(std::env::current_exe().unwrap())
        .args([
            name,
            "--exact",
            "--ignored",
            "--nocapture",
            "--test-threads",
            "1",
        ])
        .envs(env.iter().copied())
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    let out = String::from_utf8_lossy(&o.stdout);
    eprintln!("{err}");
    assert!(
        o.status.success() && out.contains("1 passed"),
        "{out}\n{err}"
    );
}

pub fn repro(png: &Path, out: &Path) -> Output {
    run(
        &[
            "--repro",
            png.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
        ],
        &[],
    )
}

pub fn render(dir: &Path, name: &str, args: &[&str], env: &[(&str, &str)]) -> Rgba {
    let out = dir.join(format!("{name}.png"));
    let mut all = vec!["--output", out.to_str().unwrap()];
    all.extend_from_slice(args);
    if let Some(result) = env.is_empty().then(|| fixture::render(&all)).flatten() {
        if let Err(e) = result {
            panic!("glview {all:?} failed (in process):\n{e}");
        }
    } else {
        let o = run(&all, env);
        assert!(
            o.status.success(),
            "glview {all:?} failed:\n{}",
            String::from_utf8_lossy(&o.stderr)
        );
    }
    let img = Rgba::load_png(&out).expect("read output");
    check_frame(&img, name);
    img
}

/// Every render: not blank, and no pure-black pixel (the scenes used in tests have a
/// non-black background and non-zero ambient, so (0,0,0) can only come from NaN or Inf
/// reaching the framebuffer).
pub fn check_frame(img: &Rgba, name: &str) {
    assert!(!img.is_uniform(), "{name}: blank frame");
    let black = img
        .data
        .chunks_exact(4)
        .filter(|p| p[..3] == [0, 0, 0])
        .count();
    assert_eq!(black, 0, "{name}: {black} black (NaN/Inf) pixels");
    let translucent = img.data.chunks_exact(4).filter(|p| p[3] != 255).count();
    assert_eq!(
        translucent, 0,
        "{name}: {translucent} pixels are not opaque"
    );
}

pub struct Diff {
    pub max: u8,
    /// Pixels whose largest channel difference exceeds the threshold given to `diff`.
    pub over: usize,
    pub mean: f64,
}

pub fn diff(a: &Rgba, b: &Rgba, threshold: u8) -> Diff {
    assert_eq!(
        (a.width, a.height),
        (b.width, b.height),
        "image sizes differ"
    );
    let mut max = 0u8;
    let mut over = 0;
    let mut sum = 0u64;
    for (p, q) in a.data.chunks_exact(4).zip(b.data.chunks_exact(4)) {
        let d = (0..3).map(|i| p[i].abs_diff(q[i])).max().unwrap();
        max = max.max(d);
        sum += u64::from(d);
        over += usize::from(d > threshold);
    }
    Diff {
        max,
        over,
        mean: sum as f64 / (a.width * a.height) as f64,
    }
}

/// Writes both images and an amplified difference image for a failed comparison.
pub fn write_diff(dir: &Path, name: &str, a: &Rgba, b: &Rgba) -> PathBuf {
    let mut d = a.clone();
    for (i, (p, q)) in a
        .data
        .chunks_exact(4)
        .zip(b.data.chunks_exact(4))
        .enumerate()
    {
        let m = (0..3).map(|k| p[k].abs_diff(q[k])).max().unwrap();
        let v = m.saturating_mul(16);
        d.data[i * 4..i * 4 + 4].copy_from_slice(&[v, v, v, 255]);
    }
    let (pa, pb, pd) = (
        dir.join(format!("{name}-a.png")),
        dir.join(format!("{name}-b.png")),
        dir.join(format!("{name}-diff.png")),
    );
    a.save_png(&pa, &[]).unwrap();
    b.save_png(&pb, &[]).unwrap();
    d.save_png(&pd, &[]).unwrap();
    pd
}

/// Asserts that two renders agree: at most `max_over` pixels differ by more than
/// `threshold`, and none by more than `hard_max`.
pub fn assert_close(
    dir: &Path,
    name: &str,
    a: &Rgba,
    b: &Rgba,
    threshold: u8,
    max_over: usize,
    hard_max: u8,
) {
    let d = diff(a, b, threshold);
    if d.over > max_over || d.max > hard_max {
        let p = write_diff(dir, name, a, b);
        panic!(
            "{name}: {} pixels differ by more than {threshold} (allowed {max_over}), max {} (allowed {hard_max}), mean {:.4}; see {}",
            d.over,
            d.max,
            d.mean,
            p.display()
        );
    }
    eprintln!(
        "{name}: max diff {}, {} pixels > {threshold}, mean {:.4}",
        d.max, d.over, d.mean
    );
}

/// Environment that makes Mesa pretend to be an old GL 2.1 driver (GLSL 1.20).
pub const GL21: &[(&str, &str)] = &[
    ("MESA_GL_VERSION_OVERRIDE", "2.1"),
    ("MESA_GLSL_VERSION_OVERRIDE", "120"),
];

/// GL 2.1 without framebuffer objects or vertex array objects (OSMesa's own buffer).
pub const GL21_NO_FBO: &[(&str, &str)] = &[
    ("MESA_GL_VERSION_OVERRIDE", "2.1"),
    ("MESA_GLSL_VERSION_OVERRIDE", "120"),
    (
        "MESA_EXTENSION_OVERRIDE",
        "-GL_ARB_framebuffer_object -GL_EXT_framebuffer_object -GL_ARB_vertex_array_object",
    ),
];

/// The exact frame settings glview uses for these command-line arguments, and the scene.
pub fn settings_for(args: &[&str]) -> (glview::render::FrameSettings, glview::scene::Scene) {
    at_repo();
    let a = glview::Options::from_words(args.iter().copied()).expect("valid options");
    let scene = glview::session::load_scene(&a).expect("load scene");
    let (s, _) = glview::session::frame_settings(&a, &scene).expect("settings");
    (s, scene)
}

/// A ray (origin, unit direction) through the centre of pixel (x, y), y = 0 at the top, in
/// the scene's local coordinates, computed in f64 from the camera's matrices.
pub struct PixelRays {
    inv: glam::DMat4,
    w: u32,
    h: u32,
}

impl PixelRays {
    pub fn new(
        s: &glview::render::FrameSettings,
        scene: &glview::scene::Scene,
        w: u32,
        h: u32,
    ) -> Self {
        let aspect = w as f32 / h as f32;
        let vp = (s.camera.projection(&scene.bounds, aspect) * s.camera.view()).as_dmat4();
        PixelRays {
            inv: vp.inverse(),
            w,
            h,
        }
    }

    pub fn ray(&self, x: u32, y: u32) -> (glam::DVec3, glam::DVec3) {
        use glam::DVec4;
        let nx = 2.0 * (x as f64 + 0.5) / self.w as f64 - 1.0;
        let ny = 1.0 - 2.0 * (y as f64 + 0.5) / self.h as f64;
        let a = self.inv * DVec4::new(nx, ny, -1.0, 1.0);
        let b = self.inv * DVec4::new(nx, ny, 1.0, 1.0);
        let (a, b) = (a.truncate() / a.w, b.truncate() / b.w);
        (a, (b - a).normalize())
    }
}

/// Ray/box slab test: the entry distance if the ray (o, d) hits the box within (tmin, tmax).
pub fn ray_box(
    o: glam::DVec3,
    d: glam::DVec3,
    lo: glam::DVec3,
    hi: glam::DVec3,
    tmin: f64,
    tmax: f64,
) -> Option<f64> {
    let (mut t0, mut t1) = (tmin, tmax);
    for i in 0..3 {
        let inv = 1.0 / d[i];
        let (mut a, mut b) = ((lo[i] - o[i]) * inv, (hi[i] - o[i]) * inv);
        if a > b {
            std::mem::swap(&mut a, &mut b);
        }
        t0 = t0.max(a);
        t1 = t1.min(b);
        if t0 > t1 {
            return None;
        }
    }
    Some(t0)
}

/// OBJ text for an axis-aligned box from `lo` to `hi` (8 `v`, 12 outward-facing `f` lines),
/// for a file that already has `before` vertices.
pub fn box_obj(lo: [f64; 3], hi: [f64; 3], before: usize) -> String {
    let mut s = String::new();
    for (x, y, z) in [
        (lo[0], lo[1], lo[2]),
        (hi[0], lo[1], lo[2]),
        (hi[0], hi[1], lo[2]),
        (lo[0], hi[1], lo[2]),
        (lo[0], lo[1], hi[2]),
        (hi[0], lo[1], hi[2]),
        (hi[0], hi[1], hi[2]),
        (lo[0], hi[1], hi[2]),
    ] {
        s += &format!("v {x} {y} {z}\n");
    }
    for f in [
        [1, 3, 2],
        [1, 4, 3],
        [5, 6, 7],
        [5, 7, 8],
        [1, 2, 6],
        [1, 6, 5],
        [2, 3, 7],
        [2, 7, 6],
        [3, 4, 8],
        [3, 8, 7],
        [4, 1, 5],
        [4, 5, 8],
    ] {
        s += &format!("f {} {} {}\n", f[0] + before, f[1] + before, f[2] + before);
    }
    s
}

/// The in-process GPU fixture: one thread owns one headless context (so one program cache)
/// and renders every request in turn, as the binary would. Tests run on many threads and a
/// GL context is current on one thread only, hence the channel.
pub mod fixture {
    use std::sync::mpsc::{channel, Sender};
    use std::sync::{Mutex, OnceLock};

    type Job = (Vec<String>, Sender<Result<(), String>>);

    fn queue() -> &'static Mutex<Sender<Job>> {
        static QUEUE: OnceLock<Mutex<Sender<Job>>> = OnceLock::new();
        QUEUE.get_or_init(|| {
            let (tx, rx) = channel::<Job>();
            std::thread::spawn(move || {
                let mut session = glview::session::Session::new();
                for (argv, reply) in rx {
                    let result = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
                        let (args, out) = one_picture(&argv[1..]).ok_or("not one picture")?;
                        session
                            .write(&args, &out)
                            .map_err(|e| format!("error: {e}"))
                    }));
                    let result = result.unwrap_or_else(|_| {
                        // The context's state is unknown after a panic: start afresh.
                        session.close();
                        Err("glview panicked".into())
                    });
                    let _ = reply.send(result);
                }
            });
            Mutex::new(tx)
        })
    }

    /// Renders `args` (with `--output`) in this process, or None when the arguments ask
    /// for another mode than one headless picture (those run the binary).
    ///
    /// The picture's options and `--output` of words that ask for one headless picture and
    /// nothing else (no mode flag, no subcommand, valid options: the binary reports errors).
    fn one_picture(words: &[String]) -> Option<(glview::Options, std::path::PathBuf)> {
        const MODES: &[&str] = &[
            "bench",
            "sheet",
            "batch",
            "--reference",
            "--compare",
            "--diff",
            "--diff-against",
            "--threshold",
            "--info",
            "--compile-shaders",
            "--check",
            "--screenshot-dir",
            "--repro",
            "--options-reference",
            "--help",
            "-h",
            "--version",
            "-V",
        ];
        let mut rest = Vec::new();
        let mut output = None;
        let mut it = words.iter();
        while let Some(w) = it.next() {
            let name = w.split('=').next().unwrap_or_default();
            if MODES.contains(&name) {
                return None;
            }
            match (w.as_str(), w.strip_prefix("--output=")) {
                ("-o" | "--output", _) => output = Some(std::path::PathBuf::from(it.next()?)),
                (_, Some(v)) => output = Some(v.into()),
                _ => rest.push(w.clone()),
            }
        }
        let out = output?;
        let still = glview::image_out::OutputFormat::of(&out).is_some();
        (still || glview::anim_out::AnimFormat::of(&out).is_some()).then_some(())?;
        Some((glview::Options::from_words(rest).ok()?, out))
    }
    pub fn render(args: &[&str]) -> Option<Result<(), String>> {
        super::at_repo();
        let argv: Vec<String> = std::iter::once("glview")
            .chain(args.iter().copied())
            .map(String::from)
            .collect();
        one_picture(&argv[1..])?;
        let (tx, rx) = channel();
        queue()
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .send((argv, tx))
            .ok()?;
        Some(
            rx.recv()
                .unwrap_or_else(|_| Err("the fixture thread is gone".into())),
        )
    }
}

/// A GLB file's JSON and binary chunk, to edit and write again (test files made from real
/// ones: quirks, pointer channels).
pub struct Glb {
    pub json: serde_json::Value,
    pub bin: Vec<u8>,
}

impl Glb {
    pub fn read(path: &Path) -> Glb {
        let bytes = std::fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let len = u32::from_le_bytes(bytes[12..16].try_into().unwrap()) as usize;
        let json = serde_json::from_slice(&bytes[20..20 + len]).unwrap();
        let bin = bytes.get(20 + len + 8..).unwrap_or_default().to_vec();
        Glb { json, bin }
    }

    /// Appends `values` (f32s) as a new accessor of `kind` ("SCALAR", "VEC3", ...) in a
    /// view of its own; its index. The buffer's byteLength follows on write.
    pub fn add_f32(&mut self, values: &[f32], kind: &str, per: usize) -> usize {
        while !self.bin.len().is_multiple_of(4) {
            self.bin.push(0);
        }
        let views = self.json["bufferViews"].as_array_mut().unwrap();
        views.push(serde_json::json!({
            "buffer": 0, "byteOffset": self.bin.len(), "byteLength": values.len() * 4
        }));
        let view = views.len() - 1;
        self.bin.extend(values.iter().flat_map(|v| v.to_le_bytes()));
        let mut acc = serde_json::json!({
            "bufferView": view, "componentType": 5126, "count": values.len() / per, "type": kind
        });
        if kind == "SCALAR" {
            let lo = values.iter().copied().fold(f32::MAX, f32::min);
            let hi = values.iter().copied().fold(f32::MIN, f32::max);
            acc["min"] = serde_json::json!([lo]);
            acc["max"] = serde_json::json!([hi]);
        }
        let accessors = self.json["accessors"].as_array_mut().unwrap();
        accessors.push(acc);
        accessors.len() - 1
    }

    /// Writes the file (its buffer's byteLength set to the chunk's length, before padding).
    pub fn write(&self, out: &Path) {
        let mut json = self.json.clone();
        if let Some(b) = json["buffers"].get_mut(0) {
            b["byteLength"] = self.bin.len().into();
        }
        write_glb(&json, &self.bin, out);
    }
}

/// `json` and `bin` as a GLB at `out`, each chunk padded to 4 bytes.
pub fn write_glb(json: &serde_json::Value, bin: &[u8], out: &Path) {
    let mut text = serde_json::to_vec(json).unwrap();
    text.resize(text.len().div_ceil(4) * 4, b' ');
    let mut bin = bin.to_vec();
    bin.resize(bin.len().div_ceil(4) * 4, 0);
    let mut glb = b"glTF".to_vec();
    glb.extend(2u32.to_le_bytes());
    glb.extend(((12 + 8 + text.len() + 8 + bin.len()) as u32).to_le_bytes());
    glb.extend((text.len() as u32).to_le_bytes());
    glb.extend(b"JSON");
    glb.extend(text);
    glb.extend((bin.len() as u32).to_le_bytes());
    glb.extend(b"BIN\0");
    glb.extend(bin);
    std::fs::write(out, glb).unwrap();
}
