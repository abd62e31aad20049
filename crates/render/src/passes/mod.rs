//! The frame as a list of passes over one frame context. Each pass is a small type in its own
//! file implementing `Pass`: it looks at the context (settings, uploaded scene, resources
//! kept between frames) and either draws or says why it did not. `--stats` lists the passes
//! that ran (`passes`) and every decision (`pass_log`).
//!
//! Frame: shadow depth → background → legacy lit | PBR lit → grid → edges → teaching view →
//! post (post.rs) → guides (the axes triad and the grid's label, in display colour).
pub mod aa;
pub mod attributes;
pub(crate) mod background;
mod cull;
pub(crate) mod edges;
pub(crate) mod frusta;
pub(crate) mod grid;
pub mod guides;
pub mod ibl;
pub mod ibl_gpu;
mod instancing;
pub(crate) mod lit;
pub(crate) mod overlay;
pub(crate) mod pbr;
pub(crate) mod pbr_khr;
mod plan;
mod posed;
pub mod post;
pub mod programs;
pub(crate) mod shadow;
mod shadow_rect;
mod skinning;
mod slots;
mod stereo;
mod textures;
mod tier;
pub(crate) mod translucent;
mod units;
mod upload;
mod view;

pub use crate::frame::{FrameSettings, Shading, ShadowSettings};
use crate::gpu::mesh::GpuMesh;
use crate::gpu::GpuRef;
use crate::scene::{Scene, Vertex};
use crate::shader::cache::{ProgramCache, ProgramKey, SharedPrograms};
use crate::Result;
pub use posed::PoseCost;
use serde::Serialize;
pub(crate) use upload::SceneGpu;

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
    pub(crate) frame: u64,
    /// The passes that drew, in order.
    pub passes: Vec<String>,
    /// Every pass of the frame with what it did or why it was skipped.
    pub(crate) pass_log: Vec<String>,
    /// The shading tier that drew the scene: `legacy` or `pbr`.
    pub(crate) tier: String,
    pub shadow: String,
    pub draw_calls: u32,
    pub triangles: u64,
    pub programs: Vec<String>,
    pub(crate) textures_bound: u32,
    /// Meshes skipped by the lit pass because their bounding sphere is outside the view.
    pub(crate) culled: u32,
    /// Triangles of large meshes not sent to the GPU, in every pass: clusters outside the
    /// view's frustum or, on closed meshes, facing away (`render/cull.rs`).
    pub(crate) triangles_skipped: u64,
    /// Why back faces of a clustered (large) mesh were sent in some pass where a closed mesh's
    /// would have been skipped: `mesh I: REASON`, once per mesh and reason (`render/cull.rs`).
    pub(crate) back_faces_kept: Vec<String>,
    /// The scene's mesh buffers so far: bytes of vertex and index data uploaded, meshes a
    /// draw needed whole after a first view drew their compact copies (a mesh cache hit's,
    /// [`crate::scene::model::meshes`]), and the bytes of the entry read for them.
    pub mesh_bytes_uploaded: u64,
    pub meshes_completed: u32,
    pub mesh_bytes_read_later: u64,
    /// CPU wall time of the frame up to glFinish.
    pub ms: f64,
    /// GPU time of the frame (GL_TIME_ELAPSED) where the driver has timer queries.
    pub(crate) gpu_ms: Option<f64>,
    /// Each post step with its time (ms between glFinish calls), listed when the renderer's
    /// `time_post` is on (`--stats`) and bloom or FXAA ran.
    pub post: Vec<post::PostStep>,
}

impl FrameStats {
    pub(crate) fn program(&mut self, label: String) {
        if !self.programs.contains(&label) {
            self.programs.push(label);
        }
    }
}

/// What a pass did this frame.
pub(crate) enum Outcome {
    /// It drew; the entry for `FrameStats::passes`.
    Ran(String),
    /// It had nothing to do, and why.
    Skipped(String),
}

/// The state passes keep between frames (depth maps, IBL textures, helper geometry).
#[derive(Default)]
pub(crate) struct Resources {
    pub(crate) shadow: shadow::ShadowState,
    pub(crate) ibl: ibl::IblState,
    pub(crate) pbr_textures: Option<pbr::MaterialTextures>,
    /// Material textures of both tiers, made on first use ([`textures::TextureTable`]).
    pub(crate) textures: textures::TextureTable,
    pub(crate) quad: Option<GpuMesh>,
    /// The background pass drew this frame (the lit passes then clear nothing).
    pub(crate) background_drawn: bool,
    pub(crate) post: post::PostState,
    /// The line meshes of `--edges` / `--wireframe`, made on first use.
    pub(crate) edges: edges::EdgeState,
    /// The square of `--grid`, made on first use.
    pub(crate) grid: grid::GridState,
    /// KHR_materials_transmission: the copy of the opaque frame with its mip chain, made on
    /// first use at the frame's size ([`pbr_khr::copy_frame`]).
    pub(crate) transmission: Option<crate::gpu::texture::Texture2d>,
    /// The stereo eyes' targets, made on the first stereo frame.
    pub(crate) stereo: stereo::StereoState,
}

impl Resources {
    /// A full-screen quad (two triangles over clip space), made on first use.
    pub(crate) fn quad(&mut self, gpu: &GpuRef) -> Result<&GpuMesh> {
        if self.quad.is_none() {
            self.quad = Some(GpuMesh::new(gpu, &quad_vertices(), &[0, 1, 2, 0, 2, 3])?);
        }
        Ok(self.quad.as_ref().expect("made above"))
    }
}

/// Everything a pass may use: the GPU, the context's program cache, the uploaded scene, the
/// kept resources, the settings, the target and the rectangle of it to draw into.
pub(crate) struct FrameCx<'a> {
    pub(crate) gpu: &'a GpuRef,
    pub(crate) programs: &'a mut ProgramCache,
    pub(crate) scene: &'a SceneGpu,
    pub(crate) res: &'a mut Resources,
    pub(crate) settings: &'a FrameSettings,
    pub(crate) target: &'a Target,
    /// x, y, width, height in the target (GL convention: y from the bottom).
    pub(crate) viewport: [u32; 4],
    pub(crate) stats: &'a mut FrameStats,
    /// The frame is offscreen: lit passes write linear, unclamped colour (`LINEAR_OUTPUT`).
    pub(crate) linear: bool,
    /// The linear frame is RGBM-encoded in the 8-bit target (bloom on the copy path).
    pub(crate) rgbm: bool,
    /// RGBM only: how lit draws blend in the shader (`uRgbmBlend`: 0 off, 1 alpha, 2 add).
    pub(crate) rgbm_blend: f32,
    /// The view large meshes are culled against, cluster by cluster: set by each pass that
    /// draws meshes (the camera's, or a light's).
    pub(crate) cull: Option<crate::scene::lod::clusters::ClusterView>,
    /// Cluster culling is on ([`Renderer::cull_clusters`]).
    pub(crate) cull_clusters: bool,
    /// Level of detail ([`Renderer::lod`]).
    pub(crate) lod: Lod,
    /// Scratch list of index ranges, kept so draws do not allocate.
    pub(crate) ranges: Vec<(u32, u32)>,
}

impl FrameCx<'_> {
    pub(crate) fn aspect(&self) -> f32 {
        self.viewport[2] as f32 / self.viewport[3].max(1) as f32
    }

    /// Binds the target and the frame's viewport.
    pub(crate) fn bind_target(&self) {
        self.gpu.bind_framebuffer(self.target.fbo);
        let [x, y, w, h] = self.viewport;
        self.gpu.viewport(x, y, w, h);
    }

    /// Clears the frame's rectangle (the whole target without a scissor when it is all of
    /// it); with `--transparent` the colour's alpha is 0.
    pub(crate) fn clear(&self, color: Option<[f32; 3]>) {
        let a = if self.settings.lighting.post.transparent {
            0.0
        } else {
            1.0
        };
        let rgbm = self.rgbm;
        let color = color.map(|[r, g, b]| {
            if rgbm {
                post::rgbm_encode([r, g, b])
            } else {
                [r * a, g * a, b * a, a]
            }
        });
        let t = self.target;
        if self.viewport == [0, 0, t.width, t.height] {
            self.gpu.clear_rgba(color);
        } else {
            self.gpu.clear_rect(self.viewport, color);
        }
    }

    /// Fetches (compiling on first use) a program and records its label in the stats.
    pub(crate) fn program(
        &mut self,
        key: &ProgramKey,
    ) -> Result<std::rc::Rc<crate::gpu::program::Program>> {
        let p = self.programs.get(key)?;
        self.stats.program(key.label());
        Ok(p)
    }

    /// The frame-wide flags every lit program carries: logarithmic depth and the offscreen
    /// frame's linear output.
    pub(crate) fn lit_flags(&self, key: ProgramKey) -> ProgramKey {
        key.switch(
            "LOG_DEPTH",
            "logz",
            self.settings.lighting.translucency.log_depth,
        )
        .switch("LINEAR_OUTPUT", "lin", self.linear)
        .switch("FRAME_RGBM", "hdr8", self.rgbm)
    }

    /// The RGBM blending uniforms of a lit program (no-ops on other programs).
    pub(crate) fn set_rgbm_blend(&self, p: &crate::gpu::program::Program) {
        if self.rgbm {
            let [x, y, w, h] = self.viewport;
            p.set_f32("uRgbmBlend", self.rgbm_blend);
            p.set_i32("uBehind", units::BEHIND_UNIT as i32);
            p.set_vec4(
                "uBehindRect",
                glam::Vec4::new(x as f32, y as f32, w as f32, h as f32),
            );
        }
    }

    /// Draws the full-screen quad with `state` (one draw call).
    pub(crate) fn draw_quad(&mut self, state: &crate::gpu::state::RenderState) -> Result<()> {
        self.quad()?;
        self.gpu.apply(state);
        if let Some(q) = &self.res.quad {
            q.draw();
        }
        self.stats.draw_calls += 1;
        Ok(())
    }

    /// A full-screen quad (two triangles over clip space), made on first use.
    pub(crate) fn quad(&mut self) -> Result<&GpuMesh> {
        self.res.quad(self.gpu)
    }
}

/// The corners of clip space with UVs, for full-screen and overlay quads.
pub(crate) fn quad_vertices() -> [Vertex; 4] {
    let v = |x: f32, y: f32| Vertex {
        position: [x, y, 0.0],
        normal: [0.0, 0.0, 1.0],
        uv: [(x + 1.0) * 0.5, (y + 1.0) * 0.5],
    };
    [v(-1., -1.), v(1., -1.), v(1., 1.), v(-1., 1.)]
}

/// One step of the frame.
pub(crate) trait Pass {
    fn name(&self) -> &'static str;
    fn run(&self, cx: &mut FrameCx) -> Result<Outcome>;
}

/// The frame, in order.
const PASSES: &[&dyn Pass] = &[
    &shadow::ShadowDepth,
    &background::Background,
    &lit::Lit,
    &pbr::Pbr,
    &grid::Grid,
    &edges::Edges,
    &shadow::ShowShadowMap,
];

/// The scene on the GPU, the context's programs and the passes' kept state.
pub struct Renderer {
    pub(crate) gpu: GpuRef,
    pub(crate) scene: SceneGpu,
    programs: SharedPrograms,
    pub(crate) res: Resources,
    timer: Option<crate::gpu::query::TimerQuery>,
    frame: u64,
    /// Time each post step (glFinish before and after): `--stats`.
    pub time_post: bool,
    /// Skip clusters of large meshes the view cannot see (default on; `--no-culling` turns
    /// it off, for comparisons: the same picture but for rare silhouette depth ties).
    pub cull_clusters: bool,
    /// Level of detail of large meshes (`--lod`, `--lod-error`).
    pub lod: Lod,
    /// The moment the scene's meshes are posed at (None: as loaded, the static pose).
    posed: Option<crate::scene::motion::Moment>,
    /// What the last [`Renderer::pose`] that changed something cost.
    pose_cost: PoseCost,
}

/// Which meshes draw coarser levels, and the error bound in pixels (0: none).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Lod {
    pub mode: crate::options::LodMode,
    pub error: f32,
}

impl Default for Lod {
    fn default() -> Lod {
        Lod {
            mode: crate::options::LodMode::Auto,
            error: crate::options::DEFAULT_LOD_ERROR,
        }
    }
}

impl Renderer {
    /// Uploads the scene once (static buffers; textures deduplicated by file).
    pub fn new(gpu: &GpuRef, mut scene: Scene) -> Result<Renderer> {
        let clusters = crate::scene::lod::clusters::prepare(&mut scene);
        Self::prepared(gpu, scene, clusters)
    }

    /// As [`Renderer::new`], with the clusters already prepared (on the loading thread).
    pub fn prepared(
        gpu: &GpuRef,
        scene: Scene,
        clusters: Vec<Option<crate::scene::lod::clusters::Clusters>>,
    ) -> Result<Renderer> {
        Self::skinning(gpu, scene, clusters, skinning::allowed())
    }

    /// As [`Renderer::new`], with every mesh a rig moves posed on the CPU (no skinning on
    /// the GPU): for comparisons (`bench --motion`).
    pub fn cpu_skinned(gpu: &GpuRef, mut scene: Scene) -> Result<Renderer> {
        let clusters = crate::scene::lod::clusters::prepare(&mut scene);
        Self::skinning(gpu, scene, clusters, false)
    }

    fn skinning(
        gpu: &GpuRef,
        scene: Scene,
        clusters: Vec<Option<crate::scene::lod::clusters::Clusters>>,
        gpu_skinning: bool,
    ) -> Result<Renderer> {
        let scene = SceneGpu::new(gpu, scene, clusters, gpu_skinning)?;
        // A scene posed before it was uploaded (a comparison's, a sheet's) is drawn at
        // that moment, and a later pose compares with it.
        let posed = scene.scene.posed;
        Ok(Renderer {
            gpu: gpu.clone(),
            scene,
            programs: ProgramCache::for_context(gpu),
            res: Resources::default(),
            timer: crate::gpu::query::TimerQuery::new(gpu)?,
            frame: 0,
            time_post: false,
            cull_clusters: true,
            lod: Lod::default(),
            posed,
            pose_cost: PoseCost::default(),
        })
    }

    pub fn scene(&self) -> &Scene {
        &self.scene.scene
    }

    /// Where the PBR tier's environment comes from (default: the built-in sky); the maps are
    /// made (or read from the disk cache) when a PBR frame first needs them.
    pub fn set_environment(&mut self, request: crate::pbr::EnvRequest) {
        self.res.ibl.request(request);
    }

    /// Takes its environment maps from (and adds them to) `envs`, the set every renderer
    /// of this context shares, instead of making its own.
    pub fn share_environments(&mut self, envs: ibl::SharedEnvironments) {
        self.res.ibl.share(envs);
    }

    /// Draws one frame into `target`.
    pub fn render(&mut self, s: &FrameSettings, target: &Target) -> Result<FrameStats> {
        self.render_viewport(s, target, [0, 0, target.width, target.height])
    }

    /// Draws one frame into a rectangle of `target` (x, y from the bottom left): a stereo
    /// frame's two eyes composed there ([`stereo`]), else one picture.
    pub fn render_viewport(
        &mut self,
        s: &FrameSettings,
        target: &Target,
        viewport: [u32; 4],
    ) -> Result<FrameStats> {
        if s.stereo.mode.composed() {
            return self.render_stereo(s, target, viewport);
        }
        self.render_mono(s, target, viewport, true)
    }

    /// One picture into a rectangle of `target`; `wait`: end with glFinish (a stereo pair's
    /// first eye does not, so the eyes' work is not serialised by a wait between them).
    fn render_mono(
        &mut self,
        s: &FrameSettings,
        target: &Target,
        viewport: [u32; 4],
        wait: bool,
    ) -> Result<FrameStats> {
        let start = crate::clock::Mark::now();
        let s = &*crate::frame::resolve(s);
        let pixels = u64::from(viewport[2]) * u64::from(viewport[3]);
        cull::build_levels(&mut self.scene, self.lod, self.cull_clusters, pixels)?;
        self.frame += 1;
        let mut stats = FrameStats {
            frame: self.frame,
            tier: s.shading.tier().into(),
            ..Default::default()
        };
        if let Some(t) = &self.timer {
            t.begin();
        }
        {
            let mut programs = self.programs.borrow_mut();
            let plan = plan::FramePlan::new(&self.gpu, &self.scene, s, target, &mut stats)?;
            let (w, h) = (viewport[2], viewport[3]);
            let hdr = if plan.offscreen {
                Target {
                    fbo: Some(post::frame_target(&mut self.res.post, &self.gpu, w, h)?),
                    width: w,
                    height: h,
                }
            } else {
                *target
            };
            let mut cx = FrameCx {
                gpu: &self.gpu,
                programs: &mut programs,
                scene: &self.scene,
                res: &mut self.res,
                settings: s,
                target: &hdr,
                viewport: if plan.offscreen {
                    [0, 0, w, h]
                } else {
                    viewport
                },
                stats: &mut stats,
                linear: plan.offscreen || plan.rgbm,
                rgbm: plan.rgbm,
                rgbm_blend: 0.0,
                cull: None,
                cull_clusters: self.cull_clusters,
                lod: self.lod,
                ranges: Vec::new(),
            };
            run_passes(&mut cx)?;
            if plan.any_post {
                run_post(&mut cx, &plan, target, viewport, self.time_post)?;
            }
            run_pass(&mut cx, &guides::Guides)?;
        }
        stats.mesh_bytes_uploaded = self.scene.uploaded.get();
        stats.meshes_completed = self.scene.completed.get();
        stats.mesh_bytes_read_later = self.scene.scene.meshes.bytes_read_later();
        self.finish_frame(start, &mut stats, wait)?;
        Ok(stats)
    }

    /// Ends the frame: checks for GL errors (debug builds), stops the timer query, waits
    /// for the GPU (glFinish) and records the frame's wall and GPU times in `stats`.
    fn finish_frame(
        &self,
        start: crate::clock::Mark,
        stats: &mut FrameStats,
        wait: bool,
    ) -> Result<()> {
        if cfg!(debug_assertions) {
            self.gpu.check_error("frame")?;
        }
        if let Some(t) = &self.timer {
            t.end();
        }
        if !wait {
            stats.ms = start.ms();
            return Ok(());
        }
        self.gpu.finish();
        stats.ms = start.ms();
        // GPU time cannot exceed the wall time up to glFinish: a driver's nonsense (llvmpipe's
        // first query of a context, which TimerQuery::new spends) is dropped, not reported.
        stats.gpu_ms = self
            .timer
            .as_ref()
            .map(|t| t.result_ns() as f64 / 1e6)
            .filter(|&g| g <= stats.ms + 1.0);
        Ok(())
    }

    /// The last frame drawn with `post.linear_out`: its linear, unclamped colour, RGB per
    /// pixel, top row first.
    pub fn read_linear(&mut self, width: u32, height: u32) -> Result<Vec<[f32; 3]>> {
        // The frame's own image: made at this size by the frame, so nothing is remade here.
        let fbo = post::frame_target(&mut self.res.post, &self.gpu, width, height)?;
        self.gpu.bind_framebuffer(Some(fbo));
        let rgba = attributes::top_first(self.gpu.read_rgba_f32(width, height), width);
        Ok(rgba.chunks_exact(4).map(|p| [p[0], p[1], p[2]]).collect())
    }

    /// Makes the next frame render its shadow maps again (e.g. after the geometry changed);
    /// the depth textures themselves are kept for reuse.
    pub fn invalidate_shadows(&mut self) {
        self.res.shadow.invalidate();
    }
}

/// Runs every pass of [`PASSES`] in order, logging what each did or why it did not.
fn run_passes(cx: &mut FrameCx) -> Result<()> {
    for pass in PASSES {
        run_pass(cx, *pass)?;
    }
    Ok(())
}

/// Runs `pass`, logging what it did or why it did not.
fn run_pass(cx: &mut FrameCx, pass: &dyn Pass) -> Result<()> {
    match pass.run(cx)? {
        Outcome::Ran(entry) => {
            cx.stats.pass_log.push(format!("{}: ran", pass.name()));
            cx.stats.passes.push(entry);
        }
        Outcome::Skipped(why) => cx
            .stats
            .pass_log
            .push(format!("{}: skipped ({why})", pass.name())),
    }
    Ok(())
}

/// The post steps (bloom, FXAA) from the offscreen or RGBM frame into the caller's
/// `target` and `viewport`, which the frame context now points at (display colour).
fn run_post<'a>(
    cx: &mut FrameCx<'a>,
    plan: &plan::FramePlan,
    target: &'a Target,
    viewport: [u32; 4],
    time_post: bool,
) -> Result<()> {
    let mut laps = post::Laps::start(cx.gpu, time_post);
    cx.target = target;
    cx.viewport = viewport;
    cx.linear = false;
    cx.rgbm = false;
    let entry = post::run(cx, plan.bloom, &mut laps)?;
    cx.stats.passes.push(entry);
    cx.stats.pass_log.push(if plan.copy {
        "post: ran (copy-to-texture path: no framebuffer objects with float render targets)".into()
    } else {
        "post: ran".into()
    });
    cx.stats.post = laps.steps;
    Ok(())
}
