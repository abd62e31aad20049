//! From parsed arguments to a scene and frame settings; shared by the window and headless
//! paths so `--keys` headless and the keys in a window give the same view.
use crate::camera::OrbitCamera;
use crate::error::{Error, Result};
use crate::frame::{AttributeView, Translucency};
use crate::frame::{FrameSettings, ShadowSettings};
use crate::keys::{self, Effect};
use crate::light::{LightOpt, LightSpec, MAX_LIGHTS};
use crate::options::{Diffuse, Options, Ortho, Show};
use crate::pbr::precompute::IblSettings;
use crate::pbr::{EnvRequest, EnvSource, OutputParams, PbrParams};
use crate::scene::clusters::Clusters;
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
pub fn load_scene(args: &Options) -> Result<Scene> {
    load_scene_with(args, true)
}

/// [`load_scene`], with the warnings printed or not (`--check` lists them in its report).
pub fn load_scene_with(args: &Options, print_warnings: bool) -> Result<Scene> {
    load_scene_prepared_with(args, print_warnings).map(|(scene, _)| scene)
}

/// As [`load_scene`], with the meshes' clusters when the mesh cache had or built them
/// ([`obj::load_prepared`]).
pub fn load_scene_prepared(args: &Options) -> Result<(Scene, Option<Vec<Option<Clusters>>>)> {
    load_scene_prepared_with(args, true)
}

fn load_scene_prepared_with(
    args: &Options,
    print_warnings: bool,
) -> Result<(Scene, Option<Vec<Option<Clusters>>>)> {
    let size = args
        .load
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
            .load
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
    let opts = load_options(args, progress);
    let scene = match &args.load.model {
        Some(path) => obj::load_prepared(path, &opts),
        None => obj::load_embedded(
            Path::new("glass_holder.obj"),
            BUILTIN_OBJ.as_bytes(),
            BUILTIN_MTL.as_bytes(),
            &opts,
        )
        .map(|s| (s, None)),
    };
    if let Some(b) = &bar {
        match &scene {
            Ok((s, _)) => b.finish_with_message(format!("loaded {} triangles", s.triangle_count())),
            Err(_) => b.finish_and_clear(),
        }
    }
    let scene = match scene {
        Ok((mut s, c)) => {
            adjust_scene(args, &mut s)?;
            Ok((s, c))
        }
        other => other,
    };
    // One warning line per problem worked around; `--check` lists them in its report instead.
    if let (Ok((s, _)), true) = (&scene, print_warnings) {
        for w in &s.warnings {
            eprintln!("warning: {w}");
        }
    }
    scene
}

/// What the options change in a loaded scene (a file's, or one a program passed in): the
/// x-rayed materials and objects, and `--single-sided`.
pub(crate) fn adjust_scene(args: &Options, s: &mut crate::scene::Scene) -> Result<()> {
    if !args.load.xray.is_empty() {
        let opacity = args
            .render
            .opacity
            .unwrap_or(crate::scene::xray::XRAY_OPACITY);
        s.xray(&args.load.xray, opacity.clamp(0.0, 1.0))
            .map_err(Error::Usage)?;
    }
    if args.load.single_sided {
        for m in &mut s.materials {
            m.double_sided = false;
        }
    }
    Ok(())
}

/// What the options ask of the loader (the mesh cache's bound is set here too).
pub fn load_options(args: &Options, progress: Option<obj::ProgressFn>) -> LoadOptions {
    crate::scene::cache::set_max_bytes(args.load.cache_size.0);
    // A hit trusts size, time and inode; this also compares the model's content hash.
    crate::scene::cache::set_verify(
        std::env::var_os("GLVIEW_CACHE_VERIFY").is_some_and(|v| v == "1"),
    );
    LoadOptions {
        textures: TextureOptions {
            allow_outside_paths: args.load.allow_outside_paths,
            max_dimension: 0,
        },
        progress,
        cache: args.load.cache,
        honor_transparency: args.load.honor_transparency,
        creases: match (args.load.flat, args.load.crease) {
            (true, _) => crate::scene::normals::Creases::Flat,
            (false, Some(d)) => crate::scene::normals::Creases::Angle(d),
            (false, None) => Default::default(),
        },
        up: args.load.up,
        texture: args.load.texture.clone(),
    }
}

/// The frame settings the options describe, with `--keys` already applied. The options
/// are typed and checked ([`Options::validate`]); this only places them in the scene.
pub fn frame_settings(args: &Options, scene: &Scene) -> Result<(FrameSettings, OrbitCamera)> {
    let (w, h) = args.picture.size;
    let aspect = w as f32 / h as f32;
    let cam = &args.camera;
    let mut camera = OrbitCamera::fit(&scene.bounds, cam.fov, aspect);
    camera.yaw_deg = cam.yaw;
    camera.pitch_deg = cam.pitch;
    if let Some(t) = cam.target {
        camera.target = scene.to_local(glam::DVec3::from_array(t));
    }
    if let Some(d) = cam.distance {
        camera.distance = d;
    }
    camera.near = cam.near;
    match cam.ortho {
        Some(Ortho::Height(h)) => camera.ortho_height = Some(h),
        Some(Ortho::Fit) => {
            camera.ortho_height = Some(OrbitCamera::fit_ortho_height(&scene.bounds, aspect))
        }
        None => {}
    }
    let (lights, headlight, kit) = lights(args, scene);
    let pbr_opts = &args.pbr;
    let pbr = PbrParams {
        base_color: pbr_opts.base_color.map(Vec3::from_array),
        metallic: pbr_opts.metallic,
        roughness: pbr_opts.roughness,
        dominant_direction: pbr_opts.dominant_direction,
        multiscatter: pbr_opts.multiscatter,
        skybox: args.render.background.is_none(),
        skybox_blur: pbr_opts.env_blur,
        ibl_intensity: pbr_opts.ibl_intensity.max(0.0),
    };
    let post = &args.post;
    let mut settings = FrameSettings {
        camera,
        lights,
        lighting: LightingParams {
            ambient: Vec3::from_array(args.light.ambient).as_dvec3(),
            wrap: args.light.diffuse == Diffuse::Wrap,
            pbr,
            pbr_terms: args.render.terms,
            output: OutputParams {
                exposure_ev: pbr_opts.exposure,
                tonemap: pbr_opts.tonemap,
            },
            headlight,
            shadow_casters: match args.shadow.lights {
                Some(n) => n.min(MAX_LIGHTS as u8),
                None if kit => 1,
                None => MAX_LIGHTS as u8,
            },
            translucency: Translucency {
                mode: args.render.translucency,
                blend: args.render.blend,
                opacity: args.render.opacity,
                log_depth: args.render.depth == crate::options::DepthMode::Log,
            },
            post: crate::frame::Post {
                bloom: crate::frame::Bloom {
                    strength: if post.no_bloom {
                        0.0
                    } else {
                        post.bloom.max(0.0)
                    },
                    threshold: post.bloom_threshold,
                    sigma: post.bloom_sigma.clamp(0.5, 64.0),
                    levels: post.bloom_levels,
                    ..Default::default()
                },
                fxaa: post.aa == crate::options::AaMode::Fxaa,
                transparent: post.transparent,
                show_bloom: args.render.show == Show::Bloom,
                linear_out: false,
            },
            attribute_view: match args.render.show {
                Show::Normals => AttributeView::Normals,
                Show::Uvs => AttributeView::Uvs,
                Show::Roughness => AttributeView::Roughness,
                Show::Metallic => AttributeView::Metallic,
                _ => AttributeView::None,
            },
            ..Default::default()
        },
        shading: args.render.shading,
        background: Vec3::from_array(args.background()),
        shadows: ShadowSettings {
            enabled: args.shadow.enabled,
            size: args.shadow.size,
            pcf: args.shadow.pcf,
            bias: args.shadow.bias,
            ..Default::default()
        },
        show_shadow_map: args.render.show == Show::ShadowMap,
    };
    let home = settings.camera;
    if let Some(k) = &cam.keys {
        for action in keys::parse_keys(k).map_err(Error::Usage)? {
            if keys::apply(action, &mut settings, &home, &scene.bounds, aspect) == Effect::Quit {
                break;
            }
        }
    }
    Ok((settings, home))
}

/// The frame's lights in the scene's coordinates, the headlight's colour, and whether they
/// are the default kit (no `--light`): a key light that casts the shadow, a fill from the
/// other side and a headlight, so every side of a model is readable from any orbit.
fn lights(args: &Options, scene: &Scene) -> (Vec<crate::light::Light>, Option<Vec3>, bool) {
    let given = &args.light.lights;
    let mut colors: Vec<Vec3> = args
        .light
        .colors
        .iter()
        .map(|c| Vec3::from_array(*c))
        .collect();
    let pick = |colors: &[Vec3], i: usize| {
        colors
            .get(i)
            .or(colors.last())
            .copied()
            .unwrap_or(Vec3::ONE)
    };
    let mut specs = Vec::new();
    let mut headlight = None;
    for l in given {
        if *l == LightOpt::Head {
            headlight = Some(pick(&colors, specs.len()));
        } else if let Some(spec) = l.spec() {
            specs.push(spec);
        }
    }
    let kit = given.is_empty();
    if kit {
        specs.push(LightSpec::default_light());
        specs.push(LightSpec::fill_light());
        headlight = Some(Vec3::splat(crate::light::KIT_HEAD));
        if colors.is_empty() {
            colors = vec![
                Vec3::splat(crate::light::KIT_KEY),
                Vec3::splat(crate::light::KIT_FILL),
            ];
        }
    }
    let lights = specs
        .iter()
        .enumerate()
        .map(|(i, spec)| spec.to_local(scene.origin, pick(&colors, i)))
        .collect();
    (lights, headlight, kit)
}

/// Where the PBR tier's environment comes from, and how its maps are made.
pub fn env_request(args: &Options) -> Result<EnvRequest> {
    let source = match (&args.pbr.env, args.pbr.env_color) {
        (Some(p), _) => EnvSource::File(p.clone()),
        (None, Some(c)) => EnvSource::Uniform(c),
        (None, None) => EnvSource::Builtin,
    };
    Ok(EnvRequest {
        source,
        settings: IblSettings {
            irradiance_size: args.pbr.irradiance_size,
            specular_size: args.pbr.ibl_size,
            levels: args.pbr.ibl_levels,
            samples: args.pbr.ibl_samples,
            lut_size: args.pbr.lut_size,
            ..Default::default()
        },
        encoding: args.pbr.ibl_encoding,
        cache: args.load.cache,
        precompute: args.pbr.ibl_precompute,
    })
}

/// Who drew a picture, for its PNG text chunks.
pub enum Renderer<'a> {
    Gpu {
        caps: &'a crate::gpu::Caps,
        backend: &'a str,
    },
    Reference,
}

/// What the picture's reproducing command line is made of (see [`crate::repro`]).
pub struct Repro<'a> {
    pub args: &'a Options,
    pub size: (u32, u32),
    pub state_keys: &'a [String],
}

impl<'a> Repro<'a> {
    /// A headless picture: the arguments' own size and keys.
    pub fn headless(args: &'a Options, keys: &'a [String]) -> Self {
        Repro {
            args,
            size: args.picture.size,
            state_keys: keys,
        }
    }
}

/// PNG text chunks that let anyone reproduce a picture: renderer, context, the camera as
/// command-line options and `glview.command`, a whole command line that renders it again.
pub fn png_text(
    r: Renderer,
    s: &FrameSettings,
    scene: &Scene,
    repro: &Repro,
) -> Vec<(&'static str, String)> {
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
    let p = &s.lighting.pbr;
    let o = &s.lighting.output;
    if s.shading == crate::frame::Shading::Pbr {
        text.push((
            "glview.pbr",
            format!(
                "--exposure {} --tonemap {}{}{}{}{}{}",
                o.exposure_ev,
                format!("{:?}", o.tonemap).to_lowercase(),
                p.metallic
                    .map(|m| format!(" --metallic {m}"))
                    .unwrap_or_default(),
                p.roughness
                    .map(|r| format!(" --roughness {r}"))
                    .unwrap_or_default(),
                p.base_color
                    .map(|c| format!(" --base-color {},{},{}", c.x, c.y, c.z))
                    .unwrap_or_default(),
                if p.dominant_direction {
                    " --dominant-direction"
                } else {
                    ""
                },
                if p.multiscatter {
                    " --multiscatter"
                } else {
                    ""
                },
            ),
        ));
    }
    text.extend([
        ("glview.tier", s.shading.tier().into()),
        ("glview.shading", format!("{:?}", s.shading).to_lowercase()),
        ("glview.model", scene.name.clone()),
    ]);
    let camera = format!(
        "--yaw {} --pitch {} --distance {} --target {},{},{} --fov {}{}{}",
        c.yaw_deg,
        c.pitch_deg,
        c.distance,
        target.x,
        target.y,
        target.z,
        c.fov_y_deg,
        c.ortho_height
            .map(|h| format!(" --ortho {h}"))
            .unwrap_or_default(),
        c.near.map(|n| format!(" --near {n}")).unwrap_or_default()
    );
    let shown = crate::repro::shown_options(
        repro.args,
        c,
        target.to_array(),
        repro.size,
        repro.state_keys,
    );
    let command = crate::repro::command_line(&shown);
    text.push(("glview.camera", camera));
    text.push((
        "glview.options",
        serde_json::to_string(&shown).unwrap_or_default(),
    ));
    text.push(("glview.command", command));
    text
}

/// `--show irradiance|specular|lut`: the PBR maps, composed on the CPU from the
/// precomputed data (no GL needed, the same on every context). None for other views.
pub fn map_view(args: &Options) -> Result<Option<crate::image_out::Rgba>> {
    let what = match args.render.show {
        Show::Irradiance => "irradiance",
        Show::Specular => "specular",
        Show::Lut => "lut",
        _ => return Ok(None),
    };
    let (data, _) = crate::render::ibl::load_or_compute(&env_request(args)?)?;
    let out = OutputParams {
        exposure_ev: args.pbr.exposure,
        tonemap: args.pbr.tonemap,
    };
    Ok(crate::pbr::views::view(
        &data,
        what,
        args.render.show_level,
        &out,
    ))
}

/// Renders headless into `path` (`--frames` times; the last frame is written).
pub fn render_headless(args: &Options, path: &Path) -> Result<()> {
    crate::picture::render(args, path, &mut None)
}

/// The framebuffer holds colour multiplied by coverage (blending over a cleared transparent
/// black, resolved or box-filtered edges); PNG wants straight alpha.
pub fn unpremultiply(img: &mut crate::image_out::Rgba) {
    for p in img.data.chunks_exact_mut(4) {
        let a = u32::from(p[3]);
        if a > 0 && a < 255 {
            for c in &mut p[..3] {
                *c = ((u32::from(*c) * 255 + a / 2) / a).min(255) as u8;
            }
        }
    }
}

/// The environment a PBR reference render integrates (None for the legacy tier).
pub fn reference_env(
    args: &Options,
    shading: crate::frame::Shading,
) -> Result<Option<crate::reference::PbrEnv>> {
    if shading != crate::frame::Shading::Pbr {
        return Ok(None);
    }
    let req = env_request(args)?;
    Ok(Some(crate::reference::PbrEnv {
        env: std::sync::Arc::new(crate::pbr::env::Environment::from_source(&req.source)?),
        samples: args.pbr.reference_samples.max(1),
    }))
}

/// `--reference`: the same scene, camera and lights through the CPU reference renderer.
pub fn render_reference(args: &Options, path: &Path) -> Result<()> {
    if args.render.show != Show::Scene {
        return Err(Error::Usage(format!(
            "--show {:?}: the reference renderer draws only the scene; drop --reference for teaching views",
            args.render.show
        )
        .to_lowercase()));
    }
    // The same bound as the GPU path on llvmpipe (its maximum viewport), checked before the
    // model is loaded or any framebuffer allocated.
    const MAX: u32 = 16384;
    if args.picture.size.0 > MAX || args.picture.size.1 > MAX {
        return Err(Error::Usage(format!(
            "--size {}x{}: the reference renderer draws at most {MAX}x{MAX}",
            args.picture.size.0, args.picture.size.1
        )));
    }
    let scene = load_scene(args)?;
    let (settings, _) = frame_settings(args, &scene)?;
    let (w, h) = args.picture.size;
    let start = std::time::Instant::now();
    let env = reference_env(args, settings.shading)?;
    let img = crate::reference::render_env(&scene, &settings, env.as_ref(), w, h);
    let keys = crate::repro::state_keys(args.camera.keys.as_deref());
    let text = png_text(
        Renderer::Reference,
        &settings,
        &scene,
        &Repro::headless(args, &keys),
    );
    img.save(path, &text)?;
    if args.picture.stats {
        println!(
            "{}",
            serde_json::json!({"reference": true, "ms": start.elapsed().as_secs_f64() * 1e3, "triangles": scene.triangle_count()})
        );
    }
    Ok(())
}

/// `--compile-shaders`: every program permutation through the driver's compiler.
pub fn compile_shaders(args: &Options) -> Result<()> {
    let hl = crate::headless::Headless::new(args.context.backend, args.context.gl, 16, 16)?;
    let mut cache = crate::shader::cache::ProgramCache::new(&hl.gpu);
    let keys = crate::render::programs::all_keys(crate::light::MAX_LIGHTS as u8);
    let start = std::time::Instant::now();
    for key in &keys {
        cache.get(key)?;
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
pub fn print_info(args: &Options) -> Result<()> {
    let hl = crate::headless::Headless::new(args.context.backend, args.context.gl, 16, 16)?;
    println!(
        "backend: {}\n{}\nstencil bits (render target): {}",
        hl.backend_name(),
        hl.gpu.caps.report(),
        hl.stencil_bits()
    );
    Ok(())
}
