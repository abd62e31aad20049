//! The options' surfaces agree: JSON round trips, words ⇄ options, keywords with their
//! names in errors, the reference page up to date. (`--flat` and `--env-color` conflict
//! with `--crease` and `--env`, so they are checked on their own.)
use super::*;
use serde_json::json;

fn kw(v: serde_json::Value) -> Result<Options, OptionError> {
    let map = v.as_object().unwrap().clone();
    Options::from_keywords(map.iter().map(|(k, v)| (k.as_str(), v)))
}

/// The model, how it is read and cached, and the camera.
const MODEL_AND_CAMERA: &[&str] = &[
    "m.obj",
    "--up",
    "+Z",
    "--crease",
    "30",
    "--texture",
    "t.png",
    "--no-cache",
    "--cache-size",
    "512M",
    "--allow-outside-paths",
    "--honor-transparency",
    "--single-sided",
    "--xray",
    "a,b",
    "--scene",
    "Slab",
    "--variant",
    "1",
    "--yaw",
    "-10.5",
    "--pitch",
    "5",
    "--distance",
    "3",
    "--target",
    "1,-2,3.25",
    "--fov",
    "30",
    "--ortho",
    "2",
    "--near",
    "0.01",
    "--camera",
    "Front",
    "--keys",
    "Left S",
];

/// Lights, shadows, the shading tier and what the picture shows.
const LIGHTS_AND_SHADING: &[&str] = &[
    "--light",
    "dir:0,-2,0",
    "--light",
    "head",
    "--light-color",
    "1,0.5,0.25",
    "--ambient",
    "0.1,0.2,0.3",
    "--diffuse",
    "wrap",
    "--no-shadows",
    "--shadow-lights",
    "1",
    "--shadow-size",
    "512",
    "--pcf",
    "4",
    "--shadow-bias",
    "0.001",
    "--shading",
    "pbr",
    "--terms",
    "ao,emissive",
    "--legacy-terms",
    "ambient,specular",
    "--show",
    "normals",
    "--show-level",
    "2",
];

/// The background, translucency, depth, culling, level of detail and edges.
const DRAWING: &[&str] = &[
    "--background",
    "0.3,0.1,0.1",
    "--translucency",
    "sorted",
    "--blend",
    "add",
    "--opacity",
    "0.5",
    "--depth",
    "log",
    "--no-culling",
    "--lod",
    "off",
    "--lod-error",
    "0.5",
    "--edges",
    "--wireframe",
    "--wireframe-only",
    "--edge-color",
    "1,0,0.5",
    "--line-width",
    "2.5",
    "--edge-method",
    "barycentric",
];

/// The environment, its image-based lighting and the PBR material overrides.
const ENVIRONMENT_AND_PBR: &[&str] = &[
    "--env",
    "e.hdr",
    "--env-blur",
    "0.5",
    "--ibl-intensity",
    "2",
    "--exposure",
    "-1",
    "--tonemap",
    "aces",
    "--base-color",
    "0.5,0.5,0.5",
    "--metallic",
    "1",
    "--roughness",
    "0.25",
    "--dominant-direction",
    "--multiscatter",
    "--ibl-levels",
    "3",
    "--ibl-size",
    "64",
    "--irradiance-size",
    "16",
    "--ibl-samples",
    "64",
    "--lut-size",
    "32",
    "--ibl-encoding",
    "rgbm",
    "--ibl-precompute",
    "cpu",
    "--reference-samples",
    "9",
];

/// Bloom, antialiasing, the output and the GL context.
const POST_AND_OUTPUT: &[&str] = &[
    "--no-bloom",
    "--bloom",
    "0.5",
    "--bloom-threshold",
    "0.8",
    "--bloom-sigma",
    "4",
    "--bloom-levels",
    "1",
    "--aa",
    "ssaa",
    "--aa-samples",
    "2",
    "--transparent",
    "--size",
    "64x48",
    "--frames",
    "2",
    "--stats",
    "--point-size",
    "5",
    "--grid",
    "--axes",
    "--gl",
    "2.1",
    "--backend",
    "egl",
    "--animation",
    "Walk",
    "--time",
    "1.25",
    "--fps",
    "24",
    "--duration",
    "3",
    "--turntable",
    "--lens-shift",
    "0.1",
    "--stereo",
    "anaglyph",
    "--anaglyph",
    "gray",
    "--glasses",
    "amber-blue",
    "--swap-eyes",
    "--eye",
    "left",
    "--eye-separation",
    "0.1",
    "--convergence",
    "3",
];

/// One non-default value for every option, set through its words: each spec's setter is
/// reached, and the JSON form and the words both give back the same value.
fn every_option_changed() -> Options {
    let words = [
        MODEL_AND_CAMERA,
        LIGHTS_AND_SHADING,
        DRAWING,
        ENVIRONMENT_AND_PBR,
        POST_AND_OUTPUT,
    ]
    .concat();
    Options::from_words(words).unwrap()
}

#[test]
fn every_option_round_trips_through_json_and_words() {
    let o = every_option_changed();
    let d = Options::default();
    for s in specs() {
        assert!(
            // The model is positional; --flat conflicts with --crease (checked below).
            !(s.words)(&o, &d).is_empty()
                || s.name == "model"
                || s.name == "flat"
                || s.name == "env-color",
            "{} is not changed by the test's words",
            s.name
        );
    }
    let json = serde_json::to_string(&o).unwrap();
    assert_eq!(Options::from_json(&json).unwrap(), o, "{json}");
    assert_eq!(Options::from_words(o.to_words()).unwrap(), o);
    assert_eq!(Options::from_words(d.to_words()).unwrap(), d);
    assert!(d.to_words().is_empty());
    let uniform = Options::from_words(["--env-color", "0.5,1,2"]).unwrap();
    assert_eq!(uniform.pbr.env_color, Some([0.5, 1.0, 2.0]));
    assert_eq!(Options::from_words(uniform.to_words()).unwrap(), uniform);
    let flat = Options::from_words(["--flat"]).unwrap();
    assert!(flat.load.flat);
    assert_eq!(
        Options::from_json(&serde_json::to_string(&flat).unwrap()).unwrap(),
        flat
    );
}

#[test]
fn keywords_equal_words() {
    let a = kw(
        json!({"model": "m.obj", "yaw": 15, "size": [64, 48], "no_shadows": true,
        "light": ["dir:0,-1,0", "head"], "light_color": [1, 0.5, 0.25], "ortho": true,
        "target": [1, 2, 3], "shading": "pbr", "xray": ["a", "b"], "cache_size": "1M"}),
    )
    .unwrap();
    let b = Options::from_words([
        "m.obj",
        "--yaw",
        "15",
        "--size",
        "64x48",
        "--no-shadows",
        "--light",
        "dir:0,-1,0",
        "--light",
        "head",
        "--light-color",
        "1,0.5,0.25",
        "--ortho",
        "--target",
        "1,2,3",
        "--shading",
        "pbr",
        "--xray",
        "a,b",
        "--cache-size",
        "1M",
    ])
    .unwrap();
    assert_eq!(a, b);
}

#[test]
fn errors_name_the_option_and_the_value() {
    let e = kw(json!({"yaw": "north"})).unwrap_err();
    assert_eq!(e.as_keyword(), "yaw: expected a number, got 'north'");
    let e = kw(json!({"shadow_bias": -0.1})).unwrap_err();
    assert!(
        e.as_keyword()
            .starts_with("shadow_bias: -0.1 is out of range"),
        "{e}"
    );
    let e = kw(json!({"yawn": 3})).unwrap_err();
    assert_eq!(e.as_keyword(), "yawn: unknown option");
    let e = kw(json!({"shading": "toon"})).unwrap_err();
    assert_eq!(
        e.as_keyword(),
        "shading: expected one of phong, gouraud, pbr, got 'toon'"
    );
    let e = Options::from_words(["--fov", "200"]).unwrap_err();
    assert_eq!(
        e.on_command_line(),
        "--fov: 200 is out of range: must be between 0 and 180"
    );
    let e = Options::from_words(["--light", "none", "--light", "head"]).unwrap_err();
    assert!(e.to_string().contains("cannot be combined"), "{e}");
    for words in [
        ["--light", "kit", "--light", "head"],
        ["--light", "file", "--light", "dir:0,-1,0"],
    ] {
        let e = Options::from_words(words).unwrap_err();
        assert!(e.to_string().contains("cannot be combined"), "{e}");
    }
    let o = Options::from_words(["--light", "kit"]).unwrap();
    assert_eq!(o.light.lights, [crate::light::LightOpt::Kit]);
    let o = Options::from_words(["--light", "file"]).unwrap();
    assert_eq!(o.light.lights, [crate::light::LightOpt::File]);
    let e = Options::from_words(["--pcf", "3"]).unwrap_err();
    assert!(
        e.to_string().contains("PCF taps must be 1, 4, 9 or 16"),
        "{e}"
    );
    let e = Options::from_words(["--no-such-option"]).unwrap_err();
    assert!(e.to_string().contains("no-such-option"), "{e}");
    let e = Options::from_words(["--flat", "--crease", "30"]).unwrap_err();
    assert!(e.to_string().contains("--flat"), "{e}");
    // JSON: unknown keys and values out of range are refused too.
    assert!(Options::from_json(r#"{"camera": {"yawn": 1}}"#).is_err());
    let e = Options::from_json(r#"{"shadow": {"pcf": 3}}"#).unwrap_err();
    assert_eq!(e.name, "pcf");
}

#[test]
fn defaults_are_the_documented_ones() {
    let o = Options::default();
    assert_eq!(
        (o.camera.yaw, o.camera.pitch, o.camera.fov),
        (30.0, 25.0, 45.0)
    );
    assert_eq!(o.picture.size, (1024, 768));
    assert!(o.shadow.enabled && o.render.culling && o.load.cache);
    assert_eq!(
        spec("shadow_bias").unwrap().default.as_deref(),
        Some("0.0002")
    );
    o.validate().unwrap();
}

/// docs/options.md is generated from the specs; regenerate it with
/// `cargo run --bin glview -- --options-reference > docs/options.md`.
#[test]
fn the_committed_reference_is_current() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../docs/options.md");
    let committed = std::fs::read_to_string(path).unwrap_or_default();
    assert!(
        committed == reference_markdown(),
        "docs/options.md is stale: run `cargo run --bin glview -- --options-reference > docs/options.md`"
    );
}
