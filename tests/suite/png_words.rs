//! Every option word in a picture's PNG text is one the command line takes, with the value the
//! picture was drawn with. A corpus of small pictures (both tiers, every tone mapping, every
//! `--show` view, the toggles, `--keys`) is drawn; in every text chunk each `--name [value]`
//! is parsed by the options' own parser (the command line's setters) and its typed value
//! compared with the picture's options (its `glview.options`); a chunk named after a choice
//! option (`glview.show`, `glview.shading`, `glview.backend`) holds that option's word for
//! what was drawn (after the keys; what `auto` chose). Each
//! picture is then drawn again by `glview --repro PICTURE.png`, pixel for pixel.
use crate::common::*;
use glview::image_out::RgbaFiles;
use glview::image_out::{png_text, Rgba};
use glview::options::{spec, Form, OptionSpec, Show};
use glview::pbr::Tonemap;
use glview::Options;
use serde_json::Value;
use std::path::Path;

/// Name and options of each picture of the corpus (64×48 each).
fn corpus() -> Vec<(String, Vec<String>)> {
    let fixed: &[(&str, &[&str])] = &[
        ("phong", &[]),
        ("gouraud", &["--shading", "gouraud"]),
        ("no-shadows", &["--no-shadows"]),
        ("bloom", &["--bloom", "0.6", "--bloom-threshold", "0.5"]),
        (
            "edges",
            &["--edges", "--edge-color", "1,0,0", "--line-width", "2"],
        ),
        ("wireframe", &["--wireframe-only"]),
        ("guides", &["--grid", "--axes"]),
        // P P: Phong → Gouraud → PBR, so the tier drawn is not the one given.
        ("keys", &["--keys", "Left Up S W P P"]),
        (
            "ortho-lights",
            &[
                "--ortho",
                "--light",
                "point:2,3,1",
                "--light",
                "head",
                "--pcf",
                "4",
            ],
        ),
        (
            "pbr-overrides",
            &[
                "--shading",
                "pbr",
                "--metallic",
                "0.8",
                "--roughness",
                "0.3",
                "--base-color",
                "0.9,0.5,0.2",
                "--exposure",
                "0.5",
                "--multiscatter",
                "--terms",
                "ibl-diffuse,ibl-specular",
            ],
        ),
    ];
    let mut c: Vec<(String, Vec<String>)> = fixed
        .iter()
        .map(|(n, a)| (n.to_string(), a.iter().map(|w| w.to_string()).collect()))
        .collect();
    for (_, word, _) in Tonemap::ALL {
        c.push((
            format!("tonemap-{word}"),
            vec![
                "--shading".into(),
                "pbr".into(),
                "--tonemap".into(),
                word.to_string(),
            ],
        ));
    }
    for (_, word, _) in Show::ALL {
        c.push((
            format!("show-{word}"),
            vec![
                "--shading".into(),
                "pbr".into(),
                "--show".into(),
                word.to_string(),
            ],
        ));
    }
    for (_, args) in &mut c {
        args.extend(["--size".into(), "64x48".into()]);
    }
    c
}

/// Draws `args` into `dir/name.png` (in this process when it can, as `common::render`), with
/// no frame checks: the map views have black borders by design.
fn draw(dir: &Path, name: &str, args: &[String]) -> std::path::PathBuf {
    let out = dir.join(format!("{name}.png"));
    let mut all = vec!["--output", out.to_str().unwrap()];
    all.extend(args.iter().map(String::as_str));
    match fixture::render(&all) {
        Some(r) => r.unwrap_or_else(|e| panic!("glview {all:?}: {e}")),
        None => {
            let o = run(&all, &[]);
            assert!(o.status.success(), "glview {all:?}: {o:?}");
        }
    }
    out
}

/// An option's value in its JSON form (`{"camera": {"yaw": 30}}` at `camera.yaw`).
fn value_at(o: &Options, s: &OptionSpec) -> Value {
    let json = serde_json::to_value(o).unwrap();
    json.pointer(&format!("/{}", s.path.replace('.', "/")))
        .cloned()
        .unwrap_or_else(|| panic!("{} is in the options' JSON", s.path))
}

/// The `--name [value]` words of a chunk and their specs; a `--word` naming no option fails.
fn option_words(key: &str, words: &[String]) -> (Vec<String>, Vec<&'static OptionSpec>) {
    let (mut out, mut specs) = (Vec::new(), Vec::new());
    let mut it = words.iter().peekable();
    while let Some(w) = it.next() {
        let Some(long) = w.strip_prefix("--") else {
            continue;
        };
        let name = long.split('=').next().unwrap_or_default();
        let s = spec(name).unwrap_or_else(|| panic!("{key}: --{name} is no option: {words:?}"));
        out.push(w.clone());
        specs.push(s);
        if w.contains('=') {
            continue;
        }
        let value = match s.form {
            Form::Value | Form::Repeat | Form::List => it.next(),
            Form::Optional => it.next_if(|v| v.parse::<f32>().is_ok()),
            Form::Flag | Form::NoFlag => None,
        };
        out.extend(value.cloned());
    }
    (out, specs)
}

/// Checks every chunk of one picture's text; returns how many option words were checked.
fn check_text(name: &str, text: &[(String, String)]) -> usize {
    let get = |k: &str| {
        text.iter()
            .find(|(key, _)| key == k)
            .map(|(_, v)| v.as_str())
    };
    let json = get("glview.options").unwrap_or_else(|| panic!("{name}: no glview.options"));
    let given = Options::from_json(json).unwrap_or_else(|e| panic!("{name}: {e}"));
    // What was drawn: the given options with the keys' effect on the tier (the frame
    // settings replay them). The map views load no scene and have no tier.
    let mut drawn = given.clone();
    if get("glview.shading").is_some() {
        let scene = glview::session::load_scene(&given).unwrap();
        drawn.render.shading = glview::session::frame_settings(&given, &scene)
            .unwrap()
            .0
            .shading;
    }
    let mut checked = 0;
    for (key, value) in text {
        let named = key.strip_prefix("glview.").and_then(spec);
        if let Some(s) = named.filter(|s| !s.choices.is_empty()) {
            let mut o = drawn.clone();
            s.set(&mut o, value)
                .unwrap_or_else(|e| panic!("{name}: {key} = {value:?}: --{} {e}", s.name));
            // `auto` given: the chunk says what it chose (`glview.backend`: egl).
            if value_at(&drawn, s) != "auto" {
                assert_eq!(value_at(&o, s), value_at(&drawn, s), "{name}: {key}");
            }
            checked += 1;
            continue;
        }
        if !value.starts_with("--") && !value.contains(" --") {
            continue;
        }
        let words = shlex::split(value)
            .unwrap_or_else(|| panic!("{name}: {key} is no shell-quoted line: {value}"));
        let (words, specs) = option_words(key, &words);
        let parsed = Options::from_words(&words).unwrap_or_else(|e| {
            panic!(
                "{name}: {key}: the command line refuses {}: {value}",
                e.on_command_line()
            )
        });
        for s in specs {
            assert_eq!(
                value_at(&parsed, s),
                value_at(&given, s),
                "{name}: {key}: --{} is not the picture's: {value}",
                s.name
            );
            checked += 1;
        }
    }
    checked
}

#[test]
fn every_option_word_in_png_text_parses_to_the_pictures_value() {
    let dir = out_dir("png-words");
    for (name, args) in corpus() {
        let png = draw(&dir, &name, &args);
        let text = png_text(&png).unwrap();
        let checked = check_text(&name, &text);
        // At least the size of glview.command, for every picture.
        assert!(checked > 0, "{name}: no option word in {text:?}");
        if args.contains(&"pbr".to_string()) && !name.starts_with("show-") {
            let pbr = text.iter().find(|(k, _)| k == "glview.pbr");
            assert!(
                pbr.is_some_and(|(_, v)| v.contains("--tonemap")),
                "{name}: {text:?}"
            );
        }
        let again = dir.join(format!("{name}-repro.png"));
        let o = repro(&png, &again);
        assert!(o.status.success(), "{name}: --repro: {o:?}");
        let (a, b) = (
            Rgba::load_png(&png).unwrap(),
            Rgba::load_png(&again).unwrap(),
        );
        assert_close(&dir, &format!("{name}-repro"), &a, &b, 0, 0, 0);
    }
}
