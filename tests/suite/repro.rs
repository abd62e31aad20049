//! A picture's PNG text carries a command line that renders it again: every option that
//! changes pixels, the camera as it was (also after `--keys` moved it) and the state keys.
use crate::common::*;
use glview::image_out::RgbaFiles;
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
    // The keys are replayed into the options they stand for: S S is no change, G Gouraud.
    assert!(
        c.contains("--shading gouraud") && !c.contains("--keys") && !c.contains("--no-shadows"),
        "{c}"
    );
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

/// `glview --repro PICTURE.png` draws the picture again from its `glview.options` JSON alone
/// (the camera as it was after keys moved it, the size, the state keys), pixel for pixel;
/// a PNG without it is refused with a one-line error naming the file.
#[test]
fn repro_draws_the_picture_again_from_its_options() {
    let dir = out_dir("repro-json");
    for (name, args) in [
        (
            "legacy",
            &[
                "--size",
                "96x72",
                "--light",
                "point:2,3,1",
                "--light",
                "head",
                "--pcf",
                "4",
                "--keys",
                "Left Up S",
                "--background",
                "0.3,0.1,0.1",
            ][..],
        ),
        (
            "pbr",
            &[
                "--size",
                "80x60",
                "--shading",
                "pbr",
                "--metallic",
                "0.8",
                "--roughness",
                "0.3",
                "--ortho",
                "--terms",
                "ibl-diffuse,ibl-specular",
            ],
        ),
    ] {
        let first = render(&dir, name, args, &[]);
        let png = dir.join(format!("{name}.png"));
        let json = png_text(&png)
            .unwrap()
            .into_iter()
            .find(|(k, _)| k == "glview.options")
            .expect("glview.options in the PNG text")
            .1;
        let opts = glview::Options::from_json(&json).expect("the JSON is valid options");
        assert_eq!(opts.picture.size, first_size(&first), "{json}");
        let again = dir.join(format!("{name}-repro.png"));
        let o = repro(&png, &again);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        assert_close(
            &dir,
            &format!("{name}-repro"),
            &first,
            &Rgba::load_png(&again).unwrap(),
            0,
            0,
            0,
        );
    }
    // A picture without glview.options (a comparison sheet's, or another program's).
    let plain = dir.join("plain.png");
    Rgba {
        width: 2,
        height: 2,
        data: vec![0; 16],
    }
    .save_png(&plain, &[])
    .unwrap();
    let o = run(
        &["--repro", plain.to_str().unwrap(), "-o", "/tmp/never.png"],
        &[],
    );
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        !o.status.success() && err.contains("plain.png") && err.contains("glview.options"),
        "{err}"
    );
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");
}

fn first_size(img: &Rgba) -> (u32, u32) {
    (img.width, img.height)
}

/// A model path in letters Latin-1 lacks (Cyrillic here) goes into the PNG's text as UTF-8
/// (an iTXt chunk: tEXt holds Latin-1 only, and refusing to write the picture was the bug),
/// and the command read back from it renders the same picture.
#[test]
fn a_path_beyond_latin1_is_kept_in_the_png_text() {
    let dir = out_dir("repro").join("модели ü");
    std::fs::create_dir_all(&dir).unwrap();
    let cube = dir.join("Куб.obj");
    std::fs::write(&cube, box_obj([-1.0, -0.5, -1.0], [1.0, 0.5, 1.0], 0)).unwrap();
    let c = reproduces("non-latin1", &[cube.to_str().unwrap(), "--size", "80x60"]);
    assert!(c.contains("модели ü/Куб.obj"), "{c}");
}
