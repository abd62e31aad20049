//! Stereo frames: each eye drawn as a whole mono frame into a target of its own (with its
//! own depth and stencil, so the nearest-layer translucency masks each eye as in a mono
//! frame), then both composed into the output rectangle by one full-screen pass
//! (`stereo.frag`) that touches neither depth nor stencil — the virtual-globe thesis's
//! conflict between interlacing and the translucency's stencil mask does not arise.
//!
//! Shared by the pair, done once: the shadow maps (kept while the lights are unchanged), the
//! environment maps, the uploaded scene, the pose, and the level of detail (chosen from the
//! mono camera, `OrbitCamera::centre`, so the eyes never show different levels).
//!
//! Without framebuffer objects (GL 2.1 drivers without FBOs, in a window) each eye is drawn
//! into the output's own lower-left corner and copied into its texture
//! (glCopyTexSubImage2D), then composed the same way: every mode works there too.
use super::{FrameStats, Renderer, Target};
use crate::frame::FrameSettings;
use crate::gpu::framebuffer::{ColorAttachment, Framebuffer};
use crate::gpu::state::RenderState;
use crate::gpu::texture::{Pixels, Sampling, Texture2d, TextureFormat};
use crate::gpu::GpuRef;
use crate::shader::cache::ProgramKey;
use crate::stereo::{anaglyph_matrices, Eye, Layout, StereoMode};
use crate::Result;

/// One eye's picture: a texture, with a framebuffer (depth and stencil) where the driver
/// has framebuffer objects.
struct EyeTarget {
    color: Texture2d,
    fbo: Option<Framebuffer>,
}

/// The eyes' targets, remade when their size changes.
#[derive(Default)]
pub(crate) struct StereoState {
    eyes: Vec<EyeTarget>,
}

pub(crate) fn key() -> ProgramKey {
    ProgramKey::new("stereo", "show_depth.vert", "stereo.frag")
}

fn mode_code(mode: StereoMode) -> i32 {
    match mode {
        StereoMode::SideBySide | StereoMode::SideBySideFull => 1,
        StereoMode::OverUnder => 2,
        StereoMode::Rows => 3,
        StereoMode::Columns => 4,
        StereoMode::Checkerboard => 5,
        _ => 0,
    }
}

impl EyeTarget {
    fn new(gpu: &GpuRef, w: u32, h: u32) -> Result<EyeTarget> {
        let color = Texture2d::new(
            gpu,
            TextureFormat::Rgba8,
            w,
            h,
            Pixels::None,
            Sampling::NEAREST,
        )?;
        let fbo = if gpu.caps.fbo {
            Some(Framebuffer::color_texture(
                gpu,
                ColorAttachment::Level(&color, 0),
                w,
                h,
                true,
            )?)
        } else {
            None
        };
        Ok(EyeTarget { color, fbo })
    }
}

impl Renderer {
    /// Draws `s`'s stereo frame into `viewport` of `target`: both eyes, then the composite.
    /// Returns the pair's stats: the right eye's passes and shadow, both eyes' draws and
    /// triangles, and the time of the whole.
    pub(crate) fn render_stereo(
        &mut self,
        s: &FrameSettings,
        target: &Target,
        viewport: [u32; 4],
    ) -> Result<FrameStats> {
        let start = crate::clock::Mark::now();
        let st = s.stereo;
        let layout = Layout::of(st.mode, viewport[2], viewport[3]);
        let (ew, eh) = layout.eye;
        let gpu = self.gpu.clone();
        let stale = self
            .res
            .stereo
            .eyes
            .first()
            .is_none_or(|e| (e.color.width, e.color.height) != (ew, eh));
        if stale {
            // The old pair goes first: two large targets twice over may not fit.
            self.res.stereo.eyes.clear();
            for _ in 0..2 {
                let e = EyeTarget::new(&gpu, ew, eh)?;
                self.res.stereo.eyes.push(e);
            }
        }
        let mut eye_settings = s.clone();
        eye_settings.stereo.mode = StereoMode::Off;
        let mut pair: Option<FrameStats> = None;
        // Target 0 holds what the left eye's place shows: the right eye when swapped, so
        // the blit and the composite never swap.
        for (i, eye) in [Eye::Left, Eye::Right].into_iter().enumerate() {
            let shown = if st.swap { eye.other() } else { eye };
            eye_settings.camera = layout.eye_camera(&s.camera, shown, &st);
            let fbo = self.res.stereo.eyes[i].fbo.as_ref().map(|f| f.raw);
            let wait = i == 1;
            let stats = match fbo {
                Some(fbo) => {
                    let t = Target {
                        fbo: Some(fbo),
                        width: ew,
                        height: eh,
                    };
                    self.render_mono(&eye_settings, &t, [0, 0, ew, eh], wait)?
                }
                None => {
                    // Copy path: drawn in the output's corner, copied out.
                    let corner = [viewport[0], viewport[1], ew, eh];
                    let stats = self.render_mono(&eye_settings, target, corner, wait)?;
                    gpu.bind_framebuffer(target.fbo);
                    let color = &self.res.stereo.eyes[i].color;
                    color.copy_region_from_framebuffer(0, viewport[0], viewport[1]);
                    stats
                }
            };
            pair = Some(match pair {
                None => stats,
                Some(left) => add_eyes(left, stats),
            });
        }
        // Halves are copied (exact, and a fraction of the composite's cost) where the
        // driver blits; everything else is composed.
        let blit = gpu.caps.fbo && gpu.caps.major >= 3;
        let how = match halves(st.mode, viewport, (ew, eh)).filter(|_| blit) {
            Some(rects) => {
                for (eye, rect) in rects.into_iter().enumerate() {
                    let fbo = self.res.stereo.eyes[eye]
                        .fbo
                        .as_ref()
                        .expect("blit: an FBO");
                    fbo.blit_to(target.fbo, rect);
                }
                "blit"
            }
            None => {
                self.compose(s, target, viewport, (ew, eh))?;
                "composite"
            }
        };
        let mut stats = pair.expect("two eyes");
        stats.passes.push(format!("stereo({}, {how})", st.mode));
        self.gpu.finish();
        // The pair's time: both eyes and the composite, to glFinish.
        stats.ms = start.ms();
        Ok(stats)
    }

    /// A quad-buffered window's frame: each eye drawn whole into its own back buffer
    /// (`target` is the window's default framebuffer, made with stereo buffers).
    pub fn render_quad_buffer(&mut self, s: &FrameSettings, target: &Target) -> Result<FrameStats> {
        let st = s.stereo;
        let (w, h) = (target.width, target.height);
        let layout = Layout::of(StereoMode::QuadBuffer, w, h);
        let mut eye_settings = s.clone();
        eye_settings.stereo.mode = StereoMode::Off;
        let mut pair: Option<FrameStats> = None;
        for eye in [Eye::Left, Eye::Right] {
            let shown = if st.swap { eye.other() } else { eye };
            eye_settings.camera = layout.eye_camera(&s.camera, shown, &st);
            self.gpu.bind_framebuffer(None);
            self.gpu.draw_buffer(match eye {
                Eye::Left => glow::BACK_LEFT,
                Eye::Right => glow::BACK_RIGHT,
            });
            let stats = self.render_mono(&eye_settings, target, [0, 0, w, h], true)?;
            pair = Some(match pair {
                None => stats,
                Some(left) => add_eyes(left, stats),
            });
        }
        self.gpu.bind_framebuffer(None);
        self.gpu.draw_buffer(glow::BACK);
        let mut stats = pair.expect("two eyes");
        stats.passes.push("stereo(quad-buffer)".into());
        Ok(stats)
    }

    /// The composite: every pixel of `viewport` from the eyes' pictures.
    fn compose(
        &mut self,
        s: &FrameSettings,
        target: &Target,
        viewport: [u32; 4],
        (ew, eh): (u32, u32),
    ) -> Result<()> {
        let st = s.stereo;
        let gpu = self.gpu.clone();
        let p = self.programs.borrow_mut().get(&key())?;
        p.bind();
        self.res.stereo.eyes[0].color.bind(0);
        self.res.stereo.eyes[1].color.bind(1);
        p.set_i32("uLeft", 0);
        p.set_i32("uRight", 1);
        p.set_vec2("uEyeSize", glam::Vec2::new(ew as f32, eh as f32));
        p.set_vec2(
            "uOrigin",
            glam::Vec2::new(viewport[0] as f32, viewport[1] as f32),
        );
        p.set_vec2(
            "uOutSize",
            glam::Vec2::new(viewport[2] as f32, viewport[3] as f32),
        );
        p.set_vec2(
            "uParity",
            glam::Vec2::new((st.parity.0 % 2) as f32, (st.parity.1 % 2) as f32),
        );
        p.set_i32("uMode", mode_code(st.mode));
        let (l, r) = anaglyph_matrices(st.method, st.glasses);
        p.set_mat3("uMatLeft", &l);
        p.set_mat3("uMatRight", &r);
        gpu.bind_framebuffer(target.fbo);
        gpu.viewport(viewport[0], viewport[1], viewport[2], viewport[3]);
        gpu.apply(&RenderState::overlay());
        self.res.quad(&gpu)?.draw();
        gpu.apply(&RenderState::default());
        Ok(())
    }
}

/// The pair's stats: the right eye's, with both eyes' draws, triangles and GPU time.
fn add_eyes(left: FrameStats, mut right: FrameStats) -> FrameStats {
    right.draw_calls += left.draw_calls;
    right.triangles += left.triangles;
    right.gpu_ms = left.gpu_ms.zip(right.gpu_ms).map(|(l, r)| l + r);
    right
}

/// The output rectangles (left eye's place first) of the modes whose eyes are halves of
/// the output, each the eye's size: the left eye left (side-by-side) or on top (over-under).
/// None for the others, and for an odd side (the composite repeats the last column or row).
fn halves(mode: StereoMode, [x, y, w, h]: [u32; 4], (ew, eh): (u32, u32)) -> Option<[[u32; 4]; 2]> {
    match mode {
        StereoMode::SideBySide | StereoMode::SideBySideFull if w == 2 * ew => {
            Some([[x, y, ew, h], [x + ew, y, ew, h]])
        }
        // GL counts rows from the bottom: the top half is the upper rectangle.
        StereoMode::OverUnder if h == 2 * eh => Some([[x, y + eh, w, eh], [x, y, w, eh]]),
        _ => None,
    }
}
