//! CPU reference renderer: the ground truth the GPU path is measured against. One ray per pixel
//! centre, in f64 throughout, through a BVH; the shading formula of `shading.rs` on the
//! interpolated normal; exact hard shadows by shadow rays (the limit a shadow map approaches).
//!
//! It means what the GPU frame means (see `render/lit.rs`): the same camera, near/far clipping,
//! back faces shaded with the flipped normal, opaque surfaces first and translucent ones blended
//! over them with (SRC_ALPHA, ONE_MINUS_SRC_ALPHA), translucent meshes casting no shadows.
//! Known differences, all where the GPU approximates:
//! - shadows are exact (no map resolution, PCF or bias);
//! - translucency: with `nearest` (the command line's default) only the nearest translucent
//!   layer blends, over the opaque surface or over black where there is none (the background
//!   is drawn only where nothing was), exactly as the GPU does it; with `sorted` the layers
//!   are composited per pixel far to near in f64, while the GPU sorts whole meshes by their
//!   centres, so interpenetrating or self-overlapping translucent meshes can differ;
//! - textures are sampled at level 0 with the magnification filter (the GPU may use mipmaps
//!   where the texture is minified); the material model otherwise as the shaders read it
//!   (`material`: samplers, UV sets, texture transforms, alpha modes, sidedness, normal maps);
//! - `show_shadow_map` (a teaching view) is ignored;
//! - `--grid`: the plane and its lines as the GPU draws them (`grid`); `--axes` and the
//!   grid's label (drawn over the finished picture, `render/guides.rs`) are not drawn.
//!
//! Measured on the built-in scene at 640×480 (llvmpipe): with `--no-shadows`, pixels without
//! a translucent layer agree to a mean of 0.000/255 (2 of 294k pixels off by more than 8/255,
//! on edges); the glass differs by its blend order, and shadows by the shadow map's
//! approximations. See `gpu_against_reference_builtin` in tests/suite/reference.rs.
pub(crate) mod bvh;
pub(crate) mod edges;
pub(crate) mod grid;
pub(crate) mod layers;
pub(crate) mod material;
pub(crate) mod pbr;
pub(crate) mod points;
pub(crate) mod surface;
pub(crate) mod transmission;
pub(crate) mod view;

use crate::frame::FrameSettings;
use crate::image_out::Rgba;
use crate::light::MAX_LIGHTS;
use crate::scene::Scene;
use bvh::{Bvh, Hit, TriRef};
use glam::DVec3;
use rayon::prelude::*;
use view::View;

/// What the reference saw at one pixel.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PixelInfo {
    /// Mesh of the nearest surface (opaque or translucent); None where the background shows.
    pub mesh: Option<usize>,
    /// Distance from the eye to that surface.
    pub distance: f64,
    /// Per light: whether that surface's shadow ray was blocked.
    pub shadowed: [bool; MAX_LIGHTS],
    /// Translucent layers blended over the opaque surface (or the background).
    pub layers: u32,
}

impl PixelInfo {
    pub fn hit(&self) -> bool {
        self.mesh.is_some()
    }
}

/// Everything shared by all pixels of one render.
pub(crate) struct Context<'a> {
    pub(crate) scene: &'a Scene,
    pub(crate) settings: &'a FrameSettings,
    pub(crate) view: View,
    /// Output size in pixels.
    pub(crate) size: (u32, u32),
    /// Opaque triangles: primary hits and shadow casters.
    pub(crate) opaque: Bvh,
    /// Translucent triangles: blended layers only.
    pub(crate) translucent: Bvh,
    pub(crate) shadows: bool,
    /// Shadow-ray offset; see `surface::light_visible`.
    pub(crate) epsilon: f64,
    /// The PBR tier's environment (None: the tier gets no image-based light).
    pub(crate) env: Option<std::sync::Arc<crate::pbr::env::Environment>>,
    /// Monte Carlo samples per lobe for the PBR tier's image-based light.
    pub(crate) pbr_samples: u32,
    /// Per mesh: the shadow-terminator lift (see `surface::light_visible`).
    pub(crate) terminator_lift: Vec<f64>,
    /// Per mesh: MikkTSpace tangents where a normal map needs them and the file gave none,
    /// as the upload makes them (empty otherwise).
    pub(crate) generated_tangents: Vec<Vec<[f32; 4]>>,
    /// `--edges` / `--wireframe`: the projected segments.
    pub(crate) edges: Option<edges::ScreenEdges>,
    /// `--grid`: the ray-cast ground plane.
    pub(crate) grid: Option<grid::RefGrid>,
}

impl<'a> Context<'a> {
    pub(crate) fn new(
        scene: &'a Scene,
        settings: &'a FrameSettings,
        width: u32,
        height: u32,
    ) -> Self {
        let (mut opaque, mut translucent) = (Vec::new(), Vec::new());
        for (mi, mesh) in scene.meshes.iter().enumerate() {
            let glass = scene
                .materials
                .get(mesh.material)
                .is_some_and(|m| m.is_translucent());
            let out = if glass { &mut translucent } else { &mut opaque };
            for (ti, idx) in mesh.indices.chunks_exact(3).enumerate() {
                let p =
                    |k: usize| DVec3::from(mesh.vertices[idx[k] as usize].position.map(f64::from));
                let tri = TriRef {
                    mesh: mi as u32,
                    tri: ti as u32,
                };
                out.push(([p(0), p(1), p(2)], tri));
            }
        }
        let mut ctx = Context {
            scene,
            settings,
            view: View::new(&settings.camera, &scene.bounds, width, height),
            size: (width, height),
            opaque: Bvh::build(opaque),
            translucent: Bvh::build(translucent),
            shadows: settings.shadows.enabled && !settings.lights.is_empty(),
            epsilon: 1e-7 * f64::from(scene.bounds.radius()),
            env: None,
            pbr_samples: pbr::DEFAULT_SAMPLES,
            terminator_lift: scene
                .meshes
                .iter()
                .map(crate::scene::terminator_lift)
                .collect(),
            generated_tangents: scene
                .meshes
                .iter()
                .map(|m| {
                    let mapped = scene
                        .materials
                        .get(m.material)
                        .is_some_and(|x| x.needs_tangents());
                    if m.has_uv && mapped && m.tangents.len() != m.vertices.len() {
                        crate::scene::geometry::tangents::generate(m)
                    } else {
                        Vec::new()
                    }
                })
                .collect(),
            edges: None,
            grid: None,
        };
        ctx.grid = grid::RefGrid::new(&ctx);
        let e = settings.lighting.edges;
        if let Some(set) = e.set() {
            let color = DVec3::from(e.line_color().map(f64::from));
            ctx.edges = Some(edges::ScreenEdges::new(
                &ctx,
                set,
                color,
                f64::from(e.width),
            ));
        }
        ctx
    }
}

/// Renders `scene` as the GPU would with settings `s`, at `width` × `height`.
pub fn render(scene: &Scene, s: &FrameSettings, width: u32, height: u32) -> Rgba {
    render_rows(scene, s, None, width, height, false).0
}

/// The environment and sample count of a PBR reference render.
#[derive(Clone)]
pub struct PbrEnv {
    pub env: std::sync::Arc<crate::pbr::env::Environment>,
    pub samples: u32,
}

/// [`render`] for any tier: `env` lights the PBR tier (ignored by the legacy tier).
pub(crate) fn render_env(
    scene: &Scene,
    s: &FrameSettings,
    env: Option<&PbrEnv>,
    width: u32,
    height: u32,
) -> Rgba {
    render_rows(scene, s, env, width, height, false).0
}

/// `render_env`, plus what each pixel saw.
pub fn render_env_with_info(
    scene: &Scene,
    s: &FrameSettings,
    env: Option<&PbrEnv>,
    width: u32,
    height: u32,
) -> (Rgba, Vec<PixelInfo>) {
    render_rows(scene, s, env, width, height, true)
}

/// [`render`], plus what each pixel saw (row-major, row 0 at the top).
pub fn render_with_info(
    scene: &Scene,
    s: &FrameSettings,
    width: u32,
    height: u32,
) -> (Rgba, Vec<PixelInfo>) {
    render_rows(scene, s, None, width, height, true)
}

/// Rows in parallel. Without `with_info` no per-pixel record is kept: at 8192² it would
/// take 2 GB.
fn render_rows(
    scene: &Scene,
    s: &FrameSettings,
    env: Option<&PbrEnv>,
    width: u32,
    height: u32,
    with_info: bool,
) -> (Rgba, Vec<PixelInfo>) {
    let s = &*crate::frame::resolve(s);
    let (w, h) = (width as usize, height as usize);
    let mut data = vec![0u8; w * h * 4];
    let mut info = vec![PixelInfo::default(); if with_info { w * h } else { 0 }];
    if w > 0 && h > 0 {
        let mut ctx = Context::new(scene, s, width, height);
        if let Some(e) = env {
            ctx.env = Some(e.env.clone());
            ctx.pbr_samples = e.samples;
        }
        let mut info_rows: Vec<&mut [PixelInfo]> = info.chunks_mut(w).collect();
        info_rows.resize_with(h, Default::default);
        // Window depths of the opaque surfaces, kept only when there are points to test.
        let points = !scene.wire.points.is_empty();
        let mut depth = vec![1.0f64; if points { w * h } else { 0 }];
        let mut depth_rows: Vec<&mut [f64]> = depth.chunks_mut(w).collect();
        depth_rows.resize_with(h, Default::default);
        data.par_chunks_mut(w * 4)
            .zip(info_rows)
            .zip(depth_rows)
            .enumerate()
            .for_each(|(y, ((row, row_info), row_depth))| {
                let mut scratch = Scratch::default();
                for x in 0..w {
                    let (c, i, z) = trace(&ctx, x as u32, y as u32, &mut scratch);
                    let px = &mut row[4 * x..4 * x + 4];
                    px[..3].copy_from_slice(&to_unorm8(c));
                    px[3] = 255;
                    if let Some(slot) = row_info.get_mut(x) {
                        *slot = i;
                    }
                    if let Some(slot) = row_depth.get_mut(x) {
                        *slot = z;
                    }
                }
            });
        if points {
            points::draw(&ctx, &mut data, &mut depth);
        }
    }
    let image = Rgba {
        width,
        height,
        data,
    };
    (image, info)
}

/// Per-thread buffers reused across pixels.
#[derive(Default)]
struct Scratch {
    layers: Vec<Hit>,
    visibility: Vec<f64>,
}

/// The pixel's colour, what it saw, and the window depth of its opaque surface (1: none).
fn trace(ctx: &Context, x: u32, y: u32, sc: &mut Scratch) -> (DVec3, PixelInfo, f64) {
    let (o, d) = ctx.view.ray(x, y, ctx.size.0, ctx.size.1);
    let mut info = PixelInfo::default();
    let record = |hit: &Hit, shadowed: u32, info: &mut PixelInfo| {
        let p = o + hit.t * d;
        info.mesh = Some(hit.tri.mesh as usize);
        info.distance = (p - ctx.view.eye).length();
        info.shadowed = std::array::from_fn(|i| shadowed & (1 << i) != 0);
    };
    // The material model's cut-outs and culled back faces are not drawn: the ray goes on.
    let opaque = ctx
        .opaque
        .closest_where(o, d, 0.0, 1.0, |h| material::drawn(ctx, h, d));
    let mut color = background(ctx, d);
    if let Some(hit) = &opaque {
        let s = surface::shade_hit(ctx, hit, d, &mut sc.visibility);
        if ctx.settings.lighting.edges.surface_shown() {
            color = s.color;
        }
        record(hit, s.shadowed, &mut info);
    }
    // GL's depth test is LESS against the opaque depth: layers strictly in front count.
    let t_end = opaque.map_or(1.0, |h| h.t);
    sc.layers.clear();
    ctx.translucent.all(o, d, 0.0, t_end, &mut sc.layers);
    sc.layers
        .retain(|l| l.t < t_end && material::drawn(ctx, l, d));
    sc.layers.sort_by(|a, b| b.t.total_cmp(&a.t));
    // A ray through an edge shared by two triangles of one mesh hits both (see bvh's
    // EDGE_SLACK); the rasterizer's fill rule draws such a point once.
    sc.layers
        .dedup_by(|a, b| a.tri.mesh == b.tri.mesh && (a.t - b.t).abs() <= 1e-12 * b.t.abs());
    let tr = &ctx.settings.lighting.translucency;
    let nearest = tr.mode != crate::frame::TranslucencyMode::Sorted
        && ctx.scene.materials.iter().any(|m| m.is_translucent());
    if nearest {
        // The nearest layer only, over the opaque surface or the background; masked, over
        // black where no opaque surface is: the background is drawn afterwards where nothing
        // was (render/translucent.rs).
        let masked = tr.mode == crate::frame::TranslucencyMode::NearestMasked;
        if masked && opaque.is_none() && !sc.layers.is_empty() {
            color = DVec3::ZERO;
        }
        let keep = sc.layers.len().saturating_sub(1);
        sc.layers.drain(..keep);
    }
    for hit in &sc.layers {
        let mesh = &ctx.scene.meshes[hit.tri.mesh as usize];
        let m = &ctx.scene.materials[mesh.material];
        let mut alpha = f64::from(tr.opacity.unwrap_or(m.draw_opacity()));
        if m.alpha_mode == crate::scene::model::material::AlphaMode::Blend {
            // BLEND: the base colour texture's and the vertex colour's alphas multiply the
            // opacity.
            alpha *= material::base_alpha(m, &material::Corners::new(ctx, hit)).1;
        }
        let s = surface::shade_hit(ctx, hit, d, &mut sc.visibility);
        color = match tr.blend {
            crate::frame::BlendFormula::Alpha => s.color * alpha + color * (1.0 - alpha),
            crate::frame::BlendFormula::Add => s.color * alpha + color,
        };
        record(hit, s.shadowed, &mut info);
        info.layers += 1;
    }
    // The grid after the surfaces, where the opaque one does not hide it (render/grid.rs).
    if let Some(g) = &ctx.grid {
        if let Some(c) = g.cover(ctx, x, y, opaque.map(|h| h.t)) {
            color = g.blend(color, c);
        }
    }
    // Lines are drawn after every surface (render/edges.rs).
    if let Some(e) = &ctx.edges {
        if e.covers(ctx, x, y) {
            color = e.color;
        }
    }
    debug_assert!(color.is_finite(), "non-finite colour at {x},{y}");
    let depth = opaque.map_or(1.0, |h| {
        let c = ctx.view.forward * (o + h.t * d).extend(1.0);
        c.z / c.w * 0.5 + 0.5
    });
    (color, info, depth)
}

/// What shows where no surface is hit: the environment through the output step (PBR tier
/// with a skybox), else the background colour.
fn background(ctx: &Context, d: DVec3) -> DVec3 {
    let s = ctx.settings;
    match &ctx.env {
        Some(env) if s.shading == crate::frame::Shading::Pbr && s.lighting.pbr.skybox => {
            let c = env.sample(d.normalize()) * f64::from(s.lighting.pbr.ibl_intensity);
            DVec3::from(s.lighting.output.apply(c.to_array()))
        }
        _ => s.background.as_dvec3(),
    }
}

/// GL's conversion to an 8-bit normalised channel: clamp, then round(x · 255).
pub fn to_unorm8(c: DVec3) -> [u8; 3] {
    c.to_array()
        .map(|x| (x.clamp(0.0, 1.0) * 255.0).round() as u8)
}
