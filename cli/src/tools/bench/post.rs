//! `glview bench --post`: anti-aliasing modes against a 4×4 supersampled render of the same
//! frame, and bloom chain depth against the full-resolution blur (levels 0), as frame time
//! against error on the built-in scene at 640×480 (medians of 7 frames after a warm-up).
use super::median;
use super::metrics::{compare, downsample};
use super::table::{num, Table};
use glview::frame::Shading;
use glview::headless::Headless;
use glview::image_out::Rgba;
use glview::options::Options;
use glview::platform::{Backend, GlRequest};
use glview::render::Renderer;
use glview::{Error, Result};

const W: u32 = 640;
const H: u32 = 480;

/// The built-in scene at W×H with the defaults.
fn base() -> Options {
    {
        let mut o: Options = Options::default();
        o.picture.size = (W, H);
        o
    }
}

/// The PBR tier with bloom (`levels` 0: the exact full-resolution blur).
fn bloom(levels: u32) -> Options {
    {
        let mut o: Options = base();
        o.render.shading = Shading::Pbr;
        o.post.bloom = 0.3;
        o.post.bloom_threshold = 0.6;
        o.post.bloom_sigma = 12.0;
        o.post.bloom_levels = levels;
        o
    }
}

/// Renders the built-in scene with `args`; `ssaa` k renders k× larger and filters
/// down; `msaa` n draws into an n-sample target. Returns the image and the median frame ms.
fn frame(args: &Options, ssaa: u32, msaa: u32) -> Result<(Rgba, f64)> {
    let scene = glview::session::load_scene(args)?;
    let (s, _) = glview::session::frame_settings(args, &scene)?;
    let mut hl = Headless::new(Backend::Auto, GlRequest::Auto, W * ssaa, H * ssaa)?;
    if msaa > 0 {
        hl.enable_msaa(msaa)?;
    }
    let mut r = Renderer::new(&hl.gpu, scene)?;
    r.render(&s, &hl.target())?;
    let times: Vec<f64> = (0..7)
        .map(|_| r.render(&s, &hl.target()).map(|st| st.ms))
        .collect::<Result<_>>()?;
    let img = downsample(hl.read(), ssaa);
    Ok((img, median(&times)))
}

pub fn run_post() -> Result<()> {
    eprintln!("bench --post: the 4×4 supersampled reference ...");
    let (reference, ref_ms) =
        frame(&base(), 4, 0).map_err(|e| Error::Usage(format!("reference: {e}")))?;
    let mut t = Table::new(&[
        "anti-aliasing",
        "frame ms",
        "mean /255",
        "> 8/255 %",
        "1 - SSIM",
    ]);
    let fxaa = {
        let mut o: Options = base();
        o.post.aa = glview::options::AaMode::Fxaa;
        o
    };
    for (label, args, ssaa, msaa) in [
        ("none", base(), 1, 0),
        ("fxaa", fxaa, 1, 0),
        ("msaa 2", base(), 1, 2),
        ("msaa 4", base(), 1, 4),
        ("ssaa 2x2", base(), 2, 0),
        ("ssaa 3x3", base(), 3, 0),
    ] {
        let (img, ms) = frame(&args, ssaa, msaa)?;
        let e = compare(&img, &reference, &[])?;
        t.row(vec![
            label.into(),
            num(ms, 1),
            num(e.mae, 3),
            num(e.wrong * 100.0, 3),
            num(1.0 - e.ssim, 5),
        ]);
    }
    t.row(vec![
        "ssaa 4x4 (reference)".into(),
        num(ref_ms, 1),
        "0".into(),
        "0".into(),
        "0".into(),
    ]);
    println!("{}", t.render());
    eprintln!("bench --post: bloom chain depth against the full-resolution blur ...");
    let with = |levels: u32| frame(&bloom(levels), 1, 0);
    let (exact, exact_ms) = with(0)?;
    let pbr = {
        let mut o: Options = base();
        o.render.shading = Shading::Pbr;
        o
    };
    let (_, plain_ms) = frame(&pbr, 1, 0)?;
    let mut b = Table::new(&[
        "bloom levels",
        "frame ms",
        "cost ms",
        "mean /255",
        "> 8/255 %",
    ]);
    b.row(vec![
        "0 (exact)".into(),
        num(exact_ms, 1),
        num(exact_ms - plain_ms, 1),
        "0".into(),
        "0".into(),
    ]);
    for levels in 1..=4 {
        let (img, ms) = with(levels)?;
        let e = compare(&img, &exact, &[])?;
        b.row(vec![
            levels.to_string(),
            num(ms, 1),
            num(ms - plain_ms, 1),
            num(e.mae, 3),
            num(e.wrong * 100.0, 3),
        ]);
    }
    println!("{}", b.render());
    Ok(())
}
