//! Pass "grid" (`--grid`, key Z): the ground grid of [`crate::grid::GridPlane`], one
//! blended square drawn after the lit tiers (either) and before the edges, with the lit
//! passes' view, lights and shadow maps (`view::View`), so it receives the model's shadow
//! through the same `shadow.glsl` lookups. The model lies above the plane, so from above the
//! model hides the grid and from below the grid is in front: the depth test settles both.
//! The shadow pass fits its maps to the model and its shadow on the plane while the grid is
//! on (`shadow.rs`). Known limit: glass in front of the grid (the nearest-layer scheme writes
//! its depth) hides the grid behind it.
use super::units::BEHIND_UNIT;
use super::view::{shadow_flags, View};
use super::{FrameCx, Outcome, Pass, Shading};
use crate::gpu::mesh::GpuMesh;
use crate::gpu::state::{Blend, DepthFunc, RenderState};
use crate::grid::GridPlane;
use crate::scene::Vertex;
use crate::shader::cache::ProgramKey;
use crate::Result;
use glam::{Mat4, Vec3};

pub(crate) struct Grid;

pub(crate) fn key() -> ProgramKey {
    ProgramKey::new("grid", "grid.vert", "grid.frag")
}

/// The grid's square, kept while the plane is the same.
#[derive(Default)]
pub(crate) struct GridState {
    made: Option<([Vec3; 4], GpuMesh)>,
}

impl GridState {
    fn mesh(&mut self, cx: &FrameCx, corners: [Vec3; 4]) -> Result<&GpuMesh> {
        if self.made.as_ref().map(|(c, _)| *c) != Some(corners) {
            let v = corners.map(|p| Vertex {
                position: p.to_array(),
                normal: [0.0, 1.0, 0.0],
                uv: [0.0; 2],
            });
            self.made = Some((corners, GpuMesh::new(cx.gpu, &v, &[0, 1, 2, 0, 2, 3])?));
        }
        Ok(&self.made.as_ref().expect("made above").1)
    }
}

impl Pass for Grid {
    fn name(&self) -> &'static str {
        "grid"
    }

    fn run(&self, cx: &mut FrameCx) -> Result<Outcome> {
        let s = cx.settings;
        if !s.lighting.guides.grid {
            return Ok(Outcome::Skipped("no --grid".into()));
        }
        if s.show_shadow_map || s.lighting.attribute_view.code() != 0 {
            return Ok(Outcome::Skipped(
                "a teaching view replaces the scene".into(),
            ));
        }
        if cx.rgbm && cx.gpu.caps.max_texture_units <= BEHIND_UNIT {
            return Ok(Outcome::Skipped(
                "no texture unit is left for the copy the RGBM frame blends over".into(),
            ));
        }
        let plane = GridPlane::for_scene(&cx.scene.scene, s.lighting.guides.up);
        let mut state = std::mem::take(&mut cx.res.grid);
        let drawn = draw(cx, &mut state, &plane);
        cx.res.grid = state;
        drawn?;
        Ok(Outcome::Ran(format!("grid({})", plane.label())))
    }
}

fn draw(cx: &mut FrameCx, state: &mut GridState, plane: &GridPlane) -> Result<()> {
    let s = cx.settings;
    let v = View::new(cx);
    // PBR's shadow term switched off (key 6) leaves the floor unshadowed as it does the model.
    let shadows = if s.shading == Shading::Pbr && !s.lighting.pbr_terms.shadows {
        0
    } else {
        v.shadows
    };
    // Log depth, the offscreen frame's linear output and the RGBM frame, as the lit passes.
    let key = cx.lit_flags(shadow_flags(
        key(),
        v.lights,
        shadows,
        s.shadows.pcf,
        v.cube_mask,
    ));
    let program = cx.program(&key)?;
    program.bind();
    v.set_uniforms(&program, cx);
    let origin = plane.origin().as_vec3();
    program.set_mat4("uModelView", &(v.view * Mat4::from_translation(origin)));
    let bounds = &cx.scene.scene.bounds;
    let (near, far) = s.camera.near_far(bounds);
    let corners = plane.corners();
    let eye = s.camera.eye();
    let reach = corners
        .iter()
        .map(|c| (*c + origin - eye).length())
        .fold(far, f32::max)
        * 1.01;
    let grid_proj = s.camera.projection_between(cx.aspect(), near, reach);
    program.set_mat4("uGridProjection", &grid_proj);
    let ortho = if s.camera.ortho_height.is_some() {
        1.0
    } else {
        0.0
    };
    program.set_vec3("uDepthRange", Vec3::new(near, far, ortho));
    program.set_f32("uUnit", plane.unit as f32);
    let o = plane.origin();
    program.set_vec2(
        "uCentre",
        (plane.centre - glam::DVec2::new(o.x, o.z)).as_vec2(),
    );
    program.set_f32("uFade", plane.fade as f32);
    program.set_f32("uWidth", s.lighting.guides.scale);
    program.set_f32("uLineAlpha", crate::grid::LINE_ALPHA as f32);
    // The offscreen PBR frame is linear; the composite encodes it again.
    let decode = cx.linear && s.shading == Shading::Pbr;
    let frame_value = |c: glam::DVec3| -> Vec3 {
        if decode {
            c.to_array()
                .map(crate::pbr::srgb_decode)
                .map(|x| x as f32)
                .into()
        } else {
            c.as_vec3()
        }
    };
    let line = glam::Vec3::from(crate::grid::line_color(s.background)).as_dvec3();
    program.set_vec3("uLineColor", frame_value(line));
    program.set_vec3("uAxisColorX", frame_value(plane.axis_colors[0]));
    program.set_vec3("uAxisColorZ", frame_value(plane.axis_colors[1]));
    program.set_f32("uAxisAlpha", crate::grid::AXIS_ALPHA as f32);
    let axis_at = plane.file_origin - glam::DVec2::new(o.x, o.z);
    program.set_vec2("uAxisAt", axis_at.as_vec2());
    program.set_f32("uTerminatorLift", 0.0);
    let ambient = s
        .lighting
        .ambient
        .dot(glam::DVec3::from(crate::grid::LUMINANCE));
    program.set_f32("uAmbient", ambient as f32);
    let up_eye = v.view.transform_vector3(Vec3::Y);
    // The side the camera is on: from below, the floor's shadowed side is out of sight.
    let above = eye.y >= plane.height as f32;
    program.set_vec3("uNormal", if above { up_eye } else { -up_eye });
    program.set_f32("uLitSide", if above { 1.0 } else { 0.0 });
    cx.bind_target();
    if cx.rgbm {
        // The fixed function cannot blend RGBM: the shader blends over a copy of the frame.
        let [x, y, w, h] = cx.viewport;
        let unit = BEHIND_UNIT;
        cx.res
            .post
            .behind(cx.gpu, w, h)?
            .copy_region_from_framebuffer(unit, x, y);
        cx.rgbm_blend = 1.0;
        cx.set_rgbm_blend(&program);
    }
    cx.gpu.apply(&RenderState {
        depth: Some(DepthFunc::LessEqual),
        depth_write: false,
        blend: if cx.rgbm { Blend::Off } else { Blend::Alpha },
        ..Default::default()
    });
    state.mesh(cx, corners)?.draw();
    cx.rgbm_blend = 0.0;
    cx.stats.draw_calls += 1;
    cx.gpu.apply(&RenderState::default());
    Ok(())
}
