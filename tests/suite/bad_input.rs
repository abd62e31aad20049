//! Bad input: every broken file either renders (exit 0) with one warning per problem, or
//! stops with one clear `error: FILE[:LINE]: ...` line and exit code 1. Never a panic, a hang
//! or unbounded memory. The malformed files are written here, one per case.
use crate::common;
use common::*;
use glview::image_out::RgbaFiles;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::time::{Duration, Instant};

const TRI: &str = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nvn 0 0 1\n";

fn write(dir: &Path, name: &str, bytes: &[u8]) -> PathBuf {
    let p = dir.join(name);
    if let Some(parent) = p.parent() {
        std::fs::create_dir_all(parent).unwrap();
    }
    std::fs::write(&p, bytes).unwrap();
    p
}

/// How long one run may take before it is killed and the test fails (a hang must fail,
/// not hang the suite).
const DEADLINE: Duration = Duration::from_secs(60);

/// Runs glview under a 2 GiB address-space limit (`--check`, no GL) or with rendering (into a
/// PNG in the test's output folder), killed at [`DEADLINE`]; returns the output.
fn glview(args: &[&str], render: bool) -> Output {
    let png = out_dir("bad-input-render").join("out.png");
    let mut cmd = if render {
        let mut c = Command::new(bin());
        c.args(args)
            .args(["--output", png.to_str().unwrap(), "--size", "32x24"]);
        c
    } else {
        // llvmpipe reserves large address ranges, so only the GL-free check runs under ulimit.
        let mut c = Command::new("sh");
        let quoted: Vec<String> = args
            .iter()
            .map(|a| format!("'{}'", a.replace('\'', "'\\''")))
            .collect();
        c.args([
            "-c",
            &format!(
                "ulimit -v 2097152; exec '{}' --check {}",
                bin(),
                quoted.join(" ")
            ),
        ]);
        c
    };
    run_with_deadline(&mut cmd, DEADLINE)
        .unwrap_or_else(|| panic!("killed after {DEADLINE:?}: {args:?}"))
}

/// Runs `cmd`, reading its output on threads (a full pipe must not block it); kills it and
/// returns None when it outlives `deadline`.
pub(crate) fn run_with_deadline(cmd: &mut Command, deadline: Duration) -> Option<Output> {
    use std::io::Read;
    let start = Instant::now();
    let mut child = cmd
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let drain = |mut r: Box<dyn Read + Send>| {
        std::thread::spawn(move || {
            let mut v = Vec::new();
            let _ = r.read_to_end(&mut v);
            v
        })
    };
    let out = drain(Box::new(child.stdout.take().unwrap()));
    let err = drain(Box::new(child.stderr.take().unwrap()));
    loop {
        if let Some(status) = child.try_wait().unwrap() {
            return Some(Output {
                status,
                stdout: out.join().unwrap(),
                stderr: err.join().unwrap(),
            });
        }
        if start.elapsed() > deadline {
            let _ = child.kill();
            let _ = child.wait();
            return None;
        }
        std::thread::sleep(Duration::from_millis(20));
    }
}

#[test]
fn a_hang_is_killed_at_the_deadline() {
    let start = Instant::now();
    let out = run_with_deadline(Command::new("sleep").arg("30"), Duration::from_millis(300));
    assert!(out.is_none(), "sleep 30 was not killed");
    assert!(start.elapsed() < Duration::from_secs(10));
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Loads with a warning containing `expect`, for `--check` and for a real render.
fn renders_with_warning(file: &Path, expect: &str) {
    let f = file.to_str().unwrap();
    for render in [false, true] {
        let o = glview(&[f], render);
        // --check lists warnings in its report (stdout); a render prints them on stderr.
        let err = if render {
            stderr(&o)
        } else {
            String::from_utf8_lossy(&o.stdout).into_owned()
        };
        assert!(o.status.success(), "{f} (render {render}) failed: {err}");
        assert!(!err.contains("panicked"), "{err}");
        let warnings: Vec<&str> = err.lines().filter(|l| l.starts_with("warning: ")).collect();
        assert!(
            warnings.iter().any(|w| w.contains(expect)),
            "{f}: no warning containing {expect:?} in:\n{err}"
        );
    }
}

/// Refused with exactly one line `error: <prefix>...<expect>...`, exit code 1.
fn clean_error(file: &str, prefix: &str, expect: &str) {
    let o = glview(&[file], false);
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(1), "{file}: {err}");
    let lines: Vec<&str> = err.lines().collect();
    assert_eq!(lines.len(), 1, "{file}: expected one line, got:\n{err}");
    assert!(
        lines[0].starts_with(&format!("error: {prefix}")),
        "{file}: {err}"
    );
    assert!(
        lines[0].contains(expect),
        "{file}: expected {expect:?} in {err}"
    );
}

#[test]
fn renders_with_a_warning() {
    let dir = out_dir("bad-input-warn");
    let d = |n: &str, b: &str| write(&dir, n, b.as_bytes());
    let cases: Vec<(PathBuf, &str)> = vec![
        (
            d(
                "nomtl.obj",
                &format!("mtllib nowhere.mtl\n{TRI}usemtl a\nf 1 2 3\n"),
            ),
            "cannot read material library",
        ),
        (
            d("undef.obj", &format!("{TRI}usemtl ghost\nf 1 2 3\n")),
            "\"ghost\" is not defined",
        ),
        (
            d("emptyuse.obj", &format!("{TRI}usemtl\nf 1 2 3\n")),
            "empty usemtl",
        ),
        (
            d("short.obj", &format!("{TRI}f 1 2\nf 1\nf 1 1 2\nf 1 2 3\n")),
            "dropped 3 face(s)",
        ),
        (
            d("refs.obj", &format!("{TRI}f 1/9/1 2/9/1 3/9/1\n")),
            "missing normal or UV",
        ),
        (
            d("unknown.obj", &format!("{TRI}frobnicate 1 2\nf 1 2 3\n")),
            "unknown statement",
        ),
        (
            d(
                "crlf.obj",
                "mtllib crlf.mtl\r\nv 0 0 0\r\nv 1 0 0\r\nv 0 1 0\r\nusemtl x\r\nf 1 2 3\r\n",
            ),
            "crlf.mtl",
        ),
        (
            d("cont.obj", &format!("{TRI}f 1 \\\n 2 3\n")),
            "backslash line continuation",
        ),
    ];
    for (p, expect) in &cases {
        renders_with_warning(p, expect);
    }
    // Non-UTF-8 bytes in a comment and an object name: repaired.
    let mut b = b"# caf\xe9\no na\xefve\n".to_vec();
    b.extend_from_slice(TRI.as_bytes());
    b.extend_from_slice(b"f 1 2 3\n");
    renders_with_warning(&write(&dir, "latin1.obj", &b), "non-UTF-8");
}

/// A PNG whose header promises `w` x `h` RGBA pixels, followed by a tiny IDAT: a
/// decompression bomb's shape without its size.
fn png_claiming(w: u32, h: u32) -> Vec<u8> {
    fn crc32(data: &[u8]) -> u32 {
        let mut c = 0xffff_ffffu32;
        for &b in data {
            c ^= u32::from(b);
            for _ in 0..8 {
                c = if c & 1 != 0 {
                    0xedb8_8320 ^ (c >> 1)
                } else {
                    c >> 1
                };
            }
        }
        !c
    }
    fn chunk(out: &mut Vec<u8>, kind: &[u8], data: &[u8]) {
        out.extend_from_slice(&(data.len() as u32).to_be_bytes());
        let mut body = kind.to_vec();
        body.extend_from_slice(data);
        out.extend_from_slice(&body);
        out.extend_from_slice(&crc32(&body).to_be_bytes());
    }
    let mut out = b"\x89PNG\r\n\x1a\n".to_vec();
    let mut ihdr = w.to_be_bytes().to_vec();
    ihdr.extend_from_slice(&h.to_be_bytes());
    ihdr.extend_from_slice(&[8, 6, 0, 0, 0]);
    chunk(&mut out, b"IHDR", &ihdr);
    chunk(
        &mut out,
        b"IDAT",
        &[0x78, 0x9c, 0x03, 0x00, 0x00, 0x00, 0x00, 0x01],
    );
    chunk(&mut out, b"IEND", &[]);
    out
}

#[test]
fn textures_that_fail_keep_the_material_colours() {
    let dir = out_dir("bad-input-tex");
    let obj = |name: &str, mtl: &str| {
        write(
            &dir,
            &format!("{name}.mtl"),
            format!("newmtl m\nKd 1 0 0\n{mtl}\n").as_bytes(),
        );
        write(
            &dir,
            &format!("{name}.obj"),
            format!("mtllib {name}.mtl\n{TRI}usemtl m\nf 1/1/1 2/2/1 3/3/1\n").as_bytes(),
        )
    };
    write(&dir, "garbage.png", b"\x89PNG\r\n\x1a\nthis is not a png");
    write(&dir, "weird.xyz", b"0123456789");
    // A PNG header that promises 100000 x 100000 pixels: refused before decoding.
    write(&dir, "bomb.png", &png_claiming(100_000, 100_000));
    renders_with_warning(&obj("missing", "map_Kd nothere.png"), "file not found");
    // The warning names the library that was read, whatever it is called.
    write(&dir, "library.mtl", b"newmtl m\nmap_Kd nothere.png\n");
    let other = write(
        &dir,
        "named.obj",
        format!("mtllib library.mtl\n{TRI}usemtl m\nf 1/1/1 2/2/1 3/3/1\n").as_bytes(),
    );
    renders_with_warning(&other, "library.mtl: material m: map_Kd");
    renders_with_warning(&obj("corrupt", "map_Kd garbage.png"), "unreadable image");
    renders_with_warning(&obj("unsupported", "map_Kd weird.xyz"), "map_Kd");
    renders_with_warning(&obj("bomb", "map_Kd bomb.png"), "refused before decoding");
}

#[test]
fn texture_paths_are_repaired_when_unambiguous() {
    let dir = out_dir("bad-input-paths");
    let (w, h, rgba) = glview::scene::generate::checker_png_rgba();
    let img = glview::image_out::Rgba {
        width: w,
        height: h,
        data: rgba,
    };
    std::fs::create_dir_all(dir.join("Tex")).unwrap();
    img.save_png(&dir.join("Tex/Checker.png"), &[]).unwrap();
    for (name, spec) in [
        ("opts", "-s 1 1 1 -bm 2 -clamp on Tex/Checker.png"),
        ("backslash", "Tex\\Checker.png"),
        ("case", "tex/checker.PNG"),
    ] {
        write(
            &dir,
            &format!("{name}.mtl"),
            format!("newmtl m\nmap_Kd {spec}\n").as_bytes(),
        );
        let p = write(
            &dir,
            &format!("{name}.obj"),
            format!("mtllib {name}.mtl\n{TRI}usemtl m\nf 1/1/1 2/2/1 3/3/1\n").as_bytes(),
        );
        let o = glview(&[p.to_str().unwrap()], false);
        let out = String::from_utf8_lossy(&o.stdout);
        assert!(
            o.status.success() && out.contains("Checker.png (64x64)"),
            "{name}: {out}{}",
            stderr(&o)
        );
        assert!(!stderr(&o).contains("warning"), "{name}: {}", stderr(&o));
    }
}

#[test]
fn texture_paths_outside_the_model_folder_are_not_read() {
    let root = out_dir("bad-input-escape");
    let (w, h, rgba) = glview::scene::generate::checker_png_rgba();
    glview::image_out::Rgba {
        width: w,
        height: h,
        data: rgba,
    }
    .save_png(&root.join("secret.png"), &[])
    .unwrap();
    let model = root.join("model");
    std::fs::create_dir_all(&model).unwrap();
    let link = model.join("link.png");
    let _ = std::fs::remove_file(&link);
    std::os::unix::fs::symlink(root.join("secret.png"), &link).unwrap();
    let abs = root.join("secret.png");
    for (name, spec) in [
        ("dotdot", "../secret.png".to_string()),
        ("absolute", abs.display().to_string()),
        ("symlink", "link.png".into()),
    ] {
        write(
            &model,
            &format!("{name}.mtl"),
            format!("newmtl m\nmap_Kd {spec}\n").as_bytes(),
        );
        let p = write(
            &model,
            &format!("{name}.obj"),
            format!("mtllib {name}.mtl\n{TRI}usemtl m\nf 1/1/1 2/2/1 3/3/1\n").as_bytes(),
        );
        let p = p.to_str().unwrap();
        renders_with_warning(Path::new(p), "outside the model's folder; not read");
        let o = glview(&[p, "--allow-outside-paths"], false);
        assert!(
            String::from_utf8_lossy(&o.stdout).contains("secret.png (64x64)"),
            "{name} with --allow-outside-paths: {}",
            stderr(&o)
        );
    }
}

#[test]
fn clean_errors_name_file_and_line() {
    let dir = out_dir("bad-input-err");
    let d = |n: &str, b: &[u8]| write(&dir, n, b).to_str().unwrap().to_string();
    let cases: Vec<(String, Option<usize>, &str)> = vec![
        (
            d("zero.obj", format!("{TRI}f 0 1 2\n").as_bytes()),
            Some(8),
            "face index 0",
        ),
        (
            d("range.obj", format!("{TRI}f 1 2 7\n").as_bytes()),
            Some(8),
            "out of range",
        ),
        (
            d("nan.obj", b"v 0 0 0\nv nan 1 0\nv 0 1 0\nf 1 2 3\n"),
            Some(2),
            "not finite",
        ),
        (
            d("overflow.obj", b"v 0 0 0\nv 1e999 1 0\nv 0 1 0\nf 1 2 3\n"),
            Some(2),
            "not finite",
        ),
        (
            d("badnum.obj", b"v 0 0 0\nv 1,5 1 0\nv 0 1 0\nf 1 2 3\n"),
            Some(2),
            "not a number",
        ),
        (
            d(
                "latin1num.obj",
                b"v 0 0 0\nv 1\xb75 1 0\nv 0 1 0\nf 1 2 3\n",
            ),
            Some(2),
            "non-UTF-8",
        ),
        (d("empty.obj", b""), None, "no triangles"),
        (
            d("badline.obj", b"v 0 0 0\nv 1 0 0\nl 1 3\n"),
            Some(3),
            "out of range",
        ),
        (
            d(
                "garbage.obj",
                b"\x7fELF\x02\x01\x01\x00\x00\x00\x00\x00\x00\x00\x00\x00\x03\x00",
            ),
            Some(1),
            "not an OBJ",
        ),
    ];
    for (file, line, expect) in &cases {
        let prefix = match line {
            Some(l) => format!("{file}:{l}: "),
            None => format!("{file}: "),
        };
        clean_error(file, &prefix, expect);
    }
    let missing = dir.join("does-not-exist.obj");
    clean_error(
        missing.to_str().unwrap(),
        missing.to_str().unwrap(),
        "No such file",
    );
    clean_error(
        dir.to_str().unwrap(),
        dir.to_str().unwrap(),
        "is a directory",
    );
    clean_error("/dev/null", "/dev/null", "not a regular file");
    // A FIFO would block a naive reader forever.
    let fifo = dir.join("fifo.obj");
    let _ = std::fs::remove_file(&fifo);
    assert!(Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .unwrap()
        .success());
    clean_error(
        fifo.to_str().unwrap(),
        fifo.to_str().unwrap(),
        "not a regular file",
    );
}

#[test]
fn bad_options_are_clear_errors() {
    for (args, expect) in [
        (vec!["--light", "spot:1,2,3"], "kind must be point or dir"),
        (vec!["--light", "dir:0,0,0"], "direction is zero"),
        (vec!["--target", "1,2"], "--target"),
        (vec!["--keys", "Left Banana"], "unknown key"),
        (vec!["--fov", "0"], "--fov"),
        (
            vec!["--reference", "--size", "20000x100"],
            "the reference renderer draws at most 16384x16384",
        ),
        (
            vec!["--light", "none", "--light", "dir:0,-1,0"],
            "cannot be combined",
        ),
    ] {
        let mut a = args.clone();
        let out = out_dir("bad-input-options").join("x.png");
        a.extend_from_slice(&["--output", out.to_str().unwrap()]);
        if !a.contains(&"--size") {
            a.extend_from_slice(&["--size", "8x8"]);
        }
        let o = run(&a, &[]);
        let err = stderr(&o);
        assert_eq!(o.status.code(), Some(1), "{args:?}: {err}");
        assert!(
            err.starts_with("error: ") && err.contains(expect) && err.lines().count() == 1,
            "{args:?}: {err}"
        );
    }
}

/// A grayscale PNG of `w` x `h` pixels, all `value`, written row by row (the file is small:
/// equal rows compress to almost nothing).
fn flat_gray_png(path: &Path, w: u32, h: u32, value: u8) {
    let file = std::io::BufWriter::new(std::fs::File::create(path).unwrap());
    let mut enc = png::Encoder::new(file, w, h);
    enc.set_color(png::ColorType::Grayscale);
    enc.set_depth(png::BitDepth::Eight);
    enc.set_compression(png::Compression::Fast);
    let mut writer = enc.write_header().unwrap();
    let mut rows = writer.stream_writer().unwrap();
    let row = vec![value; w as usize];
    for _ in 0..h {
        std::io::Write::write_all(&mut rows, &row).unwrap();
    }
    rows.finish().unwrap();
}

#[test]
fn texture_bomb_is_downscaled_within_the_memory_limit() {
    // 20000 x 20000 grayscale: 400 MB as decoded gray, 1.6 GB as RGBA, a few hundred KB on
    // disk. It must render (downscaled while decoding, with a warning) under the 2 GiB
    // address-space limit of `--check`.
    let dir = out_dir("bad-input-bomb");
    let png = dir.join("huge.png");
    if !png.exists() {
        // Written under another name and renamed: an interrupted run leaves no half file.
        let part = dir.join("huge.png.part");
        flat_gray_png(&part, 20_000, 20_000, 128);
        std::fs::rename(&part, &png).unwrap();
    }
    write(&dir, "huge.mtl", b"newmtl m\nmap_Kd huge.png\n");
    let obj = write(
        &dir,
        "huge.obj",
        format!("mtllib huge.mtl\n{TRI}usemtl m\nf 1/1/1 2/2/1 3/3/1\n").as_bytes(),
    );
    // One load under the address-space limit (`--check`): each decode of the bomb is ~35 s
    // of a debug build, so the render run (the same loader, then a 32×24 picture) is left
    // to the other texture tests.
    let o = glview(&[obj.to_str().unwrap()], false);
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success(), "{out}{}", stderr(&o));
    assert!(
        out.contains("texture 20000x20000 downscaled to 8192x8192"),
        "{out}"
    );
    assert!(out.contains("huge.png (8192x8192)"), "{out}");
}

#[test]
fn two_million_duplicate_faces_render_in_under_10_s() {
    let dir = out_dir("bad-input-dup");
    let obj = dir.join("dup.obj");
    {
        use std::io::Write;
        let mut w = std::io::BufWriter::new(std::fs::File::create(&obj).unwrap());
        w.write_all(b"v 0 0 0\nv 1 0 0\nv 0 1 0\n").unwrap();
        for _ in 0..2_000_000 {
            w.write_all(b"f 1 2 3\n").unwrap();
        }
        w.flush().unwrap();
    }
    let png = dir.join("dup.png");
    let start = Instant::now();
    let o = run_with_deadline(
        Command::new(bin()).args([
            obj.to_str().unwrap(),
            "--no-cache",
            "--output",
            png.to_str().unwrap(),
            "--size",
            "640x480",
        ]),
        Duration::from_secs(10),
    )
    .expect("2,000,000 duplicate faces: not rendered within 10 s");
    let err = stderr(&o);
    assert!(o.status.success(), "{err}");
    assert!(
        err.lines().any(|l| l.starts_with("warning: ")
            && l.contains("dropped 1999999 duplicate and 0 degenerate")),
        "{err}"
    );
    eprintln!("2M duplicate faces rendered in {:?}", start.elapsed());
}

/// Issue 13 command-line edges: negative numbers get a range error (never clap's
/// "use -- -1" hint), a zero shadow map and unknown output formats are refused.
#[test]
fn negative_and_zero_option_values_are_range_errors() {
    for args in [
        &["--distance", "-1"][..],
        &["--ortho", "-2"],
        &["--shadow-bias", "-0.001"],
        &["--shadow-size", "0"],
        &["-o", "/tmp/glview-out.bmp"],
    ] {
        let o = run(args, &[]);
        let err = stderr(&o);
        assert!(!o.status.success(), "{args:?}");
        assert!(!err.contains("-- -"), "{args:?}: {err}");
        assert!(
            err.contains("range") || err.contains("not in") || err.contains(".png, .jpg"),
            "{args:?}: {err}"
        );
    }
}

/// `-o out.jpg` writes a JPEG; the no-display fallback never overwrites glview.png.
#[test]
fn jpeg_output_and_fallback_without_overwrite() {
    let dir = out_dir("bad-input-output");
    let jpg = dir.join("out.jpg");
    let _ = std::fs::remove_file(&jpg);
    let o = run(&["-o", jpg.to_str().unwrap(), "--size", "16x12"], &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    let bytes = std::fs::read(&jpg).unwrap();
    assert_eq!(&bytes[..3], &[0xff, 0xd8, 0xff], "not a JPEG");

    let keep = b"not to be overwritten";
    for f in ["glview.png", "glview-1.png"] {
        let _ = std::fs::remove_file(dir.join(f));
    }
    std::fs::write(dir.join("glview.png"), keep).unwrap();
    let o = Command::new(bin())
        .args(["--size", "16x12"])
        .current_dir(&dir)
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(std::fs::read(dir.join("glview.png")).unwrap(), keep);
    assert!(dir.join("glview-1.png").exists());
    assert!(stderr(&o).contains("glview-1.png"), "{}", stderr(&o));
}

/// A glTF PBR extension's malformed value (the reader takes the extension's default, as for
/// a missing one) or a texture index that names nothing is a warning naming the material,
/// the extension and the key, and the model still renders.
#[test]
fn malformed_extension_values_render_with_a_warning() {
    use crate::gltf_draw::{quad, Quad};
    let dir = out_dir("bad-input-khr");
    let cases = [
        (
            "clearcoat-index",
            r#""KHR_materials_clearcoat": {"clearcoatFactor": 1, "clearcoatTexture": {"index": 99}}"#,
            "KHR_materials_clearcoat.clearcoatTexture names texture 99, which does not exist",
        ),
        (
            "clearcoat-string",
            r#""KHR_materials_clearcoat": {"clearcoatFactor": "abc"}"#,
            "KHR_materials_clearcoat.clearcoatFactor is \"abc\", not a finite number",
        ),
        (
            "sheen-colour",
            r#""KHR_materials_sheen": {"sheenColorFactor": [1, "red", 0]}"#,
            "KHR_materials_sheen.sheenColorFactor is [1,\"red\",0], not a finite number",
        ),
        (
            "volume-no-index",
            r#""KHR_materials_volume": {"thicknessTexture": {"texCoord": 0}}"#,
            "KHR_materials_volume.thicknessTexture has no texture index",
        ),
        (
            "iridescence-thickness",
            r#""KHR_materials_iridescence": {"iridescenceFactor": 1, "iridescenceThicknessMaximum": "thick"}"#,
            "KHR_materials_iridescence.iridescenceThicknessMaximum is \"thick\", not a finite number",
        ),
    ];
    for (name, ext, expect) in cases {
        let material = format!(r#""materials": [{{"name": "m", "extensions": {{{ext}}}}}]"#);
        let model = quad(&dir, name, &Quad::default(), &material);
        renders_with_warning(&model, &format!("material 0 'm': {expect}"));
    }
}
