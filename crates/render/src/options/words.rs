//! Options from the surfaces that are not serde's JSON tree: command-line words (a batch
//! line, a PNG's reproducing command, Python's `render_words`), keyword arguments (names
//! and JSON values, flat), and back to words; and the reference page generated from the
//! specs. The command line's own parser (clap, in the binary) calls the same setters.
use super::forms::Form;
use super::{spec, specs, OptionError, Options};
use serde_json::Value;

impl Options {
    /// Parses option words (`["model.obj", "--yaw", "30", "--no-shadows"]`) and validates
    /// them, with the command line's names: `--name value`, `--name=value`, switches, and
    /// one model path.
    ///
    /// ```
    /// let o = glview_render::Options::from_words(["--yaw", "-40", "--light", "head"]).unwrap();
    /// assert_eq!(o.camera.yaw, -40.0);
    /// let e = glview_render::Options::from_words(["--yaw", "north"]).unwrap_err();
    /// assert_eq!(e.on_command_line(), "--yaw: expected a number, got 'north'");
    /// ```
    pub fn from_words<I, T>(words: I) -> Result<Options, OptionError>
    where
        I: IntoIterator<Item = T>,
        T: Into<String>,
    {
        let words: Vec<String> = words.into_iter().map(Into::into).collect();
        let mut o = Options::default();
        let mut seen: Vec<&str> = Vec::new();
        let mut it = words.iter().peekable();
        while let Some(w) = it.next() {
            let Some(long) = w.strip_prefix("--") else {
                if o.load.model.is_some() {
                    return Err(OptionError::new(
                        "",
                        format!("unexpected argument '{w}' (one model at a time)"),
                    ));
                }
                o.load.model = Some(w.into());
                continue;
            };
            let (name, inline) = match long.split_once('=') {
                Some((n, v)) => (n, Some(v.to_string())),
                None => (long, None),
            };
            let s = spec(name)
                .filter(|s| s.name != "model" && !name.contains('_'))
                .ok_or_else(|| OptionError::new(name, "unknown option"))?;
            if matches!(
                s.form,
                Form::Value | Form::Flag | Form::NoFlag | Form::Optional
            ) {
                if seen.contains(&s.name) {
                    return Err(OptionError::new(name, "given more than once"));
                }
                seen.push(s.name);
            }
            let value = match (s.form, inline) {
                (Form::Flag | Form::NoFlag, Some(_)) => {
                    return Err(OptionError::new(name, "takes no value"))
                }
                (_, Some(v)) => v,
                (Form::Flag | Form::NoFlag, None) => String::new(),
                // `--ortho` alone fits the model; a number after it is its height.
                (Form::Optional, None) => match it.peek() {
                    Some(v) if v.parse::<f32>().is_ok() => it.next().cloned().unwrap_or_default(),
                    _ => String::new(),
                },
                (_, None) => it
                    .next()
                    .cloned()
                    .ok_or_else(|| OptionError::new(name, "a value is required"))?,
            };
            (s.set_word)(&mut o, &value).map_err(|m| OptionError::new(name, m))?;
        }
        o.validate()?;
        Ok(o)
    }

    /// Options from keyword arguments: names as the command line's (`_` may stand for
    /// `-`: `no_shadows`, `light_color`) with JSON values (`30`, `"dir:0,-1,0"`, `[640,
    /// 480]`, `true`); every other option at its default. Errors name the keyword.
    ///
    /// ```
    /// let kw = serde_json::json!({"yaw": 15, "size": [64, 48], "no_shadows": true});
    /// let o = glview_render::Options::from_keywords(kw.as_object().unwrap().iter().map(|(k, v)| (k.as_str(), v))).unwrap();
    /// assert_eq!((o.camera.yaw, o.picture.size, o.shadow.enabled), (15.0, (64, 48), false));
    /// let bad = serde_json::json!({"yaw": "north"});
    /// let e = glview_render::Options::from_keywords(bad.as_object().unwrap().iter().map(|(k, v)| (k.as_str(), v))).unwrap_err();
    /// assert_eq!(e.as_keyword(), "yaw: expected a number, got 'north'");
    /// ```
    pub fn from_keywords<'a>(
        pairs: impl IntoIterator<Item = (&'a str, &'a Value)>,
    ) -> Result<Options, OptionError> {
        let mut o = Options::default();
        for (name, value) in pairs {
            let s = spec(name).ok_or_else(|| OptionError::new(name, "unknown option"))?;
            (s.set_json)(&mut o, value).map_err(|m| OptionError::new(name, m))?;
        }
        o.validate()?;
        Ok(o)
    }

    /// Options from their JSON form (serde's tree: `{"camera": {"yaw": 30}}`), validated.
    pub fn from_json(json: &str) -> Result<Options, OptionError> {
        let o: Options =
            serde_json::from_str(json).map_err(|e| OptionError::new("", e.to_string()))?;
        o.validate()?;
        Ok(o)
    }

    /// The command-line words that give these options (defaults left out, the model
    /// first): `Options::from_words(o.to_words())` equals `o`.
    pub fn to_words(&self) -> Vec<String> {
        let d = Options::default();
        let mut words: Vec<String> = self
            .load
            .model
            .iter()
            .map(|p| p.to_string_lossy().into_owned())
            .collect();
        for s in specs().iter().filter(|s| s.name != "model") {
            words.extend((s.words)(self, &d));
        }
        words
    }
}

/// The reference of every option, generated from the specs (docs/options.md; a test fails
/// when the committed page differs).
pub fn reference_markdown() -> String {
    let mut md = String::from(
        "# Options\n\n<!-- Generated from crates/render/src/options/mod.rs by `glview --options-reference`; \
         a test fails when this file is stale. Do not edit. -->\n\n\
         Every picture option, declared once. The same option is a command-line flag \
         (`--shadow-bias 0.001`), a Python keyword (`shadow_bias=0.001`), a batch line's word, \
         and a key of the JSON form a PNG keeps (`{\"shadow\": {\"bias\": 0.001}}`).\n",
    );
    let mut group = "";
    for s in specs() {
        let g = s.group();
        if g != group {
            group = g;
            md.push_str(&format!(
                "\n## `{g}`\n\n| command line | Python keyword | JSON | default | meaning |\n|---|---|---|---|---|\n"
            ));
        }
        let flag = match (s.name, s.form) {
            ("model", _) => "`MODEL`".to_string(),
            (_, Form::Flag | Form::NoFlag) => format!("`--{}`", s.name),
            (_, Form::Optional) => format!("`--{} [{}]`", s.name, s.expected),
            (_, Form::Repeat) => format!("`--{} {}` (repeatable)", s.name, s.expected),
            (_, Form::List) => format!("`--{} A,B,...`", s.name),
            _ => format!("`--{} {}`", s.name, s.expected),
        };
        let mut meaning = s.doc.split_whitespace().collect::<Vec<_>>().join(" ");
        if !s.choices.is_empty() {
            let list: Vec<String> = s
                .choices
                .iter()
                .map(|(w, d)| {
                    let d = d.split_whitespace().collect::<Vec<_>>().join(" ");
                    if d.is_empty() {
                        format!("`{w}`")
                    } else {
                        format!("`{w}` ({d})")
                    }
                })
                .collect();
            meaning.push_str(&format!(" Choices: {}.", list.join(", ")));
        }
        let default = s
            .default
            .as_deref()
            .map_or_else(|| "—".to_string(), |d| format!("`{d}`"));
        md.push_str(&format!(
            "| {flag} | `{}` | `{}` | {default} | {} |\n",
            s.keyword(),
            s.path,
            meaning.replace('|', "\\|")
        ));
    }
    md
}
