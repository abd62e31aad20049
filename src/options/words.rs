//! Options ⇄ words ⇄ named values. Every [`Options`] is parsed from command-line words, so
//! clap's parsers are the one validation of each value and its message; the serde form (and
//! the Python binding's keyword arguments) is a map from option names to values that becomes
//! those words again.
use super::Options;
use crate::error::{Error, Result};
use clap::{CommandFactory, FromArgMatches};
use serde_json::Value;

/// The options alone, for parsing words that are not a whole command line.
#[derive(clap::Parser)]
#[command(name = "glview", no_binary_name = true)]
struct Only {
    #[command(flatten)]
    opts: Options,
}

/// The camera's options: what changes from picture to picture of one scene.
const CAMERA: &[&str] = &["yaw", "pitch", "distance", "target", "fov"];

thread_local! {
    /// The options' parser, built once per thread: building clap's command (a hundred
    /// arguments) cost more than parsing with it, on every render of the library API.
    static PARSER: std::cell::RefCell<clap::Command> = std::cell::RefCell::new(Only::command());
    /// A parser of the [`CAMERA`] options alone (the same arguments, cloned).
    static CAMERA_PARSER: std::cell::RefCell<clap::Command> = std::cell::RefCell::new(
        clap::Command::new("glview").no_binary_name(true).args(
            Only::command()
                .get_arguments()
                .filter(|a| CAMERA.contains(&a.get_id().as_str()))
                .cloned(),
        ),
    );
    /// The last non-camera words [`Options::from_pairs`] parsed, and what they gave.
    static LAST: std::cell::RefCell<Option<(Vec<String>, Options)>> =
        const { std::cell::RefCell::new(None) };
}

/// clap's message is several lines with usage; its first line says what is wrong.
pub(crate) fn first_line(e: &clap::Error) -> String {
    e.to_string()
        .lines()
        .next()
        .unwrap_or_default()
        .trim_start_matches("error: ")
        .to_string()
}

impl Default for Options {
    fn default() -> Self {
        Options::from_words(Vec::<String>::new()).expect("the defaults parse")
    }
}

impl Options {
    /// Parses option words (`["model.obj", "--yaw", "30"]`) and validates them: the same
    /// checks and messages as the command line, before any model is loaded.
    pub fn from_words<I, T>(words: I) -> Result<Options>
    where
        I: IntoIterator<Item = T>,
        T: Into<String>,
    {
        let opts = Options::parse(words.into_iter().map(Into::into).collect())?;
        opts.validate()?;
        Ok(opts)
    }

    /// clap's part of [`Options::from_words`]: each value's parser, no validation.
    fn parse(words: Vec<String>) -> Result<Options> {
        let matches = PARSER
            .with(|p| p.borrow_mut().try_get_matches_from_mut(&words))
            .map_err(|e| Error::Usage(first_line(&e)))?;
        let mut opts = Only::from_arg_matches(&matches)
            .map_err(|e| Error::Usage(first_line(&e)))?
            .opts;
        opts.words = words;
        Ok(opts)
    }

    /// Options from names and values: `{"yaw": 30, "light": ["dir:0,-1,0"], "size":
    /// [640, 480], "no-shadows": true}`. Names are the long options without `--` (`_` may
    /// stand for `-`; `model` is the model file). Values: `true` is a flag given, `false` or
    /// null one left out; a list of numbers is one comma-separated value (`WxH` for `size`),
    /// any other list repeats the option.
    ///
    /// Renders of a turntable or a sweep (the Python binding's calls) change only the
    /// camera: the other options' words are parsed once per thread while they stay the same
    /// ([`LAST`]), and the camera's by a parser of just those arguments (clap's parse of all
    /// of them, defaults included, took ~45 µs a call). The result is the full parse's.
    pub fn from_pairs<'a>(
        pairs: impl IntoIterator<Item = (&'a str, &'a Value)>,
    ) -> Result<Options> {
        let mut words = Vec::new();
        let mut camera = Vec::new();
        // Every word in the pairs' order: the whole command line, parsed where the split
        // parse fails, so a bad value gets the error (and the order of errors) it always had.
        let mut all = Vec::new();
        let mut model = None;
        for (name, value) in pairs {
            let name = name.replace('_', "-");
            if name == "model" {
                model = Some(scalar(value).ok_or_else(|| bad(&name, value))?);
                continue;
            }
            let flag = format!("--{name}");
            let mut these = Vec::new();
            match value {
                Value::Null | Value::Bool(false) => {}
                Value::Bool(true) => these.push(flag),
                Value::Array(items) if items.iter().all(Value::is_number) => {
                    let sep = if name == "size" { "x" } else { "," };
                    let parts: Vec<String> = items.iter().filter_map(scalar).collect();
                    these.extend([flag, parts.join(sep)]);
                }
                Value::Array(items) => {
                    for item in items {
                        these.push(flag.clone());
                        these.push(scalar(item).ok_or_else(|| bad(&name, item))?);
                    }
                }
                other => these.extend([flag, scalar(other).ok_or_else(|| bad(&name, other))?]),
            }
            all.extend(these.iter().cloned());
            if CAMERA.contains(&name.as_str()) {
                camera.extend(these);
            } else {
                words.extend(these);
            }
        }
        // The model goes first: a value-less `--ortho` must not swallow it.
        let all: Vec<String> = model.iter().cloned().chain(all).collect();
        let rest: Vec<String> = model.into_iter().chain(words).collect();
        match Options::split_parse(rest, &camera) {
            Ok(mut opts) => {
                opts.words = all;
                opts.validate()?;
                Ok(opts)
            }
            Err(_) => Options::from_words(all),
        }
    }

    /// [`Options::from_pairs`]'s parse: `rest` (the non-camera words) as last time or by
    /// clap, then the `camera` words over it; not validated, `words` not set.
    fn split_parse(rest: Vec<String>, camera: &[String]) -> Result<Options> {
        let cached = LAST.with(|l| {
            l.borrow()
                .as_ref()
                .filter(|(w, _)| *w == rest)
                .map(|(_, o)| o.clone())
        });
        let mut opts = match cached {
            Some(o) => o,
            None => {
                let o = Options::parse(rest.clone())?;
                LAST.with(|l| *l.borrow_mut() = Some((rest, o.clone())));
                o
            }
        };
        if !camera.is_empty() {
            let m = CAMERA_PARSER
                .with(|p| p.borrow_mut().try_get_matches_from_mut(camera))
                .map_err(|e| Error::Usage(first_line(&e)))?;
            // The field types of `Options` (yaw, pitch and fov have defaults, so are there).
            let f32_of = |id: &str| m.get_one::<f32>(id).copied();
            opts.yaw = f32_of("yaw").unwrap_or(opts.yaw);
            opts.pitch = f32_of("pitch").unwrap_or(opts.pitch);
            opts.fov = f32_of("fov").unwrap_or(opts.fov);
            opts.distance = f32_of("distance");
            opts.target = m.get_one::<String>("target").cloned();
        }
        Ok(opts)
    }

    /// The options given (defaults left out) as names and values, by name;
    /// options given more than once are lists. The inverse of [`Options::from_pairs`].
    pub fn to_pairs(&self) -> serde_json::Map<String, Value> {
        PARSER.with(|p| self.pairs_with(&p.borrow()))
    }

    fn pairs_with(&self, cmd: &clap::Command) -> serde_json::Map<String, Value> {
        let mut map = serde_json::Map::new();
        let mut words = self.words.iter().peekable();
        while let Some(w) = words.next() {
            let Some(long) = w.strip_prefix("--") else {
                map.insert("model".into(), Value::String(w.clone()));
                continue;
            };
            let (name, inline) = match long.split_once('=') {
                Some((n, v)) => (n, Some(v.to_string())),
                None => (long, None),
            };
            let Some(arg) = cmd.get_arguments().find(|a| a.get_long() == Some(name)) else {
                continue;
            };
            let takes = arg.get_action().takes_values();
            let value = match inline {
                Some(v) => Value::String(v),
                // `--ortho` alone fits the model: its value is optional.
                None if takes
                    && (name != "ortho"
                        || words.peek().is_some_and(|v| v.parse::<f32>().is_ok())) =>
                {
                    Value::String(words.next().cloned().unwrap_or_default())
                }
                None => Value::Bool(true),
            };
            let repeats = matches!(arg.get_action(), clap::ArgAction::Append);
            match map.get_mut(name) {
                Some(Value::Array(list)) if repeats => list.push(value),
                _ if repeats => {
                    map.insert(name.into(), Value::Array(vec![value]));
                }
                _ => {
                    map.insert(name.into(), value);
                }
            }
        }
        map
    }

    /// The checks that need more than one value or a parsed list (lights, colours, ranges
    /// between options), with the messages the command line prints; no model is needed.
    pub fn validate(&self) -> Result<()> {
        let mut probe = crate::scene::Scene::from_meshes("options", Vec::new(), Vec::new());
        probe.bounds = crate::scene::Bounds {
            min: glam::Vec3::splat(-1.0),
            max: glam::Vec3::splat(1.0),
        };
        crate::run::frame_settings(self, &probe)?;
        crate::run::env_request(self)?;
        Ok(())
    }
}

fn scalar(v: &Value) -> Option<String> {
    match v {
        Value::String(s) => Some(s.clone()),
        Value::Number(n) => Some(n.to_string()),
        Value::Bool(b) => Some(b.to_string()),
        _ => None,
    }
}

fn bad(name: &str, v: &Value) -> Error {
    Error::Usage(format!("--{name}: {v} is not a value of this option"))
}

impl serde::Serialize for Options {
    fn serialize<S: serde::Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        self.to_pairs().serialize(s)
    }
}

impl<'de> serde::Deserialize<'de> for Options {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
        let map = serde_json::Map::<String, Value>::deserialize(d)?;
        Options::from_pairs(map.iter().map(|(k, v)| (k.as_str(), v)))
            .map_err(serde::de::Error::custom)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `from_pairs` parses the camera apart from the rest and keeps the rest's parse: the
    /// options must be what the whole command line gives, on a repeated rest (the kept
    /// parse), after another rest, and camera values must fail with the command line's words.
    #[test]
    fn camera_pairs_parse_as_the_whole_command_line() {
        let rests = [
            serde_json::json!({"light": ["dir:0,-1,0"], "single_sided": true}),
            serde_json::json!({"model": "m.obj", "ortho": true, "size": [64, 48]}),
        ];
        let cameras = [
            serde_json::json!({}),
            serde_json::json!({"yaw": 15}),
            serde_json::json!({"yaw": -40.5, "pitch": 10, "distance": 3.5, "target": "1,-2,3", "fov": 30}),
            serde_json::json!({"pitch": -80}),
        ];
        for rest in rests.iter().chain(rests.iter()) {
            for camera in &cameras {
                let mut map = rest.as_object().unwrap().clone();
                map.extend(camera.as_object().unwrap().clone());
                let got = Options::from_pairs(map.iter().map(|(k, v)| (k.as_str(), v))).unwrap();
                let mut whole = Options::from_words(got.words.clone()).unwrap();
                whole.words.clone_from(&got.words);
                assert_eq!(format!("{got:?}"), format!("{whole:?}"), "{map:?}");
            }
        }
        for (name, value) in [
            ("yaw", serde_json::json!("abc")),
            ("distance", serde_json::json!(-1)),
            ("fov", serde_json::json!("wide")),
        ] {
            let map = serde_json::json!({ name: value.clone() });
            let map = map.as_object().unwrap();
            let got = Options::from_pairs(map.iter().map(|(k, v)| (k.as_str(), v))).unwrap_err();
            let v = scalar(&value).unwrap();
            let whole = Options::from_words([format!("--{name}"), v]).unwrap_err();
            assert_eq!(got.to_string(), whole.to_string());
        }
        // Where the split parse fails, the error is the whole command line's, first error
        // first (here a conflict among the rest, or a flag where a value belongs, before a
        // bad camera value). The map's keys are in sorted order, as the words below.
        for (pairs, words) in [
            (
                serde_json::json!({"crease": 30, "flat": true, "yaw": "abc"}),
                &["--crease", "30", "--flat", "--yaw", "abc"][..],
            ),
            (
                serde_json::json!({"light": true, "yaw": 15}),
                &["--light", "--yaw", "15"],
            ),
            (
                serde_json::json!({"target": true, "yaw": 5}),
                &["--target", "--yaw", "5"],
            ),
        ] {
            let map = pairs.as_object().unwrap();
            let got = Options::from_pairs(map.iter().map(|(k, v)| (k.as_str(), v))).unwrap_err();
            let whole = Options::from_words(words.iter().copied()).unwrap_err();
            assert_eq!(got.to_string(), whole.to_string(), "{pairs}");
        }
    }

    #[test]
    fn words_pairs_and_serde_round_trip() {
        let o = Options::from_words([
            "m.obj",
            "--yaw=10",
            "--light",
            "dir:0,-1,0",
            "--light",
            "head",
            "--no-shadows",
            "--size",
            "64x48",
            "--ortho",
        ])
        .unwrap();
        assert_eq!((o.yaw, o.size, o.ortho), (10.0, (64, 48), Some(None)));
        let json = serde_json::to_string(&o).unwrap();
        assert_eq!(
            json,
            r#"{"light":["dir:0,-1,0","head"],"model":"m.obj","no-shadows":true,"ortho":true,"size":"64x48","yaw":"10"}"#
        );
        let back: Options = serde_json::from_str(&json).unwrap();
        assert_eq!(back.to_pairs(), o.to_pairs());
        assert_eq!(back.lights, ["dir:0,-1,0", "head"]);
        let typed: Options = serde_json::from_str(
            r#"{"size": [32, 16], "ambient": [0.5, 0.5, 0.5], "no_shadows": true}"#,
        )
        .unwrap();
        assert_eq!(
            (typed.size, typed.ambient.as_str()),
            ((32, 16), "0.5,0.5,0.5")
        );
        assert!(typed.no_shadows);
    }

    #[test]
    fn bad_values_have_the_command_lines_messages() {
        let e = Options::from_words(["--shadow-bias", "-0.1"])
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("out of range: the bias is in depth-buffer units"),
            "{e}"
        );
        let e = Options::from_words(["--fov", "200"])
            .unwrap_err()
            .to_string();
        assert_eq!(e, "invalid option: --fov 200 must be between 0 and 180");
        let e = Options::from_words(["--light", "none", "--light", "head"]).unwrap_err();
        assert!(e.to_string().contains("cannot be combined"), "{e}");
        let e = Options::from_words(["--no-such-option"])
            .unwrap_err()
            .to_string();
        assert!(e.contains("--no-such-option"), "{e}");
        assert!(serde_json::from_str::<Options>(r#"{"pcf": 3}"#).is_err());
    }
}
