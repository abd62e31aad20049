//! `glview sheet MODEL --views N --tiers phong,pbr -o sheet.png`: a labelled grid of turntable
//! views (columns) by tiers (rows), for a coursework report. One context and one upload for
//! the whole sheet; a progress bar on a terminal.
use super::{canvas, PaneTier};
use crate::cli::SheetCommand;
use crate::frame::FrameSettings;
use crate::headless::Headless;
use crate::options::Options;
use crate::render::Renderer;
use crate::{Error, Result};

/// The (yaw, pitch) of each column: `--angles` as given, else N views around the model at the
/// command line's pitch.
pub fn angles(cmd: &SheetCommand, pitch: f32) -> Result<Vec<(f32, f32)>> {
    if let Some(list) = &cmd.angles {
        return list
            .split(',')
            .map(|pair| {
                let (y, p) = pair
                    .split_once(':')
                    .ok_or_else(|| Error::Usage(format!("--angles: {pair:?} is not YAW:PITCH")))?;
                let num = |s: &str| {
                    s.trim()
                        .parse::<f32>()
                        .ok()
                        .filter(|v| v.is_finite())
                        .ok_or_else(|| Error::Usage(format!("--angles: {s:?} is not a number")))
                };
                Ok((num(y)?, num(p)?))
            })
            .collect();
    }
    if cmd.views == 0 || cmd.views > 64 {
        return Err(Error::Usage("--views must be 1 to 64".into()));
    }
    Ok((0..cmd.views)
        .map(|i| (360.0 * i as f32 / cmd.views as f32, pitch))
        .collect())
}

pub fn run(cmd: &SheetCommand) -> Result<()> {
    let (sheet, text, summary) = sheet_image(cmd)?;
    sheet.save_png(&cmd.output, &text)?;
    eprintln!("sheet: {summary} written to {}", cmd.output.display());
    Ok(())
}

/// The sheet, its PNG text and a one-line summary, without writing it (the library and
/// Python).
pub fn sheet_image(
    cmd: &SheetCommand,
) -> Result<(crate::image_out::Rgba, crate::image_out::PngText, String)> {
    // The words after `--` are the user's: they go through the options' own parser (its
    // checks and messages); the sheet's model and size are set on the result.
    let mut args = Options::from_words(cmd.view_options.iter().cloned())?;
    if cmd.model.is_some() {
        args.load.model.clone_from(&cmd.model);
    }
    args.picture.size = cmd.size;
    let tiers = super::parse_tiers(&cmd.tiers, "--tiers")?;
    let views = angles(cmd, args.camera.pitch)?;
    let scene = crate::run::load_scene(&args)?;
    let (base, _) = crate::run::frame_settings(&args, &scene)?;
    let (w, h) = args.picture.size;
    let (cols, rows) = (views.len() as u32, tiers.len() as u32);
    let label =
        |tier: &PaneTier, yaw: f32, pitch: f32| format!("{} yaw {yaw} pitch {pitch}", tier.name());
    let labels: Vec<String> = tiers
        .iter()
        .flat_map(|t| views.iter().map(move |(y, p)| label(t, *y, *p)))
        .collect();
    let strip = canvas::strip_height(w, &labels.iter().map(String::as_str).collect::<Vec<_>>());
    let cell_h = h + strip;
    let mut sheet = canvas::blank(w * cols, cell_h * rows, [24, 24, 28]);
    let hl = Headless::new(args.context.backend, args.context.gl, w, h)?;
    let mut renderer = Renderer::new(&hl.gpu, scene.clone())?;
    renderer.set_environment(crate::run::env_request(&args)?);
    let bar = indicatif::ProgressBar::new(u64::from(cols * rows));
    if let Ok(style) = indicatif::ProgressStyle::with_template("sheet [{bar:30}] {pos}/{len} {msg}")
    {
        bar.set_style(style);
    }
    for (r, tier) in tiers.iter().enumerate() {
        for (c, (yaw, pitch)) in views.iter().enumerate() {
            let mut s: FrameSettings = base.clone();
            s.camera.yaw_deg = *yaw;
            s.camera.pitch_deg = *pitch;
            let img = match tier {
                PaneTier::Gpu(shading) => {
                    s.shading = *shading;
                    renderer.render(&s, &hl.target())?;
                    hl.read()
                }
                PaneTier::Reference(shading) => {
                    s.shading = *shading;
                    let env = crate::run::reference_env(&args, *shading)?;
                    crate::reference::render_env(&scene, &s, env.as_ref(), w, h)
                }
            };
            let (x, y) = (c as u32 * w, r as u32 * cell_h);
            let text = label(tier, *yaw, *pitch);
            canvas::paste(&mut sheet, &canvas::strip_sized(w, strip, &text), x, y);
            canvas::paste(&mut sheet, &img, x, y + strip);
            bar.inc(1);
        }
    }
    bar.finish_and_clear();
    let text = vec![
        ("Software", format!("glview {}", env!("CARGO_PKG_VERSION"))),
        (
            "glview.sheet",
            format!("tiers {} views {:?}", cmd.tiers, views),
        ),
        ("glview.model", scene.name.clone()),
    ];
    let summary = format!("{rows} x {cols} views of {}", scene.name);
    Ok((sheet, text, summary))
}
