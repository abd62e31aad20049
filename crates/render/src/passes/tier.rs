//! The skeleton both lit tiers (the legacy `lit` pass and `pbr`) share, so each tier says only
//! what differs ([`Tier`]): the view is set up, the target cleared, the visible meshes put in
//! draw order and drawn through the translucency scheme ([`run`]); each mesh gets its
//! program, the program its per-frame uniforms once, then the material's uniforms and
//! textures, and the mesh is drawn with each of its render states ([`draw_meshes`]).
use super::view::View;
use super::FrameCx;
use crate::gpu::program::Program;
use crate::gpu::state::RenderState;
use crate::shader::cache::ProgramKey;
use crate::Result;

/// What the skeleton knows about a mesh to draw.
pub(crate) struct MeshDraw {
    pub(crate) material: usize,
    pub(crate) translucent: bool,
    pub(crate) has_uv: bool,
    pub(crate) has_uv1: bool,
    pub(crate) has_tangents: bool,
    pub(crate) has_colors: bool,
    /// GL_POINTS: round disks of the frame's point size (`POINTS`).
    pub(crate) points: bool,
    /// Points without normals are drawn in their unlit colour.
    pub(crate) unlit_points: bool,
}

/// A mesh's program, before the material's flags ([`super::slots::flags`]) and the frame's
/// ([`FrameCx::lit_flags`]) are added, and the tier's textures for it.
pub(crate) struct Prepared<M> {
    pub(crate) key: ProgramKey,
    /// The base colour texture is drawn (BLEND reads its alpha only then).
    pub(crate) textured: bool,
    pub(crate) maps: M,
}

/// What a lit tier does differently. A value lives for one [`draw_meshes`] call (a fresh
/// clone each), so state kept in it (a texture known to be bound) starts over with each call.
pub(crate) trait Tier: Clone {
    /// The textures `prepare` found for a mesh, for `material` to bind.
    type Maps;
    /// The mesh's program key and textures (uploading them on first use).
    fn prepare(&mut self, cx: &mut FrameCx, v: &View, m: &MeshDraw)
        -> Result<Prepared<Self::Maps>>;
    /// The tier's uniforms a program keeps for the frame, set the first time it draws (after
    /// the view's).
    fn program_uniforms(&self, p: &Program, cx: &FrameCx, v: &View);
    /// The tier's material uniforms and texture bindings for mesh `m`.
    fn material(&mut self, p: &Program, cx: &mut FrameCx, m: &MeshDraw, maps: Self::Maps);
    /// Whether material `material` is drawn after a copy of the opaque frame, which it reads
    /// (KHR_materials_transmission in the PBR tier).
    fn transmissive(&self, _cx: &FrameCx, _material: usize) -> bool {
        false
    }
    /// The opaque frame's copy is made, with `levels` mip levels to blur across.
    fn frame_copied(&mut self, _levels: f32) {}
}

/// A lit pass after its own checks and set-up: view, clear, draw order, then the meshes
/// through the translucency scheme ([`super::translucent::draw_frame`]).
pub(crate) fn run<T: Tier>(cx: &mut FrameCx, tier: T) -> Result<()> {
    let v = View::new(cx);
    cx.bind_target();
    super::translucent::clear(cx);
    let (order, first) = v.draw_order(cx);
    // Opaque meshes that see through themselves (transmission) are drawn after a copy of
    // everything opaque behind them, then the translucent ones as always.
    let (thin, rest): (Vec<usize>, Vec<usize>) = order[..first]
        .iter()
        .partition(|&&i| tier.transmissive(cx, cx.scene.meshes[i].material));
    if thin.is_empty() || !super::pbr_khr::frame_allows(cx) {
        return super::translucent::draw_frame(cx, &order, first, &mut |cx, meshes, states| {
            draw_meshes(cx, &v, tier.clone(), meshes, states)
        });
    }
    let opaque = rest.len();
    super::translucent::draw_frame(cx, &rest, opaque, &mut |cx, meshes, states| {
        draw_meshes(cx, &v, tier.clone(), meshes, states)
    })?;
    let levels = super::pbr_khr::copy_frame(cx)?;
    let mut seeing = tier.clone();
    seeing.frame_copied(levels);
    draw_meshes(cx, &v, seeing, &thin, &|_| {
        vec![crate::gpu::state::RenderState::default()]
    })?;
    cx.stats.pass_log.push(format!(
        "transmission: {} mesh(es) over the opaque frame's copy ({levels} mip levels)",
        thin.len()
    ));
    let glass = &order[first..];
    if glass.is_empty() {
        return Ok(());
    }
    super::translucent::draw_frame(cx, glass, 0, &mut |cx, meshes, states| {
        draw_meshes(cx, &v, tier.clone(), meshes, states)
    })
}

/// Draws `meshes` with `tier`'s programs; `states` gives each mesh's draws (one render state
/// per draw call, by whether the mesh is translucent).
pub(crate) fn draw_meshes<T: Tier>(
    cx: &mut FrameCx,
    v: &View,
    mut tier: T,
    meshes: &[usize],
    states: &dyn Fn(bool) -> Vec<RenderState>,
) -> Result<()> {
    let scene = cx.scene;
    let edges = cx.settings.lighting.edges;
    // The surfaces' polygon offset under edges (`edges.rs`), the same for every mesh.
    let offset = (edges.mode != crate::frame::EdgeMode::Off)
        .then(|| super::edges::surface_offset(edges.width));
    // A program keeps its uniforms: the per-frame ones are set once per program per frame,
    // only the material changes from mesh to mesh.
    let mut uniforms_set: Vec<ProgramKey> = Vec::new();
    for &i in meshes {
        let dm = &scene.meshes[i];
        let m = MeshDraw {
            material: dm.material,
            translucent: dm.translucent,
            has_uv: dm.has_uv,
            has_uv1: dm.has_uv1,
            has_tangents: dm.has_tangents,
            has_colors: dm.has_colors,
            points: dm.primitive == crate::gpu::mesh::Primitive::Points,
            unlit_points: !dm.has_normals,
        };
        let mat = &scene.scene.materials[m.material];
        let prepared = tier.prepare(cx, v, &m)?;
        let key = super::slots::flags(
            prepared.key,
            mat,
            m.has_uv1,
            prepared.textured,
            m.has_colors,
        )
        .switch("POINTS", "pts", m.points)
        .switch("INSTANCED", "inst", dm.instances.is_some());
        let key = super::skinning::key(key, dm.skin);
        // (A material that is unlit already has the define.)
        let key = if m.unlit_points && !mat.unlit {
            key.switch("UNLIT", "unlit", true)
        } else {
            key
        };
        let key = cx.lit_flags(key);
        let program = cx.program(&key)?;
        program.bind();
        if !uniforms_set.contains(&key) {
            uniforms_set.push(key);
            v.set_uniforms(&program, cx);
            tier.program_uniforms(&program, cx, v);
            // The polygon offset below, for programs that write a logarithmic depth.
            program.set_f32("uLogDepthOffset", offset.map_or(0.0, |o| o.0));
            if m.points {
                program.set_f32("uPointSize", point_size(cx));
            }
        }
        super::slots::set_uniforms(&program, mat, m.has_uv1);
        super::skinning::set_joints(&program, &scene.skins, dm.skin);
        program.set_f32("uNormalScale", mat.normal_scale);
        program.set_f32("uTerminatorLift", dm.terminator_lift);
        program.set_f32(
            "uOpacity",
            super::translucent::opacity(cx, mat, m.translucent),
        );
        cx.set_rgbm_blend(&program);
        tier.material(&program, cx, &m, prepared.maps);
        let mut mesh_states = states(m.translucent);
        if offset.is_some() {
            for st in &mut mesh_states {
                // Lines on the surface must win the depth test (`edges.rs`); without the
                // surface (`--wireframe-only`) it still hides the lines behind it.
                st.polygon_offset = st.polygon_offset.or(offset);
                if !edges.surface {
                    st.color_write = false;
                    // The background fills every pixel the surface did not colour.
                    st.stencil = None;
                }
            }
        }
        super::translucent::draw_states(cx, i, &program, &mesh_states)?;
    }
    cx.gpu.apply(&RenderState::default());
    Ok(())
}

/// The frame's point diameter in its own pixels: the settings' size is for a picture of their
/// height, and the viewport may be larger (SSAA) or another height (a resized window).
pub(crate) fn point_size(cx: &FrameCx) -> f32 {
    let (px, at) = cx.settings.lighting.point_size;
    let scale = if at == 0 {
        1.0
    } else {
        cx.viewport[3] as f32 / at as f32
    };
    (px * scale).max(1.0)
}
