//! `glview bench --lod`: level of detail's time against error at 1280×720. For the 2M-triangle
//! sphere, the dragon and a Khronos model (SheenCloth, when found), in both tiers: per
//! error bound (0 = `--lod off`, then 0.25, 0.5, 1, 2 pixels, with `--lod on` so every
//! large mesh takes part), the triangles drawn (shadow pass + lit pass), the frame with its
//! shadow pass (median), and the picture's difference from `--lod off`'s.
use super::median;
use super::metrics::compare;
use super::sphere;
use super::table::{num, Table};
use glview::frame::Shading;
use glview::options::{LodMode, Options};
use glview::render::{Lod, Renderer};
use glview::scene::lod::clusters;
use glview::Result;
use std::path::{Path, PathBuf};
use std::time::Instant;

const SIZE: (u32, u32) = (1280, 720);
/// The bounds measured, in pixels (0: every triangle).
/// Triangles of the generated sphere (the 2M one).
pub const SPHERE: u64 = 2_000_000;
/// The bounds measured, in pixels (0: every triangle).
pub const BOUNDS: [f32; 5] = [0.0, 0.25, 0.5, 1.0, 2.0];

/// The models: the generated sphere of `triangles`, the dragon, and the Khronos model `khronos` if it exists.
fn models(
    work: &Path,
    models_dir: &Path,
    triangles: u64,
    khronos: Option<&Path>,
) -> Result<Vec<PathBuf>> {
    let mut models = vec![sphere::ensure(work, triangles)?];
    let dragon = models_dir.join("dragon-200k/dragon_vrip_res2.obj");
    for m in std::iter::once(dragon).chain(khronos.map(Path::to_path_buf)) {
        if m.is_file() {
            models.push(m);
        } else {
            eprintln!("bench --lod: {} not found, skipped", m.display());
        }
    }
    Ok(models)
}

pub fn run_lod(
    work: &Path,
    models_dir: &Path,
    rounds: usize,
    triangles: u64,
    khronos: Option<&Path>,
) -> Result<()> {
    super::ensure_dir(work)?;
    let models = models(work, models_dir, triangles, khronos)?;
    let hl = super::open_headless(
        "lod",
        SIZE,
        &format!("shadow pass every frame, medians of {rounds}"),
    )?;
    let mut table = Table::new(&[
        "model",
        "tier",
        "bound px",
        "triangles drawn",
        "frame ms",
        "mean /255",
        "p99 /255",
        "> 8/255 %",
        "1 - SSIM",
    ]);
    for model in &models {
        let name = model.file_name().unwrap_or_default().to_string_lossy();
        let mut scene = glview::scene::load(model, &Default::default())?;
        let t = Instant::now();
        let prepared = clusters::prepare(&mut scene);
        let prepare_ms = t.elapsed().as_secs_f64() * 1e3;
        let (tris, lod_tris) = prepared.iter().flatten().fold((0, 0), |(a, b), c| {
            let coarse: u64 = c.lod.levels.iter().map(|l| u64::from(l.part.count)).sum();
            (
                a + c.list.iter().map(|k| u64::from(k.count)).sum::<u64>(),
                b + coarse,
            )
        });
        println!(
            "{name}: clusters and levels built in {prepare_ms:.0} ms; {tris} triangles in clusters, {lod_tris} in coarser levels"
        );
        let mut renderer = Renderer::prepared(&hl.gpu, scene, prepared)?;
        for shading in [Shading::Phong, Shading::Pbr] {
            let mut args = Options::default();
            args.load.model = Some(model.clone());
            args.picture.size = SIZE;
            args.render.shading = shading;
            let (settings, _) = glview::session::frame_settings(&args, renderer.scene())?;
            let mut reference = None;
            for bound in BOUNDS {
                renderer.lod = Lod {
                    mode: if bound > 0.0 {
                        LodMode::On
                    } else {
                        LodMode::Off
                    },
                    error: bound,
                };
                let mut times = Vec::new();
                let mut drawn = 0;
                for round in 0..=rounds {
                    renderer.invalidate_shadows();
                    let s = renderer.render(&settings, &hl.target())?;
                    if round > 0 {
                        times.push(s.ms);
                    }
                    drawn = s.triangles;
                }
                let img = hl.read();
                let reference = reference.get_or_insert_with(|| img.clone());
                let e = compare(&img, reference, &[])?;
                table.row(vec![
                    name.to_string(),
                    shading.word().into(),
                    if bound > 0.0 {
                        num(f64::from(bound), 2)
                    } else {
                        "off".into()
                    },
                    drawn.to_string(),
                    num(median(&times), 1),
                    num(e.mae, 3),
                    num(e.p99, 1),
                    num(e.wrong * 100.0, 3),
                    num(1.0 - e.ssim, 5),
                ]);
            }
        }
    }
    println!("{}", table.render());
    Ok(())
}
