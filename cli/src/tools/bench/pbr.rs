//! `glview bench --pbr`: every knob of the PBR tier's precomputation as cost (CPU
//! precompute time, frame time) against error (mean linear difference from the Monte Carlo
//! reference on spheres lit by the shared studio HDR, over four materials). Writes
//! `pbr.csv`, `pbr.json` and `pbr.png` (error against precompute time, Pareto front in red,
//! default ringed).
use super::plot::{self, Panel, Point};
use super::table::{csv_line, num, Table};
use super::{ensure_dir, median, write_file};
use glview::headless::Headless;
use glview::image_out::Rgba;
use glview::metrics::linear_error;
use glview::options::Options;
use glview::pbr::env::Environment;
use glview::pbr::precompute::IblSettings;
use glview::pbr::{Encoding, EnvRequest, EnvSource, PrecomputeOn};
use glview::platform::{Backend, GlRequest};
use glview::reference::{render_env_with_info, PbrEnv};
use glview::render::Renderer;
use glview::scene::Scene;
use glview::shader::cache::{ProgramCache, SharedPrograms};
use glview::Result;
use std::path::Path;
use std::sync::Arc;
use std::time::Instant;

/// One setting of the precomputation.
struct Knob {
    label: String,
    settings: IblSettings,
    encoding: Encoding,
    /// Shader options beyond the precomputation (dominant direction, multiscatter).
    extra: fn(&mut Options),
    /// Precompute on the GPU (`--ibl-precompute gpu`).
    gpu: bool,
}

fn knobs() -> Vec<Knob> {
    let d = IblSettings::default();
    let k = |label: &str, settings: IblSettings| Knob {
        label: label.into(),
        settings,
        encoding: Encoding::Float,
        extra: |_| {},
        gpu: false,
    };
    let mut v = vec![k("default", d)];
    for levels in [3, 4, 5, 8] {
        v.push(k(&format!("levels {levels}"), IblSettings { levels, ..d }));
    }
    for specular_size in [32, 64, 256] {
        v.push(k(
            &format!("specular {specular_size}"),
            IblSettings { specular_size, ..d },
        ));
    }
    for samples in [16, 32, 64, 512] {
        v.push(k(
            &format!("samples {samples}"),
            IblSettings { samples, ..d },
        ));
    }
    for lut_size in [16, 32, 128] {
        v.push(k(&format!("lut {lut_size}"), IblSettings { lut_size, ..d }));
    }
    for irradiance_size in [8, 16, 64] {
        v.push(k(
            &format!("irradiance {irradiance_size}"),
            IblSettings {
                irradiance_size,
                ..d
            },
        ));
    }
    v.push(Knob {
        encoding: Encoding::Rgbm,
        ..k("rgbm", d)
    });
    v.push(Knob {
        extra: |o| o.pbr.dominant_direction = true,
        ..k("dominant direction", d)
    });
    v.push(Knob {
        extra: |o| o.pbr.multiscatter = true,
        ..k("multiscatter", d)
    });
    v.push(Knob {
        gpu: true,
        ..k("GPU precompute", d)
    });
    v
}

/// The materials the error is averaged over: (metallic, roughness).
const MATERIALS: &[(f32, f32)] = &[(1.0, 0.25), (1.0, 0.5), (1.0, 0.75), (0.0, 0.5)];
const SIZE: u32 = 128;

fn options_for(hdr: &Path, metallic: f32, roughness: f32, extra: fn(&mut Options)) -> Options {
    let mut o = {
        let mut o: Options = Options::default();
        o.load.model = Some("models/sphere.obj".into());
        o.render.shading = glview::frame::Shading::Pbr;
        o.light.lights = vec![glview::light::LightOpt::None];
        o.pbr.tonemap = glview::pbr::Tonemap::None;
        o.pbr.exposure = -1.0;
        o.render.background = Some([1.0, 0.0, 1.0]);
        o.pbr.metallic = Some(metallic);
        o.pbr.roughness = Some(roughness);
        o.pbr.env = Some(hdr.into());
        o.picture.size = (SIZE, SIZE);
        o
    };
    extra(&mut o);
    o
}

/// One material's Monte Carlo reference: the scene, its picture, and which pixels hit it.
struct Reference {
    scene: Scene,
    image: Rgba,
    hit: Vec<bool>,
}

/// What one knob measured: precompute and frame time (medians) and the error per material.
struct Measured {
    precompute_ms: f64,
    frame_ms: f64,
    errors: Vec<f64>,
}

/// The bench's results in its four outputs: the printed table, CSV, JSON and plot points.
struct Results {
    table: Table,
    csv: Vec<String>,
    json: Vec<serde_json::Value>,
    points: Vec<Point>,
}

/// Runs the PBR bench with `samples` Monte Carlo samples per lobe for the reference.
pub fn run_pbr(out_dir: &Path, hdr: &Path, samples: u32) -> Result<()> {
    ensure_dir(out_dir)?;
    let env = Arc::new(Environment::load(hdr)?);
    let hl = Headless::new(Backend::Auto, GlRequest::Auto, SIZE, SIZE)?;
    eprintln!("bench --pbr: references ({samples} samples per lobe) ...");
    let references = references(hdr, &env, samples)?;
    let mut results = Results::new();
    for knob in knobs() {
        if knob.gpu {
            if let Some(why) = glview::render::ibl_gpu::unsupported(&hl.gpu) {
                eprintln!("  GPU precompute: skipped ({why})");
                continue;
            }
        }
        // Held until the knob's frames are drawn: their renderers share this context's
        // cache, so each knob compiles the lit programs once.
        let programs = ProgramCache::for_context(&hl.gpu);
        let precompute_ms = precompute_ms(&hl, &programs, &env, &knob)?;
        let (frame_ms, errors) = frame_and_errors(&hl, hdr, &knob, &references)?;
        results.push(
            &knob,
            Measured {
                precompute_ms,
                frame_ms,
                errors,
            },
        );
    }
    results.write(out_dir)
}

/// The Monte Carlo reference of each of [`MATERIALS`], on the CPU.
fn references(hdr: &Path, env: &Arc<Environment>, samples: u32) -> Result<Vec<Reference>> {
    let mut references = Vec::new();
    for (m, r) in MATERIALS {
        let args = options_for(hdr, *m, *r, |_| {});
        let scene = glview::session::load_scene(&args)?;
        let (settings, _) = glview::session::frame_settings(&args, &scene)?;
        let pe = PbrEnv {
            env: env.clone(),
            samples,
        };
        let (image, info) = render_env_with_info(&scene, &settings, Some(&pe), SIZE, SIZE);
        let hit: Vec<bool> = info.iter().map(|i| i.hit()).collect();
        references.push(Reference { scene, image, hit });
    }
    Ok(references)
}

/// The knob's precompute time: the median of three cold runs, on the GPU or the CPU.
fn precompute_ms(
    hl: &Headless,
    programs: &SharedPrograms,
    env: &Environment,
    knob: &Knob,
) -> Result<f64> {
    let mut times = Vec::new();
    for _ in 0..3 {
        let t = Instant::now();
        if knob.gpu {
            glview::render::ibl_gpu::compute(
                &hl.gpu,
                &mut programs.borrow_mut(),
                env,
                &knob.settings,
            )?;
        } else {
            let _ = glview::pbr::precompute::compute(env, &knob.settings);
        }
        times.push(t.elapsed().as_secs_f64() * 1e3);
    }
    Ok(median(&times))
}

/// Renders each material's sphere with the knob's environment maps: the median frame time
/// (five timed frames per material after one untimed, which makes the maps) and the mean
/// linear error of each material against its reference.
fn frame_and_errors(
    hl: &Headless,
    hdr: &Path,
    knob: &Knob,
    references: &[Reference],
) -> Result<(f64, Vec<f64>)> {
    let req = EnvRequest {
        source: EnvSource::File(hdr.into()),
        settings: knob.settings,
        encoding: knob.encoding,
        cache: false,
        precompute: if knob.gpu {
            PrecomputeOn::Gpu
        } else {
            PrecomputeOn::Cpu
        },
    };
    let mut errors = Vec::new();
    let mut frame_ms = Vec::new();
    for ((m, r), reference) in MATERIALS.iter().zip(references) {
        let args = options_for(hdr, *m, *r, knob.extra);
        let (settings, _) = glview::session::frame_settings(&args, &reference.scene)?;
        let mut renderer = Renderer::new(&hl.gpu, reference.scene.clone())?;
        renderer.set_environment(req.clone());
        renderer.render(&settings, &hl.target())?;
        for _ in 0..5 {
            frame_ms.push(renderer.render(&settings, &hl.target())?.ms);
        }
        let img = hl.read();
        errors.push(linear_error(&img, &reference.image, &reference.hit).0);
    }
    Ok((median(&frame_ms), errors))
}

impl Results {
    fn new() -> Results {
        let table = Table::new(&[
            "setting",
            "precompute ms",
            "frame ms",
            "mean error",
            "r 0.25",
            "r 0.5",
            "r 0.75",
            "dielectric",
        ]);
        let csv = vec![csv_line(
            &[
                "setting",
                "precompute_ms",
                "frame_ms",
                "mean_error",
                "e_m1_r025",
                "e_m1_r05",
                "e_m1_r075",
                "e_m0_r05",
            ]
            .map(String::from),
        )];
        Results {
            table,
            csv,
            json: Vec::new(),
            points: Vec::new(),
        }
    }

    /// Adds one knob's figures to every output and prints its progress line.
    fn push(&mut self, knob: &Knob, m: Measured) {
        let errors = m.errors;
        let mean = errors.iter().sum::<f64>() / errors.len() as f64;
        let (pre, frame) = (m.precompute_ms, m.frame_ms);
        let mut cells = vec![knob.label.clone(), num(pre, 0), num(frame, 2), num(mean, 4)];
        cells.extend(errors.iter().map(|e| num(*e, 4)));
        self.table.row(cells.clone());
        self.csv.push(csv_line(&cells));
        self.json.push(serde_json::json!({"setting": knob.label, "precompute_ms": pre, "frame_ms": frame, "mean_error": mean, "errors": errors}));
        self.points.push(Point {
            label: knob.label.clone(),
            group: "pbr",
            x: pre,
            y: mean,
            default: knob.label == "default",
        });
        eprintln!(
            "  {}: precompute {pre:.0} ms, frame {frame:.2} ms, error {mean:.4}",
            knob.label
        );
    }

    /// Prints the table and writes `pbr.csv`, `pbr.json` and `pbr.png` into `out_dir`.
    fn write(self, out_dir: &Path) -> Result<()> {
        println!("{}", self.table.render());
        write_file(&out_dir.join("pbr.csv"), &(self.csv.join("\n") + "\n"))?;
        write_file(
            &out_dir.join("pbr.json"),
            &serde_json::to_string_pretty(&self.json).unwrap_or_default(),
        )?;
        plot::error_vs_time(
            &out_dir.join("pbr.png"),
            "PBR tier: precomputation knobs against the Monte Carlo reference (studio HDR)",
            &[Panel {
                x_title: "CPU precompute time (ms), median of 3".into(),
                y_title: "mean linear error on the spheres".into(),
                points: self.points,
            }],
        )?;
        eprintln!("wrote {}", out_dir.join("pbr.{csv,json,png}").display());
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The options built in code equal the command line the bench used to parse, so its
    /// figures are those of `glview models/sphere.obj --shading pbr ...`.
    #[test]
    fn options_equal_their_command_line() {
        let hdr = Path::new("studio.hdr");
        let words = "models/sphere.obj --shading pbr --light none --tonemap none --exposure -1 \
                     --background 1,0,1 --metallic 1 --roughness 0.25 --env studio.hdr \
                     --size 128x128 --multiscatter";
        let words: Vec<&str> = words.split_whitespace().collect();
        let parsed = Options::from_words(words.clone()).expect("the command parses");
        let built = options_for(hdr, 1.0, 0.25, |o| o.pbr.multiscatter = true);
        assert_eq!(built, parsed);
    }
}
