//! `glview bench --frame`: the frame of a big model at 1280×720 on this driver, as the
//! issue measures it — the generated 1M-triangle sphere (and the dragon when ../shared has
//! it) with the default light kit and its shadow — for three renderers of the same scene in
//! one process, interleaved round by round: as uploaded before clusters (file order, every
//! triangle sent), reordered for the vertex cache only, and reordered with cluster culling
//! (the default). Per renderer: the frame with the shadow pass forced, with the map reused
//! (an orbiting camera), and without shadows; medians, and triangles sent per frame.
use super::table::{num, Table};
use super::{median, sphere};
use glview::headless::Headless;
use glview::options::Options;
use glview::render::{FrameSettings, Renderer};
use glview::scene::lod::clusters;
use glview::Result;
use std::path::Path;
use std::time::Instant;

const SIZE: (u32, u32) = (1280, 720);

/// One way of uploading the scene.
struct Variant {
    name: &'static str,
    renderer: Renderer,
    prepare_ms: f64,
    /// Frame times: shadow pass forced, map reused, no shadows.
    times: [Vec<f64>; 3],
    triangles: [u64; 3],
}

pub fn run_frame(work: &Path, models_dir: &Path, rounds: usize, triangles: u64) -> Result<()> {
    super::ensure_dir(work)?;
    let big = sphere::ensure(work, triangles)?;
    let mut models = vec![big];
    let dragon = models_dir.join("dragon-200k/dragon_vrip_res2.obj");
    if dragon.is_file() {
        models.push(dragon);
    }
    let hl = super::open_headless("frame", SIZE, &format!("medians of {rounds} rounds"))?;
    let mut table = Table::new(&[
        "model",
        "upload",
        "prepare ms",
        "shadow pass ms",
        "map reused ms",
        "no shadows ms",
        "triangles sent (pass + lit)",
    ]);
    for model in &models {
        let args = {
            let mut o = Options::default();
            o.load.model = Some(model.clone());
            o.picture.size = SIZE;
            o
        };
        let scene = glview::session::load_scene(&args)?;
        let (settings, _) = glview::session::frame_settings(&args, &scene)?;
        let mut off = settings.clone();
        off.shadows.enabled = false;
        let mut variants = Vec::new();
        for (name, reorder, cull) in [
            ("file order, all sent", false, false),
            ("reordered, all sent", true, false),
            ("reordered + culled", true, true),
        ] {
            let mut s = scene.clone();
            let t = Instant::now();
            let prepared = if reorder {
                clusters::prepare(&mut s)
            } else {
                vec![None; s.meshes.len()]
            };
            let prepare_ms = t.elapsed().as_secs_f64() * 1e3;
            let mut renderer = Renderer::prepared(&hl.gpu, s, prepared)?;
            renderer.cull_clusters = cull;
            variants.push(Variant {
                name,
                renderer,
                prepare_ms,
                times: Default::default(),
                triangles: [0; 3],
            });
        }
        // One warm-up round (programs compiled, buffers touched), then interleaved rounds so
        // load from elsewhere on the machine falls on every variant alike.
        for round in 0..=rounds {
            for v in &mut variants {
                let runs = frames(&mut v.renderer, &hl, &settings, &off)?;
                if round > 0 {
                    for (k, (ms, tris)) in runs.into_iter().enumerate() {
                        v.times[k].push(ms);
                        v.triangles[k] = tris;
                    }
                }
            }
        }
        let name = model.file_name().unwrap_or_default().to_string_lossy();
        for v in &variants {
            table.row(vec![
                name.to_string(),
                v.name.into(),
                num(v.prepare_ms, 0),
                num(median(&v.times[0]), 1),
                num(median(&v.times[1]), 1),
                num(median(&v.times[2]), 1),
                format!(
                    "{} / {} / {}",
                    v.triangles[0], v.triangles[1], v.triangles[2]
                ),
            ]);
        }
        let (base, best) = (&variants[0], &variants[2]);
        println!(
            "{name}: shadow pass frame {:.2}x, reused-map frame {:.2}x, no-shadow frame {:.2}x the file-order renderer's",
            median(&best.times[0]) / median(&base.times[0]),
            median(&best.times[1]) / median(&base.times[1]),
            median(&best.times[2]) / median(&base.times[2]),
        );
    }
    println!("{}", table.render());
    Ok(())
}

/// The three frames of one round: (ms, triangles sent).
fn frames(
    r: &mut Renderer,
    hl: &Headless,
    shadowed: &FrameSettings,
    off: &FrameSettings,
) -> Result<[(f64, u64); 3]> {
    r.invalidate_shadows();
    let forced = r.render(shadowed, &hl.target())?;
    let reused = r.render(shadowed, &hl.target())?;
    let plain = r.render(off, &hl.target())?;
    Ok([forced, reused, plain].map(|s| (s.ms, s.triangles)))
}
