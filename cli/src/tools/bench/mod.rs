//! `glview bench`: the instruments that choose the defaults. `quality` measures frame time
//! against error for every quality knob (error = distance from the CPU reference render);
//! `load` measures parse, upload, time to first PNG and peak memory against f3d. Both print a
//! table and write CSV/JSON (and a plot) into `docs/bench/` by default.
pub mod animated;
pub mod child;
pub mod f3d;
pub mod frame;
pub mod instancing;
pub mod khr;
pub mod knobs;
pub mod load;
pub mod load_report;
pub mod lod;
pub mod motion;
pub use glview::metrics;
pub mod pbr;
pub mod plot;
pub mod post;
pub mod quality;
pub mod scenes;
pub mod serve;
pub mod sphere;
pub mod stereo;
pub mod summary;
pub mod table;
pub mod translucency;

pub use load::{run_load, LoadOptions};
pub use quality::{run_quality, QualityOptions};

use std::path::PathBuf;

/// Everything `glview bench [--load]` accepts: flatten this into a clap subcommand.
#[derive(Clone, Debug, clap::Args)]
pub struct BenchArgs {
    /// Measure loading (parse, upload, time to PNG, memory) against f3d instead of quality.
    #[arg(long)]
    pub load: bool,
    /// Measure the PBR tier's precomputation knobs against the Monte Carlo reference.
    #[arg(long, conflicts_with = "load")]
    pub pbr: bool,
    /// Measure anti-aliasing modes and bloom chain depth (cost against error).
    #[arg(long, conflicts_with_all = ["load", "pbr"])]
    pub post: bool,
    /// Measure nearest-layer translucency against sorted and opaque drawing (and log depth).
    #[arg(long, conflicts_with_all = ["load", "pbr"])]
    pub translucency: bool,
    /// Measure the frame of the 1M-triangle sphere (and the dragon) at 1280x720: shadow pass
    /// forced, map reused and no shadows, without and with reordering and cluster culling.
    #[arg(long, conflicts_with_all = ["load", "pbr", "post", "translucency"])]
    pub frame: bool,
    /// Measure the glTF PBR extensions' programs (clearcoat, sheen, specular/ior) against
    /// the core material's on a full-frame sphere.
    #[arg(long, conflicts_with_all = ["load", "pbr", "post", "translucency", "frame"])]
    pub khr: bool,
    /// Measure EXT_mesh_gpu_instancing: frame time of generated files of 125 and 10,000
    /// instanced cubes against their twins with the instances written out as nodes.
    #[arg(long, conflicts_with_all = ["load", "pbr", "post", "translucency", "frame", "khr"])]
    pub instancing: bool,
    /// Measure level of detail: per error bound, triangles drawn, frame ms and the picture's
    /// difference from --lod off, on the 2M-triangle sphere, the dragon and a Khronos model.
    #[arg(long, conflicts_with_all = ["load", "pbr", "post", "translucency", "frame"])]
    pub lod: bool,
    /// With --lod: a Khronos sample model with a large mesh (docs/benchmarks.md uses
    /// SheenCloth: 115k triangles, textured).
    #[arg(long)]
    pub lod_khronos: Option<PathBuf>,
    /// Measure `glview serve` under 1, 5 and 30 simulated viewers and in teacher mode
    /// (frames/s, input→frame latency, bytes a frame; docs/serve.md).
    #[arg(long, conflicts_with_all = ["load", "pbr", "post", "translucency", "frame"])]
    pub serve: bool,
    /// Measure stereo frames against mono frames of the same output size, every mode, in
    /// the window's path (the frame) and the server's (frame and read-back).
    #[arg(long, conflicts_with_all = ["load", "pbr", "post", "translucency", "frame"])]
    pub stereo: bool,
    /// With --serve: seconds each scenario runs.
    #[arg(long, default_value_t = 5.0)]
    pub serve_seconds: f64,
    /// With --serve: the view size.
    #[arg(long, default_value = "800x600")]
    pub serve_size: String,
    /// Measure animated pictures: the encoding time of a 3-second animated picture (45 frames
    /// of 640x480: a turntable of the built-in scene, or --animated-model's animation) as GIF,
    /// APNG and WebP beside the time to draw its frames.
    #[arg(long, conflicts_with_all = ["load", "pbr", "post", "translucency", "frame"])]
    pub animated: bool,
    /// With --animated: a model whose first animation plays (a turntable without one).
    #[arg(long)]
    pub animated_model: Option<PathBuf>,
    /// Measure playing an animation: the frame time of a skinned figure at 1024x768 posed
    /// anew each frame (pose and upload apart) against the same model standing still.
    #[arg(long, conflicts_with_all = ["load", "pbr", "post", "translucency", "frame"])]
    pub motion: bool,
    /// With --motion: the animated model (default: Khronos' CesiumMan, committed).
    #[arg(long, default_value = "tests/data/khronos/motion/CesiumMan.glb")]
    pub motion_model: PathBuf,
    /// With --pbr: Monte Carlo samples per lobe of the reference.
    #[arg(long, default_value_t = 16384)]
    pub pbr_samples: u32,
    #[command(flatten)]
    pub quality: QualityOptions,
    #[command(flatten)]
    pub load_options: LoadOptions,
}

/// Runs the benchmark `args` selects.
pub fn run(args: &BenchArgs) -> glview::Result<()> {
    if args.post {
        return post::run_post();
    }
    if args.stereo {
        return stereo::run_stereo(&args.quality.models_dir);
    }
    if args.animated {
        return animated::run_animated(args.animated_model.as_deref());
    }
    if args.serve {
        return serve::run_serve(
            &args.quality.models_dir,
            args.serve_seconds,
            &args.serve_size,
        );
    }
    if args.motion {
        return motion::run_motion(&args.motion_model, (1024, 768));
    }
    if args.khr {
        return khr::run_khr();
    }
    if args.instancing {
        return instancing::run_instancing(&args.load_options.work_dir().join("instancing"));
    }
    if args.translucency {
        return translucency::run_translucency(&args.quality.models_dir);
    }
    if args.lod {
        let work = args.load_options.work_dir();
        let rounds = if args.quality.quick { 3 } else { 5 };
        return lod::run_lod(
            &work,
            &args.quality.models_dir,
            rounds,
            lod::SPHERE,
            args.lod_khronos.as_deref(),
        );
    }
    if args.frame {
        let work = args.load_options.work_dir();
        let rounds = if args.quality.quick {
            3
        } else {
            args.quality.repeat.max(5)
        };
        return frame::run_frame(
            &work,
            &args.quality.models_dir,
            rounds,
            args.load_options.sphere_triangles,
        );
    }
    if args.pbr {
        let hdr = args
            .quality
            .models_dir
            .join("../hdr/studio_small_03_1k.hdr");
        return pbr::run_pbr(&args.quality.out_dir, &hdr, args.pbr_samples);
    }
    if args.load {
        let mut opts = args.load_options.clone();
        // One --out-dir, --models-dir and --quick serve both benchmarks.
        opts.out_dir = Some(args.quality.out_dir.clone());
        opts.models_dir = Some(args.quality.models_dir.clone());
        opts.quick |= args.quality.quick;
        run_load(&opts)
    } else {
        run_quality(&args.quality)
    }
}

/// The median of `v` (the mean of the middle two for an even count); NaN when empty.
pub fn median(v: &[f64]) -> f64 {
    let mut s: Vec<f64> = v.iter().copied().filter(|x| !x.is_nan()).collect();
    if s.is_empty() {
        return f64::NAN;
    }
    s.sort_by(f64::total_cmp);
    let n = s.len();
    if n % 2 == 1 {
        s[n / 2]
    } else {
        (s[n / 2 - 1] + s[n / 2]) / 2.0
    }
}

/// The default folder of the shared test models, beside the repository.
pub fn default_models_dir() -> PathBuf {
    PathBuf::from("../shared/models")
}

/// Creates `dir` (and parents) or says which folder could not be made.
pub(crate) fn ensure_dir(dir: &std::path::Path) -> glview::Result<()> {
    std::fs::create_dir_all(dir).map_err(|e| glview::Error::io(dir, e))
}

/// Opens the headless context a frame benchmark draws in, `size` pixels, and prints the
/// table's title line: the mode, size, renderer and driver, `setup` (what each figure is),
/// and the load average — the figures mean nothing without them.
pub(crate) fn open_headless(
    mode: &str,
    size: (u32, u32),
    setup: &str,
) -> glview::Result<glview::headless::Headless> {
    use glview::platform::{Backend, GlRequest};
    let hl = glview::headless::Headless::new(Backend::Auto, GlRequest::Auto, size.0, size.1)?;
    println!(
        "glview bench --{mode}: {}x{} on {} ({}), {setup}, load average {}",
        size.0,
        size.1,
        hl.gpu.caps.renderer,
        hl.gpu.caps.version,
        quality::loadavg()
    );
    Ok(hl)
}

/// Writes `text` to `path`, mapping the error to the library's.
pub(crate) fn write_file(path: &std::path::Path, text: &str) -> glview::Result<()> {
    std::fs::write(path, text).map_err(|e| glview::Error::io(path, e))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn medians() {
        assert_eq!(median(&[3.0, 1.0, 2.0]), 2.0);
        assert_eq!(median(&[4.0, 1.0, 2.0, 3.0]), 2.5);
        assert!(median(&[]).is_nan());
    }

    #[test]
    fn args_are_consistent() {
        use clap::{Args, Command};
        BenchArgs::augment_args(Command::new("bench")).debug_assert();
    }
}
