//! From parsed arguments to a scene and frame settings; shared by the window and headless
//! paths so `--keys` headless and the keys in a window give the same view.
use crate::camera::OrbitCamera;
use crate::cli::{Args, Diffuse, Show};
use crate::error::{Error, Result};
use crate::keys::{self, Effect};
use crate::light::{parse_vec3, LightSpec, MAX_LIGHTS};
use crate::render::{FrameSettings, ShadowSettings};
use crate::scene::material::TextureOptions;
use crate::scene::obj::{self, LoadOptions};
use crate::scene::Scene;
use crate::shading::LightingParams;
use glam::Vec3;
use std::path::Path;

/// The built-in scene: the committed output of `src/scene/generate.rs`.
pub const BUILTIN_OBJ: &str = include_str!("../models/glass_holder.obj");
pub const BUILTIN_MTL: &str = include_str!("../models/glass_holder.mtl");

/// Loads the model (or the built-in scene). Files that take a while show an indicatif bar
/// on stderr (bytes scanned, then the triangle count); it stays hidden when stderr is not a
/// terminal.
pub fn load_scene(args: &Args) -> Result<Scene> {
    let size = args
        .model
        .as_ref()
        .and_then(|p| std::fs::metadata(p).ok())
        .map_or(0, |m| m.len());
    // About 1 s of loading on a slow machine: below that a bar would only flicker.
    let bar = (size > 16 << 20).then(|| {
        let b = indicatif::ProgressBar::new(size);
        let style = indicatif::ProgressStyle::with_template(
            "{msg} [{bar:30}] {bytes}/{total_bytes} {elapsed}",
        )
        .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar());
        b.set_style(style);
        let name = args
            .model
            .as_ref()
            .map(|p| p.display().to_string())
            .unwrap_or_default();
        b.set_message(format!("loading {name}"));
        b
    });
    let progress = bar.clone().map(|b| {
        std::sync::Arc::new(move |done: u64, _total: u64| b.set_position(done)) as obj::ProgressFn
    });
    let opts = LoadOptions {
        textures: TextureOptions {
            allow_outside_paths: args.allow_outside_paths,
            max_dimension: 0,
        },
        progress,
        cache: !args.no_cache,
        honor_transparency: args.honor_transparency,
        creases: match (args.flat, args.crease) {
            (true, _) => crate::scene::normals::Creases::Flat,
            (false, Some(d)) => crate::scene::normals::Creases::Angle(d),
            (false, None) => Default::default(),
        },
        up: args.up,
        texture: args.texture.clone(),
    };
    let scene = match &args.model {
        Some(path) => obj::load(path, &opts),
        None => obj::load_embedded(
            Path::new("glass_holder.obj"),
            BUILTIN_OBJ.as_bytes(),
            BUILTIN_MTL.as_bytes(),
            &opts,
        ),
    };
    if let Some(b) = &bar {
        match &scene {
            Ok(s) => b.finish_with_message(format!("loaded {} triangles", s.triangle_count())),
            Err(_) => b.finish_and_clear(),
        }
    }
    // One warning line per problem worked around; `--check` lists them in its report instead.
    if let (Ok(s), false) = (&scene, args.check) {
        for w in &s.warnings {
            eprintln!("warning: {w}");
        }
    }
    scene
}

fn color(s: &str, what: &str) -> Result<Vec3> {
    let v = parse_vec3(s).map_err(|e| Error::Usage(format!("{what}: {e}")))?;
    Ok(v.as_vec3())
}

/// The frame settings the arguments describe, with `--keys` already applied.
pub fn frame_settings(args: &Args, scene: &Scene) -> Result<(FrameSettings, OrbitCamera)> {
    let (w, h) = args.size;
    let aspect = w as f32 / h as f32;
    if !(args.fov > 0.0 && args.fov < 180.0) {
        return Err(Error::Usage(format!(
            "--fov {} must be between 0 and 180",
            args.fov
        )));
    }
    let mut camera = OrbitCamera::fit(&scene.bounds, args.fov, aspect);
    camera.yaw_deg = args.yaw;
    camera.pitch_deg = args.pitch;
    if let Some(t) = &args.target {
        let t = parse_vec3(t).map_err(|e| Error::Usage(format!("--target: {e}")))?;
        camera.target = scene.to_local(t);
    }
    if let Some(d) = args.distance {
        if !(d.is_finite() && d > 0.0) {
            return Err(Error::Usage(format!("--distance {d} must be positive")));
        }
        camera.distance = d;
    }
    if let Some(h) = args.ortho {
        if !(h.is_finite() && h > 0.0) {
            return Err(Error::Usage(format!("--ortho {h} must be positive")));
        }
        camera.ortho_height = Some(h);
    }
    if args.lights.len() > 1 && args.lights.iter().any(|l| l == "none") {
        return Err(Error::Usage(
            "--light none means no lights; it cannot be combined with other --light options".into(),
        ));
    }
    let mut specs = Vec::new();
    for l in &args.lights {
        if let Some(spec) = LightSpec::parse(l).map_err(Error::Usage)? {
            specs.push(spec);
        }
    }
    if args.lights.is_empty() {
        specs.push(LightSpec::default_light());
    }
    if specs.len() > MAX_LIGHTS {
        return Err(Error::Usage(format!(
            "{} lights given; at most {MAX_LIGHTS}",
            specs.len()
        )));
    }
    let colors: Vec<Vec3> = args
        .light_colors
        .iter()
        .map(|c| color(c, "--light-color"))
        .collect::<Result<_>>()?;
    let lights = specs
        .iter()
        .enumerate()
        .map(|(i, spec)| {
            let c = colors
                .get(i)
                .or(colors.last())
                .copied()
                .unwrap_or(Vec3::ONE);
            spec.to_local(scene.origin, c)
        })
        .collect();
    let ambient = color(&args.ambient, "--ambient")?.as_dvec3();
    let mut settings = FrameSettings {
        camera,
        lights,
        lighting: LightingParams {
            ambient,
            wrap: args.diffuse == Diffuse::Wrap,
            ..Default::default()
        },
        shading: args.shading,
        background: color(&args.background, "--background")?,
        shadows: ShadowSettings {
            enabled: !args.no_shadows,
            size: args.shadow_size,
            pcf: args.pcf,
            bias: args.shadow_bias,
            ..Default::default()
        },
        show_shadow_map: args.show == Show::ShadowMap,
    };
    let home = settings.camera;
    if let Some(k) = &args.keys {
        for action in keys::parse_keys(k).map_err(Error::Usage)? {
            if keys::apply(action, &mut settings, &home, &scene.bounds, aspect) == Effect::Quit {
                break;
            }
        }
    }
    Ok((settings, home))
}

/// Who drew a picture, for its PNG text chunks.
pub enum Renderer<'a> {
    Gpu {
        caps: &'a crate::gpu::Caps,
        backend: &'a str,
    },
    Reference,
}

/// PNG text chunks that let anyone reproduce a picture: renderer, context and the camera as
/// command-line options.
pub fn png_text(r: Renderer, s: &FrameSettings, scene: &Scene) -> Vec<(&'static str, String)> {
    let mut text = vec![("Software", format!("glview {}", env!("CARGO_PKG_VERSION")))];
    match r {
        Renderer::Gpu { caps, backend } => text.extend([
            ("glview.renderer", caps.renderer.clone()),
            ("glview.gl_version", caps.version.clone()),
            ("glview.dialect", caps.dialect.name().into()),
            ("glview.backend", backend.into()),
        ]),
        Renderer::Reference => text.push((
            "glview.renderer",
            "reference (CPU ray casting, f64, exact shadows)".into(),
        )),
    }
    let c = &s.camera;
    let target = scene.origin + c.target.as_dvec3();
    text.extend([
        ("glview.tier", "legacy".into()),
        ("glview.shading", format!("{:?}", s.shading).to_lowercase()),
        ("glview.model", scene.name.clone()),
        (
            "glview.camera",
            format!(
                "--yaw {} --pitch {} --distance {} --target {},{},{} --fov {}{}",
                c.yaw_deg,
                c.pitch_deg,
                c.distance,
                target.x,
                target.y,
                target.z,
                c.fov_y_deg,
                c.ortho_height
                    .map(|h| format!(" --ortho {h}"))
                    .unwrap_or_default()
            ),
        ),
    ]);
    text
}

/// Renders headless into `path` (`--frames` times; the last frame is written).
pub fn render_headless(args: &Args, path: &Path) -> Result<()> {
    let scene = load_scene(args)?;
    let (settings, _) = frame_settings(args, &scene)?;
    let (w, h) = args.size;
    let hl = crate::headless::Headless::new(args.backend, args.gl, w, h)?;
    let gpu = Renderer::Gpu {
        caps: &hl.gpu.caps,
        backend: hl.backend_name(),
    };
    let text = png_text(gpu, &settings, &scene);
    let mut renderer = crate::render::Renderer::new(&hl.gpu, scene)?;
    for _ in 0..args.frames.max(1) {
        let stats = renderer.render(&settings, &hl.target())?;
        if args.stats {
            println!("{}", serde_json::to_string(&stats).unwrap_or_default());
        }
    }
    let img = hl.read();
    drop(renderer);
    img.save(path, &text)
}

/// `--reference`: the same scene, camera and lights through the CPU reference renderer.
pub fn render_reference(args: &Args, path: &Path) -> Result<()> {
    let scene = load_scene(args)?;
    let (settings, _) = frame_settings(args, &scene)?;
    let (w, h) = args.size;
    let start = std::time::Instant::now();
    let img = crate::reference::render(&scene, &settings, w, h);
    let text = png_text(Renderer::Reference, &settings, &scene);
    img.save(path, &text)?;
    if args.stats {
        println!(
            "{}",
            serde_json::json!({"reference": true, "ms": start.elapsed().as_secs_f64() * 1e3, "triangles": scene.triangle_count()})
        );
    }
    Ok(())
}

/// `--compile-shaders`: every program permutation through the driver's compiler.
pub fn compile_shaders(args: &Args) -> Result<()> {
    let hl = crate::headless::Headless::new(args.backend, args.gl, 16, 16)?;
    let mut cache = crate::shader::cache::ProgramCache::new(&hl.gpu);
    let keys = crate::shader::cache::all_keys(crate::light::MAX_LIGHTS as u8);
    let start = std::time::Instant::now();
    for key in &keys {
        cache.get(*key)?;
    }
    println!(
        "compiled and linked {} programs for {} ({}) in {:.1} s",
        keys.len(),
        hl.gpu.caps.dialect.name(),
        hl.gpu.caps.version,
        start.elapsed().as_secs_f64()
    );
    Ok(())
}

/// `glview --info`: what the driver gave.
pub fn print_info(args: &Args) -> Result<()> {
    let hl = crate::headless::Headless::new(args.backend, args.gl, 16, 16)?;
    println!("backend: {}\n{}", hl.backend_name(), hl.gpu.caps.report());
    Ok(())
}

pub fn main(args: &Args) -> Result<()> {
    if let Some(crate::cli::Command::Bench(b)) = &args.command {
        return match b.soak {
            Some(rounds) => crate::soak::run(args, rounds),
            None => crate::bench::run(&b.bench),
        };
    }
    if args.info {
        return print_info(args);
    }
    if args.compile_shaders {
        return compile_shaders(args);
    }
    if args.reference {
        let out = args
            .output
            .clone()
            .unwrap_or_else(|| "glview-reference.png".into());
        return render_reference(args, &out);
    }
    if args.check {
        let scene = load_scene(args)?;
        print!("{}", crate::scene::report::report(&scene));
        return Ok(());
    }
    if let Some(out) = &args.output {
        return render_headless(args, out);
    }
    if crate::app::display_available() {
        match crate::app::run_window(args) {
            Err(Error::Context(e)) => eprintln!("warning: no window ({e}); rendering headless"),
            other => return other,
        }
    }
    // Never overwrite silently: glview.png, else glview-1.png, glview-2.png, ...
    let out = std::iter::once("glview.png".to_string())
        .chain((1..).map(|i| format!("glview-{i}.png")))
        .map(std::path::PathBuf::from)
        .find(|p| !p.exists())
        .unwrap_or_else(|| "glview.png".into());
    let out = out.as_path();
    render_headless(args, out)?;
    eprintln!("no display: wrote {}", out.display());
    Ok(())
}
