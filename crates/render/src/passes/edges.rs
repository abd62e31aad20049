//! Pass "edges": lines over the model (`--edges`: boundary and creased edges; `--wireframe`:
//! every triangle edge), GL_LINES of an index buffer over each mesh's welded corners, made
//! from the scene (`scene::edges`) on the first frame that asks and kept until the set
//! changes. The lit tiers draw the surface with a polygon offset while lines are on
//! (`tier.rs`), so a line lying on the surface passes the LEQUAL depth test and a line behind
//! it does not; no geometry shader, so every context draws it, GL 2.1 included. 1-pixel lines
//! are GL lines; core profiles guarantee no other glLineWidth, so wider ones
//! (`--line-width`) are a screen-space quad per segment, widened in `edges.vert`.
//! `--edge-method barycentric` (measured against lines: docs/design.md) draws the triangles
//! again instead, each corner unshared with its barycentric coordinate and the triangle's
//! mask of edges in the set, at the surface's depth and offset.
use super::{FrameCx, Outcome, Pass};
use crate::gpu::mesh::{GpuMesh, Primitive, Streams};
use crate::gpu::state::{DepthFunc, RenderState};
use crate::scene::geometry::edges::{self, EdgeSet};
use crate::shader::cache::ProgramKey;
use crate::Result;

pub(crate) struct Edges;

/// The line meshes of one edge set, one per scene mesh that has lines.
#[derive(Default)]
pub(crate) struct EdgeState {
    /// The set and the geometry the meshes hold.
    made: Option<(EdgeSet, Geometry)>,
    meshes: Vec<GpuMesh>,
    segments: u64,
}

/// What the edge meshes are made of.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Geometry {
    Lines,
    Quads,
    Barycentric,
}

pub(crate) fn key() -> ProgramKey {
    ProgramKey::new("edges", "edges.vert", "edges.frag")
}

/// The polygon offset the lit tiers draw the surface with while lines `width` pixels wide
/// are on: (1, 1) covers a 1-pixel line's half-pixel distance from the pixel centres it
/// lights; a wide line's edge lies width/2 pixels from the segment, so its depth slope
/// factor grows with it.
pub(crate) fn surface_offset(width: f32) -> (f32, f32) {
    ((0.5 * width + 0.5).max(1.0), 1.0)
}

impl EdgeState {
    fn ensure(&mut self, cx: &FrameCx, set: EdgeSet, geometry: Geometry) -> Result<()> {
        if self.made == Some((set, geometry)) {
            return Ok(());
        }
        self.meshes.clear();
        self.segments = 0;
        // Meshes skinned on the GPU hold the static pose: their lines are made from a CPU
        // pose of the moment drawn.
        let posed = cx.scene.cpu_posed_skins()?;
        for (i, m) in (&cx.scene.scene.meshes).into_iter().enumerate() {
            let m = posed.iter().find(|p| p.0 == i).map_or(m, |p| &p.1);
            // The barycentric soup counts its edges itself: no second weld through extract.
            let (vertices, indices, primitive, segments) = if geometry == Geometry::Barycentric {
                let (v, i, n) = soup(m, set);
                (v, i, Primitive::Triangles, n)
            } else {
                let lines = edges::extract(m, set);
                let n = lines.segments.len();
                if geometry == Geometry::Quads {
                    let (v, i) = quads(&lines);
                    (v, i, Primitive::Triangles, n)
                } else {
                    let v = lines
                        .positions
                        .iter()
                        .map(|&position| crate::scene::Vertex {
                            position,
                            ..Default::default()
                        })
                        .collect();
                    let i = lines.segments.iter().flatten().copied().collect();
                    (v, i, Primitive::Lines, n)
                }
            };
            if segments == 0 {
                continue;
            }
            self.segments += segments as u64;
            self.meshes.push(GpuMesh::with_streams(
                cx.gpu,
                &vertices,
                &indices,
                Streams::default(),
                primitive,
            )?);
        }
        self.made = Some((set, geometry));
        Ok(())
    }
}

/// Four corners and two triangles per segment: each corner holds its end (position), the
/// other end (normal) and its side (uv.x, ±1, flipped at the far end so both ends' +1
/// corners lie on the same side).
fn quads(lines: &edges::EdgeLines) -> (Vec<crate::scene::Vertex>, Vec<u32>) {
    let mut v = Vec::with_capacity(lines.segments.len() * 4);
    let mut i = Vec::with_capacity(lines.segments.len() * 6);
    for s in &lines.segments {
        let [a, b] = s.map(|c| lines.positions[c as usize]);
        let base = v.len() as u32;
        for (p, q, side) in [(a, b, 1.0), (a, b, -1.0), (b, a, -1.0), (b, a, 1.0)] {
            v.push(crate::scene::Vertex {
                position: p,
                normal: q,
                uv: [side, 0.0],
            });
        }
        i.extend([base, base + 1, base + 3, base, base + 3, base + 2]);
    }
    (v, i)
}

/// The triangles with unshared corners: corner k's normal is the k-th unit vector (its
/// barycentric coordinate), every corner's uv.x the triangle's edge mask; and how many edges
/// of `set` the masks hold.
fn soup(m: &crate::scene::Mesh, set: EdgeSet) -> (Vec<crate::scene::Vertex>, Vec<u32>, usize) {
    let (masks, n) = edges::triangle_masks(m, set);
    let mut v = Vec::with_capacity(m.indices.len());
    for (t, mask) in m.indices.chunks_exact(3).zip(masks) {
        for (k, &i) in t.iter().enumerate() {
            let mut bary = [0.0; 3];
            bary[k] = 1.0;
            v.push(crate::scene::Vertex {
                // (Loaders check indices; a bad one draws at the origin, never panics.)
                position: m.vertices.get(i as usize).map_or([0.0; 3], |v| v.position),
                normal: bary,
                uv: [f32::from(mask), 0.0],
            });
        }
    }
    let i = (0..v.len() as u32).collect();
    (v, i, n)
}

impl Pass for Edges {
    fn name(&self) -> &'static str {
        "edges"
    }

    fn run(&self, cx: &mut FrameCx) -> Result<Outcome> {
        let e = cx.settings.lighting.edges;
        let Some(set) = e.set() else {
            return Ok(Outcome::Skipped("no --edges or --wireframe".into()));
        };
        if cx.settings.show_shadow_map || cx.settings.lighting.attribute_view.code() != 0 {
            return Ok(Outcome::Skipped(
                "a teaching view replaces the scene".into(),
            ));
        }
        let mut state = std::mem::take(&mut cx.res.edges);
        let drawn = draw(cx, &mut state, set, e);
        cx.res.edges = state;
        drawn
    }
}

fn draw(
    cx: &mut FrameCx,
    state: &mut EdgeState,
    set: EdgeSet,
    e: crate::frame::Edges,
) -> Result<Outcome> {
    let bary = e.method == crate::frame::EdgeMethod::Barycentric;
    let wide = e.width > 1.0 && !bary;
    let geometry = match (bary, wide) {
        (true, _) => Geometry::Barycentric,
        (false, true) => Geometry::Quads,
        (false, false) => Geometry::Lines,
    };
    state.ensure(cx, set, geometry)?;
    let log_depth = cx.settings.lighting.translucency.log_depth;
    let program = cx.program(
        &key()
            .switch("LOG_DEPTH", "logz", log_depth)
            .switch("WIDE", "wide", wide)
            .switch("BARYCENTRIC", "bary", bary),
    )?;
    program.bind();
    program.set_f32("uWidth", e.width);
    if wide {
        let [_, _, w, h] = cx.viewport;
        program.set_vec2("uViewport", glam::Vec2::new(w as f32, h as f32));
    }
    let s = cx.settings;
    program.set_mat4("uModelView", &s.camera.view());
    program.set_mat4(
        "uProjection",
        &s.camera.projection(&cx.scene.scene.bounds, cx.aspect()),
    );
    if log_depth {
        let (_, far) = s.camera.near_far(&cx.scene.scene.bounds);
        program.set_f32("uLogDepthC", crate::frame::LOG_DEPTH_C);
        program.set_f32("uLogDepthFar", far);
    }
    let [r, g, b] = e.line_color();
    let color = if cx.rgbm {
        super::post::rgbm_encode([r, g, b])
    } else {
        [r, g, b, 1.0]
    };
    program.set_vec4("uColor", glam::Vec4::from(color));
    cx.bind_target();
    cx.gpu.apply(&RenderState {
        depth: Some(DepthFunc::LessEqual),
        depth_write: false,
        // The triangles again at the surface's depth: the same offset.
        polygon_offset: bary.then(|| surface_offset(e.width)),
        ..Default::default()
    });
    for m in &state.meshes {
        m.draw();
        cx.stats.draw_calls += 1;
    }
    cx.gpu.apply(&RenderState::default());
    let what = match set {
        EdgeSet::Feature { crease_deg } => format!("feature, crease {crease_deg}°"),
        EdgeSet::All => "wireframe".into(),
    };
    let width = match geometry {
        Geometry::Quads => format!(", {} px quads", e.width),
        Geometry::Barycentric => format!(", {} px barycentric", e.width),
        Geometry::Lines => String::new(),
    };
    Ok(Outcome::Ran(format!(
        "edges({what}, {} lines{width})",
        state.segments
    )))
}
