//! What reproduces a picture, for its PNG text: the options it was drawn with (`--keys`
//! replayed into them), the camera and size of the moment in place of the ones given (a
//! window's view has moved since start-up), as JSON (`glview.options`, read back by `glview --repro FILE.png`) and
//! as a command line for people (`glview.command`).
use crate::camera::OrbitCamera;
use crate::options::{Camera, Load, Options, Ortho, Picture};

/// The options without the camera and the picture group (size, frames, stats): what
/// [`shown_options`] fills in with the moment's camera and size.
fn scene_part(args: &Options) -> Options {
    let mut o = args.clone();
    o.camera = Camera::default();
    o.picture = Picture::default();
    o
}

/// What decides the uploaded scene of a picture: the load options (with the x-ray opacity
/// they bake in), the name of a scene given in memory (the library API's models), and the
/// model file's size and time (so a file changed between two pictures is read again). Equal
/// keys share a GPU scene: the camera, tier, lights, environment, exposure,
/// post-processing and size are the view's and upload nothing.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct SceneKey {
    given: Option<String>,
    load: Load,
    xray_opacity: Option<Option<f32>>,
    stamp: Stamp,
}

/// The model file's size and modification time (`None` without a model or a readable file).
pub(crate) type Stamp = Option<(u64, Option<std::time::SystemTime>)>;

/// One `stat` of the model file: kept per picture (a few µs) because it is what sees a file
/// rewritten between two pictures of one session.
pub(crate) fn stamp(args: &Options) -> Stamp {
    let m = std::fs::metadata(args.load.model.as_ref()?).ok()?;
    Some((m.len(), m.modified().ok()))
}

fn xray_opacity(args: &Options) -> Option<Option<f32>> {
    (!args.load.xray.is_empty()).then_some(args.render.opacity)
}

impl SceneKey {
    /// The key of the scene `args` draws (`given`: the caller's name of an in-memory scene).
    pub(crate) fn new(args: &Options, given: Option<&str>, stamp: Stamp) -> SceneKey {
        SceneKey {
            given: given.map(str::to_string),
            load: args.load.clone(),
            xray_opacity: xray_opacity(args),
            stamp,
        }
    }

    /// Whether a picture of `args` draws this scene: the typed options compared in place
    /// (nothing serialised or cloned per picture).
    pub(crate) fn matches(&self, args: &Options, given: Option<&str>, stamp: &Stamp) -> bool {
        self.given.as_deref() == given
            && self.load == args.load
            && self.xray_opacity == xray_opacity(args)
            && self.stamp == *stamp
    }
}

/// The options that draw this picture again: `args` (their `--keys` already replayed into
/// them) with the camera as it is (`target` in the file's coordinates) and this size.
pub(crate) fn shown_options(
    args: &Options,
    camera: &OrbitCamera,
    target: [f64; 3],
    size: (u32, u32),
) -> Options {
    let mut o = scene_part(args);
    o.picture.size = size;
    let c = &mut o.camera;
    c.yaw = camera.yaw_deg;
    c.pitch = camera.pitch_deg;
    c.distance = Some(camera.distance);
    c.target = Some(target);
    c.fov = camera.fov_y_deg;
    c.ortho = camera.ortho_height.map(Ortho::Height);
    c.near = camera.near;
    c.keys = None;
    o
}

/// `glview WORDS...`, shell-quoted.
pub fn command_line(o: &Options) -> String {
    let words: Vec<String> = std::iter::once("glview".to_string())
        .chain(o.to_words())
        .map(|w| quote(&w))
        .collect();
    words.join(" ")
}

/// A word as a POSIX shell reads it back: as it is when it has only safe characters, else
/// in single quotes (a `'` inside closes, escapes and reopens them).
pub(crate) fn quote(w: &str) -> String {
    let safe = |c: char| c.is_ascii_alphanumeric() || "-_.,:/=+@%^".contains(c);
    if !w.is_empty() && w.chars().all(safe) {
        w.to_string()
    } else {
        format!("'{}'", w.replace('\'', "'\\''"))
    }
}

/// The options a PNG of glview's was drawn with (its `glview.options` text).
pub fn options_of_png(path: &std::path::Path) -> crate::Result<Options> {
    let text = crate::image_out::png_text(path)?;
    let json = text
        .iter()
        .find(|(k, _)| k == "glview.options")
        .map(|(_, v)| v)
        .ok_or_else(|| {
            crate::Error::Usage(format!(
                "{}: no glview.options text (not drawn by glview, or by a glview before 0.2)",
                path.display()
            ))
        })?;
    Options::from_json(json).map_err(|e| {
        crate::Error::Usage(format!(
            "{}: glview.options: {}",
            path.display(),
            e.as_keyword()
        ))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_scene_key_ignores_the_camera_and_the_command_keeps_the_rest() {
        let a = Options::from_words([
            "my model.obj",
            "--yaw=10",
            "--ortho",
            "--light",
            "dir:0,-1,0",
            "--stats",
            "--shadow-bias",
            "0.001",
            "--fov",
            "50",
            "--keys",
            "Left S",
        ])
        .unwrap();
        let b = Options::from_words([
            "my model.obj",
            "--light",
            "dir:0,-1,0",
            "--shadow-bias",
            "0.001",
        ])
        .unwrap();
        let key = SceneKey::new(&a, None, stamp(&a));
        assert!(key.matches(&b, None, &stamp(&b)));
        assert!(!key.matches(&b, Some("arrays"), &stamp(&b)));
        let mut c = b.clone();
        c.load.flat = true;
        assert!(!key.matches(&c, None, &stamp(&c)));
        let b = crate::scene::Bounds {
            min: glam::Vec3::splat(-1.0),
            max: glam::Vec3::splat(1.0),
        };
        let cam = OrbitCamera::fit(&b, 45.0, 1.0);
        let shown = shown_options(&a, &cam, [1.0, 2.0, 3.0], (64, 48));
        let line = command_line(&shown);
        assert!(
            line.starts_with("glview 'my model.obj' --yaw ")
                && !line.contains("--keys")
                && line.contains("--light dir:0,-1,0 ")
                && line.contains("--shadow-bias 0.001 ")
                && line.contains("--size 64x48")
                && !line.contains("--stats"),
            "{line}"
        );
        assert_eq!(quote("it's"), "'it'\\''s'");
        assert_eq!(quote(""), "''");
        let again = Options::from_json(&serde_json::to_string(&shown).unwrap()).unwrap();
        assert_eq!(again, shown);
    }
}
