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
    pub fn headless(args: &'a Options) -> Self {
        Repro {
            args,
            size: args.picture.size,
        }
    }
}

/// PNG text chunks that let anyone reproduce a picture: renderer, context, the camera as
/// command-line options and `glview.command`, a whole command line that renders it again.
pub fn png_text(
    r: Drawer,
    s: &FrameSettings,
    scene: &Scene,
    repro: &Repro,
) -> Vec<(&'static str, String)> {
    let mut text = vec![("Software", format!("glview {}", env!("CARGO_PKG_VERSION")))];
    match r {
        Drawer::Gpu { caps, backend } => text.extend([
            ("glview.renderer", caps.renderer.clone()),
            ("glview.gl_version", caps.version.clone()),
            ("glview.dialect", caps.dialect.name().into()),
            ("glview.backend", backend.into()),
        ]),
        Drawer::Reference => text.push((
            "glview.renderer",
            "reference (CPU ray casting, f64, exact shadows)".into(),
        )),
    }
    let c = &s.camera;
    let target = scene.origin + c.target.as_dvec3();
    let p = &s.lighting.pbr;
    let o = &s.lighting.output;
    if s.shading == crate::frame::Shading::Pbr {
        text.push((
            "glview.pbr",
            format!(
                "--exposure {} --tonemap {}{}{}{}{}{}",
                o.exposure_ev,
                format!("{:?}", o.tonemap).to_lowercase(),
                p.metallic
                    .map(|m| format!(" --metallic {m}"))
                    .unwrap_or_default(),
                p.roughness
                    .map(|r| format!(" --roughness {r}"))
                    .unwrap_or_default(),
                p.base_color
                    .map(|c| format!(" --base-color {},{},{}", c.x, c.y, c.z))
                    .unwrap_or_default(),
                if p.dominant_direction {
                    " --dominant-direction"
                } else {
                    ""
                },
                if p.multiscatter {
                    " --multiscatter"
                } else {
                    ""
                },
            ),
        ));
    }
    text.extend([
        ("glview.tier", s.shading.tier().into()),
        ("glview.shading", format!("{:?}", s.shading).to_lowercase()),
        ("glview.model", scene.name.clone()),
    ]);
    let camera = format!(
        "--yaw {} --pitch {} --distance {} --target {},{},{} --fov {}{}{}",
        c.yaw_deg,
        c.pitch_deg,
        c.distance,
        target.x,
        target.y,
        target.z,
        c.fov_y_deg,
        c.ortho_height
            .map(|h| format!(" --ortho {h}"))
            .unwrap_or_default(),
        c.near.map(|n| format!(" --near {n}")).unwrap_or_default()
    );
    let shown = crate::repro::shown_options(repro.args, c, target.to_array(), repro.size);
    let command = crate::repro::command_line(&shown);
    text.push(("glview.camera", camera));
    text.push((
        "glview.options",
        serde_json::to_string(&shown).unwrap_or_default(),
    ));
    text.push(("glview.command", command));
    text
}
