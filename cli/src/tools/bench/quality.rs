//! Run time against error, per quality knob. For each scene: the CPU reference (exact hard
//! shadows, Phong) once at pixel centres and once supersampled, then every knob setting
//! rendered on the GPU, timed and compared with both. Every setting is measured against the
//! same truth — the exact image — so Gouraud and "shadows off" sit on the same plot.
//!
//! Timing: frames are interleaved (each round renders every setting once) so that load from
//! other processes spreads over all settings instead of spoiling a few; the shadow pass is
//! forced in the timed frame and a second frame right after it measures the map reused.
use super::knobs::{knobs, Knob};
use super::metrics::{self, ImageError};
use super::scenes::{self, LoadedScene};
use super::summary::{self, Report, Row, SceneInfo};
use super::{ensure_dir, median};
use glview::headless::Headless;
use glview::image_out::Rgba;
use glview::image_out::RgbaFiles;
use glview::platform::{Backend, GlRequest};
use glview::render::Renderer;
use glview::{Error, Result};
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Rounds rendered and thrown away before timing (shader compilation, first allocation).
const WARMUP: usize = 2;

/// Reference samples per pixel side for the anti-aliased truth (4 → 16 rays per pixel).
const SUPERSAMPLE: u32 = 4;

#[derive(Clone, Debug, clap::Args)]
pub struct QualityOptions {
    /// A ~1-minute subset: two scenes, fewer settings, fewer frames.
    #[arg(long)]
    pub quick: bool,
    /// Timed frames per setting (the median is reported; at least 7 outside --quick).
    #[arg(long, default_value_t = 11)]
    pub repeat: usize,
    /// Render size of the quality bench, WxH.
    #[arg(long = "bench-size", default_value = "640x480", value_parser = parse_size)]
    pub size: (u32, u32),
    /// Only these scenes (repeat the option): glass_holder, sphere, box_floor, box_point,
    /// bunny_floor, dragon_floor.
    #[arg(long = "scene")]
    pub scenes: Vec<String>,
    /// Where CSV, JSON and plots are written.
    #[arg(long, default_value = "docs/bench")]
    pub out_dir: PathBuf,
    /// Folder of the shared models (stanford-bunny, dragon-200k, ...).
    #[arg(long, default_value_os_t = super::default_models_dir())]
    pub models_dir: PathBuf,
    /// Also write each scene's references and every GPU render as PNG under OUT_DIR/images.
    #[arg(long)]
    pub save_images: bool,
}

fn parse_size(s: &str) -> std::result::Result<(u32, u32), String> {
    let (w, h) = s.split_once(['x', 'X']).ok_or("size must be WxH")?;
    let w: u32 = w.trim().parse().map_err(|_| format!("bad width {w:?}"))?;
    let h: u32 = h.trim().parse().map_err(|_| format!("bad height {h:?}"))?;
    if w == 0 || h == 0 || w > 4096 || h > 4096 {
        return Err(format!("size {w}x{h} out of range (1..4096)"));
    }
    Ok((w, h))
}

/// What a scene's GPU renders are compared with.
struct Truth {
    exact: Rgba,
    antialiased: Rgba,
    /// Pixels behind translucent layers: the reference composites them per pixel and the GPU
    /// per mesh (a documented difference of the reference), so no knob can fix them.
    ignore: Vec<bool>,
}

fn truth(loaded: &LoadedScene, size: (u32, u32), info: &mut SceneInfo) -> Truth {
    let (w, h) = size;
    let t = Instant::now();
    let (exact, pixels) =
        glview::reference::render_with_info(&loaded.scene, &loaded.settings, w, h);
    info.reference_ms = t.elapsed().as_secs_f64() * 1e3;
    let t = Instant::now();
    let fine = glview::reference::render(
        &loaded.scene,
        &loaded.settings,
        w * SUPERSAMPLE,
        h * SUPERSAMPLE,
    );
    info.reference_aa_ms = t.elapsed().as_secs_f64() * 1e3;
    let ignore: Vec<bool> = pixels.iter().map(|p| p.layers > 0).collect();
    info.ignored = ignore.iter().filter(|&&i| i).count() as f64 / ignore.len().max(1) as f64;
    Truth {
        exact,
        antialiased: metrics::downsample(fine, SUPERSAMPLE),
        ignore,
    }
}

/// `glview bench`: measures every knob on every scene, prints the tables and writes
/// `quality.csv`, `quality.json` and `quality.png` into the output folder.
pub fn run_quality(opts: &QualityOptions) -> Result<()> {
    let started = Instant::now();
    let repeat = if opts.quick {
        opts.repeat.clamp(3, 5)
    } else {
        opts.repeat.max(7)
    };
    let specs: Vec<_> = scenes::default_set()
        .into_iter()
        .filter(|s| opts.scenes.is_empty() || opts.scenes.iter().any(|n| n == s.name))
        .filter(|s| !opts.quick || !opts.scenes.is_empty() || s.quick)
        .collect();
    if specs.is_empty() {
        let names: Vec<&str> = scenes::default_set().iter().map(|s| s.name).collect();
        return Err(Error::Usage(format!(
            "no bench scene matches {:?}; scenes: {}",
            opts.scenes,
            names.join(", ")
        )));
    }
    ensure_dir(&opts.out_dir)?;
    let images = opts.out_dir.join("images");
    if opts.save_images {
        ensure_dir(&images)?;
    }
    let knobs = knobs(opts.quick);
    let (w, h) = opts.size;
    let hl = Headless::new(Backend::Auto, GlRequest::Auto, w, h)?;
    let caps = hl.gpu.caps.clone();
    let load_before = loadavg();
    eprintln!(
        "bench: {} ({}, {}), {w}x{h}, {} scene(s) x {} settings, {WARMUP} warm-up + {repeat} \
         timed rounds; load average {load_before}",
        caps.renderer,
        caps.version,
        hl.backend_name(),
        specs.len(),
        knobs.len()
    );
    let mut rows = Vec::new();
    let mut infos = Vec::new();
    for spec in &specs {
        let loaded = spec.load(&opts.models_dir, opts.size)?;
        let mut info = SceneInfo {
            name: loaded.name.clone(),
            command: loaded.command.clone(),
            triangles: loaded.scene.triangle_count(),
            reference_ms: 0.0,
            reference_aa_ms: 0.0,
            ignored: 0.0,
        };
        let truth = truth(&loaded, opts.size, &mut info);
        eprintln!(
            "bench: {}: {} triangles; reference {:.1} s, {SUPERSAMPLE}x{SUPERSAMPLE} \
             supersampled {:.1} s; {:.2} % of pixels behind glass ignored",
            loaded.name,
            info.triangles,
            info.reference_ms / 1e3,
            info.reference_aa_ms / 1e3,
            100.0 * info.ignored
        );
        if opts.save_images {
            let file = |what: &str| images.join(format!("{}_{what}.png", loaded.name));
            truth.exact.save_png(&file("reference"), &[])?;
            truth.antialiased.save_png(&file("reference_aa"), &[])?;
        }
        let scene_rows = measure_scene(&hl, &loaded, &knobs, repeat, &truth, opts, &images)?;
        print!("{}", summary::scene_table(&info, &scene_rows));
        println!();
        rows.extend(scene_rows);
        infos.push(info);
    }
    let summary = summary::summarize(&knobs, &rows);
    print!("{}", summary::summary_table(&summary));
    let report = Report {
        renderer: caps.renderer.clone(),
        gl_version: caps.version.clone(),
        backend: hl.backend_name(),
        size: opts.size,
        warmup_rounds: WARMUP,
        timed_rounds: repeat,
        supersample: SUPERSAMPLE,
        wrong_threshold: metrics::WRONG_THRESHOLD,
        load_average: format!("{load_before} before, {} after", loadavg()),
        scenes: infos,
        summary,
        rows,
    };
    summary::write_outputs(&opts.out_dir, &report)?;
    eprintln!(
        "bench: done in {:.0} s; wrote quality.csv, quality.json and quality.png in {}",
        started.elapsed().as_secs_f64(),
        opts.out_dir.display()
    );
    Ok(())
}

/// The 1-, 5- and 15-minute load averages: other work on the machine skews the timings.
pub(crate) fn loadavg() -> String {
    std::fs::read_to_string("/proc/loadavg")
        .map(|s| s.split_whitespace().take(3).collect::<Vec<_>>().join(" "))
        .unwrap_or_else(|_| "unknown".into())
}

fn measure_scene(
    hl: &Headless,
    loaded: &LoadedScene,
    knobs: &[Knob],
    repeat: usize,
    truth: &Truth,
    opts: &QualityOptions,
    images: &Path,
) -> Result<Vec<Row>> {
    let target = hl.target();
    let mut renderer = Renderer::new(&hl.gpu, loaded.scene.clone())?;
    let settings: Vec<_> = knobs.iter().map(|k| k.apply(&loaded.settings)).collect();
    let mut full = vec![Vec::with_capacity(repeat); knobs.len()];
    let mut reused = vec![Vec::with_capacity(repeat); knobs.len()];
    let mut errors = vec![(ImageError::default(), ImageError::default()); knobs.len()];
    for round in 0..WARMUP + repeat {
        let timed = round >= WARMUP;
        for (i, (knob, s)) in knobs.iter().zip(&settings).enumerate() {
            renderer.invalidate_shadows();
            let stats = renderer.render(s, &target)?;
            if knob.shadows && stats.shadow != "rendered" {
                return Err(Error::Unsupported(format!(
                    "{}: the shadow pass did not run ({}); cannot time shadow knobs",
                    loaded.name, stats.shadow
                )));
            }
            let again = renderer.render(s, &target)?;
            if timed {
                // Wall time to glFinish. GL_TIME_ELAPSED (FrameStats::gpu_ms) exists on
                // llvmpipe but only spans rasterisation: vertex shading and binning run before
                // the query starts, so it undercounts a frame several times over.
                full[i].push(stats.ms);
                reused[i].push(again.ms);
            }
            if round + 1 == WARMUP + repeat {
                let image = hl.read();
                if opts.save_images {
                    let name = knob.label.replace(['/', ' '], "_");
                    image.save_png(&images.join(format!("{}_{name}.png", loaded.name)), &[])?;
                }
                errors[i] = (
                    metrics::compare(&image, &truth.exact, &truth.ignore)?,
                    metrics::compare(&image, &truth.antialiased, &truth.ignore)?,
                );
            }
        }
    }
    let off = knobs
        .iter()
        .position(|k| !k.shadows)
        .map_or(f64::NAN, |i| median(&full[i]));
    Ok(knobs
        .iter()
        .enumerate()
        .map(|(i, knob)| {
            let ms = median(&full[i]);
            Row {
                scene: loaded.name.clone(),
                knob: knob.clone(),
                default: knob.is_default(),
                ms,
                ms_min: full[i].iter().copied().fold(f64::INFINITY, f64::min),
                ms_reused: median(&reused[i]),
                ms_vs_off: ms / off,
                error: errors[i].0,
                error_aa: errors[i].1,
            }
        })
        .collect())
}
