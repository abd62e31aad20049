//! The attribute buffers of a frame for the library API: per pixel the depth along the view
//! axis, the eye-space normal and the object (scene mesh) and material ids. Two draws of the
//! scene's triangle meshes into a float target of the picture's size, with the lit pass's
//! camera, so exactly the pixels the picture shows are covered. Depth alone (no normals, no
//! ids) is read from the frame's own depth buffer where it holds the picture's depth, with no
//! second draw: half the cost of a colour + depth picture (README, Python).
use super::view::lod_view_proj;
use super::Renderer;
use crate::frame::FrameSettings;
use crate::gpu::framebuffer::{ColorAttachment, Framebuffer};
use crate::gpu::mesh::Primitive;
use crate::gpu::state::RenderState;
use crate::gpu::texture::{Pixels, Sampling, Texture2d, TextureFormat};
use crate::shader::cache::ProgramKey;
use crate::{Error, Result};
use glam::Mat3;

/// Attribute buffers, top row first, `width * height` entries each.
#[derive(Clone, Debug, Default)]
pub struct Attributes {
    pub width: u32,
    pub height: u32,
    /// Distance from the eye along the view axis (eye-space −z); infinity where nothing is.
    pub depth: Vec<f32>,
    /// Eye-space unit normal facing the camera (x right, y up, z towards the eye); zero where
    /// nothing is. Empty unless asked for.
    pub normals: Vec<[f32; 3]>,
    /// Index of the scene mesh (object/group) seen; −1 where nothing is.
    pub object_ids: Vec<i32>,
    /// Index of the material seen; −1 where nothing is.
    pub material_ids: Vec<i32>,
}

/// What a render returns besides the colour.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Outputs {
    /// Distance along the view axis per pixel.
    pub depth: bool,
    /// Eye-space normals (a draw and read-back of their own).
    pub normals: bool,
    /// Object and material ids.
    pub ids: bool,
    /// The colour as float32, linear and unclamped (a second frame, kept offscreen).
    pub linear: bool,
}

impl Outputs {
    /// Whether any attribute buffer (depth, normals, ids) is asked for.
    pub fn any(&self) -> bool {
        self.depth || self.normals || self.ids
    }
}

/// Whether a frame's target holds the picture's depth (see [`Renderer::attributes`]), and
/// whether a stencil buffer is beside it (which picks the faster read).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FrameDepth {
    No,
    Depth,
    WithStencil,
}

pub(crate) fn key() -> ProgramKey {
    ProgramKey::new("attributes", "attributes.vert", "attributes.frag")
}

impl Renderer {
    /// The attribute program of a mesh skinned on the GPU (its `SKINNED` variant) with the
    /// view set and its joints; None for any other mesh.
    fn skinned_program(
        &self,
        dm: &super::upload::DrawMesh,
        view: &glam::Mat4,
        proj: &glam::Mat4,
    ) -> Result<Option<std::rc::Rc<crate::gpu::program::Program>>> {
        if dm.skin.is_none() {
            return Ok(None);
        }
        let p = self
            .programs
            .borrow_mut()
            .get(&super::skinning::key(key(), dm.skin))?;
        p.bind();
        p.set_mat4("uModelView", view);
        p.set_mat4("uProjection", proj);
        p.set_mat3("uNormalMatrix", &Mat3::from_mat4(*view));
        super::skinning::set_joints(&p, &self.scene.skins, dm.skin);
        Ok(Some(p))
    }

    /// Draws the attribute buffers of the frame `s` at `width`×`height`, then binds
    /// `target` again (frames expect their target bound: a deleted framebuffer leaves the
    /// context's default one, which a surfaceless EGL context does not have).
    ///
    /// `frame_depth`: whether the target's depth buffer is the frame's, single-sampled, at
    /// the picture's size (no MSAA, no supersampling): then depth alone is read from it.
    pub fn attributes(
        &mut self,
        s: &FrameSettings,
        width: u32,
        height: u32,
        target: &super::Target,
        want: Outputs,
        frame_depth: FrameDepth,
    ) -> Result<Attributes> {
        if want.depth && !want.normals && !want.ids && frame_depth != FrameDepth::No {
            let stencil = frame_depth == FrameDepth::WithStencil;
            if let Some(depth) = self.frame_depth(s, width, height, stencil) {
                return Ok(Attributes {
                    width,
                    height,
                    depth,
                    ..Default::default()
                });
            }
        }
        let normals = want.normals;
        let gpu = self.gpu.clone();
        if !TextureFormat::Rgba32F.supported(&gpu.caps) || !gpu.caps.fbo {
            return Err(Error::Unsupported(format!(
                "depth, normals and ids need float render targets (GL 3.0, ES 3.0 with \
                 EXT_color_buffer_float); {} has none",
                gpu.caps.version
            )));
        }
        let tex = Texture2d::new(
            &gpu,
            TextureFormat::Rgba32F,
            width,
            height,
            Pixels::None,
            Sampling::NEAREST,
        )?;
        let fbo =
            Framebuffer::color_texture(&gpu, ColorAttachment::Level(&tex, 0), width, height, true)?;
        // Levels a draw here uses exist before it, as for the picture's passes.
        let pixels = u64::from(width) * u64::from(height);
        super::cull::build_levels(&mut self.scene, self.lod, self.cull_clusters, pixels)?;
        let program = self.programs.borrow_mut().get(&key())?;
        // Instanced meshes draw with the INSTANCED variant; every instance carries the
        // instanced mesh's id.
        let instanced = match self.scene.meshes.iter().any(|m| m.instances.is_some()) {
            true => Some(self.programs.borrow_mut().get(&key().switch(
                "INSTANCED",
                "inst",
                true,
            ))?),
            false => None,
        };
        let view = s.camera.view();
        let aspect = width as f32 / height.max(1) as f32;
        let proj = s.camera.projection(&self.scene.scene.bounds, aspect);
        for p in std::iter::once(&program).chain(&instanced) {
            p.bind();
            p.set_mat4("uModelView", &view);
            p.set_mat4("uProjection", &proj);
            p.set_mat3("uNormalMatrix", &Mat3::from_mat4(view));
        }
        // The same levels of detail as the picture's lit pass, so ids and depth cover exactly
        // what it drew.
        let lod_view = crate::scene::lod::clusters::ClusterView::new(proj * view).with_lod(
            lod_view_proj(&s.camera, &self.scene.scene.bounds, aspect),
            width,
            height,
            self.lod.error,
        );
        let mut ranges = Vec::new();
        let mut planes = Vec::with_capacity(2);
        // The normals' draw and read-back only when asked: it is half of the pass's time.
        let modes: &[f32] = if normals { &[0.0, 1.0] } else { &[0.0] };
        for &mode in modes {
            fbo.bind();
            gpu.viewport(0, 0, width, height);
            gpu.apply(&RenderState::default());
            gpu.clear_rgba(Some([-1.0, -1.0, -1.0, 0.0]));
            for (i, dm) in self.scene.meshes.iter().enumerate() {
                if dm.primitive == Primitive::Triangles {
                    let skinned = self.skinned_program(dm, &view, &proj)?;
                    let p = match (&dm.instances, &instanced, &skinned) {
                        (_, _, Some(p)) => p,
                        (Some(_), Some(p), _) => p,
                        _ => &program,
                    };
                    p.bind();
                    p.set_f32("uMode", mode);
                    p.set_vec2("uIds", glam::Vec2::new(i as f32, dm.material as f32));
                    let lod =
                        super::cull::uses_lod(self.lod, self.cull_clusters, dm.triangles, pixels);
                    match &dm.clusters {
                        Some(c) if lod => {
                            c.visible(&lod_view, false, &mut ranges);
                            dm.draw_ranges(&self.scene, i, &ranges)?;
                        }
                        _ => dm.draw(&self.scene, i)?,
                    }
                }
            }
            planes.push(top_first(gpu.read_rgba_f32(width, height), width));
        }
        drop(fbo);
        gpu.bind_framebuffer(target.fbo);
        gpu.check_error("attributes")?;
        let ids = &planes[0];
        let normals = planes.get(1).map_or(&[][..], |p| &p[..]);
        let covered = |p: &[f32]| p[3] > 0.5;
        Ok(Attributes {
            width,
            height,
            depth: ids
                .chunks_exact(4)
                .map(|p| if covered(p) { p[2] } else { f32::INFINITY })
                .collect(),
            normals: normals
                .chunks_exact(4)
                .map(|p| {
                    if covered(p) {
                        [p[0], p[1], p[2]]
                    } else {
                        [0.0; 3]
                    }
                })
                .collect(),
            object_ids: ids
                .chunks_exact(4)
                .map(|p| if covered(p) { p[0] as i32 } else { -1 })
                .collect(),
            material_ids: ids
                .chunks_exact(4)
                .map(|p| if covered(p) { p[1] as i32 } else { -1 })
                .collect(),
        })
    }
}

impl Renderer {
    /// The bound target's depth buffer as distances along the view axis (infinity where
    /// nothing was drawn), when it holds exactly the triangles the attribute pass would draw
    /// (the caller has checked that the frame drew straight into it): desktop GL (ES cannot
    /// read depth back), no logarithmic depth (the buffer holds another function of
    /// distance), no lines or points (the attribute pass draws triangles only).
    fn frame_depth(
        &self,
        s: &FrameSettings,
        width: u32,
        height: u32,
        stencil: bool,
    ) -> Option<Vec<f32>> {
        let gpu = &self.gpu;
        if gpu.caps.embedded
            || s.lighting.translucency.log_depth
            || !self.scene.scene.wire.is_empty()
        {
            return None;
        }
        let (mut raw, mut top_first) = gpu.read_depth_u32(width, height, stencil);
        // A framebuffer without the stencil buffer it was taken to have refuses the
        // DEPTH_STENCIL read (INVALID_OPERATION): read the depth alone then.
        if stencil && gpu.check_error("depth read-back").is_err() {
            (raw, top_first) = gpu.read_depth_u32(width, height, false);
        }
        let aspect = width as f32 / height.max(1) as f32;
        let proj = s
            .camera
            .projection(&self.scene.scene.bounds, aspect)
            .as_dmat4();
        Some(depth_distances(&raw, width as usize, top_first, &proj))
    }
}

/// Window depths read as u32 (top row first where `top_first`, else bottom row first) to
/// distances along the view axis, top row first; infinity where the depth is the far
/// plane's (nothing drawn).
///
/// The top 24 bits of each value are the 24-bit buffer's z (a DEPTH_COMPONENT read repeats
/// z's top bits below it, a DEPTH_STENCIL read puts the stencil there), so z = u >> 8,
/// and window depth d = z / Z (Z = 2^24 − 1, also the far plane). With NDC depth 2d − 1
/// and clip z = A·z_eye + B: perspective (clip w = −z_eye) gives distance
/// B / (2d − 1 + A) = K / (z − C), K = B·Z/2, C = (1 − A)·Z/2; orthographic (w = 1) gives
/// (B + 1 − 2d) / A, linear in z. z − C is formed as the integer difference z − ⌊C⌋,
/// exact, then rounded once to f32 (it cancels towards the far plane, where a float depth
/// would lose it), and the fraction of C taken off: so the loop is integer and f32 lanes
/// only, with no branch, and vectorises. Runs of [`RUN`] pixels that are all background
/// (most of a picture of one model) are filled with infinity without dividing.
pub(crate) fn depth_distances(
    raw: &[u32],
    width: usize,
    top_first: bool,
    proj: &glam::DMat4,
) -> Vec<f32> {
    const Z: u32 = (1 << 24) - 1;
    let zf = f64::from(Z);
    let (a, b) = (proj.z_axis.z, proj.w_axis.z);
    let perspective = proj.z_axis.w != 0.0;
    let c = (1.0 - a) * zf / 2.0;
    let (ci, cf) = (c.floor(), (c - c.floor()) as f32);
    // C beyond i32 (far/(far − near) > 128: a near plane at the far one) takes f64 per pixel.
    let wide = !(f64::from(i32::MIN)..=f64::from(i32::MAX)).contains(&ci);
    let ci = ci.clamp(f64::from(i32::MIN), f64::from(i32::MAX)) as i32;
    let k64 = b * zf / 2.0;
    let k = k64 as f32;
    let (p, q) = (((b + 1.0) / a) as f32, (-2.0 / (a * zf)) as f32);
    let width = width.max(1);
    let rows = raw.len() / width;
    let mut out = vec![0f32; rows * width];
    let convert = |dst: &mut [f32], src: &[u32]| {
        if src.iter().all(|&u| u >> 8 == Z) {
            dst.fill(f32::INFINITY);
        } else if perspective && wide {
            for (o, &u) in dst.iter_mut().zip(src) {
                let z = u >> 8;
                let v = (k64 / (f64::from(z) - c)) as f32;
                *o = if z == Z { f32::INFINITY } else { v };
            }
        } else if perspective {
            for (o, &u) in dst.iter_mut().zip(src) {
                let z = u >> 8;
                let v = k / (((z as i32).wrapping_sub(ci)) as f32 - cf);
                *o = if z == Z { f32::INFINITY } else { v };
            }
        } else {
            for (o, &u) in dst.iter_mut().zip(src) {
                let z = u >> 8;
                let v = p + q * z as f32;
                *o = if z == Z { f32::INFINITY } else { v };
            }
        }
    };
    for (r, dst) in out.chunks_exact_mut(width).enumerate() {
        let row = if top_first { r } else { rows - 1 - r };
        let src = &raw[row * width..][..width];
        let mut runs = dst.chunks_exact_mut(RUN).zip(src.chunks_exact(RUN));
        for (d, s) in &mut runs {
            convert(d, s);
        }
        let done = width - width % RUN;
        convert(&mut dst[done..], &src[done..]);
    }
    out
}

/// Pixels per background test in [`depth_distances`].
const RUN: usize = 16;

/// GL's rows are bottom-up; the picture's are top-down (RGBA rows of `width` pixels).
pub(crate) fn top_first(mut data: Vec<f32>, width: u32) -> Vec<f32> {
    let row_bytes = width as usize * 4 * std::mem::size_of::<f32>();
    crate::gpu::flip_rows(bytemuck::cast_slice_mut(&mut data), row_bytes);
    data
}

#[cfg(test)]
mod tests {
    use super::depth_distances;
    use glam::DMat4;

    /// The window depth a 24-bit buffer stores for eye distance `t`, read back as u32 (the
    /// value with its top byte repeated below it, as GL converts it).
    fn stored(proj: &DMat4, t: f64) -> u32 {
        let clip = *proj * glam::DVec4::new(0.0, 0.0, -t, 1.0);
        let d = (clip.z / clip.w + 1.0) / 2.0;
        let z = (d * f64::from((1u32 << 24) - 1)).round() as u32;
        (z << 8) | (z >> 16)
    }

    /// Against the distance the stored 24-bit value stands for, in f64: within a few f32
    /// roundings (the buffer's own step is the larger error, and it is not this function's).
    #[test]
    fn distances_equal_the_f64_inverse_of_the_stored_depth() {
        for proj in [
            DMat4::perspective_rh_gl(0.8, 1.5, 0.05, 400.0),
            DMat4::perspective_rh_gl(0.8, 1.5, 2.0, 9.0),
            // A near plane at the far one: C beyond i32, the f64 path.
            DMat4::perspective_rh_gl(0.8, 1.5, 1.0, 1.001),
            DMat4::orthographic_rh_gl(-2.0, 2.0, -1.5, 1.5, 0.5, 30.0),
        ] {
            let (near, far) = if proj.z_axis.w != 0.0 {
                let (a, b) = (proj.z_axis.z, proj.w_axis.z);
                (b / (a - 1.0), b / (a + 1.0))
            } else {
                let (a, b) = (proj.z_axis.z, proj.w_axis.z);
                ((b + 1.0) / a, (b - 1.0) / a)
            };
            let ts: Vec<f64> = (0..=64)
                .map(|i| near + (far - near) * f64::from(i) / 64.0 * 0.999)
                .collect();
            // Two rows, so the bottom-up order is checked too: the second row is the first
            // row of the picture.
            let mut raw: Vec<u32> = ts.iter().map(|&t| stored(&proj, t)).collect();
            raw.extend(std::iter::repeat_n(u32::MAX, ts.len()));
            let out = depth_distances(&raw, ts.len(), false, &proj);
            let (top, bottom) = out.split_at(ts.len());
            assert!(
                top.iter().all(|v| v.is_infinite()),
                "cleared depth is infinity"
            );
            let same = depth_distances(&raw, ts.len(), true, &proj);
            assert_eq!(
                same[..ts.len()],
                bottom[..],
                "top-first rows are not flipped"
            );
            // A DEPTH_STENCIL read has the stencil byte where the repeated bits were.
            let with_stencil: Vec<u32> = raw.iter().map(|u| u & !0xFF | 0x5A).collect();
            let out_stencil = depth_distances(&with_stencil, ts.len(), false, &proj);
            assert_eq!(out_stencil, out, "the stencil byte changes no distance");
            // Background among drawn pixels, inside a run of 16 and in the last, short one.
            let mut holes = raw.clone();
            holes[5] = u32::MAX;
            holes[64] = u32::MAX;
            let out_holes = depth_distances(&holes, ts.len(), false, &proj);
            for (i, (h, o)) in out_holes[ts.len()..].iter().zip(bottom).enumerate() {
                if i == 5 || i == 64 {
                    assert!(h.is_infinite(), "pixel {i}: {h}");
                } else {
                    assert_eq!(h, o, "pixel {i}");
                }
            }
            for ((&t, &got), &u) in ts.iter().zip(bottom).zip(&raw) {
                let z = f64::from(u >> 8);
                let d = z / f64::from((1u32 << 24) - 1);
                let (a, b) = (proj.z_axis.z, proj.w_axis.z);
                let exact = if proj.z_axis.w != 0.0 {
                    b / (2.0 * d - 1.0 + a)
                } else {
                    (b - (2.0 * d - 1.0)) / a
                };
                let err = (f64::from(got) - exact).abs() / exact;
                assert!(
                    err < 4e-7,
                    "t {t}: {got} against {exact} (relative {err:e})"
                );
                // And near the distance drawn: the buffer's step at this depth.
                assert!((f64::from(got) - t).abs() / t < 2e-3, "t {t}: {got}");
            }
        }
    }
}
