//! Pass 1, shadow depth. Each shadow-casting light gets a depth texture rendered from the
//! light, either through a framebuffer object with the texture as depth attachment, or — on
//! drivers without framebuffer objects — by drawing into the target's own depth buffer and
//! copying it with glCopyTexSubImage2D (the map is then at most the target's size, and the
//! lit pass clears and draws the frame afterwards). Maps are reused while the lights, the
//! settings and the geometry are unchanged.
use super::frusta::{self, light_view_proj, ShadowProjection};
use super::{FrameCx, FrameSettings, Outcome, Pass, Target};
use crate::gpu::framebuffer::Framebuffer;
use crate::gpu::state::RenderState;
use crate::gpu::texture::Texture2d;
use crate::gpu::GpuRef;
use crate::light::{Light, LightKind};
use crate::scene::lod::clusters::ClusterView;
use crate::scene::model::material::AlphaMode;
use crate::scene::Bounds;
use crate::shader::cache::ProgramKey;
use crate::Result;
use glam::Mat4;

/// Pass "shadow": one depth map per light, or the reason there is none.
pub(crate) struct ShadowDepth;
/// Pass "show": the teaching view of light 0's depth map.
pub(crate) struct ShowShadowMap;

pub(crate) fn depth_key() -> ProgramKey {
    ProgramKey::new("depth", "depth.vert", "depth.frag")
}

pub(crate) fn show_key() -> ProgramKey {
    ProgramKey::new("showdepth", "show_depth.vert", "show_depth.frag")
}

pub(crate) struct ShadowMap {
    pub(crate) texture: Texture2d,
    fbo: Option<Framebuffer>,
    /// Light view-projections (local coordinates → light clip space): one, or six faces.
    pub(crate) views: Vec<Mat4>,
    pub(crate) projection: ShadowProjection,
    /// Side of one view's square in texels.
    pub(crate) face: u32,
    /// Radius of the bounds the views are fitted to (the model's, or with `--grid` also its
    /// shadow on the floor): a texel spans about 2·radius/face.
    pub(crate) radius: f32,
}

impl ShadowMap {
    /// Eye space → texture space of each view (atlas tile included): what the lit pass needs.
    pub(crate) fn eye_to_texture(&self, view: &Mat4) -> Vec<Mat4> {
        let inv_view = view.inverse();
        self.views
            .iter()
            .enumerate()
            .map(|(f, vp)| {
                let tile = if self.projection == ShadowProjection::Cube {
                    frusta::atlas_tile(f)
                } else {
                    Mat4::IDENTITY
                };
                tile * frusta::bias_matrix() * *vp * inv_view
            })
            .collect()
    }
}

#[derive(Clone, Debug, PartialEq)]
struct ShadowKey {
    lights: Vec<Light>,
    /// `--grid`: the maps also hold the model's shadow on the floor.
    grid: bool,
    size: u32,
    slope_bias: f32,
}

#[derive(Default)]
pub(crate) struct ShadowState {
    pub(crate) maps: Vec<ShadowMap>,
    key: Option<ShadowKey>,
    /// The boxes where casters moved since the maps were drawn (one per moving draw mesh):
    /// the next pass draws only their rectangles again ([`super::shadow_rect`]).
    moved: Vec<Bounds>,
    /// Where each moving draw mesh was last drawn.
    pub(crate) boxes: super::shadow_rect::MovedBoxes,
}

impl ShadowState {
    /// The maps are drawn again, whole, at the next frame.
    pub(crate) fn invalidate(&mut self) {
        self.key = None;
        self.moved.clear();
    }

    /// A caster moved within box `b` (its old and new places): the next frame draws that
    /// part of the maps again; nothing to do when they are to be drawn whole anyway. Past
    /// [`MOVED_BOXES`] boxes, one box holds them all (each box draws every caster again).
    pub(crate) fn moved(&mut self, b: &Bounds) {
        if self.key.is_none() {
            return;
        }
        self.moved.push(*b);
        if self.moved.len() > MOVED_BOXES {
            let all = self.moved.iter().fold(Bounds::empty(), |a, b| a.union(b));
            self.moved = vec![all];
        }
    }
}

/// At most this many boxes of moved casters are drawn apart in one pass.
const MOVED_BOXES: usize = 8;

/// Why there is no shadow pass this frame, if there is none.
fn skip_reason(gpu: &GpuRef, s: &FrameSettings) -> Option<&'static str> {
    let caps = &gpu.caps;
    if !s.shadows.enabled {
        Some("off (--no-shadows)")
    } else if s.lights.is_empty() {
        Some("off (no lights)")
    } else if s.lighting.shadow_casters == 0 {
        Some("off (--shadow-lights 0)")
    } else if !caps.shadow_maps() {
        Some("off (no depth textures or shadow compare: shadows off)")
    } else {
        None
    }
}

fn is_masked(cx: &FrameCx, i: usize) -> bool {
    let m = &cx.scene.meshes[i];
    matches!(
        cx.scene.scene.materials[m.material].alpha_mode,
        AlphaMode::Mask(_)
    )
}

/// The depth program for mesh `i`: MASK materials discard their cut-out texels as the lit
/// passes do, so what is not drawn casts no shadow.
fn mask_key(cx: &FrameCx, i: usize, textured: bool) -> ProgramKey {
    let m = &cx.scene.meshes[i];
    let depth_key = || {
        super::skinning::key(
            depth_key().switch("INSTANCED", "inst", m.instances.is_some()),
            m.skin,
        )
    };
    if !is_masked(cx, i) {
        return depth_key();
    }
    let model = &cx.scene.scene.materials[m.material];
    let key =
        depth_key()
            .switch("HAS_TEXTURE", "tex", textured)
            .switch("HAS_COLOR", "vc", m.has_colors);
    super::slots::flags(key, model, m.has_uv1, textured, m.has_colors)
}

/// The map size actually used: the request, limited by the driver and, on the copy path,
/// by the target's size (the light's view is drawn into the target first).
pub(crate) fn effective_size(gpu: &GpuRef, s: &FrameSettings, target: &Target) -> u32 {
    let caps = &gpu.caps;
    let mut size = s.shadows.size.clamp(16, caps.max_texture_size.max(16));
    if caps.fbo {
        size = size.min(caps.max_viewport.0.min(caps.max_viewport.1).max(16));
    } else {
        size = size.min(target.width).min(target.height);
    }
    size
}

/// Runs the depth pass if needed; afterwards `r.shadow.maps` holds one map per casting light.
fn run(cx: &mut FrameCx) -> Result<Outcome> {
    let (s, target) = (cx.settings, cx.target);
    let no_casters = !cx.scene.meshes.iter().any(|m| m.casts_shadow());
    let reason =
        skip_reason(cx.gpu, s).or(no_casters.then_some("no opaque triangles to cast a shadow"));
    if let Some(reason) = reason {
        cx.stats.shadow = reason.into();
        cx.res.shadow.maps.clear();
        cx.res.shadow.key = None;
        return Ok(Outcome::Skipped(reason.into()));
    }
    let size = effective_size(cx.gpu, s, target);
    // Only the first `shadow_casters` lights cast (the key light of the default kit): the
    // others, the headlight among them, neither get maps nor invalidate them.
    let casters = &s.lights[..s.lights.len().min(usize::from(s.lighting.shadow_casters))];
    let key = ShadowKey {
        lights: casters.to_vec(),
        grid: s.lighting.guides.grid,
        size,
        slope_bias: s.shadows.slope_bias,
    };
    if cx.res.shadow.key.as_ref() == Some(&key) {
        let moved = std::mem::take(&mut cx.res.shadow.moved);
        if moved.is_empty() {
            cx.stats.shadow = format!("reused ({} map(s))", cx.res.shadow.maps.len());
            return Ok(Outcome::Skipped(cx.stats.shadow.clone()));
        }
        return update_moved(cx, &moved);
    }
    let gpu = cx.gpu.clone();
    let maps = allocate_maps(cx, casters, size)?;
    for map in &maps {
        draw_map(cx, map, None)?;
    }
    cx.cull = None;
    gpu.apply(&RenderState::default());
    let entry = log_entry(&maps, size, gpu.caps.fbo);
    cx.stats.shadow = "rendered".into();
    gpu.check_error("shadow pass")?;
    cx.res.shadow.maps = maps;
    cx.res.shadow.key = Some(key);
    cx.res.shadow.moved.clear();
    Ok(Outcome::Ran(entry))
}

/// Draws the maps again inside the rectangles of boxes `moved` only (casters moved there
/// and nowhere else); the rest of each map is as the last pass left it. A map whose
/// rectangles cover half of it or more is drawn whole: llvmpipe clears a whole depth
/// texture on a fast path and a scissored rectangle on a slow one (CesiumMan's 2,048² map,
/// its rectangle all but the whole: +2 ms a frame), and a whole draw gives the same depths.
fn update_moved(cx: &mut FrameCx, moved: &[Bounds]) -> Result<Outcome> {
    let gpu = cx.gpu.clone();
    let maps = std::mem::take(&mut cx.res.shadow.maps);
    let (mut texels, mut whole) = (0u64, 0u64);
    let drawn = maps.iter().try_for_each(|map| {
        let rects: Vec<Vec<[u32; 4]>> = map
            .views
            .iter()
            .map(|vp| super::shadow_rect::rects(vp, moved, map.face))
            .collect();
        let area: u64 = rects
            .iter()
            .flatten()
            .map(|r| u64::from(r[2]) * u64::from(r[3]))
            .sum();
        let all = u64::from(map.texture.width) * u64::from(map.texture.height);
        whole += all;
        if area * 2 >= all {
            texels += all;
            draw_map(cx, map, None)
        } else {
            texels += area;
            draw_map(cx, map, Some(&rects))
        }
    });
    cx.res.shadow.maps = maps;
    drawn?;
    cx.cull = None;
    gpu.apply(&RenderState::default());
    gpu.check_error("shadow pass (moved casters)")?;
    cx.stats.shadow = if texels < whole {
        format!("updated where casters moved ({texels} of {whole} texels)")
    } else {
        "rendered (casters moved over half the maps or more)".into()
    };
    Ok(Outcome::Ran(format!(
        "shadow(moved casters: {texels} of {whole} texels)"
    )))
}

/// Where one light's map lies in its depth texture.
struct Layout {
    /// The light's view-projections: one, or six cube faces.
    views: Vec<Mat4>,
    projection: ShadowProjection,
    /// Side of one view's square in texels.
    face: u32,
    /// The depth texture's size.
    width: u32,
    height: u32,
}

/// Spot and directional lights get one square view of `size`; point lights that do not
/// fit one frustum get six cube faces in a 3×2 atlas.
fn layout(light: &Light, bounds: &Bounds, size: u32) -> Layout {
    match (light_view_proj(light, bounds), light.kind) {
        (Some((vp, projection)), _) => Layout {
            views: vec![vp],
            projection,
            face: size,
            width: size,
            height: size,
        },
        (None, LightKind::Point(p)) => {
            // Six faces at half the size keep the atlas (3×2 faces) near the texel count
            // of one full-size map.
            let face = (size / 2).max(16);
            Layout {
                views: frusta::cube_faces(p, bounds).to_vec(),
                projection: ShadowProjection::Cube,
                face,
                width: face * 3,
                height: face * 2,
            }
        }
        (None, LightKind::Directional(_)) => unreachable!("directional lights always fit"),
    }
}

/// One map per casting light, laid out by [`layout`]. Depth textures (and their FBOs) of
/// the right size are kept from the last pass: allocating a 2048² map costs more than
/// drawing into it on llvmpipe. Textures are all made before any is drawn into.
fn allocate_maps(cx: &mut FrameCx, casters: &[Light], size: u32) -> Result<Vec<ShadowMap>> {
    let gpu = cx.gpu.clone();
    let use_fbo = gpu.caps.fbo;
    let bounds = if cx.settings.lighting.guides.grid {
        crate::grid::shadow_bounds(&cx.scene.scene.bounds, casters)
    } else {
        cx.scene.scene.bounds
    };
    let mut maps = Vec::new();
    let mut old: Vec<Option<ShadowMap>> = std::mem::take(&mut cx.res.shadow.maps)
        .into_iter()
        .map(Some)
        .collect();
    for light in casters {
        let Layout {
            views,
            projection,
            face,
            width: w,
            height: h,
        } = layout(light, &bounds, size);
        let kept = old
            .iter_mut()
            .find(|m| {
                m.as_ref()
                    .is_some_and(|m| (m.texture.width, m.texture.height) == (w, h))
            })
            .and_then(Option::take);
        let (texture, fbo) = match kept {
            Some(m) => (m.texture, m.fbo),
            None => {
                let texture = if gpu.caps.packed_shadow() {
                    Texture2d::packed_depth(&gpu, w, h)?
                } else {
                    Texture2d::depth(&gpu, w, h)?
                };
                let fbo = if use_fbo {
                    Some(Framebuffer::shadow(&gpu, &texture)?)
                } else {
                    None
                };
                (texture, fbo)
            }
        };
        maps.push(ShadowMap {
            texture,
            fbo,
            views,
            projection,
            face,
            radius: bounds.radius(),
        });
    }
    Ok(maps)
}

/// Renders one light's depth into `map`: each view (one, or six atlas tiles) in turn,
/// through the map's FBO or, on the copy path, into the target and copied from there.
/// With `rects` (per view), only those rectangles are cleared and drawn (every caster
/// again in each: where rectangles overlap the last draws the same depths).
fn draw_map(cx: &mut FrameCx, map: &ShadowMap, rects: Option<&[Vec<[u32; 4]>]>) -> Result<()> {
    let gpu = cx.gpu.clone();
    let target = cx.target;
    // The map's framebuffer has no colour buffer (or, packed, its colour is the depth); on
    // the copy path the light's view is drawn into the target, whose colour must not change.
    let state = RenderState {
        polygon_offset: (!shader_offset(&gpu)).then(|| polygon_offset(cx.settings)),
        color_write: map.fbo.is_some(),
        ..Default::default()
    };
    gpu.apply(&state);
    if let Some(fbo) = &map.fbo {
        fbo.bind();
        if rects.is_none() {
            gpu.clear_rgba(clear_colour(&gpu));
        }
    } else {
        gpu.bind_target(target.fbo, target.width, target.height);
    }
    let whole = [0, 0, map.face, map.face];
    for (f, vp) in map.views.iter().enumerate() {
        let tile = if map.views.len() > 1 {
            ((f as u32 % 3) * map.face, (f as u32 / 3) * map.face)
        } else {
            (0, 0)
        };
        // Where the view is drawn: its tile of the map's framebuffer, or the target's
        // corner, copied into its tile afterwards.
        let at = if map.fbo.is_some() { tile } else { (0, 0) };
        gpu.viewport(at.0, at.1, map.face, map.face);
        // A light's view takes its levels by its own texel size.
        cx.cull = Some(ClusterView::new(*vp).with_lod(*vp, map.face, map.face, cx.lod.error));
        let rects = rects.map(|r| &r[f]);
        match rects {
            None => {
                if map.fbo.is_none() {
                    gpu.clear(None);
                }
                draw_casters(cx, vp, &state)?;
            }
            Some(rects) => {
                for r in rects {
                    redraw_rect(cx, vp, &state, [at.0 + r[0], at.1 + r[1], r[2], r[3]])?;
                }
            }
        }
        if map.fbo.is_none() {
            for &r in rects.map_or(&[whole][..], Vec::as_slice) {
                map.texture
                    .copy_from_framebuffer((tile.0 + r[0], tile.1 + r[1]), r);
            }
        }
    }
    Ok(())
}

/// Clears rectangle `r` of the bound map (and its colour, where the map is packed depth) and
/// draws every caster again inside it, with view `vp`.
fn redraw_rect(cx: &mut FrameCx, vp: &Mat4, state: &RenderState, r: [u32; 4]) -> Result<()> {
    let gpu = cx.gpu.clone();
    gpu.clear_rect(r, clear_colour(&gpu));
    gpu.scissor(Some(r));
    let drawn = draw_casters(cx, vp, state);
    gpu.scissor(None);
    drawn
}

/// Draws every shadow-casting mesh with the light's view-projection `vp`. MASK materials
/// draw with the cut-out program (their base texture bound); everything else with the plain
/// one, which is bound again only when the program changes; packed depth's programs are
/// given the polygon offset they add themselves ([`shader_offset`]).
fn draw_casters(cx: &mut FrameCx, vp: &Mat4, state: &RenderState) -> Result<()> {
    let (factor, units) = if shader_offset(cx.gpu) {
        polygon_offset(cx.settings)
    } else {
        (0.0, 0.0)
    };
    let mut current: Option<ProgramKey> = None;
    for i in 0..cx.scene.meshes.len() {
        if !cx.scene.meshes[i].casts_shadow() {
            continue;
        }
        let texture = if is_masked(cx, i) {
            let (material, has_uv) = (cx.scene.meshes[i].material, cx.scene.meshes[i].has_uv);
            super::view::base_texture(cx, material, has_uv)?
        } else {
            None
        };
        let key = mask_key(cx, i, texture.is_some());
        if current.as_ref() != Some(&key) {
            let p = cx.program(&key)?;
            p.bind();
            p.set_mat4("uLightMvp", vp);
            p.set_vec2("uPolygonOffset", glam::Vec2::new(factor, units));
            p.set_i32("uDiffuseMap", super::units::BASE_UNIT as i32);
            current = Some(key);
        }
        let dm = &cx.scene.meshes[i];
        if dm.skin.is_some() {
            let p = cx.program(current.as_ref().expect("set above"))?;
            super::skinning::set_joints(&p, &cx.scene.skins, dm.skin);
        }
        if is_masked(cx, i) {
            let p = cx.program(current.as_ref().expect("set above"))?;
            let model = &cx.scene.scene.materials[dm.material];
            super::slots::set_uniforms(&p, model, dm.has_uv1);
            if let Some(t) = texture {
                cx.res.textures.texture(t).bind(super::units::BASE_UNIT);
            }
        }
        super::cull::draw(cx, i, state)?;
    }
    Ok(())
}

/// The maps' polygon offset (slope factor, units): the slope-scaled bias of the settings.
fn polygon_offset(s: &FrameSettings) -> (f32, f32) {
    (s.shadows.slope_bias, s.shadows.slope_bias)
}

/// What a map's colour is cleared to: packed depth's "nothing drawn here", white, which
/// unpacks to just over 1; None where the map has no colour to clear.
fn clear_colour(gpu: &GpuRef) -> Option<[f32; 4]> {
    gpu.caps.packed_shadow().then_some([1.0; 4])
}

/// Whether depth.frag adds the polygon offset itself (and writes the depth it tests):
/// packed depth where the shader can write depth. Whether gl_FragCoord.z includes the
/// rasteriser's offset differs between drivers (llvmpipe's does); without EXT_frag_depth the
/// rasteriser's is all there is.
fn shader_offset(gpu: &GpuRef) -> bool {
    gpu.caps.packed_shadow() && gpu.caps.frag_depth
}

/// The pass entry of `--stats`: how many maps, their projections, size and path.
fn log_entry(maps: &[ShadowMap], size: u32, use_fbo: bool) -> String {
    let kinds: Vec<&str> = maps.iter().map(|m| m.projection.name()).collect();
    format!(
        "shadow({} map(s) [{}], {size}², {})",
        maps.len(),
        kinds.join(","),
        if use_fbo { "fbo" } else { "copy" }
    )
}

impl Pass for ShadowDepth {
    fn name(&self) -> &'static str {
        "shadow"
    }

    fn run(&self, cx: &mut FrameCx) -> Result<Outcome> {
        run(cx)
    }
}

impl Pass for ShowShadowMap {
    fn name(&self) -> &'static str {
        "show"
    }

    /// Light 0's depth map as grey over the frame.
    fn run(&self, cx: &mut FrameCx) -> Result<Outcome> {
        if !cx.settings.show_shadow_map {
            return Ok(Outcome::Skipped("no teaching view asked for".into()));
        }
        if cx.res.shadow.maps.is_empty() {
            return Err(crate::Error::Usage(format!(
                "--show shadow-map: there is no shadow map this frame (shadow pass {})",
                cx.stats.shadow
            )));
        }
        let program = cx.program(&show_key())?;
        cx.quad()?;
        let map = &cx.res.shadow.maps[0];
        map.texture.set_compare(false);
        map.texture.bind(0);
        program.bind();
        program.set_i32("uDepth", 0);
        // A perspective view-projection P·V with rigid V has row 3 = −V.row 2 and
        // row 2 = A·V.row 2 + (0, 0, 0, B): A, B and so near and far come out of the matrix.
        let m = map.views[0];
        let (r2, r3) = (m.row(2), m.row(3));
        let perspective = map.projection != ShadowProjection::Ortho;
        let a = -r2.truncate().dot(r3.truncate());
        let b = r2.w + a * r3.w;
        program.set_f32("uPerspective", if perspective { 1.0 } else { 0.0 });
        program.set_vec2("uAB", glam::Vec2::new(a, b));
        program.set_vec2("uNearFar", glam::Vec2::new(b / (a - 1.0), b / (a + 1.0)));
        cx.bind_target();
        cx.gpu.apply(&RenderState::overlay());
        if let Some(q) = &cx.res.quad {
            q.draw();
        }
        cx.res.shadow.maps[0].texture.set_compare(true);
        cx.stats.draw_calls += 1;
        Ok(Outcome::Ran("show(shadow-map)".into()))
    }
}
