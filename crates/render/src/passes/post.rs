//! Post-processing after the lit passes: bloom (the first seed document: the bright parts —
//! threshold with a soft knee — blurred with a separable Gaussian on a chain downsampled
//! `levels` times, added back), the output step, then FXAA. Two paths:
//! - **offscreen** (framebuffer objects with float render targets: GL 3.x, ES 3.0 with
//!   EXT_color_buffer_float): the lit passes draw linear and unclamped into a float frame;
//!   every post step draws into its own texture's framebuffer.
//! - **copy** (everything else, e.g. GL 2.1 without framebuffer objects): the lit passes draw
//!   into the target itself — RGBM-encoded linear colour (range 8, `rgbm.glsl`) when bloom is
//!   on, the finished picture otherwise — and each post step draws into the target's
//!   rectangle and is copied into an 8-bit texture with glCopyTexSubImage2D. RGBM does not
//!   blend, so glass blends in its shader over a copy of the frame per draw
//!   (`translucent::draw_states`); `--transparent` skips bloom there, saying so.
//!
//! With `--stats` each step is timed between two glFinish calls (`FrameStats::post`).
use super::FrameCx;
use crate::frame::{Bloom, Shading};
use crate::gpu::framebuffer::{ColorAttachment, Framebuffer};
use crate::gpu::state::RenderState;
use crate::gpu::texture::{Pixels, Sampling, Texture2d, TextureFormat};
use crate::gpu::GpuRef;
use crate::shader::cache::{ProgramCache, ProgramKey};
use crate::{Error, Result};

/// The RGBM range of the copy path's encoded frame (`GLVIEW_RGBM_RANGE` in rgbm.glsl).
pub(crate) const RGBM_RANGE: f32 = 8.0;

/// The CPU twin of `glviewRgbmEncode`: linear RGB to RGBM in [0, 1].
pub(crate) fn rgbm_encode(c: [f32; 3]) -> [f32; 4] {
    let c = c.map(|v| (v / RGBM_RANGE).clamp(0.0, 1.0));
    let m = c.iter().fold(1e-6f32, |a, &b| a.max(b));
    let m = (m * 255.0).ceil() / 255.0;
    [c[0] / m, c[1] / m, c[2] / m, m]
}

/// Decodes 8-bit RGBM.
pub(crate) fn rgbm_decode(p: [u8; 4]) -> [f32; 3] {
    let m = f32::from(p[3]) / 255.0 * RGBM_RANGE;
    [0, 1, 2].map(|i| f32::from(p[i]) / 255.0 * m)
}

/// A colour texture, with its framebuffer on the offscreen path; on the copy path (`fbo`
/// None) it is drawn in the canvas and copied.
pub(crate) struct Surface {
    pub(crate) color: Texture2d,
    pub(crate) fbo: Option<Framebuffer>,
}

impl Surface {
    fn new(gpu: &GpuRef, w: u32, h: u32, depth: bool, linear: bool) -> Result<Surface> {
        let copy = copy_path(gpu);
        // The frame itself (depth) is 32-bit float, read texel for texel (nearest): the
        // composite then sees exactly the colour the direct path would have written, so a
        // bloom that adds nothing changes no pixel. The chain is 16-bit, filtered. On the copy
        // path everything is 8-bit: RGBM (read nearest) or the display image.
        let format = if copy {
            TextureFormat::Rgba8
        } else if depth {
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
        let fbo = if copy {
            None
        } else {
            Some(Framebuffer::color_texture(
                gpu,
                ColorAttachment::Level(&color, 0),
                w,
                h,
                depth,
            )?)
        };
        Ok(Surface { color, fbo })
    }
}

/// Where copy-path steps draw before their copy: the frame's target and the lower-left
/// corner of its rectangle.
#[derive(Clone, Copy, Default)]
pub(crate) struct Canvas {
    pub(crate) fbo: Option<glow::Framebuffer>,
    pub(crate) x: u32,
    pub(crate) y: u32,
}

#[derive(Default)]
pub(crate) struct PostState {
    /// The offscreen frame, with depth and stencil (copy path: the frame's copy).
    pub(crate) frame: Option<Surface>,
    /// Bright pass and the downsampled chain (level 0 at full size), plus a blur scratch.
    chain: Vec<Surface>,
    scratch: Option<Surface>,
    /// The composited display image FXAA reads.
    display: Option<Surface>,
    pub(crate) canvas: Canvas,
    /// Copy path with bloom: the frame translucent surfaces blend over (RGBM, nearest).
    behind: Option<Texture2d>,
}

impl PostState {
    /// The `w`×`h` texture translucent surfaces read what lies behind them from.
    pub(crate) fn behind(&mut self, gpu: &GpuRef, w: u32, h: u32) -> Result<&Texture2d> {
        if self
            .behind
            .as_ref()
            .is_none_or(|t| (t.width, t.height) != (w, h))
        {
            self.behind = Some(Texture2d::new(
                gpu,
                TextureFormat::Rgba8,
                w,
                h,
                Pixels::None,
                Sampling::NEAREST,
            )?);
        }
        Ok(self.behind.as_ref().expect("made above"))
    }
}

/// One timed post step for `--stats`.
#[derive(Clone, Debug, serde::Serialize)]
pub struct PostStep {
    pub pass: String,
    pub ms: f64,
}

/// Times post steps between glFinish calls when on (`--stats`); otherwise only names them.
pub(crate) struct Laps {
    on: bool,
    t: f64,
    pub(crate) steps: Vec<PostStep>,
}

impl Laps {
    /// Waits for the frame so far (when on) and starts the clock.
    pub(crate) fn start(gpu: &GpuRef, on: bool) -> Laps {
        if on {
            gpu.finish();
        }
        Laps {
            on,
            t: crate::clock::now(),
            steps: Vec::new(),
        }
    }

    fn lap(&mut self, gpu: &GpuRef, pass: String) {
        if !self.on {
            return;
        }
        gpu.finish();
        let now = crate::clock::now();
        self.steps.push(PostStep {
            pass,
            ms: now - self.t,
        });
        self.t = now;
    }
}

/// Whether this context post-processes by copying from the target (no framebuffer objects
/// with float render targets).
pub(crate) fn copy_path(gpu: &GpuRef) -> bool {
    let c = &gpu.caps;
    !(c.fbo && c.float_render && c.half_float_textures)
}

fn key(frag: &'static str, name: &'static str, rgbm: bool) -> ProgramKey {
    ProgramKey::new(name, "show_depth.vert", frag).switch("FRAME_RGBM", "hdr8", rgbm)
}

/// The post programs without the composite's output variants (for `--compile-shaders`).
pub(crate) fn keys() -> Vec<ProgramKey> {
    [false, true]
        .into_iter()
        .flat_map(|rgbm| {
            [
                key("bright.frag", "bright", rgbm),
                key("down.frag", "down", rgbm),
                key("blur.frag", "blur", rgbm),
                composite_key(None, rgbm),
                composite_key(Some(3), rgbm),
            ]
        })
        .chain([key("fxaa.frag", "fxaa", false), super::aa::box_key()])
        .collect()
}

fn composite_key(tonemap: Option<i32>, rgbm: bool) -> ProgramKey {
    let k = key("composite.frag", "composite", rgbm);
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

/// Makes the offscreen frame `w`×`h`, returning its framebuffer (offscreen path).
pub(crate) fn frame_target(
    state: &mut PostState,
    gpu: &GpuRef,
    w: u32,
    h: u32,
) -> Result<glow::Framebuffer> {
    ensure(&mut state.frame, gpu, w, h, true, false)?;
    state
        .frame
        .as_ref()
        .and_then(|f| f.fbo.as_ref())
        .map(|f| f.raw)
        .ok_or_else(|| Error::Unsupported("no offscreen frame on the copy path".into()))
}

/// Draws the bound program over all of `s`: into its framebuffer, or on the copy path into
/// the canvas, then copied into its texture.
fn draw_into(gpu: &GpuRef, quad: &crate::gpu::mesh::GpuMesh, s: &Surface, canvas: Canvas) {
    let (w, h) = (s.color.width, s.color.height);
    match &s.fbo {
        Some(f) => {
            f.bind();
            gpu.viewport(0, 0, w, h);
            quad.draw();
        }
        None => {
            gpu.bind_framebuffer(canvas.fbo);
            gpu.viewport(canvas.x, canvas.y, w, h);
            quad.draw();
            s.color.copy_region_from_framebuffer(0, canvas.x, canvas.y);
        }
    }
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
    laps: &mut Laps,
) -> Result<usize> {
    let rgbm = copy_path(gpu);
    let canvas = state.canvas;
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
            // RGBM is read nearest and interpolated after decoding, in the shaders.
            let s = Surface::new(gpu, lw, lh, false, !rgbm)?;
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
    let p = programs.get(&key("bright.frag", "bright", rgbm))?;
    p.bind();
    input.bind(0);
    p.set_i32("uImage", 0);
    p.set_f32("uThreshold", b.threshold);
    p.set_f32("uKnee", b.knee);
    draw_into(gpu, quad, &state.chain[0], canvas);
    laps.lap(gpu, "bright".into());
    let p = programs.get(&key("down.frag", "down", rgbm))?;
    p.bind();
    p.set_i32("uImage", 0);
    for i in 1..=levels {
        let src = &state.chain[i - 1].color;
        p.set_vec2(
            "uSrcTexel",
            glam::Vec2::new(1.0 / src.width as f32, 1.0 / src.height as f32),
        );
        src.bind(0);
        draw_into(gpu, quad, &state.chain[i], canvas);
        laps.lap(gpu, format!("down 1/{}", 1 << i));
    }
    // The blur reads whole texels: nearest filtering on the level and on the scratch.
    let last = &state.chain[levels];
    last.color.set_filter(false);
    let weights = gaussian(b.sigma / (1u32 << levels) as f32);
    let p = programs.get(&key("blur.frag", "blur", rgbm))?;
    p.bind();
    p.set_i32("uImage", 0);
    p.set_i32("uRadius", weights.len() as i32 - 1);
    for (i, w) in weights.iter().enumerate() {
        p.set_f32(&format!("uWeights[{i}]"), *w);
    }
    let scratch = state.scratch.as_ref().expect("made above");
    p.set_vec2("uStep", glam::Vec2::new(1.0 / lw as f32, 0.0));
    last.color.bind(0);
    draw_into(gpu, quad, scratch, canvas);
    p.set_vec2("uStep", glam::Vec2::new(0.0, 1.0 / lh as f32));
    scratch.color.bind(0);
    draw_into(gpu, quad, last, canvas);
    last.color.set_filter(!rgbm);
    laps.lap(gpu, format!("blur 1/{}", 1 << levels));
    Ok(levels)
}

/// The post steps after the lit passes. `bloom`: bloom runs (the frame is linear: the float
/// frame, or on the copy path RGBM in the target); without it on the copy path the target
/// already holds the finished picture and only FXAA runs. `cx.target`/`cx.viewport` are the
/// real target and rectangle when this is called.
pub(crate) fn run(cx: &mut FrameCx, bloom_on: bool, laps: &mut Laps) -> Result<String> {
    let copy = copy_path(cx.gpu);
    let [vx, vy, w, h] = cx.viewport;
    cx.res.post.canvas = Canvas {
        fbo: cx.target.fbo,
        x: vx,
        y: vy,
    };
    cx.quad()?;
    cx.gpu.apply(&RenderState::overlay());
    if copy && bloom_on {
        ensure(&mut cx.res.post.frame, cx.gpu, w, h, true, false)?;
        cx.bind_target();
        let f = cx.res.post.frame.as_ref().expect("made above");
        f.color.copy_region_from_framebuffer(0, vx, vy);
        laps.lap(cx.gpu, "copy frame".into());
    }
    let level = if bloom_on {
        let settings = cx.settings.lighting.post.bloom;
        let r = &mut *cx.res;
        let quad = r.quad.as_ref().expect("made above");
        // The frame is read while the chain is written: take it out meanwhile.
        let frame = r
            .post
            .frame
            .take()
            .ok_or_else(|| Error::Unsupported("no frame to post-process".into()))?;
        let level = bloom(
            cx.gpu,
            cx.programs,
            &mut r.post,
            quad,
            &frame.color,
            &settings,
            laps,
        );
        r.post.frame = Some(frame);
        Some(level?)
    } else {
        None
    };
    let composite = !copy || bloom_on;
    if composite {
        finish(cx, level, laps)?;
    } else {
        // Copy path, FXAA only: the target holds the finished picture.
        ensure(&mut cx.res.post.display, cx.gpu, w, h, false, true)?;
        cx.bind_target();
        let d = cx.res.post.display.as_ref().expect("made above");
        d.color.copy_region_from_framebuffer(0, vx, vy);
        laps.lap(cx.gpu, "copy frame".into());
        fxaa(cx, laps)?;
    }
    cx.gpu.apply(&RenderState::default());
    let path = if copy { "copy, " } else { "" };
    let fx = if cx.settings.lighting.post.fxaa {
        ", fxaa"
    } else {
        ""
    };
    let comp = if composite { "composite" } else { "" };
    Ok(match level {
        Some(l) => format!("post({path}bloom 1/{}, {comp}{fx})", 1 << l),
        None => format!("post({path}{comp}{fx})")
            .replace("(, ", "(")
            .replace(", )", ")"),
    })
}

/// Composites the frame (plus bloom) through the output step into the target, or into the
/// display image when FXAA follows.
fn finish(cx: &mut FrameCx, bloom_level: Option<usize>, laps: &mut Laps) -> Result<()> {
    let rgbm = copy_path(cx.gpu);
    let s = cx.settings;
    if s.lighting.post.fxaa {
        // Made before the inputs are bound: creating a texture binds it on the active unit.
        let [_, _, w, h] = cx.viewport;
        ensure(&mut cx.res.post.display, cx.gpu, w, h, false, true)?;
    }
    let tonemap = (s.shading == Shading::Pbr).then(|| s.lighting.output.tonemap.code());
    let p = cx.program(&composite_key(tonemap, rgbm))?;
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
            let c = &cx.res.post.chain[i].color;
            c.bind(1);
            p.set_vec2(
                "uBloomSize",
                glam::Vec2::new(c.width as f32, c.height as f32),
            );
            let strength = s.lighting.post.bloom.strength;
            if s.lighting.post.show_bloom && strength <= 0.0 {
                1.0
            } else {
                strength
            }
        }
        None => {
            frame.color.bind(1);
            p.set_vec2("uBloomSize", glam::Vec2::ONE);
            0.0
        }
    };
    p.set_i32("uBloom", 1);
    p.set_f32("uStrength", strength);
    let view = s.lighting.post.show_bloom;
    p.set_f32("uSceneWeight", if view { 0.0 } else { 1.0 });
    p.set_f32("uExposure", 2f32.powf(s.lighting.output.exposure_ev));
    cx.gpu.apply(&RenderState::overlay());
    if s.lighting.post.fxaa {
        // Composite into a display image first: FXAA works on what is shown.
        let r = &*cx.res;
        let d = r.post.display.as_ref().expect("made above");
        draw_into(
            cx.gpu,
            r.quad.as_ref().expect("made above"),
            d,
            r.post.canvas,
        );
        cx.stats.draw_calls += 1;
        laps.lap(cx.gpu, "composite".into());
        fxaa(cx, laps)?;
    } else {
        cx.bind_target();
        if let Some(q) = &cx.res.quad {
            q.draw();
        }
        cx.stats.draw_calls += 1;
        laps.lap(cx.gpu, "composite".into());
    }
    Ok(())
}

/// FXAA from the display image into the target.
fn fxaa(cx: &mut FrameCx, laps: &mut Laps) -> Result<()> {
    let p = cx.program(&key("fxaa.frag", "fxaa", false))?;
    p.bind();
    let d = cx.res.post.display.as_ref().expect("made by the caller");
    d.color.bind(0);
    p.set_i32("uImage", 0);
    p.set_vec2(
        "uTexel",
        glam::Vec2::new(1.0 / d.color.width as f32, 1.0 / d.color.height as f32),
    );
    cx.gpu.apply(&RenderState::overlay());
    cx.bind_target();
    if let Some(q) = &cx.res.quad {
        q.draw();
    }
    cx.stats.draw_calls += 1;
    laps.lap(cx.gpu, "fxaa".into());
    Ok(())
}

/// The bloom buffer of an image (linear RGB, `w`×`h`, rows bottom-up): bright pass and blur,
/// read back at the blur's resolution. For tests and the teaching view. On the copy path the
/// image goes in RGBM-encoded and the steps draw in the lower-left corner of the default
/// framebuffer (which must be at least `w`×`h`).
pub fn bloom_buffer(
    gpu: &GpuRef,
    rgb: &[f32],
    w: u32,
    h: u32,
    b: &Bloom,
) -> Result<(u32, u32, Vec<f32>)> {
    let copy = copy_path(gpu);
    let programs = ProgramCache::for_context(gpu);
    let mut state = PostState::default();
    let data: Vec<f32> = rgb
        .chunks_exact(3)
        .flat_map(|c| {
            if copy {
                rgbm_encode([c[0], c[1], c[2]])
            } else {
                [c[0], c[1], c[2], 1.0]
            }
        })
        .collect();
    let bytes: Vec<u8> = data
        .iter()
        .map(|v| (v * 255.0).round().clamp(0.0, 255.0) as u8)
        .collect();
    let input = Texture2d::new(
        gpu,
        if copy {
            TextureFormat::Rgba8
        } else {
            TextureFormat::Rgba16F
        },
        w,
        h,
        if copy {
            Pixels::U8(&bytes)
        } else {
            Pixels::F32(&data)
        },
        Sampling {
            linear: !copy,
            mipmaps: false,
            repeat: false,
        },
    )?;
    let quad = crate::gpu::mesh::GpuMesh::new(gpu, &super::quad_vertices(), &[0, 1, 2, 0, 2, 3])?;
    let mut laps = Laps::start(gpu, false);
    let level = bloom(
        gpu,
        &mut programs.borrow_mut(),
        &mut state,
        &quad,
        &input,
        b,
        &mut laps,
    )?;
    let s = &state.chain[level];
    let (lw, lh) = (s.color.width, s.color.height);
    let out = match &s.fbo {
        Some(f) => {
            f.bind();
            gpu.read_rgba_f32(lw, lh)
                .chunks_exact(4)
                .flat_map(|p| [p[0], p[1], p[2]])
                .collect()
        }
        None => {
            // The last step drew the blurred level in the corner of the default framebuffer.
            gpu.bind_framebuffer(None);
            let mut px = gpu.read_rgba(lw, lh);
            crate::gpu::flip_rows(&mut px, lw as usize * 4);
            px.chunks_exact(4)
                .flat_map(|p| rgbm_decode([p[0], p[1], p[2], p[3]]))
                .collect()
        }
    };
    gpu.bind_framebuffer(None);
    gpu.apply(&RenderState::default());
    Ok((lw, lh, out))
}
