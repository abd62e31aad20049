//! A picture's PNG text carries a command line that renders it again: every option that
//! changes pixels, the camera as it was (also after `--keys` moved it) and the state keys.
use crate::common::*;
use glview::image_out::{png_text, Rgba};

/// Renders `args`, reads `glview.command`, renders that command again and compares.
fn reproduces(name: &str, args: &[&str]) -> String {
    let dir = out_dir("repro");
    let first = render(&dir, name, args, &[]);
    let text = png_text(&dir.join(format!("{name}.png"))).unwrap();
    let command = text
        .iter()
        .find(|(k, _)| k == "glview.command")
        .map(|(_, v)| v.clone())
        .expect("glview.command in the PNG text");
    let words = shlex::split(&command).expect("a shell-quoted command line");
    assert_eq!(words[0], "glview");
    let again = dir.join(format!("{name}-again.png"));
    let mut argv: Vec<&str> = words[1..].iter().map(String::as_str).collect();
    argv.extend(["-o", again.to_str().unwrap()]);
    // A separate process: exactly what a user pasting the line gets.
    let o = run(&argv, &[]);
    assert!(o.status.success(), "{command}: {o:?}");
    let second = Rgba::load_png(&again).unwrap();
    assert_close(&dir, name, &first, &second, 0, 0, 0);
    command
}

#[test]
fn png_text_command_rerenders_the_same_picture() {
    let dir = out_dir("repro");
    let cube = dir.join("cube with space.obj");
    std::fs::write(&cube, box_obj([-1.0, -0.5, -1.0], [1.0, 0.5, 1.0], 0)).unwrap();
    let cube = cube.to_str().unwrap();
    // Legacy tier, every kind of option that changes pixels, camera moved by keys.
    let c = reproduces(
        "legacy",
        &[
            cube,
            "--size",
            "120x90",
            "--light",
            "point:2,3,1",
            "--light",
            "head",
            "--light-color",
            "1,0.8,0.6",
            "--ambient",
            "0.1,0.2,0.3",
            "--background",
            "0.3,0.1,0.1",
            "--diffuse",
            "wrap",
            "--pcf",
            "4",
            "--shadow-bias",
            "0.001",
            "--keys",
            "Left Left Up S S G",
            "--stats",
        ],
    );
    assert!(c.contains("--keys 'S S G'"), "{c}");
    assert!(!c.contains("--stats") && !c.contains("Left"), "{c}");
    // PBR tier knobs, fitted orthographic view, a bare flag before the model.
    let c = reproduces(
        "pbr",
        &[
            "--size",
            "100x80",
            "--shading",
            "pbr",
            "--metallic",
            "0.8",
            "--roughness",
            "0.3",
            "--exposure",
            "0.5",
            "--no-shadows",
            "--ortho",
        ],
    );
    assert!(
        c.contains("--ortho "),
        "the fitted height is written out: {c}"
    );
}
