//! One frame of a view: drawn through the session on the render thread (so a still is the
//! command line's picture of the same options) and read back ([`draw`]), then encoded on a
//! worker ([`encode`]): JPEG for a preview, PNG with the picture's text (its options, its
//! command line) for a still.
use glview::image_out::RgbaFiles;
use glview::render::attributes::Outputs;
use glview::session::{Profile, Session, View};
use std::time::Instant;

#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Kind {
    /// While input arrives: `scale` of the view's size, JPEG of this quality.
    Preview { scale: f32, quality: u8 },
    /// Full size, lossless.
    Still,
    /// No picture: the view's state only, for a page that draws it itself (local mode).
    State,
}

pub struct Picture<'a> {
    pub view: &'a View,
    /// The list the model's name comes from, and what takes the server's paths out of the
    /// command and the PNG text (relative to the served folder, as the viewer's names are).
    pub models: &'a super::models::Models,
    pub kind: Kind,
    /// The header carries the view's state, for a page that draws it.
    pub state: bool,
}

fn ms(t: Instant) -> f64 {
    (t.elapsed().as_secs_f64() * 1e4).round() / 10.0
}

/// The options a frame of `view` is drawn with: a preview's are scaled down.
pub fn options_for(view: &View, kind: Kind) -> glview::Options {
    let mut o = view.picture();
    if let Kind::Preview { scale, .. } = kind {
        let (w, h) = o.picture.size;
        let s = |v: u32| ((v as f32 * scale).round() as u32).clamp(16, v.max(16));
        o.picture.size = (s(w), s(h));
    }
    o
}

/// A frame drawn and read back, to be encoded.
pub struct Drawn {
    /// Without the scheduler's fields and the encoder's.
    pub header: serde_json::Value,
    /// None for [`Kind::State`].
    image: Option<glview::image_out::Rgba>,
    text: Vec<(&'static str, String)>,
    kind: Kind,
}

/// Draws the frame: its header (without the scheduler's fields) and pixels.
pub fn draw(session: &mut Session, p: &Picture) -> glview::Result<Drawn> {
    let o = options_for(p.view, p.kind);
    let view = p.view.options().picture.size;
    let views = views_json(session, &o)?;
    let motion = motion_json(p.view, session.scene(&o)?.animations());
    let t = Instant::now();
    let mut profile = Profile::default();
    let still = p.kind == Kind::Still;
    let (image, text, diff, command, settings) = if p.kind == Kind::State {
        let scene = session.scene(&o)?;
        let (settings, _) = glview::view::settings::frame_settings(&o, scene)?;
        let command = p.models.scrub(&glview::repro::command_line(&o));
        (None, Vec::new(), None, command, settings)
    } else if p.view.compare() {
        let pair = glview::compare::phong_pbr(session, &o, still)?;
        let command = format!(
            "{} --compare phong,pbr",
            p.models.scrub(&glview::repro::command_line(&o))
        );
        let text = vec![
            ("Software", format!("glview {}", env!("CARGO_PKG_VERSION"))),
            ("glview.compare", "phong,pbr".to_string()),
            ("glview.command", command.clone()),
        ];
        let diff = pair.numbers.map(|(n, pixels)| {
            let mut v = serde_json::to_value(n).unwrap_or_default();
            v["model_pixels"] = pixels.into();
            v
        });
        (Some(pair.image), text, diff, command, pair.settings)
    } else {
        let drawn = session.draw(&o, None, Outputs::default(), &mut profile)?;
        let command = p.models.scrub(&glview::repro::command_line(&o));
        // A preview is JPEG, without text: only a still's is made.
        let text = if still {
            let text = drawn.text();
            text.into_iter()
                .map(|(k, v)| (k, p.models.scrub(&v)))
                .collect()
        } else {
            Vec::new()
        };
        (Some(drawn.image), text, None, command, drawn.settings)
    };
    let draw_ms = ms(t);
    // What the overlay shows: the settings the picture was drawn with.
    let tier = if p.view.compare() {
        "phong | pbr".to_string()
    } else {
        settings.shading.to_string()
    };
    let (width, height) = image.as_ref().map_or(view, |i| (i.width, i.height));
    let header = serde_json::json!({
        "still": p.kind == Kind::Still,
        "width": width,
        "height": height,
        "view": [view.0, view.1],
        "model": p.models.name_of(p.view.options().load.model.as_deref()),
        "compare": p.view.compare(),
        "tier": tier,
        "shadows": settings.shadows.enabled,
        "bloom": settings.lighting.post.bloom.strength > 0.0,
        "stereo": p.view.options().stereo.mode.word(),
        "ms": {
            // Drawing to glFinish, then the read-back; the compare view's two panes are
            // timed as one.
            "render": if profile.frames_ms.is_empty() { draw_ms } else { round(profile.frames_ms.iter().sum()) },
            "read": round(profile.readback_ms),
            "draw": draw_ms,
        },
        "diff": diff,
        "command": command,
        // The camera absolutely, as `--yaw --pitch [--distance] [--target] --fov` take it:
        // what a shared link carries (distance and target none: fitted).
        "camera": camera_json(&p.view.options().camera),
        "views": views,
        "motion": motion,
    });
    // The view itself, for a page that draws it (local mode): its options with the page's
    // paths for the files the scene request gave it (`/scene`), never the server's. A page
    // on the stream is not sent it.
    let mut header = header;
    if p.state {
        header["state"] = page_view(p.view);
    }
    Ok(Drawn {
        header,
        image,
        text,
        kind: p.kind,
    })
}

/// `view` as a page that draws it takes it ([`Kind::State`]'s `state`): the paths in its
/// options are the page's (`glview::export::live::page_paths`).
fn page_view(view: &View) -> serde_json::Value {
    let mut v = serde_json::to_value(view).unwrap_or_default();
    let paged = glview::export::live::page_paths(view.options());
    v["options"] = serde_json::to_value(paged).unwrap_or_default();
    v
}

/// Encodes a drawn frame (off the render thread, but a state's: there is nothing to
/// encode): its full header and image bytes.
pub fn encode(d: Drawn) -> glview::Result<(serde_json::Value, Vec<u8>)> {
    let t = Instant::now();
    let (bytes, format, encoder) = match (d.kind, d.image) {
        (Kind::Still, Some(image)) => (image.png_bytes(&d.text), "png", "png"),
        (Kind::Preview { quality, .. }, Some(image)) => {
            let (b, encoder) = image.jpeg_bytes(quality)?;
            (b, "jpeg", encoder)
        }
        _ => (Vec::new(), "none", "none"),
    };
    let mut header = d.header;
    header["format"] = format.into();
    header["encoder"] = encoder.into();
    header["ms"]["encode"] = ms(t).into();
    Ok((header, bytes))
}

fn round(v: f64) -> f64 {
    (v * 10.0).round() / 10.0
}

/// A view's camera as a link carries it.
fn camera_json(c: &glview::options::Camera) -> serde_json::Value {
    serde_json::json!({
        "yaw": c.yaw,
        "pitch": c.pitch,
        "distance": c.distance,
        "target": c.target,
        "fov": c.fov,
    })
}

/// How many of a list's names the page is told, and how many characters of each: the names
/// are the file author's, so a frame's header stays small whatever the file holds (K and V
/// still reach every camera and variant).
const MAX_NAMES: usize = 64;
const MAX_NAME_CHARS: usize = 80;

/// What the page's camera and variant pickers offer and show: the file's camera and variant
/// names (never a path) and the ones this picture is drawn with (none: the orbit camera, the
/// file's own materials). JSON escapes them; the page sets them as text, never as markup.
fn views_json(session: &mut Session, o: &glview::Options) -> glview::Result<serde_json::Value> {
    let views = &session.scene(o)?.views;
    Ok(views_of(views, o.camera.view.as_deref()))
}

/// [`views_json`] of the scene's `views`, looked at through `--camera` `camera`.
fn views_of(views: &glview::scene::model::views::Views, camera: Option<&str>) -> serde_json::Value {
    let names = |list: &mut dyn Iterator<Item = &str>| -> Vec<String> {
        list.take(MAX_NAMES)
            .map(|n| n.chars().take(MAX_NAME_CHARS).collect())
            .collect()
    };
    serde_json::json!({
        "cameras": names(&mut views.cameras.iter().map(|c| c.name.as_str())),
        "camera": camera.and_then(|q| views.camera_index(q).ok()),
        "variants": names(&mut views.variants.iter().map(String::as_str)),
        "variant": views.variant,
    })
}

/// What the page's play controls show: the file's animations (bounded as the views' names
/// are), the one shown or played, its time (null: the static pose) and whether it plays.
fn motion_json(view: &View, all: &[glview::scene::motion::AnimationInfo]) -> serde_json::Value {
    let animations: Vec<_> = all
        .iter()
        .take(MAX_NAMES)
        .map(|a| {
            serde_json::json!({
                "name": a.name.chars().take(MAX_NAME_CHARS).collect::<String>(),
                "duration": a.duration,
                "together": a.together,
            })
        })
        .collect();
    serde_json::json!({
        "animations": animations,
        "animation": view.animation_index(all).ok(),
        "time": view.options().motion.time,
        "playing": view.playing(),
        "fps": view.options().motion.fps,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A file's names reach the page bounded: 64 of each list, 80 characters (not bytes) of
    /// each; the indices are the drawn ones whatever the bound.
    #[test]
    fn views_are_bounded() {
        let mut views = glview::scene::model::views::Views {
            variants: (0..100)
                .map(|i| format!("{i}{}", "é".repeat(200)))
                .collect(),
            variant: Some(99),
            ..Default::default()
        };
        let v = views_of(&views, None);
        let names = v["variants"].as_array().unwrap();
        assert_eq!(names.len(), MAX_NAMES);
        assert!(names
            .iter()
            .all(|n| n.as_str().unwrap().chars().count() == MAX_NAME_CHARS));
        assert_eq!(
            (v["variant"].as_u64(), v["camera"].as_u64()),
            (Some(99), None)
        );
        assert_eq!(v["cameras"], serde_json::json!([]));
        views.variants.clear();
        views.variant = None;
        assert_eq!(
            views_of(&views, Some("0"))["camera"],
            serde_json::Value::Null
        );
    }
}
