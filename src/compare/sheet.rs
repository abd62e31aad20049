//! `glview sheet MODEL --views N --tiers phong,pbr -o sheet.png`: a labelled grid of turntable
//! views (columns) by tiers (rows), for a coursework report. One context and one upload for
//! the whole sheet; its progress goes to the installed reporter.
use super::{canvas, PaneTier};
use crate::frame::FrameSettings;
use crate::options::Options;
use crate::{Error, Result};

/// A contact sheet's layout: which views (columns) of which tiers (rows), each cell `size`.
#[derive(Clone, Debug)]
pub struct Sheet {
    /// The picture options every cell starts from (model, lights, PBR settings, ...).
    pub options: Options,
    /// Number of turntable views (yaw 0, 360/N, ...).
    pub views: u32,
    /// Explicit views instead: YAW:PITCH,YAW:PITCH,...
    pub angles: Option<String>,
    /// Rows: tiers (phong, gouraud, pbr, reference, reference-pbr).
    pub tiers: String,
    /// Size of each cell.
    pub size: (u32, u32),
}

/// The (yaw, pitch) of each column: `--angles` as given, else N views around the model at the
/// command line's pitch.
pub(crate) fn angles(cmd: &Sheet, pitch: f32) -> Result<Vec<(f32, f32)>> {
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

/// The sheet, its PNG text and a one-line summary, without writing it (the library and
/// Python).
pub fn sheet_image(
    cmd: &Sheet,
) -> Result<(crate::image_out::Rgba, crate::image_out::PngText, String)> {
    let mut args = cmd.options.clone();
    args.picture.size = cmd.size;
    let tiers = super::parse_tiers(&cmd.tiers, "--tiers")?;
    let views = angles(cmd, args.camera.pitch)?;
    let (mut scene, clusters) = crate::session::load_scene_prepared(&args)?;
    crate::session::pose_scene(&args, &mut scene)?;
    let (base, _) = crate::session::frame_settings(&args, &scene)?;
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
    let bar = crate::progress::start(
        "sheet",
        u64::from(cols * rows),
        crate::progress::Unit::Items,
    );
    let mut done = 0;
    let mut session = crate::session::Session::new();
    session.with_scene(&args, scene.clone(), clusters, (w, h), |hl, renderer| {
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
                        let env = crate::session::reference_env(&args, *shading)?;
                        crate::reference::render_env(&scene, &s, env.as_ref(), w, h)
                    }
                };
                let (x, y) = (c as u32 * w, r as u32 * cell_h);
                let text = label(tier, *yaw, *pitch);
                canvas::paste(&mut sheet, &canvas::strip_sized(w, strip, &text), x, y);
                canvas::paste(&mut sheet, &img, x, y + strip);
                done += 1;
                if let Some(b) = &bar {
                    b.set(done);
                }
            }
        }
        Ok(())
    })?;
    if let Some(b) = &bar {
        b.finish(None);
    }
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
