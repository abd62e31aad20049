//! `glview bench --load`: speed against a peer. For the shared models and a generated
//! 1M-triangle sphere: OBJ parse and GPU upload throughput (in process), time to the first
//! PNG at 1280×720 and peak memory for glview and for f3d (separate processes, the same
//! files, interleaved runs, medians), and the 1M-triangle frame time with shadows.
use super::child::{self, Measured};
use super::load_report::{load_table, write_outputs, FrameTime, LoadReport, LoadRow};
use super::{ensure_dir, f3d, median, sphere};
use glview::headless::Headless;
use glview::platform::{Backend, GlRequest};
use glview::render::Renderer;
use glview::scene;
use glview::{Error, Result};
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Output size of the time-to-PNG runs and of the large-model frame time.
const SIZE: (u32, u32) = (1280, 720);

#[derive(Clone, Debug, clap::Args)]
pub struct LoadOptions {
    /// Timed runs per file and program for the time to first PNG (the median is reported).
    #[arg(long, default_value_t = 5)]
    pub runs: usize,
    /// Do not run f3d (glview's figures only).
    #[arg(long)]
    pub no_f3d: bool,
    /// The glview executable to time (default: this program if it is glview, else the
    /// `glview` beside it).
    #[arg(long)]
    pub glview_bin: Option<PathBuf>,
    /// Triangles of the generated sphere.
    #[arg(long, default_value_t = 1_000_000)]
    pub sphere_triangles: u64,
    /// Folder for the generated sphere and scratch PNGs (default: the user's cache folder).
    #[arg(long)]
    pub work_dir: Option<PathBuf>,
    /// Where load.csv and load.json go (default docs/bench; `glview bench` passes --out-dir).
    #[arg(skip)]
    pub out_dir: Option<PathBuf>,
    /// The shared models folder (default ../shared/models; `glview bench` passes --models-dir).
    #[arg(skip)]
    pub models_dir: Option<PathBuf>,
    /// Fewer files and runs (`glview bench --load --quick`).
    #[arg(skip)]
    pub quick: bool,
}

/// The shared models timed, smallest first; `--quick` keeps the marked ones.
const SHARED: &[(&str, bool)] = &[
    ("teapot-small/teapot.obj", false),
    ("suzanne/suzanne.obj", true),
    ("bunny-small/bunny.obj", false),
    ("spot/spot_triangulated.obj", false),
    ("stanford-bunny/stanford-bunny.obj", true),
    ("dragon-200k/dragon_vrip_res2.obj", false),
];

fn default_work_dir() -> PathBuf {
    let cache = std::env::var_os("XDG_CACHE_HOME")
        .map(PathBuf::from)
        .filter(|p| p.is_absolute())
        .or_else(|| std::env::var_os("HOME").map(|h| PathBuf::from(h).join(".cache")));
    cache.map_or_else(std::env::temp_dir, |c| c.join("glview").join("bench"))
}

impl LoadOptions {
    /// `--work-dir`, else the default: where the generated sphere and scratch files go for
    /// every benchmark that makes them (--load, --lod, --frame).
    pub(crate) fn work_dir(&self) -> PathBuf {
        self.work_dir.clone().unwrap_or_else(default_work_dir)
    }
}

fn glview_binary(opts: &LoadOptions) -> Result<PathBuf> {
    if let Some(p) = &opts.glview_bin {
        return Ok(p.clone());
    }
    let exe = std::env::current_exe().map_err(|e| Error::io("current executable", e))?;
    if exe.file_stem().is_some_and(|s| s == "glview") {
        return Ok(exe);
    }
    let sibling = exe.with_file_name("glview");
    if sibling.is_file() {
        Ok(sibling)
    } else {
        Err(Error::Usage(format!(
            "no glview executable beside {}; pass --glview-bin",
            exe.display()
        )))
    }
}

/// Times `f` `n` times; the median in milliseconds.
fn time_ms<T>(n: usize, mut f: impl FnMut() -> Result<T>) -> Result<f64> {
    let mut v = Vec::with_capacity(n);
    for _ in 0..n.max(1) {
        let t = Instant::now();
        let out = f()?;
        v.push(t.elapsed().as_secs_f64() * 1e3);
        drop(out);
    }
    Ok(median(&v))
}

fn median_measured(v: &[Measured]) -> Measured {
    Measured {
        seconds: median(&v.iter().map(|m| m.seconds).collect::<Vec<_>>()),
        peak_mib: median(&v.iter().map(|m| m.peak_mib).collect::<Vec<_>>()),
    }
}

/// `glview bench --load`.
pub fn run_load(opts: &LoadOptions) -> Result<()> {
    let started = Instant::now();
    let out_dir = opts.out_dir.clone().unwrap_or_else(|| "docs/bench".into());
    let models = opts
        .models_dir
        .clone()
        .unwrap_or_else(super::default_models_dir);
    let work = opts.work_dir();
    ensure_dir(&out_dir)?;
    ensure_dir(&work)?;
    let runs = if opts.quick {
        opts.runs.clamp(1, 3)
    } else {
        opts.runs.max(3)
    };
    let glview = glview_binary(opts)?;
    let has_cache = help_mentions(&glview, "--no-cache");
    let peer = if opts.no_f3d { None } else { f3d::find() };
    if peer.is_none() && !opts.no_f3d {
        eprintln!("warning: f3d is not installed (scripts/bench.sh installs it); glview only");
    }
    let xvfb = match &peer {
        Some(_) => Some(f3d::Xvfb::start(SIZE)?),
        None => None,
    };
    let mut files: Vec<PathBuf> = SHARED
        .iter()
        .filter(|(_, q)| !opts.quick || *q)
        .map(|(p, _)| models.join(p))
        .collect();
    if let Some(missing) = files.iter().find(|p| !p.is_file()) {
        return Err(Error::Usage(format!(
            "{} is missing (run from the repository root with ../shared beside it)",
            missing.display()
        )));
    }
    eprintln!("bench: writing the sphere into {}", work.display());
    let big = sphere::ensure(&work, opts.sphere_triangles)?;
    files.push(big.clone());
    let hl = Headless::new(Backend::Auto, GlRequest::Auto, 64, 64)?;
    let renderer_name = hl.gpu.caps.renderer.clone();
    let f3d_version = peer.as_deref().map(f3d::version);
    eprintln!(
        "bench: {} vs {}, {runs} runs per file, {}x{}",
        glview.display(),
        f3d_version.as_deref().unwrap_or("no peer"),
        SIZE.0,
        SIZE.1
    );
    let programs = Programs {
        glview,
        has_cache,
        f3d: peer,
        display: xvfb.as_ref().map(|x| x.display.clone()),
    };
    let mut rows = Vec::new();
    for file in &files {
        let row = measure_file(file, runs, &hl, &programs, &work)?;
        eprintln!(
            "bench: {}: parse {:.0} ms, upload {:.0} ms, glview {:.2} s, f3d {}",
            row.file,
            row.parse_ms,
            row.upload_ms,
            row.glview.seconds,
            row.f3d
                .as_ref()
                .map_or("-".into(), |m| format!("{:.2} s", m.seconds))
        );
        rows.push(row);
    }
    drop(hl);
    drop(xvfb);
    let large_frame = frame_time(&big)?;
    let report = LoadReport {
        renderer: renderer_name,
        f3d: f3d_version,
        size: SIZE,
        runs,
        memory: child::memory_method(),
        glview_has_cache: has_cache,
        rows,
        large_frame,
    };
    print!("{}", load_table(&report));
    write_outputs(&out_dir, &report)?;
    eprintln!(
        "bench: done in {:.0} s; wrote load.csv and load.json in {}",
        started.elapsed().as_secs_f64(),
        out_dir.display()
    );
    Ok(())
}

fn help_mentions(program: &Path, what: &str) -> bool {
    std::process::Command::new(program)
        .arg("--help")
        .output()
        .is_ok_and(|o| String::from_utf8_lossy(&o.stdout).contains(what))
}

/// The programs timed and where they run.
struct Programs {
    glview: PathBuf,
    /// The glview binary has a mesh cache (and `--no-cache` for the cold runs).
    has_cache: bool,
    f3d: Option<PathBuf>,
    /// DISPLAY for f3d.
    display: Option<String>,
}

fn measure_file(
    file: &Path,
    runs: usize,
    hl: &Headless,
    programs: &Programs,
    work: &Path,
) -> Result<LoadRow> {
    let (glview, has_cache) = (&programs.glview, programs.has_cache);
    let bytes = std::fs::metadata(file)
        .map_err(|e| Error::io(file, e))?
        .len();
    let opts = scene::LoadOptions::default();
    let scene = scene::load(file, &opts)?;
    let triangles = scene.triangle_count();
    let parse_ms = time_ms(runs, || Ok(scene::load(file, &opts)?))?;
    let warm_load_ms = if bytes >= glview::scene::cache::MIN_SIZE {
        let cached = scene::LoadOptions {
            cache: true,
            ..Default::default()
        };
        scene::load(file, &cached)?;
        Some(time_ms(runs, || Ok(scene::load(file, &cached)?))?)
    } else {
        None
    };
    let upload_ms = time_ms(runs, || {
        let r = Renderer::new(&hl.gpu, scene.clone());
        hl.gpu.finish();
        r
    })?;
    let png = work.join("bench_out.png");
    let size = format!("{}x{}", SIZE.0, SIZE.1);
    let mut glview_args = vec![
        file.display().to_string(),
        "--output".into(),
        png.display().to_string(),
        "--size".into(),
        size,
    ];
    let warm_args = glview_args.clone();
    if has_cache {
        glview_args.push("--no-cache".into());
    }
    let f3d_png = work.join("bench_out_f3d.png");
    let f3d_args = f3d::args(file, &f3d_png, SIZE);
    let f3d_env: Vec<(&str, String)> = programs
        .display
        .iter()
        .map(|d| ("DISPLAY", d.clone()))
        .collect();
    let (mut g, mut w, mut p) = (Vec::new(), Vec::new(), Vec::new());
    // Round 0 is a warm-up (file in the page cache, cache file written); then the programs
    // alternate so that other load on the machine hits both alike.
    for round in 0..=runs {
        let m = child::measure(glview, &glview_args, &[])?;
        let warm = if has_cache {
            Some(child::measure(glview, &warm_args, &[])?)
        } else {
            None
        };
        let peer_m = match &programs.f3d {
            Some(f) => Some(child::measure(f, &f3d_args, &f3d_env)?),
            None => None,
        };
        if round > 0 {
            g.push(m);
            w.extend(warm);
            p.extend(peer_m);
        }
    }
    Ok(LoadRow {
        file: file.file_name().map_or_else(
            || file.display().to_string(),
            |n| n.to_string_lossy().into(),
        ),
        bytes,
        triangles,
        parse_ms,
        warm_load_ms,
        upload_ms,
        glview: median_measured(&g),
        glview_warm: (!w.is_empty()).then(|| median_measured(&w)),
        f3d: (!p.is_empty()).then(|| median_measured(&p)),
    })
}

/// The large model's frame time at 1280×720 with the default shadows.
fn frame_time(file: &Path) -> Result<FrameTime> {
    let args = {
        let mut o: glview::options::Options = Default::default();
        o.load.model = Some(file.to_path_buf());
        o.picture.size = SIZE;
        o
    };
    let scene = glview::session::load_scene(&args)?;
    let (settings, _) = glview::session::frame_settings(&args, &scene)?;
    let hl = Headless::new(Backend::Auto, GlRequest::Auto, SIZE.0, SIZE.1)?;
    let target = hl.target();
    let triangles = scene.triangle_count();
    let mut r = Renderer::new(&hl.gpu, scene)?;
    let (mut full, mut reused) = (Vec::new(), Vec::new());
    for round in 0..9 {
        r.invalidate_shadows();
        let a = r.render(&settings, &target)?;
        let b = r.render(&settings, &target)?;
        if round >= 2 {
            full.push(a.ms);
            reused.push(b.ms);
        }
    }
    Ok(FrameTime {
        file: file.display().to_string(),
        triangles,
        ms_shadow_pass: median(&full),
        ms_reused: median(&reused),
    })
}
