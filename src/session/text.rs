//! A picture's PNG text: who drew it (renderer, context, dialect), the tier, the camera,
//! and what reproduces it (the options as JSON, a command line for people).
use crate::frame::FrameSettings;
use crate::options::Options;
use crate::scene::Scene;

/// Who drew a picture, for its PNG text chunks.
pub enum Drawer<'a> {
    Gpu {
        caps: &'a crate::gpu::Caps,
        backend: &'a str,
    },
    Reference,
}

/// What the picture's reproducing command line is made of (see [`crate::repro`]): the
/// options it was drawn from, `--keys` already replayed into them ([`super::View`]).
pub struct Repro<'a> {
    pub args: &'a Options,
    pub size: (u32, u32),
}

impl<'a> Repro<'a> {
    /// A headless picture: the options' own size.
    pub(crate) fn headless(args: &'a Options) -> Self {
        Repro {
            args,
            size: args.picture.size,
        }
    }
}

/// PNG text chunks that let anyone reproduce a picture: renderer, context, the camera (and
/// in the PBR tier the PBR options) as command-line options, `glview.options`, the options
/// as JSON, and `glview.command`, a whole command line that renders it again. Every option
/// word is the specs' ([`crate::options::OptionSpec::value_words`]), never spelled here.
pub fn png_text(
    r: Drawer,
    s: &FrameSettings,
    scene: &Scene,
    repro: &Repro,
) -> Vec<(&'static str, String)> {
    let drawer = match r {
        Drawer::Gpu { caps, backend } => gpu_text(caps, backend),
        Drawer::Reference => vec![(
            "glview.renderer",
            "reference (CPU ray casting, f64, exact shadows)".into(),
        )],
    };
    let mut shown = repro.args.clone();
    shown.picture.size = repro.size;
    PictureText::of(drawer, s, scene, shown).text()
}

fn gpu_text(caps: &crate::gpu::Caps, backend: &str) -> Vec<(&'static str, String)> {
    vec![
        ("glview.renderer", caps.renderer.clone()),
        ("glview.gl_version", caps.version.clone()),
        ("glview.dialect", caps.dialect.name().into()),
        ("glview.backend", backend.into()),
    ]
}

/// A picture's PNG text, not built yet: what it is made of, kept beside the picture so that
/// the options' JSON, the command line and the option groups' words are made only for a
/// picture that is written as PNG or asked for its text ([`PictureText::text`]), not for
/// every array, JPEG preview or JPEG batch line. [`png_text`] is the same text made at once.
#[derive(Clone, Debug)]
pub struct PictureText {
    /// Who drew it (renderer, context, dialect, backend; or the reference).
    drawer: Vec<(&'static str, String)>,
    camera: crate::camera::OrbitCamera,
    shading: crate::frame::Shading,
    origin: glam::DVec3,
    model: String,
    /// The options drawn (`--keys` replayed into them), at the picture's size.
    shown: Options,
}

impl PictureText {
    /// The text of a picture drawn by `caps`/`backend` with `s` of `scene` from `shown`:
    /// [`png_text`]'s, when [`PictureText::text`] is called.
    pub fn new(
        caps: &crate::gpu::Caps,
        backend: &str,
        s: &FrameSettings,
        scene: &Scene,
        shown: Options,
    ) -> PictureText {
        PictureText::of(gpu_text(caps, backend), s, scene, shown)
    }

    fn of(
        drawer: Vec<(&'static str, String)>,
        s: &FrameSettings,
        scene: &Scene,
        shown: Options,
    ) -> PictureText {
        PictureText {
            drawer,
            camera: s.camera,
            shading: s.shading,
            origin: scene.origin,
            model: scene.name.clone(),
            shown,
        }
    }

    /// The PNG text chunks, made now.
    pub fn text(&self) -> Vec<(&'static str, String)> {
        let mut text = vec![("Software", format!("glview {}", env!("CARGO_PKG_VERSION")))];
        text.extend(self.drawer.iter().cloned());
        let c = &self.camera;
        let target = self.origin + c.target.as_dvec3();
        let size = self.shown.picture.size;
        let shown = crate::repro::shown_options(&self.shown, c, target.to_array(), size);
        if self.shading == crate::frame::Shading::Pbr {
            text.push(("glview.pbr", group_words(&shown, "pbr", &[])));
        }
        text.extend([
            ("glview.tier", self.shading.tier().into()),
            ("glview.shading", self.shading.word().into()),
            ("glview.model", self.model.clone()),
        ]);
        // The shown options' keys are already replayed into them (none are left).
        text.push(("glview.camera", group_words(&shown, "camera", &["keys"])));
        text.extend(reproducing(&shown));
        text
    }
}

/// The PNG text of a teaching view drawn without a scene (`--show irradiance`, `specular`,
/// `lut`): what is shown and what draws it again (its options; no camera or model decides it).
pub(crate) fn map_view_text(args: &Options) -> Vec<(&'static str, String)> {
    let mut shown = args.clone();
    shown.camera = Default::default();
    shown.picture = crate::options::Picture {
        size: args.picture.size,
        ..Default::default()
    };
    let mut text = vec![
        ("Software", format!("glview {}", env!("CARGO_PKG_VERSION"))),
        ("glview.show", args.render.show.word().into()),
    ];
    text.extend(reproducing(&shown));
    text
}

/// `glview.options` (the JSON `--repro` reads) and `glview.command` (the same for people).
fn reproducing(shown: &Options) -> [(&'static str, String); 2] {
    [
        (
            "glview.options",
            serde_json::to_string(shown).unwrap_or_default(),
        ),
        ("glview.command", crate::repro::command_line(shown)),
    ]
}

/// The command-line words of one option group's values in `o`, defaults included (the text
/// states what the picture was drawn with), spelled by the options' own specs so every word
/// is one the command line takes; `except` names options left out.
fn group_words(o: &Options, group: &str, except: &[&str]) -> String {
    let words: Vec<String> = crate::options::specs()
        .iter()
        .filter(|s| s.group() == group && !except.contains(&s.name))
        .flat_map(|s| s.value_words(o))
        .map(|w| crate::repro::quote(&w))
        .collect();
    words.join(" ")
}
