//! From parsed arguments to a scene and frame settings; shared by the window and headless
//! paths so `--keys` headless and the keys in a window give the same view.
use crate::camera::OrbitCamera;
use crate::error::{Error, Result};
use crate::frame::{AttributeView, Translucency};
use crate::frame::{FrameSettings, ShadowSettings};
use crate::keys::{self, Effect};
use crate::light::{parse_vec3, LightSpec, MAX_LIGHTS};
use crate::options::{Diffuse, Options, Show};
use crate::pbr::precompute::IblSettings;
use crate::pbr::{EnvRequest, EnvSource, OutputParams, PbrParams};
use crate::scene::clusters::Clusters;
use crate::scene::material::TextureOptions;
use crate::scene::obj::{self, LoadOptions};
use crate::scene::Scene;
use crate::shading::{LightingParams, PbrTerms};
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
    let opts = load_options(args, progress);
    let scene = match &args.model {
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
    if !args.xray.is_empty() {
        let opacity = args.opacity.unwrap_or(crate::scene::xray::XRAY_OPACITY);
        s.xray(&args.xray, opacity.clamp(0.0, 1.0))
            .map_err(Error::Usage)?;
    }
    if args.single_sided {
        for m in &mut s.materials {
            m.pbr_inputs.model.double_sided = false;
        }
    }
    Ok(())
}

/// What the options ask of the loader (the mesh cache's bound is set here too).
pub fn load_options(args: &Options, progress: Option<obj::ProgressFn>) -> LoadOptions {
    crate::scene::cache::set_max_bytes(args.cache_size);
    // A hit trusts size, time and inode; this also compares the model's content hash.
    crate::scene::cache::set_verify(
        std::env::var_os("GLVIEW_CACHE_VERIFY").is_some_and(|v| v == "1"),
    );
    LoadOptions {
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
    }
}

fn color(s: &str, what: &str) -> Result<Vec3> {
    let v = parse_vec3(s).map_err(|e| Error::Usage(format!("{what}: {e}")))?;
    Ok(v.as_vec3())
}

/// The frame settings the arguments describe, with `--keys` already applied.
pub fn frame_settings(args: &Options, scene: &Scene) -> Result<(FrameSettings, OrbitCamera)> {
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
    if let Some(n) = args.near {
        if !(n.is_finite() && n > 0.0) {
            return Err(Error::Usage(format!("--near {n} must be positive")));
        }
        camera.near = Some(n);
    }
    match args.ortho {
        Some(Some(h)) if !(h.is_finite() && h > 0.0) => {
            return Err(Error::Usage(format!("--ortho {h} must be positive")));
        }
        Some(Some(h)) => camera.ortho_height = Some(h),
        Some(None) => {
            camera.ortho_height = Some(OrbitCamera::fit_ortho_height(&scene.bounds, aspect))
        }
        None => {}
    }
    if args.lights.len() > 1 && args.lights.iter().any(|l| l == "none") {
        return Err(Error::Usage(
            "--light none means no lights; it cannot be combined with other --light options".into(),
        ));
    }
    let mut specs = Vec::new();
    let mut headlight = None;
    let colors: Vec<Vec3> = args
        .light_colors
        .iter()
        .map(|c| color(c, "--light-color"))
        .collect::<Result<_>>()?;
    for l in &args.lights {
        if l == "head" {
            let i = specs.len();
            headlight = Some(
                colors
                    .get(i)
                    .or(colors.last())
                    .copied()
                    .unwrap_or(Vec3::ONE),
            );
        } else if let Some(spec) = LightSpec::parse(l).map_err(Error::Usage)? {
            specs.push(spec);
        }
    }
    // The default kit: a key light that casts the shadow, a fill from the other side and a
    // headlight, so every side of a model is readable from any orbit.
    let kit = args.lights.is_empty();
    let mut kit_colors = Vec::new();
    if kit {
        specs.push(LightSpec::default_light());
        specs.push(LightSpec::fill_light());
        kit_colors = vec![
            Vec3::splat(crate::light::KIT_KEY),
            Vec3::splat(crate::light::KIT_FILL),
        ];
        headlight = Some(Vec3::splat(crate::light::KIT_HEAD));
    }
    if specs.len() + usize::from(headlight.is_some()) > MAX_LIGHTS {
        return Err(Error::Usage(format!(
            "{} lights given; at most {MAX_LIGHTS}",
            specs.len()
        )));
    }
    let colors = if kit && colors.is_empty() {
        kit_colors
    } else {
        colors
    };
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
    let unit = |v: Option<f32>, what: &str| -> Result<Option<f32>> {
        match v {
            Some(x) if !(0.0..=1.0).contains(&x) => {
                Err(Error::Usage(format!("{what} {x} must be between 0 and 1")))
            }
            v => Ok(v),
        }
    };
    let pbr = PbrParams {
        base_color: args
            .base_color
            .as_deref()
            .map(|c| color(c, "--base-color"))
            .transpose()?,
        metallic: unit(args.metallic, "--metallic")?,
        roughness: unit(args.roughness, "--roughness")?,
        dominant_direction: args.dominant_direction,
        multiscatter: args.multiscatter,
        skybox: args.background.is_none(),
        skybox_blur: unit(Some(args.env_blur), "--env-blur")?.unwrap_or(0.0),
        ibl_intensity: args.ibl_intensity.max(0.0),
    };
    if !args.exposure.is_finite() {
        return Err(Error::Usage(format!(
            "--exposure {} must be finite",
            args.exposure
        )));
    }
    let mut settings = FrameSettings {
        camera,
        lights,
        lighting: LightingParams {
            ambient,
            wrap: args.diffuse == Diffuse::Wrap,
            pbr,
            pbr_terms: parse_terms(&args.terms)?,
            output: OutputParams {
                exposure_ev: args.exposure,
                tonemap: args.tonemap,
            },
            headlight,
            shadow_casters: match args.shadow_lights {
                Some(n) => n.min(MAX_LIGHTS as u8),
                None if kit => 1,
                None => MAX_LIGHTS as u8,
            },
            translucency: Translucency {
                mode: args.translucency,
                blend: args.blend,
                opacity: unit(args.opacity, "--opacity")?,
                log_depth: args.depth == crate::options::DepthMode::Log,
            },
            post: crate::frame::Post {
                bloom: crate::frame::Bloom {
                    strength: if args.no_bloom {
                        0.0
                    } else {
                        args.bloom.max(0.0)
                    },
                    threshold: args.bloom_threshold,
                    sigma: args.bloom_sigma.clamp(0.5, 64.0),
                    levels: args.bloom_levels,
                    ..Default::default()
                },
                fxaa: args.aa == crate::options::AaMode::Fxaa,
                transparent: args.transparent,
                show_bloom: args.show == Show::Bloom,
                linear_out: false,
            },
            attribute_view: match args.show {
                Show::Normals => AttributeView::Normals,
                Show::Uvs => AttributeView::Uvs,
                Show::Roughness => AttributeView::Roughness,
                Show::Metallic => AttributeView::Metallic,
                _ => AttributeView::None,
            },
            ..Default::default()
        },
        shading: args.shading,
        background: color(
            args.background.as_deref().unwrap_or(DEFAULT_BACKGROUND),
            "--background",
        )?,
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

/// The background colour without `--background`.
pub const DEFAULT_BACKGROUND: &str = "0.1,0.1,0.12";

/// `--terms a,b,...`: the PBR terms to draw.
pub fn parse_terms(s: &str) -> Result<PbrTerms> {
    let all = PbrTerms::default();
    let none = PbrTerms {
        direct_diffuse: false,
        direct_specular: false,
        ibl_diffuse: false,
        ibl_specular: false,
        ao: false,
        shadows: false,
        emissive: false,
        normal_map: false,
    };
    match s.trim() {
        "all" | "" => return Ok(all),
        "none" => return Ok(none),
        _ => {}
    }
    let mut t = none;
    for name in s.split(',').map(str::trim) {
        let b = match name {
            "direct-diffuse" => &mut t.direct_diffuse,
            "direct-specular" => &mut t.direct_specular,
            "ibl-diffuse" => &mut t.ibl_diffuse,
            "ibl-specular" => &mut t.ibl_specular,
            "ao" => &mut t.ao,
            "shadows" => &mut t.shadows,
            "emissive" => &mut t.emissive,
            "normal-map" => &mut t.normal_map,
            other => {
                return Err(Error::Usage(format!(
                    "--terms: unknown term {other:?} (direct-diffuse, direct-specular, \
                     ibl-diffuse, ibl-specular, ao, shadows, emissive, normal-map, all, none)"
                )))
            }
        };
        *b = true;
    }
    Ok(t)
}

/// Where the PBR tier's environment comes from, and how its maps are made.
pub fn env_request(args: &Options) -> Result<EnvRequest> {
    let source = match (&args.env, &args.env_color) {
        (Some(p), _) => EnvSource::File(p.clone()),
        (None, Some(c)) => {
            let c = color(c, "--env-color")?;
            if c.min_element() < 0.0 {
                return Err(Error::Usage("--env-color must not be negative".into()));
            }
            EnvSource::Uniform(c.to_array())
        }
        (None, None) => EnvSource::Builtin,
    };
    Ok(EnvRequest {
        source,
        settings: IblSettings {
            irradiance_size: args.irradiance_size,
            specular_size: args.ibl_size,
            levels: args.ibl_levels,
            samples: args.ibl_samples,
            lut_size: args.lut_size,
            ..Default::default()
        },
        encoding: args.ibl_encoding,
        cache: !args.no_cache,
        precompute: args.ibl_precompute,
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
            size: args.size,
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
    let command = crate::repro::command_line(repro.args, repro.size, repro.state_keys, &camera);
    text.push(("glview.camera", camera));
    text.push(("glview.command", command));
    text
}

/// `--show irradiance|specular|lut`: the PBR maps, composed on the CPU from the
/// precomputed data (no GL needed, the same on every context). None for other views.
pub fn map_view(args: &Options) -> Result<Option<crate::image_out::Rgba>> {
    let what = match args.show {
        Show::Irradiance => "irradiance",
        Show::Specular => "specular",
        Show::Lut => "lut",
        _ => return Ok(None),
    };
    let (data, _) = crate::render::ibl::load_or_compute(&env_request(args)?)?;
    let out = OutputParams {
        exposure_ev: args.exposure,
        tonemap: args.tonemap,
    };
    Ok(crate::pbr::views::view(&data, what, args.show_level, &out))
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
        samples: args.reference_samples.max(1),
    }))
}

/// `--reference`: the same scene, camera and lights through the CPU reference renderer.
pub fn render_reference(args: &Options, path: &Path) -> Result<()> {
    if args.show != Show::Scene {
        return Err(Error::Usage(format!(
            "--show {:?}: the reference renderer draws only the scene; drop --reference for teaching views",
            args.show
        )
        .to_lowercase()));
    }
    // The same bound as the GPU path on llvmpipe (its maximum viewport), checked before the
    // model is loaded or any framebuffer allocated.
    const MAX: u32 = 16384;
    if args.size.0 > MAX || args.size.1 > MAX {
        return Err(Error::Usage(format!(
            "--size {}x{}: the reference renderer draws at most {MAX}x{MAX}",
            args.size.0, args.size.1
        )));
    }
    let scene = load_scene(args)?;
    let (settings, _) = frame_settings(args, &scene)?;
    let (w, h) = args.size;
    let start = std::time::Instant::now();
    let env = reference_env(args, settings.shading)?;
    let img = crate::reference::render_env(&scene, &settings, env.as_ref(), w, h);
    let keys = crate::repro::state_keys(args.keys.as_deref());
    let text = png_text(
        Renderer::Reference,
        &settings,
        &scene,
        &Repro::headless(args, &keys),
    );
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
pub fn compile_shaders(args: &Options) -> Result<()> {
    let hl = crate::headless::Headless::new(args.backend, args.gl, 16, 16)?;
    let mut cache = crate::shader::cache::ProgramCache::new(&hl.gpu);
    let keys = crate::shader::cache::all_keys(crate::light::MAX_LIGHTS as u8);
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
    let hl = crate::headless::Headless::new(args.backend, args.gl, 16, 16)?;
    println!(
        "backend: {}\n{}\nstencil bits (render target): {}",
        hl.backend_name(),
        hl.gpu.caps.report(),
        hl.stencil_bits()
    );
    Ok(())
}
