//! The headless modes besides a picture of the scene: the PBR maps as pictures, the CPU
//! reference renderer, every shader compiled, the driver's report.
use super::settings::{load_scene, reference_env};
use super::text::{png_text, Drawer, Repro};
use crate::error::{Error, Result};
use crate::image_out::RgbaFiles;
use crate::options::{Options, Show};
use crate::pbr::OutputParams;
use glview_render::view::settings::env_request;
use std::path::Path;

/// `--show irradiance|specular|lut`: the PBR maps, composed on the CPU from the
/// precomputed data (no GL needed, the same on every context). None for other views.
pub(crate) fn map_view(args: &Options) -> Result<Option<crate::image_out::Rgba>> {
    let what = match args.render.show {
        Show::Irradiance => "irradiance",
        Show::Specular => "specular",
        Show::Lut => "lut",
        _ => return Ok(None),
    };
    let (data, _) = crate::render::ibl::load_or_compute(&env_request(args)?)?;
    let out = OutputParams::from(&args.pbr);
    Ok(crate::pbr::views::view(
        &data,
        what,
        args.render.show_level,
        &out,
    ))
}

/// Renders headless into `path` (`--frames` times; the last frame is written), in a
/// session of its own.
pub fn render_headless(args: &Options, path: &Path) -> Result<()> {
    super::Session::new().write(args, path)
}

/// `--reference`: the same scene, camera and lights through the CPU reference renderer.
pub fn render_reference(args: &Options, path: &Path) -> Result<()> {
    if args.render.show != Show::Scene {
        return Err(Error::Usage(format!(
            "--show {}: the reference renderer draws only the scene; drop --reference for teaching views",
            args.render.show
        )));
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
    let mut scene = load_scene(args)?;
    // Posed as the GPU path poses it, before the camera is fitted to its bounds.
    super::pose_scene(args, &mut scene)?;
    let shown = super::View::settled(args, &scene)?;
    let settings = crate::frame::FrameSettings::new(&shown, &scene)?;
    let (w, h) = args.picture.size;
    let start = std::time::Instant::now();
    let env = reference_env(args, settings.shading)?;
    let img = crate::reference::render_env(&scene, &settings, env.as_ref(), w, h);
    let text = png_text(
        Drawer::Reference,
        &settings,
        &scene,
        &Repro::headless(&shown),
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
    // Every dialect, ES 2.0 / WebGL 1 included, is asked for every program it can draw.
    let (keys, skipped) =
        crate::render::programs::keys_for(&hl.gpu.caps, crate::light::MAX_LIGHTS as u8);
    let start = std::time::Instant::now();
    for key in &keys {
        cache.get(key)?;
    }
    let skipped = if skipped > 0 {
        format!(" ({skipped} that write depth skipped: no EXT_frag_depth)")
    } else {
        String::new()
    };
    println!(
        "compiled and linked {} programs for {} ({}) in {:.1} s{skipped}",
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
