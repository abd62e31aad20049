//! The lesson page: page/page.html with its style, script and data filled in. The data (the
//! grid, every picture as a data URI, the numbers) is one JSON block the script reads; the
//! page has a Content-Security-Policy that allows no request at all, so it opens the same
//! from disk, from an LMS, or offline.
use super::live::Payload;
use super::render::Rendered;
use super::{ExportOptions, Grid};

const TEMPLATE: &str = include_str!("page/page.html");
const STYLE: &str = include_str!("page/page.css");
const SCRIPT: &str = include_str!("page/page.js");
/// The live page's script (modern JS: it runs only where WebAssembly does; page.js, ES5,
/// keeps the turntable working in every browser).
const LIVE_SCRIPT: &str = include_str!("page/live.js");
/// What the live page and `glview serve`'s local mode share: the renderer's start.
pub const START_SCRIPT: &str = include_str!("page/start.js");

/// The page of a rendered grid, drawing live with `live`.
pub(crate) fn html(
    opts: &ExportOptions,
    grid: &Grid,
    r: &Rendered,
    title: &str,
    live: Option<&Payload>,
) -> String {
    let uri = |p: &Vec<u8>| format!("data:{};base64,{}", r.mime, base64(p));
    let command = command_line(opts);
    // The pictures' own size: side-by-side-full's are twice as wide as --size.
    let shown_size = {
        let (w, h) = crate::view::settings::output_size(&opts.options);
        [w, h]
    };
    let data = serde_json::json!({
        "title": title,
        "model": r.model,
        "command": command,
        "size": shown_size,
        "yaws": grid.yaws,
        "pitches": grid.pitches,
        "start": grid.start(),
        "dragDegPerPixel": crate::keys::DRAG_DEG_PER_PIXEL,
        "phong": r.phong.iter().map(uri).collect::<Vec<_>>(),
        "pbr": r.pbr.iter().map(uri).collect::<Vec<_>>(),
        "numbers": r.numbers,
        "live": live.map(|l| &l.data),
    });
    // Inside a <script> element only `<` can end it early (`</script>`, `<!--`); in JSON it
    // occurs only in strings, where \u003c means the same character.
    let data = data.to_string().replace('<', "\\u003c");
    let caption = opts.caption.as_deref().unwrap_or("");
    let [w, h] = shown_size;
    fill(TEMPLATE, |name| {
        match name {
        "TITLE" => Some(html_escape(title)),
        "CAPTION" => Some(html_escape(caption)),
        "MODEL" => Some(html_escape(&r.model)),
        "COMMAND" => Some(html_escape(&command)),
        "WIDTH" => Some(w.to_string()),
        "HEIGHT" => Some(h.to_string()),
        "STYLE" => Some(STYLE.to_string()),
        "SCRIPT" => Some(SCRIPT.to_string()),
        "DATA" => Some(data.clone()),
        // WebAssembly compiles only where the policy says so.
        "WASM_CSP" => Some(
            if live.is_some() {
                " 'wasm-unsafe-eval'"
            } else {
                ""
            }
            .into(),
        ),
        "LIVE" => Some(live.map_or(String::new(), |l| {
            // The glue is wasm-bindgen's own text; `</script` cannot occur in it unescaped
            // (it is code, not data), checked anyway.
            let glue = l.glue.replace("</script", "<\\/script");
            format!(
                "<script>{glue}</script>\n<script>{START_SCRIPT}</script>\n<script>{LIVE_SCRIPT}</script>"
            )
        })),
        _ => None,
    }
    })
}

/// The command line that makes this page again.
fn command_line(opts: &ExportOptions) -> String {
    let q = crate::repro::quote;
    let mut words = vec!["glview".to_string(), "export".to_string()];
    let model = opts.options.load.model.as_ref();
    words.extend(model.map(|m| q(&m.display().to_string())));
    words.push("-o".into());
    words.push("lesson.html".into());
    let (w, h) = opts.options.picture.size;
    words.push(format!("--size {w}x{h}"));
    words.push(format!("--yaw-steps {}", opts.yaw_steps));
    words.push(format!("--pitch-steps {}", opts.pitch_steps));
    words.push(format!("--pitch-step {}", opts.pitch_step));
    if opts.png {
        words.push("--png".into());
    } else {
        words.push(format!("--quality {}", opts.quality));
    }
    for (flag, v) in [("--title", &opts.title), ("--caption", &opts.caption)] {
        if let Some(v) = v {
            words.push(format!("{flag} {}", q(v)));
        }
    }
    // The view options but the model and size, which are the export's own arguments.
    let mut view = opts.options.clone();
    view.load.model = None;
    view.picture.size = crate::options::Options::default().picture.size;
    let rest: Vec<String> = view.to_words().iter().map(|w| q(w)).collect();
    if !rest.is_empty() {
        words.push("--".into());
        words.extend(rest);
    }
    words.join(" ")
}

/// `template` with every `{{NAME}}` replaced by `value(NAME)` in one pass (so a title that
/// says `{{DATA}}` stays text); unknown names stay as they are.
fn fill(template: &str, value: impl Fn(&str) -> Option<String>) -> String {
    let mut out = String::with_capacity(template.len());
    let mut rest = template;
    while let Some(i) = rest.find("{{") {
        out.push_str(&rest[..i]);
        let after = &rest[i + 2..];
        match after
            .find("}}")
            .and_then(|j| Some((j, value(&after[..j])?)))
        {
            Some((j, v)) => {
                out.push_str(&v);
                rest = &after[j + 2..];
            }
            None => {
                out.push_str("{{");
                rest = after;
            }
        }
    }
    out.push_str(rest);
    out
}

fn html_escape(s: &str) -> String {
    super::scorm::xml_escape(s)
}

/// Standard base64 (RFC 4648, padded), as data URIs take it.
pub(crate) fn base64(bytes: &[u8]) -> String {
    const ABC: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::with_capacity(bytes.len().div_ceil(3) * 4);
    for chunk in bytes.chunks(3) {
        let b = [
            chunk[0],
            *chunk.get(1).unwrap_or(&0),
            *chunk.get(2).unwrap_or(&0),
        ];
        let n = (u32::from(b[0]) << 16) | (u32::from(b[1]) << 8) | u32::from(b[2]);
        for k in 0..4 {
            if k <= chunk.len() {
                out.push(ABC[(n >> (18 - 6 * k) & 63) as usize] as char);
            } else {
                out.push('=');
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn base64_matches_rfc_4648_vectors() {
        for (i, o) in [
            ("", ""),
            ("f", "Zg=="),
            ("fo", "Zm8="),
            ("foo", "Zm9v"),
            ("foob", "Zm9vYg=="),
            ("fooba", "Zm9vYmE="),
            ("foobar", "Zm9vYmFy"),
        ] {
            assert_eq!(base64(i.as_bytes()), o);
        }
    }

    /// The page runs in old browsers: its script is ES5 (no `let`/`const`, arrow functions,
    /// template strings, classes or modules).
    #[test]
    fn script_is_es5() {
        let code: String = SCRIPT
            .lines()
            .map(|l| l.split("//").next().unwrap_or(""))
            .collect::<Vec<_>>()
            .join("\n");
        for token in [
            "let ", "const ", "=>", "`", "class ", "import ", "export ", "async ", "...",
        ] {
            assert!(!code.contains(token), "page.js uses {token:?}");
        }
    }

    #[test]
    fn fill_replaces_in_one_pass() {
        let v = |n: &str| match n {
            "A" => Some("{{B}}".to_string()),
            "B" => Some("b".to_string()),
            _ => None,
        };
        assert_eq!(fill("x{{A}}y{{B}}z{{C}}{{", v), "x{{B}}ybz{{C}}{{");
    }
}
