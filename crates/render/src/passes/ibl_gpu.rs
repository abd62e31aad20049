//! The split-sum maps computed on the GPU (`--ibl-precompute gpu`): the algorithms of
//! `pbr::precompute` in `prefilter.frag`, one draw per cube face into a 32-bit float
//! texture, read back so the disk cache and the upload stay the CPU path's. The BRDF table
//! is environment-independent and stays on the CPU. Needs framebuffer objects, float render
//! targets and GLSL 3.30 or ES 3.00 (texelFetch, textureLod); GL 2.1 computes on the CPU.
use crate::gpu::framebuffer::{ColorAttachment, Framebuffer};
use crate::gpu::mesh::GpuMesh;
use crate::gpu::state::RenderState;
use crate::gpu::texture::{Pixels, Sampling, Texture2d, TextureFormat};
use crate::gpu::{Dialect, GpuRef};
use crate::pbr::env::Environment;
use crate::pbr::precompute::{self, Cube, IblData, IblSettings};
use crate::shader::cache::{ProgramCache, ProgramKey};
use crate::{Error, Result};
use std::f64::consts::PI;

/// Why this context cannot compute the maps, if it cannot.
pub fn unsupported(gpu: &GpuRef) -> Option<String> {
    let c = &gpu.caps;
    if matches!(c.dialect, Dialect::Glsl120 | Dialect::Glsl100Es) {
        Some(format!(
            "{} has no texelFetch/textureLod in fragment shaders",
            c.dialect.name()
        ))
    } else if !c.fbo || !c.float_render || !c.half_float_textures {
        Some("no float render targets".into())
    } else {
        None
    }
}

/// Whether the driver rasterises on the CPU (llvmpipe, softpipe, swrast): there the rayon
/// precomputation is faster (measured by `glview bench --pbr`).
pub(crate) fn software(gpu: &GpuRef) -> bool {
    let r = gpu.caps.renderer.to_lowercase();
    ["llvmpipe", "softpipe", "swrast", "software"]
        .iter()
        .any(|s| r.contains(s))
}

fn key(mode: i32) -> ProgramKey {
    ProgramKey::new("prefilter", "show_depth.vert", "prefilter.frag").count("MODE", "mode", mode)
}

pub fn compute(
    gpu: &GpuRef,
    programs: &mut ProgramCache,
    env: &Environment,
    s: &IblSettings,
) -> Result<IblData> {
    if let Some(why) = unsupported(gpu) {
        return Err(Error::Unsupported(format!(
            "--ibl-precompute gpu: {} cannot ({why}); use cpu",
            gpu.caps.version
        )));
    }
    let start = crate::clock::Mark::now();
    // The caller's framebuffer, bound back at the end: a surfaceless context has no default
    // framebuffer, and a clear or draw into it fails with GL_INVALID_FRAMEBUFFER_OPERATION.
    let previous = gpu.bound_framebuffer();
    // The CPU's own box-filtered chain, uploaded level by level: the same filtering as the
    // CPU path, and no glGenerateMipmap (which ES 3.0 refuses for RGBA16F).
    let mips = env.mips();
    let data: Vec<Vec<f32>> = mips
        .iter()
        .map(|(t, _, _)| t.iter().flat_map(|p| [p[0], p[1], p[2], 1.0]).collect())
        .collect();
    let levels: Vec<(u32, u32, Pixels)> = mips
        .iter()
        .zip(&data)
        .map(|((_, w, h), d)| (*w as u32, *h as u32, Pixels::F32(d)))
        .collect();
    let env_tex = Texture2d::with_levels(gpu, TextureFormat::Rgba16F, &levels, true)?;
    let quad = GpuMesh::new(gpu, &super::quad_vertices(), &[0, 1, 2, 0, 2, 3])?;
    gpu.apply(&RenderState::overlay());
    let texel_omega = 2.0 * PI * PI / (env.width * env.height) as f64;
    // Irradiance sums the mip level at most 256 wide, as the CPU does.
    let mut level = 0u32;
    let (mut lw, mut lh) = (env.width as u32, env.height as u32);
    while lw > 256 {
        level += 1;
        lw = (lw / 2).max(1);
        lh = (lh / 2).max(1);
    }
    let mut cube = |mode: i32, size: u32, r: f32| -> Result<Cube> {
        let program = programs.get(&key(mode))?;
        program.bind();
        env_tex.bind(0);
        program.set_i32("uEnv", 0);
        program.set_f32("uRoughness", r);
        program.set_i32("uSamples", s.samples as i32);
        program.set_f32("uTexelOmega", texel_omega as f32);
        program.set_i32("uLevel", level as i32);
        program.set_ivec2("uLevelSize", lw as i32, lh as i32);
        let cube_omega = 4.0 * PI / (6.0 * f64::from(size * size));
        program.set_f32(
            "uMirrorLod",
            (0.5 * (cube_omega / texel_omega).log2()) as f32,
        );
        let target = Texture2d::new(
            gpu,
            TextureFormat::Rgba32F,
            size,
            size,
            Pixels::None,
            Sampling::NEAREST,
        )?;
        let fbo =
            Framebuffer::color_texture(gpu, ColorAttachment::Level(&target, 0), size, size, false)?;
        // Creating the target bound it to unit 0: bind the environment again.
        env_tex.bind(0);
        let mut faces = Vec::with_capacity(6);
        for face in 0..6 {
            fbo.bind();
            gpu.viewport(0, 0, size, size);
            program.set_i32("uFace", face);
            quad.draw();
            let px = gpu.read_rgba_f32(size, size);
            faces.push(px.chunks_exact(4).map(|p| [p[0], p[1], p[2]]).collect());
        }
        gpu.bind_framebuffer(previous);
        Ok(Cube { size, faces })
    };
    let irradiance = cube(0, s.irradiance_size, 0.0)?;
    let mut specular = Vec::new();
    for i in 0..s.levels.max(2) {
        specular.push(cube(1, s.level_size(i), s.level_roughness(i))?);
    }
    gpu.finish();
    gpu.check_error("GPU precomputation")?;
    Ok(IblData {
        settings: *s,
        irradiance,
        specular,
        lut: precompute::lut(s.lut_size, s.lut_samples),
        compute_ms: start.ms(),
    })
}
