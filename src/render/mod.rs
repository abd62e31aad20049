//! The frame: which passes run and why. `shadow` fills depth maps (skipped when nothing needs
//! them or nothing changed), `lit` draws the legacy tier, `show` draws the teaching view.
//! Every frame reports what it did in [`FrameStats`].
pub mod frusta;
pub mod lit;
pub mod shadow;

use crate::camera::OrbitCamera;
use crate::gpu::mesh::GpuMesh;
use crate::gpu::texture::Texture2d;
use crate::gpu::GpuRef;
use crate::light::Light;
use crate::scene::Scene;
use crate::shader::cache::ProgramCache;
use crate::shading::LightingParams;
use crate::Result;
use glam::Vec3;
use serde::Serialize;
use std::time::Instant;

#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum, Serialize)]
pub enum Shading {
    Phong,
    Gouraud,
}

#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct ShadowSettings {
    pub enabled: bool,
    /// Depth map size in texels (square).
    pub size: u32,
    /// Compared taps per lookup: 1, 4, 9 or 16.
    pub pcf: u8,
    /// Constant depth bias in [0, 1] depth units, on top of the slope-scaled polygon offset.
    pub bias: f32,
    /// glPolygonOffset(factor, units) in the depth pass: the slope-scaled part of the bias.
    pub slope_bias: f32,
    /// Offset of the lookup point along the surface normal, in shadow-map texels.
    pub normal_offset: f32,
}

impl Default for ShadowSettings {
    fn default() -> Self {
        ShadowSettings {
            enabled: true,
            size: 2048,
            pcf: 1,
            bias: 0.0002,
            slope_bias: 2.0,
            normal_offset: 1.5,
        }
    }
}

/// Everything a frame depends on besides the scene.
#[derive(Clone, Debug, PartialEq)]
pub struct FrameSettings {
    pub camera: OrbitCamera,
    pub lights: Vec<Light>,
    pub lighting: LightingParams,
    pub shading: Shading,
    pub background: Vec3,
    pub shadows: ShadowSettings,
    /// Draw light 0's depth map instead of the scene (teaching view).
    pub show_shadow_map: bool,
}

/// Where a frame goes: a framebuffer object, or the default framebuffer (None).
#[derive(Clone, Copy, Debug)]
pub struct Target {
    pub fbo: Option<glow::Framebuffer>,
    pub width: u32,
    pub height: u32,
}

/// What one frame did; `--stats` prints it as one JSON line.
#[derive(Clone, Debug, Default, Serialize)]
pub struct FrameStats {
    pub frame: u64,
    pub passes: Vec<String>,
    pub shadow: String,
    pub draw_calls: u32,
    pub triangles: u64,
    pub programs: Vec<String>,
    pub textures_bound: u32,
    /// Meshes skipped by the lit pass because their bounding sphere is outside the view.
    pub culled: u32,
    /// CPU wall time of the frame up to glFinish.
    pub ms: f64,
    /// GPU time of the frame (GL_TIME_ELAPSED) where the driver has timer queries.
    pub gpu_ms: Option<f64>,
}

impl FrameStats {
    fn program(&mut self, label: String) {
        if !self.programs.contains(&label) {
            self.programs.push(label);
        }
    }
}

pub(crate) struct DrawMesh {
    pub mesh: GpuMesh,
    pub material: usize,
    pub texture: Option<usize>,
    pub center: Vec3,
    /// Bounding sphere radius around `center`, for frustum culling.
    pub radius: f32,
    pub triangles: u64,
    pub translucent: bool,
}

/// Uploads a decoded texture, downscaled (with a warning) when it exceeds the driver's
/// maximum texture size.
fn upload_texture(gpu: &GpuRef, t: &crate::scene::Texture) -> Result<Texture2d> {
    let max = gpu.caps.max_texture_size.max(1);
    if t.width <= max && t.height <= max {
        return Texture2d::from_rgba(gpu, t.width, t.height, &t.rgba);
    }
    let scale = f64::from(max) / f64::from(t.width.max(t.height));
    let (w, h) = (
        ((f64::from(t.width) * scale) as u32).clamp(1, max),
        ((f64::from(t.height) * scale) as u32).clamp(1, max),
    );
    log::warn!(
        "{}: {}x{} is larger than the driver's maximum texture size {max}: downscaled to {w}x{h}",
        t.path.display(),
        t.width,
        t.height
    );
    let img = image::RgbaImage::from_raw(t.width, t.height, t.rgba.clone()).ok_or_else(|| {
        crate::Error::Unsupported(format!("{}: bad pixel buffer", t.path.display()))
    })?;
    let small = image::imageops::resize(&img, w, h, image::imageops::FilterType::Triangle);
    Texture2d::from_rgba(gpu, w, h, small.as_raw())
}

/// The scene on the GPU plus the passes' cached state.
pub struct Renderer {
    pub gpu: GpuRef,
    pub(crate) scene: Scene,
    pub(crate) meshes: Vec<DrawMesh>,
    pub(crate) textures: Vec<Texture2d>,
    pub(crate) programs: ProgramCache,
    pub(crate) shadow: shadow::ShadowPass,
    pub(crate) quad: Option<GpuMesh>,
    timer: Option<crate::gpu::query::TimerQuery>,
    frame: u64,
}

impl Renderer {
    /// Uploads the scene once (static buffers; textures deduplicated by file).
    pub fn new(gpu: &GpuRef, scene: Scene) -> Result<Renderer> {
        let mut textures: Vec<Texture2d> = Vec::new();
        let mut texture_paths = Vec::new();
        let mut meshes = Vec::with_capacity(scene.meshes.len());
        for m in &scene.meshes {
            let mat = &scene.materials[m.material];
            let texture = match (&mat.diffuse_map, m.has_uv) {
                (Some(t), true) => Some(match texture_paths.iter().position(|p| p == &t.path) {
                    Some(i) => i,
                    None => {
                        textures.push(upload_texture(gpu, t)?);
                        texture_paths.push(t.path.clone());
                        textures.len() - 1
                    }
                }),
                _ => None,
            };
            let mut b = crate::scene::Bounds::empty();
            for v in &m.vertices {
                b.include(v.position.into());
            }
            let center = b.center();
            let radius = m
                .vertices
                .iter()
                .map(|v| (Vec3::from(v.position) - center).length())
                .fold(0.0f32, f32::max);
            meshes.push(DrawMesh {
                mesh: GpuMesh::new(gpu, &m.vertices, &m.indices)?,
                material: m.material,
                texture,
                center,
                radius,
                triangles: m.triangle_count() as u64,
                translucent: mat.is_translucent(),
            });
        }
        gpu.check_error("upload")?;
        let caps = &gpu.caps;
        if !caps.depth_texture || !caps.shadow_compare {
            log::warn!(
                "{}: no depth textures or shadow compare: shadows off",
                caps.version
            );
        }
        Ok(Renderer {
            gpu: gpu.clone(),
            scene,
            meshes,
            textures,
            programs: ProgramCache::new(gpu),
            shadow: shadow::ShadowPass::default(),
            quad: None,
            timer: crate::gpu::query::TimerQuery::new(gpu)?,
            frame: 0,
        })
    }

    pub fn scene(&self) -> &Scene {
        &self.scene
    }

    /// Draws one frame into `target`.
    pub fn render(&mut self, s: &FrameSettings, target: &Target) -> Result<FrameStats> {
        let start = Instant::now();
        self.frame += 1;
        let mut stats = FrameStats {
            frame: self.frame,
            ..Default::default()
        };
        if let Some(t) = &self.timer {
            t.begin();
        }
        // 1. shadow depth pass (or the reason it is skipped)
        shadow::run(self, s, target, &mut stats)?;
        // 2. lit pass
        lit::run(self, s, target, &mut stats)?;
        // 3. teaching view
        if s.show_shadow_map {
            shadow::show_map(self, target, &mut stats)?;
        }
        if cfg!(debug_assertions) {
            self.gpu.check_error("frame")?;
        }
        if let Some(t) = &self.timer {
            t.end();
        }
        self.gpu.finish();
        stats.ms = start.elapsed().as_secs_f64() * 1e3;
        // llvmpipe answers the very first TIME_ELAPSED query of a context with the time since
        // boot; GPU time cannot exceed the wall time up to glFinish, so such a value is dropped.
        stats.gpu_ms = self
            .timer
            .as_ref()
            .map(|t| t.result_ns() as f64 / 1e6)
            .filter(|&g| g <= stats.ms + 1.0);
        Ok(stats)
    }

    /// Makes the next frame render its shadow maps again (e.g. after the geometry changed);
    /// the depth textures themselves are kept for reuse.
    pub fn invalidate_shadows(&mut self) {
        self.shadow.invalidate();
    }
}
