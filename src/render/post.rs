//! Post-processing over an offscreen linear frame (`Post::offscreen`): the lit passes draw
//! into a 16-bit float target with the output step off; then bloom (the first seed
//! document: the bright parts — threshold with a soft knee — blurred with a separable
//! Gaussian on a chain downsampled `levels` times, added back) and the output step into the
//! real target. Needs framebuffer objects with float render targets (GL 3.x, ES 3.0 with
//! EXT_color_buffer_float); elsewhere the frame is drawn directly and `--stats` says bloom
//! was skipped and why.
use super::FrameCx;
use crate::frame::{Bloom, Shading};
use crate::gpu::framebuffer::{ColorAttachment, Framebuffer};
use crate::gpu::state::RenderState;
use crate::gpu::texture::{Pixels, Sampling, Texture2d, TextureFormat};
use crate::gpu::GpuRef;
use crate::shader::cache::{ProgramCache, ProgramKey};
use crate::{Error, Result};

/// A colour texture with its framebuffer.
pub(crate) struct Surface {
    pub color: Texture2d,
    pub fbo: Framebuffer,
}

impl Surface {
    fn new(gpu: &GpuRef, w: u32, h: u32, depth: bool, linear: bool) -> Result<Surface> {
        // The frame itself (depth) is 32-bit float, read texel for texel (nearest): the
        // composite then sees exactly the colour the direct path would have written, so a
        // bloom that adds nothing changes no pixel. The chain is 16-bit, filtered.
        let format = if depth {
            TextureFormat::Rgba32F
        } else {
            TextureFormat::Rgba16F
        };
        let color = Texture2d::new(
            gpu,
            format,
            w,
            h,
            Pixels::None,
            Sampling {
                linear,
                mipmaps: false,
                repeat: false,
            },
        )?;
        let fbo = Framebuffer::color_texture(gpu, ColorAttachment::Level(&color, 0), w, h, depth)?;
        Ok(Surface { color, fbo })
    }
}

#[derive(Default)]
pub(crate) struct PostState {
    /// The offscreen frame, with depth and stencil.
    pub frame: Option<Surface>,
    /// Bright pass and the downsampled chain (level 0 at full size), plus a blur scratch.
    chain: Vec<Surface>,
    scratch: Option<Surface>,
    /// The composited display image FXAA reads.
    display: Option<Surface>,
}

/// Why this context cannot draw offscreen, if it cannot.
pub fn unsupported(gpu: &GpuRef) -> Option<&'static str> {
    let c = &gpu.caps;
    (!(c.fbo && c.float_render && c.half_float_textures))
        .then_some("needs framebuffer objects with float render targets")
}

fn key(frag: &'static str, name: &'static str) -> ProgramKey {
    ProgramKey::new(name, "show_depth.vert", frag)
}

/// The post programs without the composite's output variants (for `--compile-shaders`).
pub fn keys() -> Vec<ProgramKey> {
    vec![
        key("bright.frag", "bright"),
        key("down.frag", "down"),
        key("blur.frag", "blur"),
        composite_key(None),
        composite_key(Some(3)),
        key("fxaa.frag", "fxaa"),
    ]
}

fn composite_key(tonemap: Option<i32>) -> ProgramKey {
    let k = key("composite.frag", "composite");
    match tonemap {
        Some(t) => k.count("TONEMAP", "tm", t),
        None => k,
    }
}

/// Normalised Gaussian weights, centre first, radius ⌈3σ⌉ (at most 32 taps a side).
pub fn gaussian(sigma: f32) -> Vec<f32> {
    let r = ((3.0 * sigma).ceil() as usize).clamp(1, 32);
    let w: Vec<f64> = (0..=r)
        .map(|i| (-((i * i) as f64) / (2.0 * f64::from(sigma) * f64::from(sigma))).exp())
        .collect();
    let sum = w[0] + 2.0 * w[1..].iter().sum::<f64>();
    w.iter().map(|x| (x / sum) as f32).collect()
}

fn ensure(
    slot: &mut Option<Surface>,
    gpu: &GpuRef,
    w: u32,
    h: u32,
    depth: bool,
    linear: bool,
) -> Result<()> {
    if slot
        .as_ref()
        .is_none_or(|s| (s.color.width, s.color.height) != (w, h))
    {
        *slot = Some(Surface::new(gpu, w, h, depth, linear)?);
    }
    Ok(())
}

/// Makes the offscreen frame `w`×`h`, returning its framebuffer.
pub(crate) fn frame_target(
    state: &mut PostState,
    gpu: &GpuRef,
    w: u32,
    h: u32,
) -> Result<glow::Framebuffer> {
    ensure(&mut state.frame, gpu, w, h, true, false)?;
    Ok(state.frame.as_ref().expect("made above").fbo.raw)
}

fn draw_quad(gpu: &GpuRef, quad: &crate::gpu::mesh::GpuMesh, s: &Surface) {
    s.fbo.bind();
    gpu.viewport(0, 0, s.color.width, s.color.height);
    quad.draw();
}

/// Bright pass and blur of `input` (`w`×`h`); returns the index of the blurred level in
/// `state.chain`.
pub(crate) fn bloom(
    gpu: &GpuRef,
    programs: &mut ProgramCache,
    state: &mut PostState,
    quad: &crate::gpu::mesh::GpuMesh,
    input: &Texture2d,
    b: &Bloom,
) -> Result<usize> {
    let (w, h) = (input.width, input.height);
    let levels = b.levels as usize;
    state.chain.truncate(levels + 1);
    for i in 0..=levels {
        let (lw, lh) = ((w >> i).max(1), (h >> i).max(1));
        let fits = state
            .chain
            .get(i)
            .is_some_and(|s| (s.color.width, s.color.height) == (lw, lh));
        if !fits {
            let s = Surface::new(gpu, lw, lh, false, true)?;
            if i < state.chain.len() {
                state.chain[i] = s;
            } else {
                state.chain.push(s);
            }
        }
    }
    let (lw, lh) = ((w >> levels).max(1), (h >> levels).max(1));
    ensure(&mut state.scratch, gpu, lw, lh, false, false)?;
    gpu.apply(&RenderState::overlay());
    let p = programs.get(&key("bright.frag", "bright"))?;
    p.bind();
    input.bind(0);
    p.set_i32("uImage", 0);
    p.set_f32("uThreshold", b.threshold);
    p.set_f32("uKnee", b.knee);
    draw_quad(gpu, quad, &state.chain[0]);
    let p = programs.get(&key("down.frag", "down"))?;
    p.bind();
    p.set_i32("uImage", 0);
    for i in 1..=levels {
        state.chain[i - 1].color.bind(0);
        draw_quad(gpu, quad, &state.chain[i]);
    }
    // The blur reads whole texels: nearest filtering on the level and on the scratch.
    let last = &state.chain[levels];
    last.color.set_filter(false);
    let weights = gaussian(b.sigma / (1u32 << levels) as f32);
    let p = programs.get(&key("blur.frag", "blur"))?;
    p.bind();
    p.set_i32("uImage", 0);
    p.set_i32("uRadius", weights.len() as i32 - 1);
    for (i, w) in weights.iter().enumerate() {
        p.set_f32(&format!("uWeights[{i}]"), *w);
    }
    let scratch = state.scratch.as_ref().expect("made above");
    p.set_vec2("uStep", glam::Vec2::new(1.0 / lw as f32, 0.0));
    last.color.bind(0);
    draw_quad(gpu, quad, scratch);
    p.set_vec2("uStep", glam::Vec2::new(0.0, 1.0 / lh as f32));
    scratch.color.bind(0);
    draw_quad(gpu, quad, last);
    last.color.set_filter(true);
    Ok(levels)
}

/// Composites the offscreen frame (plus bloom) into the real target through the output step.
pub(crate) fn finish(cx: &mut FrameCx, bloom_level: Option<usize>) -> Result<()> {
    let s = cx.settings;
    let tonemap = (s.shading == Shading::Pbr).then(|| s.lighting.output.tonemap.code());
    let p = cx.program(&composite_key(tonemap))?;
    p.bind();
    let frame = cx
        .res
        .post
        .frame
        .as_ref()
        .ok_or_else(|| Error::Unsupported("no offscreen frame".into()))?;
    frame.color.bind(0);
    p.set_i32("uImage", 0);
    let strength = match bloom_level {
        Some(i) => {
            cx.res.post.chain[i].color.bind(1);
            s.lighting.post.bloom.strength
        }
        None => {
            frame.color.bind(1);
            0.0
        }
    };
    p.set_i32("uBloom", 1);
    p.set_f32("uStrength", strength);
    let view = s.lighting.post.show_bloom;
    p.set_f32("uSceneWeight", if view { 0.0 } else { 1.0 });
    p.set_f32("uExposure", 2f32.powf(s.lighting.output.exposure_ev));
    cx.quad()?;
    cx.gpu.apply(&RenderState::overlay());
    let fxaa = s.lighting.post.fxaa;
    if fxaa {
        // Composite into a display image first: FXAA works on what is shown.
        let [_, _, w, h] = cx.viewport;
        ensure(&mut cx.res.post.display, cx.gpu, w, h, false, true)?;
        let d = cx.res.post.display.as_ref().expect("made above");
        d.fbo.bind();
        cx.gpu.viewport(0, 0, w, h);
    } else {
        cx.bind_target();
    }
    if let Some(q) = &cx.res.quad {
        q.draw();
    }
    cx.stats.draw_calls += 1;
    if fxaa {
        let p = cx.program(&key("fxaa.frag", "fxaa"))?;
        p.bind();
        let d = cx.res.post.display.as_ref().expect("made above");
        d.color.bind(0);
        p.set_i32("uImage", 0);
        p.set_vec2(
            "uTexel",
            glam::Vec2::new(1.0 / d.color.width as f32, 1.0 / d.color.height as f32),
        );
        cx.bind_target();
        if let Some(q) = &cx.res.quad {
            q.draw();
        }
        cx.stats.draw_calls += 1;
    }
    cx.gpu.apply(&RenderState::default());
    Ok(())
}

/// The bloom buffer of an image (linear RGB, `w`×`h`, rows bottom-up): bright pass and blur,
/// read back at the blur's resolution. For tests and the teaching view.
pub fn bloom_buffer(
    gpu: &GpuRef,
    rgb: &[f32],
    w: u32,
    h: u32,
    b: &Bloom,
) -> Result<(u32, u32, Vec<f32>)> {
    let programs = ProgramCache::for_context(gpu);
    let mut state = PostState::default();
    let data: Vec<f32> = rgb
        .chunks_exact(3)
        .flat_map(|c| [c[0], c[1], c[2], 1.0])
        .collect();
    let input = Texture2d::new(
        gpu,
        TextureFormat::Rgba16F,
        w,
        h,
        Pixels::F32(&data),
        Sampling {
            linear: true,
            mipmaps: false,
            repeat: false,
        },
    )?;
    let quad = crate::gpu::mesh::GpuMesh::new(gpu, &super::quad_vertices(), &[0, 1, 2, 0, 2, 3])?;
    let level = bloom(
        gpu,
        &mut programs.borrow_mut(),
        &mut state,
        &quad,
        &input,
        b,
    )?;
    let s = &state.chain[level];
    s.fbo.bind();
    let (lw, lh) = (s.color.width, s.color.height);
    let px = gpu.read_rgba_f32(lw, lh);
    gpu.bind_framebuffer(None);
    gpu.apply(&RenderState::default());
    Ok((
        lw,
        lh,
        px.chunks_exact(4)
            .flat_map(|p| [p[0], p[1], p[2]])
            .collect(),
    ))
}
