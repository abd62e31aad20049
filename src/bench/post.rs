//! `glview bench --post`: anti-aliasing modes against a 4×4 supersampled render of the same
//! frame, and bloom chain depth against the full-resolution blur (levels 0), as frame time
//! against error on the built-in scene at 640×480 (medians of 7 frames after a warm-up).
use super::median;
use super::metrics::{compare, downsample};
use super::table::{num, Table};
use crate::cli::Args;
use crate::headless::Headless;
use crate::image_out::Rgba;
use crate::platform::{Backend, GlRequest};
use crate::render::Renderer;
use crate::{Error, Result};
use clap::Parser;

const W: u32 = 640;
const H: u32 = 480;

/// Renders the built-in scene with `extra` options; `ssaa` k renders k× larger and filters
/// down; `msaa` n draws into an n-sample target. Returns the image and the median frame ms.
fn frame(extra: &[&str], ssaa: u32, msaa: u32) -> Result<(Rgba, f64)> {
    let mut argv = vec!["glview".to_string(), "--size".into(), format!("{W}x{H}")];
    argv.extend(extra.iter().map(|s| s.to_string()));
    let args = Args::try_parse_from(&argv).map_err(|e| Error::Usage(e.to_string()))?;
    let scene = crate::run::load_scene(&args)?;
    let (s, _) = crate::run::frame_settings(&args, &scene)?;
    let mut hl = Headless::new(Backend::Auto, GlRequest::Auto, W * ssaa, H * ssaa)?;
    if msaa > 0 {
        hl.enable_msaa(msaa)?;
    }
    let mut r = Renderer::new(&hl.gpu, scene)?;
    r.render(&s, &hl.target())?;
    let times: Vec<f64> = (0..7)
        .map(|_| r.render(&s, &hl.target()).map(|st| st.ms))
        .collect::<Result<_>>()?;
    let img = downsample(&hl.read(), ssaa);
    Ok((img, median(&times)))
}

pub fn run_post() -> Result<()> {
    eprintln!("bench --post: the 4×4 supersampled reference ...");
    let (reference, ref_ms) =
        frame(&[], 4, 0).map_err(|e| Error::Usage(format!("reference: {e}")))?;
    let mut t = Table::new(&[
        "anti-aliasing",
        "frame ms",
        "mean /255",
        "> 8/255 %",
        "1 - SSIM",
    ]);
    for (label, extra, ssaa, msaa) in [
        ("none", vec![], 1, 0),
        ("fxaa", vec!["--aa", "fxaa"], 1, 0),
        ("msaa 2", vec![], 1, 2),
        ("msaa 4", vec![], 1, 4),
        ("ssaa 2x2", vec![], 2, 0),
        ("ssaa 3x3", vec![], 3, 0),
    ] {
        let (img, ms) = frame(&extra, ssaa, msaa)?;
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
    let bloom = [
        "--shading",
        "pbr",
        "--bloom",
        "0.3",
        "--bloom-threshold",
        "0.6",
        "--bloom-sigma",
        "12",
    ];
    let with = |levels: &str| {
        let mut v = bloom.to_vec();
        v.extend_from_slice(&["--bloom-levels", levels]);
        frame(&v, 1, 0)
    };
    let (exact, exact_ms) = with("0")?;
    let (_, plain_ms) = frame(&["--shading", "pbr"], 1, 0)?;
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
    for levels in ["1", "2", "3", "4"] {
        let (img, ms) = with(levels)?;
        let e = compare(&img, &exact, &[])?;
        b.row(vec![
            levels.into(),
            num(ms, 1),
            num(ms - plain_ms, 1),
            num(e.mae, 3),
            num(e.wrong * 100.0, 3),
        ]);
    }
    println!("{}", b.render());
    Ok(())
}
