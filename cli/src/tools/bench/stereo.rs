//! `glview bench --stereo`: a stereo frame against a mono frame of the same output size, on
//! the built-in scene and the dragon (when present) at 1280×720 — the window's path (the
//! renderer's frame to glFinish, as the window draws before its swap) and the server's
//! (`Session::draw`: the frame plus its read-back, as a viewer's still is made before its
//! encode). Medians of 10 frames after one warm-up; the shadow and environment maps are
//! kept between frames in both, as in a window or a server. Also what a half-height eye
//! costs (the rows mode drawing each eye at half size would pay that instead).
use super::median;
use super::table::{num, Table};
use glview::headless::Headless;
use glview::options::Options;
use glview::platform::{Backend, GlRequest};
use glview::render::Renderer;
use glview::stereo::StereoMode;
use glview::Result;
use std::path::Path;
use std::time::Instant;

const MODES: [StereoMode; 7] = [
    StereoMode::Anaglyph,
    StereoMode::SideBySideFull,
    StereoMode::SideBySide,
    StereoMode::OverUnder,
    StereoMode::Rows,
    StereoMode::Columns,
    StereoMode::Checkerboard,
];

pub fn run_stereo(models_dir: &Path) -> Result<()> {
    let (w, h) = (1280, 720);
    let mut scenes = vec![("built-in", Options::default())];
    let dragon = models_dir.join("dragon-200k/dragon_vrip_res2.obj");
    if dragon.is_file() {
        let mut o = Options::default();
        o.load.model = Some(dragon);
        scenes.push(("dragon 202k", o));
    }
    let mut table = Table::new(&[
        "scene",
        "mode",
        "output",
        "window ms",
        "vs mono",
        "server ms",
        "vs mono",
    ]);
    for (name, mut args) in scenes {
        args.picture.size = (w, h);
        let scene = glview::session::load_scene(&args)?;
        let mono_window = window_ms(&args, &scene, None)?;
        let mono_server = server_ms(&args)?;
        let mono_size = |m| glview::stereo::output_size(m, (w, h));
        table.row(vec![
            name.into(),
            "mono".into(),
            format!("{w}x{h}"),
            num(mono_window, 1),
            "1.00x".into(),
            num(mono_server, 1),
            "1.00x".into(),
        ]);
        for mode in MODES {
            let mut o = args.clone();
            o.stereo.mode = mode;
            // Against a mono frame of the same output size (side-by-side-full's is twice as wide).
            let (ow, oh) = mono_size(mode);
            let (base_w, base_s) = if (ow, oh) == (w, h) {
                (mono_window, mono_server)
            } else {
                let mut m = args.clone();
                m.picture.size = (ow, oh);
                (window_ms(&m, &scene, None)?, server_ms(&m)?)
            };
            let win = window_ms(&o, &scene, None)?;
            let srv = server_ms(&o)?;
            table.row(vec![
                name.into(),
                mode.word().into(),
                format!("{ow}x{oh}"),
                num(win, 1),
                format!("{:.2}x", win / base_w),
                num(srv, 1),
                format!("{:.2}x", srv / base_s),
            ]);
        }
        let half = window_ms(&args, &scene, Some((w, h / 2)))?;
        table.row(vec![
            name.into(),
            "one eye at half height".into(),
            format!("{w}x{}", h / 2),
            num(half, 1),
            format!("{:.2}x", half / mono_window),
            String::new(),
            String::new(),
        ]);
    }
    println!("{}", table.render());
    Ok(())
}

/// The renderer's frame to glFinish (the window's path), median of 10; `viewport` draws a
/// smaller rectangle of the target instead of all of it.
fn window_ms(
    args: &Options,
    scene: &glview::scene::Scene,
    viewport: Option<(u32, u32)>,
) -> Result<f64> {
    let (w, h) = glview::view::settings::output_size(args);
    let hl = Headless::new(Backend::Auto, GlRequest::Auto, w, h)?;
    let (s, _) = glview::session::frame_settings(args, scene)?;
    let mut r = Renderer::new(&hl.gpu, scene.clone())?;
    let rect = viewport.map_or([0, 0, w, h], |(vw, vh)| [0, 0, vw, vh]);
    r.render_viewport(&s, &hl.target(), rect)?;
    let times: Vec<f64> = (0..10)
        .map(|_| r.render_viewport(&s, &hl.target(), rect).map(|st| st.ms))
        .collect::<Result<_>>()?;
    Ok(median(&times))
}

/// `Session::draw` (frame and read-back: the server's still before its encode), median of 10.
fn server_ms(args: &Options) -> Result<f64> {
    let mut session = glview::session::Session::new();
    let mut profile = glview::session::Profile::default();
    session.draw(args, None, Default::default(), &mut profile)?;
    let times: Vec<f64> = (0..10)
        .map(|_| {
            let t = Instant::now();
            session
                .draw(args, None, Default::default(), &mut profile)
                .map(|_| t.elapsed().as_secs_f64() * 1e3)
        })
        .collect::<Result<_>>()?;
    Ok(median(&times))
}
