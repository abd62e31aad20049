//! `glview bench --translucency`: the cost of nearest-layer translucency against sorted and
//! against drawing everything opaque, with and without logarithmic depth, on the built-in
//! scene and on the dragon with every surface x-rayed; 1280×720, shadow maps reused, median
//! of 10 frames after one warm-up. Prints a table.
use super::median;
use super::table::{num, Table};
use glview::frame::TranslucencyMode;
use glview::headless::Headless;
use glview::options::Options;
use glview::platform::{Backend, GlRequest};
use glview::render::Renderer;
use glview::Result;
use std::path::Path;

pub fn run_translucency(models_dir: &Path) -> Result<()> {
    let (w, h) = (1280, 720);
    let hl = Headless::new(Backend::Auto, GlRequest::Auto, w, h)?;
    let dragon = models_dir.join("dragon-200k/dragon_vrip_res2.obj");
    let builtin = {
        let mut o: Options = Options::default();
        o.picture.size = (w, h);
        o
    };
    let mut scenes = vec![("built-in", builtin.clone())];
    if dragon.is_file() {
        let xrayed = {
            let mut o: Options = builtin;
            o.load.model = Some(dragon);
            o.load.xray = vec!["default".into()];
            o
        };
        scenes.push(("dragon 202k, x-rayed", xrayed));
    }
    let mut table = Table::new(&["scene", "mode", "depth", "frame ms", "vs opaque"]);
    for (name, args) in scenes {
        let scene = glview::session::load_scene(&args)?;
        let (base, _) = glview::session::frame_settings(&args, &scene)?;
        let mut opaque_scene = scene.clone();
        for m in &mut opaque_scene.materials {
            m.opacity = None;
        }
        let mut opaque_ms = f64::NAN;
        for (mode, log) in [
            (None, false),
            (Some(TranslucencyMode::Sorted), false),
            (Some(TranslucencyMode::Nearest), false),
            (None, true),
            (Some(TranslucencyMode::Nearest), true),
        ] {
            let mut s = base.clone();
            s.lighting.translucency.log_depth = log;
            if let Some(m) = mode {
                s.lighting.translucency.mode = m;
            }
            let sc = if mode.is_some() {
                scene.clone()
            } else {
                opaque_scene.clone()
            };
            let mut r = Renderer::new(&hl.gpu, sc)?;
            r.render(&s, &hl.target())?;
            let times: Vec<f64> = (0..10)
                .map(|_| r.render(&s, &hl.target()).map(|st| st.ms))
                .collect::<Result<_>>()?;
            let ms = median(&times);
            if mode.is_none() && !log {
                opaque_ms = ms;
            }
            let mode_name = mode.map_or("opaque", |m| m.word()).to_string();
            table.row(vec![
                name.to_string(),
                mode_name,
                if log { "log" } else { "standard" }.into(),
                num(ms, 1),
                format!("{:.2}x", ms / opaque_ms),
            ]);
        }
    }
    println!("{}", table.render());
    Ok(())
}
