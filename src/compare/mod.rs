//! Comparisons for coursework: several tiers side by side on one camera (`--compare`), the
//! difference of two with its numbers (`--diff`), a render against a stored picture
//! (`--diff-against`), and contact sheets (`glview sheet`). One context, one scene upload:
//! every GPU pane is a viewport of one frame target.
pub use glview_render::image::canvas;
pub mod diff;
pub mod sheet;
/// The window's and the browser's `C` view (in the render crate, which both draw with).
pub use crate::view::split;

use crate::frame::{FrameSettings, Shading};
use crate::image_out::Rgba;
use crate::image_out::RgbaFiles;
use crate::scene::lod::clusters::Clusters;
use crate::scene::Scene;
use crate::{Error, Result};

/// What one pane shows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PaneTier {
    Gpu(Shading),
    /// The CPU reference renderer in the given tier.
    Reference(Shading),
}

impl PaneTier {
    pub(crate) fn name(self) -> String {
        match self {
            PaneTier::Gpu(s) => s.word().into(),
            PaneTier::Reference(Shading::Pbr) => "reference-pbr".into(),
            PaneTier::Reference(_) => "reference".into(),
        }
    }
}

/// Parses `phong,pbr,reference,...`.
pub fn parse_tiers(s: &str, what: &str) -> Result<Vec<PaneTier>> {
    let tiers = s
        .split(',')
        .map(|t| match t.trim() {
            "phong" => Ok(PaneTier::Gpu(Shading::Phong)),
            "gouraud" => Ok(PaneTier::Gpu(Shading::Gouraud)),
            "pbr" => Ok(PaneTier::Gpu(Shading::Pbr)),
            "reference" => Ok(PaneTier::Reference(Shading::Phong)),
            "reference-pbr" => Ok(PaneTier::Reference(Shading::Pbr)),
            other => Err(Error::Usage(format!(
                "{what}: unknown tier {other:?} (phong, gouraud, pbr, reference, reference-pbr)"
            ))),
        })
        .collect::<Result<Vec<_>>>()?;
    if tiers.is_empty() || tiers.len() > 8 {
        return Err(Error::Usage(format!("{what}: give 1 to 8 tiers")));
    }
    Ok(tiers)
}

/// The lights a frame is lit by: the placed ones and the headlight (the default kit is key,
/// fill and headlight: 3).
pub fn light_count(s: &FrameSettings) -> usize {
    s.lights.len() + usize::from(s.lighting.headlight.is_some())
}

/// A pane's label: tier and the settings that matter for it.
pub fn label(tier: PaneTier, s: &FrameSettings) -> String {
    let shadows = if s.shadows.enabled && !s.lights.is_empty() {
        format!("shadows {}", s.shadows.size)
    } else {
        "no shadows".into()
    };
    let lights = match light_count(s) {
        1 => "1 light".to_string(),
        n => format!("{n} lights"),
    };
    match tier {
        PaneTier::Gpu(Shading::Pbr) | PaneTier::Reference(Shading::Pbr) => format!(
            "{} {lights} {shadows} {:?}",
            tier.name(),
            s.lighting.output.tonemap
        ),
        _ => format!("{} {lights} {shadows}", tier.name()),
    }
}

/// One frame, several tiers: one context, one upload, one pane (viewport) per GPU tier.
pub(crate) struct Panes {
    pub(crate) images: Vec<Rgba>,
    pub(crate) labels: Vec<String>,
    /// Per pane, where the model covers a pixel (row-major, top row first), when asked for.
    pub(crate) coverage: Vec<Vec<bool>>,
}

/// Renders each tier at `args.size` on one camera: GPU tiers as viewports of one target,
/// reference tiers on the CPU.
pub(crate) fn render_panes(
    args: &crate::options::Options,
    scene: Scene,
    clusters: Option<Vec<Option<Clusters>>>,
    tiers: &[PaneTier],
) -> Result<Panes> {
    render_panes_with(args, scene, clusters, tiers, false)
}

/// [`render_panes`], with each pane's coverage where `coverage` is set: the GPU tiers are
/// drawn once more with a transparent background (alpha = coverage), the reference records
/// which pixels hit a surface.
pub(crate) fn render_panes_with(
    args: &crate::options::Options,
    scene: Scene,
    clusters: Option<Vec<Option<Clusters>>>,
    tiers: &[PaneTier],
    coverage: bool,
) -> Result<Panes> {
    let (w, h) = crate::view::settings::output_size(args);
    let (base, _) = crate::session::frame_settings(args, &scene)?;
    let n = tiers.len() as u32;
    let gpu_tiers = tiers.iter().any(|t| matches!(t, PaneTier::Gpu(_)));
    let mut images = vec![None; tiers.len()];
    let mut covered = vec![Vec::new(); tiers.len()];
    if gpu_tiers {
        let mut session = crate::session::Session::new();
        session.with_scene(args, scene.clone(), clusters, (w * n, h), |hl, renderer| {
            let (imgs, cov) = gpu_panes(
                hl,
                renderer,
                &base,
                tiers,
                (w, h),
                coverage,
                args.picture.stats,
            )?;
            for (i, (img, c)) in imgs.into_iter().zip(cov).enumerate() {
                if let Some(img) = img {
                    images[i] = Some(img);
                    covered[i] = c;
                }
            }
            Ok(())
        })?;
    }
    for (i, t) in tiers.iter().enumerate() {
        if let PaneTier::Reference(shading) = t {
            let s = FrameSettings {
                shading: *shading,
                ..base.clone()
            };
            let env = crate::session::reference_env(args, *shading)?;
            if coverage {
                let (img, info) =
                    crate::reference::render_env_with_info(&scene, &s, env.as_ref(), w, h);
                images[i] = Some(img);
                covered[i] = info.iter().map(|p| p.hit()).collect();
            } else {
                images[i] = Some(crate::reference::render_env(&scene, &s, env.as_ref(), w, h));
            }
        }
    }
    Ok(Panes {
        images: images
            .into_iter()
            .map(|i| i.expect("every pane drawn"))
            .collect(),
        labels: tiers.iter().map(|t| label(*t, &base)).collect(),
        coverage: covered,
    })
}

/// Per pane: its picture (None for a reference tier), and where the model covers a pixel.
type GpuPanes = (Vec<Option<Rgba>>, Vec<Vec<bool>>);

/// The GPU tiers' panes (None for the others), `size` each, as viewports of `hl`'s target
/// side by side, and with `coverage` where each covers a pixel (drawn once more with a
/// transparent background: alpha = coverage).
fn gpu_panes(
    hl: &crate::headless::Headless,
    renderer: &mut crate::render::Renderer,
    base: &FrameSettings,
    tiers: &[PaneTier],
    (w, h): (u32, u32),
    coverage: bool,
    print_stats: bool,
) -> Result<GpuPanes> {
    let mut images = vec![None; tiers.len()];
    let mut covered = vec![Vec::new(); tiers.len()];
    let gpu = |t: &PaneTier| match t {
        PaneTier::Gpu(s) => Some(*s),
        PaneTier::Reference(_) => None,
    };
    for pass in [false, true] {
        if pass && !coverage {
            break;
        }
        for (i, shading) in tiers
            .iter()
            .enumerate()
            .filter_map(|(i, t)| Some((i, gpu(t)?)))
        {
            let mut s = FrameSettings {
                shading,
                ..base.clone()
            };
            s.lighting.post.transparent = pass;
            let stats = renderer.render_viewport(&s, &hl.target(), [i as u32 * w, 0, w, h])?;
            if print_stats && !pass {
                println!("{}", serde_json::to_string(&stats).unwrap_or_default());
            }
        }
        let all = hl.read();
        for i in (0..tiers.len()).filter(|&i| gpu(&tiers[i]).is_some()) {
            let pane = crop(&all, i as u32 * w, w);
            if pass {
                covered[i] = pane.data.chunks_exact(4).map(|p| p[3] > 0).collect();
            } else {
                images[i] = Some(pane);
            }
        }
    }
    Ok((images, covered))
}

/// [`phong_pbr`]'s picture, numbers and frame settings.
pub struct PhongPbr {
    /// Phong left, PBR right.
    pub image: Rgba,
    /// The difference over the model's pixels, and how many those are.
    pub numbers: Option<(diff::DiffNumbers, usize)>,
    /// The panes' settings but for the tier (`--keys` applied).
    pub settings: FrameSettings,
}

/// Phong | PBR of `args` (each pane `args.picture.size`, framed for it, as `--compare
/// phong,pbr` draws them) with the session's kept renderer, side by side in one picture,
/// and with `numbers` their difference over the model's pixels with the count of those
/// pixels (`--diff phong,pbr`'s model part): the server's compare view.
pub fn phong_pbr(
    session: &mut crate::session::Session,
    args: &crate::options::Options,
    numbers: bool,
) -> Result<PhongPbr> {
    let (w, h) = crate::view::settings::output_size(args);
    let tiers = [PaneTier::Gpu(Shading::Phong), PaneTier::Gpu(Shading::Pbr)];
    let ((mut images, covered), settings) =
        session.with_renderer(args, (2 * w, h), |hl, renderer| {
            let (base, _) = crate::session::frame_settings(args, renderer.scene())?;
            let panes = gpu_panes(hl, renderer, &base, &tiers, (w, h), numbers, false)?;
            Ok((panes, base))
        })?;
    let (b, a) = (images.pop().flatten(), images.pop().flatten());
    let (a, b) = (a.expect("two panes"), b.expect("two panes"));
    let mut out = canvas::blank(2 * w, h, [0, 0, 0]);
    canvas::paste(&mut out, &a, 0, 0);
    canvas::paste(&mut out, &b, w, 0);
    let numbers = if numbers {
        let covered = diff::union(&covered[0], &covered[1]);
        let n = covered.iter().filter(|&&c| c).count();
        diff::over_pixels(&a, &b, &covered)?.map(|d| (d, n))
    } else {
        None
    };
    Ok(PhongPbr {
        image: out,
        numbers,
        settings,
    })
}

/// Columns x0..x0+w of `img`.
pub(crate) fn crop(img: &Rgba, x0: u32, w: u32) -> Rgba {
    let mut data = Vec::with_capacity((w * img.height * 4) as usize);
    for y in 0..img.height {
        let s = ((y * img.width + x0) * 4) as usize;
        data.extend_from_slice(&img.data[s..s + (w * 4) as usize]);
    }
    Rgba {
        width: w,
        height: img.height,
        data,
    }
}

/// `--compare A,B,...`: the panes side by side under label strips, one PNG.
pub fn compare(
    args: &crate::options::Options,
    tiers_arg: &str,
    path: &std::path::Path,
) -> Result<()> {
    let (out, text) = compare_image(args, tiers_arg)?;
    out.save_png(path, &text)
}

/// The `--compare` picture and its PNG text, without writing it (the library and Python).
pub fn compare_image(
    args: &crate::options::Options,
    tiers_arg: &str,
) -> Result<(Rgba, crate::image_out::PngText)> {
    let tiers = parse_tiers(tiers_arg, "--compare")?;
    let (mut scene, clusters) = crate::session::load_scene_prepared(args)?;
    crate::session::pose_scene(args, &mut scene)?;
    let name = scene.name.clone();
    let panes = render_panes(args, scene, clusters, &tiers)?;
    let (w, h) = crate::view::settings::output_size(args);
    let labels: Vec<&str> = panes.labels.iter().map(String::as_str).collect();
    let strip = canvas::strip_height(w, &labels);
    let mut out = canvas::blank(w * tiers.len() as u32, h + strip, [24, 24, 28]);
    for (i, (img, label)) in panes.images.iter().zip(&labels).enumerate() {
        canvas::paste(
            &mut out,
            &canvas::strip_sized(w, strip, label),
            i as u32 * w,
            0,
        );
        canvas::paste(&mut out, img, i as u32 * w, strip);
    }
    let text = vec![
        ("Software", format!("glview {}", env!("CARGO_PKG_VERSION"))),
        ("glview.compare", tiers_arg.to_string()),
        ("glview.model", name),
        ("glview.pane_size", format!("{w}x{h}")),
        ("glview.label_height", strip.to_string()),
    ];
    Ok((out, text))
}
