//! Every shader permutation compiles and links in every dialect the machine offers: GLSL 3.30
//! (core), GLSL ES 3.00, GLSL 1.20 (Mesa emulating a GL 2.1 driver) and GLSL 1.20 on OSMesa
//! without framebuffer or vertex-array objects. A broken shader reports the driver's log and
//! the numbered source.
use crate::common;
use common::*;

#[test]
fn every_permutation_compiles_in_every_dialect() {
    let expected = glview::render::programs::all_keys(glview::light::MAX_LIGHTS as u8).len();
    for (name, args, env) in [
        (
            "GLSL 3.30",
            vec!["--gl", "core", "--backend", "egl"],
            &[][..],
        ),
        (
            "GLSL ES 3.00",
            vec!["--gl", "es3", "--backend", "egl"],
            &[][..],
        ),
        ("GLSL 1.20", vec!["--gl", "2.1", "--backend", "egl"], GL21),
        (
            "GLSL 1.20",
            vec!["--gl", "2.1", "--backend", "osmesa"],
            GL21_NO_FBO,
        ),
    ] {
        let mut a = vec!["--compile-shaders"];
        a.extend_from_slice(&args);
        let o = run(&a, env);
        let out = String::from_utf8_lossy(&o.stdout);
        assert!(
            o.status.success(),
            "{args:?}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
        assert!(
            out.contains(&format!(
                "compiled and linked {expected} programs for {name}"
            )),
            "{args:?}: {out}"
        );
        eprint!("{out}");
    }
}

#[test]
fn a_broken_shader_shows_the_log_and_numbered_source() {
    use glview::headless::Headless;
    use glview::platform::{Backend, GlRequest};
    let hl = Headless::new(Backend::Egl, GlRequest::Core, 8, 8).expect("EGL context");
    let vs = "#version 330 core\nin vec3 aPosition;\nvoid main() { gl_Position = vec4(aPosition, 1.0); }\n";
    let fs = "#version 330 core\nout vec4 c;\nvoid main() {\n    c = vec4(undefined_thing);\n}\n";
    let before = hl.gpu.live_objects();
    let err = match glview::gpu::program::Program::new(&hl.gpu, "broken", vs, fs) {
        Ok(_) => panic!("a broken shader linked"),
        Err(e) => e.to_string(),
    };
    assert!(
        err.contains("shader broken (GLSL 3.30) failed to compile the fragment shader"),
        "{err}"
    );
    assert!(err.contains("undefined_thing"), "no driver log: {err}");
    assert!(
        err.contains("   4     c = vec4(undefined_thing);"),
        "no numbered source: {err}"
    );
    assert_eq!(
        hl.gpu.live_objects(),
        before,
        "a failed compile leaked objects"
    );
}

/// Issue #41's limit, the GLSL side of clippy's `too_many_lines` (clippy.toml): no function in
/// a shader source is longer than this, from its signature to its closing brace, comments and
/// preprocessor lines included.
const GLSL_FUNCTION_LINES: usize = 120;

/// A GLSL function: where it starts and how many lines it spans.
#[derive(Debug)]
struct GlslFunction {
    name: String,
    line: usize,
    lines: usize,
}

/// Every function definition in `source`, found by its braces at the top level with a `(` in
/// what precedes them (a struct's braces have none). Comments and preprocessor lines are
/// skipped, so a brace in either is not counted. Unbalanced braces are an error, as they would
/// make the lengths wrong.
fn glsl_functions(source: &str) -> Result<Vec<GlslFunction>, String> {
    let mut found = Vec::new();
    let (mut depth, mut in_block_comment) = (0usize, false);
    // The text since the last top-level `;` or `}`, and the line where it started.
    let (mut header, mut header_line) = (String::new(), 0);
    // The function being read: its name and first line.
    let mut current: Option<(String, usize)> = None;
    for (index, line) in source.lines().enumerate() {
        let number = index + 1;
        if !in_block_comment && line.trim_start().starts_with('#') {
            continue;
        }
        let mut chars = line.chars().peekable();
        while let Some(c) = chars.next() {
            if in_block_comment {
                if c == '*' && chars.peek() == Some(&'/') {
                    chars.next();
                    in_block_comment = false;
                }
                continue;
            }
            match c {
                '/' if chars.peek() == Some(&'/') => break,
                '/' if chars.peek() == Some(&'*') => {
                    chars.next();
                    in_block_comment = true;
                }
                '{' => {
                    if depth == 0 && header.contains('(') {
                        let before = &header[..header.find('(').unwrap_or(0)];
                        let name = before.split_whitespace().last().unwrap_or("?");
                        current = Some((name.to_owned(), header_line));
                    }
                    depth += 1;
                }
                '}' => {
                    depth = depth
                        .checked_sub(1)
                        .ok_or_else(|| format!("line {number}: a `}}` closes nothing"))?;
                    if depth == 0 {
                        if let Some((name, line)) = current.take() {
                            let lines = number - line + 1;
                            found.push(GlslFunction { name, line, lines });
                        }
                        header.clear();
                    }
                }
                ';' if depth == 0 => header.clear(),
                _ if depth == 0 => {
                    if header.trim().is_empty() && !c.is_whitespace() {
                        header_line = number;
                    }
                    header.push(c);
                }
                _ => {}
            }
        }
        if depth == 0 {
            header.push(' ');
        }
    }
    if depth != 0 {
        return Err(format!("{depth} `{{` left open at the end"));
    }
    Ok(found)
}

/// Every `.frag`, `.vert` and `.glsl` file under `dir`, sorted.
fn shader_files(dir: &std::path::Path) -> Vec<std::path::PathBuf> {
    let mut files = Vec::new();
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            files.extend(shader_files(&path));
        } else if matches!(
            path.extension().and_then(|e| e.to_str()),
            Some("frag" | "vert" | "glsl")
        ) {
            files.push(path);
        }
    }
    files.sort();
    files
}

#[test]
fn glsl_function_lengths_are_counted_from_signature_to_closing_brace() {
    let source = "uniform vec3 uA; // {\n\
                  struct S {\n    float x;\n};\n\
                  #define F(x) { x }\n\
                  vec3 f(vec3 a,\n       float b) {\n    /* } */\n    return a * b;\n}\n\
                  void main() { if (true) { } }\n";
    let found = glsl_functions(source).unwrap();
    let got: Vec<(&str, usize, usize)> = found
        .iter()
        .map(|f| (f.name.as_str(), f.line, f.lines))
        .collect();
    assert_eq!(got, [("f", 6, 5), ("main", 11, 1)]);
    assert!(glsl_functions("void main() {\n").is_err());
    assert!(glsl_functions("}\n").is_err());
}

#[test]
fn no_glsl_function_is_longer_than_the_limit() {
    let files = shader_files(&repo().join("shaders_gl"));
    assert!(files.len() > 20, "shaders_gl holds {} shaders", files.len());
    let mut longest: Option<(String, GlslFunction)> = None;
    let mut too_long = Vec::new();
    for file in &files {
        let source = std::fs::read_to_string(file).unwrap();
        let shown = file
            .strip_prefix(repo())
            .unwrap_or(file)
            .display()
            .to_string();
        let functions = glsl_functions(&source).unwrap_or_else(|e| panic!("{shown}: {e}"));
        for f in functions {
            if f.lines > GLSL_FUNCTION_LINES {
                too_long.push(format!("{shown}:{} {} ({} lines)", f.line, f.name, f.lines));
            }
            if longest.as_ref().is_none_or(|(_, l)| f.lines > l.lines) {
                longest = Some((shown.clone(), f));
            }
        }
    }
    let (file, f) = longest.expect("no GLSL function found");
    eprintln!(
        "longest GLSL function: {file}:{} {} ({} lines)",
        f.line, f.name, f.lines
    );
    assert!(
        too_long.is_empty(),
        "longer than {GLSL_FUNCTION_LINES} lines; split them into named functions:\n{}",
        too_long.join("\n")
    );
}
