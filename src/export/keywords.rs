//! The export's own options as keywords (Python's `glview.export(model, path, **options)`):
//! the same fields and checks as the command line's `glview export` arguments.
use super::ExportOptions;
use crate::options::Options;
use crate::{Error, Result};
use serde_json::Value;

impl ExportOptions {
    /// `options` (the picture's) with the export's keywords of `export` (a JSON object:
    /// yaw_steps, pitch_steps, pitch_step, quality, png, title, caption, max_size, scorm,
    /// live (True, False or "only"), web_dir);
    /// an unknown keyword or a value of the wrong kind is a usage error naming it.
    pub fn with_keywords(options: Options, export: &Value) -> Result<ExportOptions> {
        let mut o = ExportOptions {
            options,
            ..ExportOptions::default()
        };
        let Some(map) = export.as_object() else {
            return Err(Error::Usage("export options must be keywords".into()));
        };
        for (k, v) in map {
            if v.is_null() {
                continue;
            }
            let bad = |what: &str| Error::Usage(format!("export: {k} must be {what}, got {v}"));
            let count = || {
                v.as_u64()
                    .and_then(|n| u32::try_from(n).ok())
                    .ok_or_else(|| bad("a whole number"))
            };
            let text = || v.as_str().map(String::from).ok_or_else(|| bad("a string"));
            match k.as_str() {
                "yaw_steps" => o.yaw_steps = count()?,
                "pitch_steps" => o.pitch_steps = count()?,
                "pitch_step" => o.pitch_step = v.as_f64().ok_or_else(|| bad("a number"))? as f32,
                "quality" => {
                    o.quality = u8::try_from(count()?).map_err(|_| bad("1 to 100"))?;
                }
                "png" => o.png = v.as_bool().ok_or_else(|| bad("True or False"))?,
                "title" => o.title = Some(text()?),
                "caption" => o.caption = Some(text()?),
                "max_size" => o.max_size = Some(v.as_u64().ok_or_else(|| bad("bytes"))?),
                "scorm" => o.scorm = Some(text()?.into()),
                "live" => {
                    o.live = match (v.as_bool(), v.as_str()) {
                        (Some(true), _) => super::Live::Live,
                        (Some(false), _) => super::Live::Off,
                        (_, Some("only")) => super::Live::Only,
                        _ => return Err(bad("True, False or \"only\"")),
                    }
                }
                "web_dir" => o.web_dir = Some(text()?.into()),
                _ => {
                    return Err(Error::Usage(format!(
                        "export: unknown option {k:?} (yaw_steps, pitch_steps, pitch_step, \
                         quality, png, title, caption, max_size, scorm, live, web_dir, and the picture's)"
                    )))
                }
            }
        }
        Ok(o)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    #[test]
    fn keywords_fill_the_same_fields_and_refuse_the_rest() {
        let o = ExportOptions::with_keywords(
            Options::default(),
            &json!({"yaw_steps": 8, "png": true, "title": "T", "scorm": "x.zip", "caption": null}),
        )
        .unwrap();
        assert_eq!((o.yaw_steps, o.pitch_steps, o.png), (8, 5, true));
        assert_eq!(o.title.as_deref(), Some("T"));
        assert_eq!(o.scorm, Some("x.zip".into()));
        let live = |v| ExportOptions::with_keywords(Options::default(), &json!({"live": v}));
        assert_eq!(live(json!(true)).unwrap().live, super::super::Live::Live);
        assert_eq!(live(json!("only")).unwrap().live, super::super::Live::Only);
        assert_eq!(live(json!(false)).unwrap().live, super::super::Live::Off);
        assert!(live(json!("yes")).is_err());
        for bad in [
            json!({"yaw_steps": -1}),
            json!({"quality": 300}),
            json!({"colour": 1}),
        ] {
            let e = ExportOptions::with_keywords(Options::default(), &bad).unwrap_err();
            assert!(e.to_string().contains("export: "), "{e}");
        }
    }
}
