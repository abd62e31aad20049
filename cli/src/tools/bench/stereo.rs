//! `glview bench --stereo`: a stereo frame against a mono frame of the same output size, on
//! the built-in scene and the dragon (when present) at 1280×720 — the window's path (the
//! renderer's frame to glFinish, as the window draws before its swap) and the server's
//! (`Session::draw`: the frame plus its read-back, as a viewer's still is made before its
//! encode). Mono and stereo frames are drawn in turn (15 each after a warm-up) so a busy
//! machine slows both alike; medians. The shadow and environment maps are kept between
//! frames in both, as in a window or a server. Also what a half-height eye
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
        "mono ms",
        "window ms",
        "vs mono",
        "server ms",
        "vs mono",
    ]);
    for (name, mut args) in scenes {
        args.picture.size = (w, h);
        let scene = glview::session::load_scene(&args)?;
        for mode in MODES {
            let mut stereo = args.clone();
            stereo.stereo.mode = mode;
            // Against a mono frame of the same output size (side-by-side-full's is twice as wide).
            let (ow, oh) = glview::stereo::output_size(mode, (w, h));
            let mut mono = args.clone();
            mono.picture.size = (ow, oh);
            let (m, s) = window_ms(&mono, &stereo, &scene)?;
            let (ms, ss) = server_ms(&mono, &stereo)?;
            table.row(vec![
                name.into(),
                mode.word().into(),
                format!("{ow}x{oh}"),
                num(m, 1),
                num(s, 1),
                format!("{:.2}x", s / m),
                num(ss, 1),
                format!("{:.2}x", ss / ms),
            ]);
        }
        // What one eye at half height costs (rows drawing each eye at half size would pay
        // this twice instead of a full eye twice).
        let mut half = args.clone();
        half.picture.size = (w, h / 2);
        let (full, halved) = window_ms(&args, &half, &scene)?;
        table.row(vec![
            name.into(),
            "mono at half height".into(),
            format!("{w}x{}", h / 2),
            num(full, 1),
            num(halved, 1),
            format!("{:.2}x", halved / full),
            String::new(),
            String::new(),
        ]);
    }
    println!("{}", table.render());
    Ok(())
}

/// Frames of `a` and `b` drawn in turn, 15 of each after a warm-up, on one context (so a
/// busy machine slows both alike): the medians, to glFinish (the window's path).
fn window_ms(a: &Options, b: &Options, scene: &glview::scene::Scene) -> Result<(f64, f64)> {
    let size = |o: &Options| glview::view::settings::output_size(o);
    let (w, h) = (size(a).0.max(size(b).0), size(a).1.max(size(b).1));
    let hl = Headless::new(Backend::Auto, GlRequest::Auto, w, h)?;
    let mut r = Renderer::new(&hl.gpu, scene.clone())?;
    let mut sets = Vec::new();
    for o in [a, b] {
        let (s, _) = glview::session::frame_settings(o, scene)?;
        let (ow, oh) = size(o);
        r.render_viewport(&s, &hl.target(), [0, 0, ow, oh])?;
        sets.push((s, [0, 0, ow, oh]));
    }
    let (mut ta, mut tb) = (Vec::new(), Vec::new());
    for _ in 0..15 {
        for (i, (s, rect)) in sets.iter().enumerate() {
            let ms = r.render_viewport(s, &hl.target(), *rect)?.ms;
            if i == 0 {
                ta.push(ms)
            } else {
                tb.push(ms)
            }
        }
    }
    Ok((median(&ta), median(&tb)))
}

/// `Session::draw` of `a` and `b` in turn (frame and read-back: the server's still before
/// its encode), 15 of each after a warm-up: the medians.
fn server_ms(a: &Options, b: &Options) -> Result<(f64, f64)> {
    let mut session = glview::session::Session::new();
    let mut profile = glview::session::Profile::default();
    for o in [a, b] {
        session.draw(o, None, Default::default(), &mut profile)?;
    }
    let (mut ta, mut tb) = (Vec::new(), Vec::new());
    for _ in 0..15 {
        for (i, o) in [a, b].into_iter().enumerate() {
            let t = Instant::now();
            session.draw(o, None, Default::default(), &mut profile)?;
            let ms = t.elapsed().as_secs_f64() * 1e3;
            if i == 0 {
                ta.push(ms)
            } else {
                tb.push(ms)
            }
        }
    }
    Ok((median(&ta), median(&tb)))
}
