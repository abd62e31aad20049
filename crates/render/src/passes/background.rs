//! Pass "background": in the PBR tier, the environment behind the model (a full-screen quad at
//! the far plane reading one specular level: sharp, or blurred with `--env-blur`). Otherwise
//! the lit pass clears to the background colour and this pass does not run. With
//! `--translucency nearest-masked` the background is drawn after the model instead, only
//! where the stencil is not 1 (`fill_unmarked`).
use super::units::SKY_UNIT;
use super::{FrameCx, Outcome, Pass, Shading};
use crate::frame::TranslucencyMode;
use crate::gpu::state::{DepthFunc, RenderState, Stencil, StencilFunc};
use crate::shader::cache::ProgramKey;
use crate::Result;
use glam::Mat3;

pub(crate) struct Background;

pub(crate) fn fill_key() -> ProgramKey {
    ProgramKey::new("fill", "show_depth.vert", "fill.frag")
}

pub(crate) fn skybox_key(rgbm: bool, tonemap: i32) -> ProgramKey {
    ProgramKey::new("skybox", "skybox.vert", "skybox.frag")
        .switch("IBL_RGBM", "rgbm", rgbm)
        .count("TONEMAP", "tm", tonemap)
}

/// Whether this frame masks the background by the stencil (`nearest-masked`, with
/// translucent meshes): the background comes last, never behind a translucent surface.
pub(crate) fn masked(cx: &FrameCx) -> bool {
    cx.settings.lighting.translucency.mode == TranslucencyMode::NearestMasked
        && cx.scene.meshes.iter().any(|m| m.translucent)
}

impl Pass for Background {
    fn name(&self) -> &'static str {
        "background"
    }

    fn run(&self, cx: &mut FrameCx) -> Result<Outcome> {
        cx.res.background_drawn = false;
        let s = cx.settings;
        if s.shading != Shading::Pbr {
            return Ok(Outcome::Skipped(
                "legacy tier: the lit pass clears to the background colour".into(),
            ));
        }
        let pbr = &s.lighting.pbr;
        if !pbr.skybox {
            return Ok(Outcome::Skipped("--background colour".into()));
        }
        if s.lighting.post.transparent {
            return Ok(Outcome::Skipped("--transparent".into()));
        }
        if masked(cx) {
            return Ok(Outcome::Skipped(
                "drawn after the translucent surfaces, where the stencil is not 1".into(),
            ));
        }
        // The maps first: computing them on the GPU binds its own framebuffers.
        cx.res.ibl.ensure(cx.gpu, cx.programs)?;
        cx.bind_target();
        cx.clear(Some(s.background.to_array()));
        draw_skybox(
            cx,
            RenderState {
                depth: Some(DepthFunc::LessEqual),
                depth_write: false,
                ..Default::default()
            },
        )
        .map(Outcome::Ran)
    }
}

/// The background where the stencil is not 1 (nothing was drawn there): the environment in
/// the PBR tier with a skybox, else the background colour. Depth is not tested: the stencil
/// alone decides, so the depth range need not hold the background.
pub(crate) fn fill_unmarked(cx: &mut FrameCx) -> Result<()> {
    if cx.settings.lighting.post.transparent {
        return Ok(());
    }
    let state = RenderState {
        depth: None,
        depth_write: false,
        stencil: Some(Stencil {
            func: StencilFunc::NotEqual,
            reference: 1,
            write: false,
        }),
        ..Default::default()
    };
    let s = cx.settings;
    if s.shading == Shading::Pbr && s.lighting.pbr.skybox {
        draw_skybox(cx, state)?;
    } else {
        let program = cx.program(&fill_key())?;
        program.bind();
        let c = s.background.to_array();
        let c = if cx.rgbm {
            super::post::rgbm_encode(c)
        } else {
            [c[0], c[1], c[2], 1.0]
        };
        program.set_vec4("uColor", glam::Vec4::from(c));
        cx.draw_quad(&state)?;
    }
    cx.gpu.apply(&RenderState::default());
    Ok(())
}

/// The environment over the frame with `state`; returns the `passes` entry.
fn draw_skybox(cx: &mut FrameCx, state: RenderState) -> Result<String> {
    let s = cx.settings;
    let pbr = &s.lighting.pbr;
    let ibl = cx.res.ibl.ensure(cx.gpu, cx.programs)?;
    let rgbm = ibl.rgbm;
    let n = ibl.specular.len();
    let level = ((pbr.skybox_blur.clamp(0.0, 1.0) * (n - 1) as f32).round() as usize).min(n - 1);
    ibl.specular[level].bind(SKY_UNIT);
    cx.stats.textures_bound += 1;
    let key = skybox_key(rgbm, s.lighting.output.tonemap.code())
        .switch("LINEAR_OUTPUT", "lin", cx.linear)
        .switch("FRAME_RGBM", "hdr8", cx.rgbm);
    let program = cx.program(&key)?;
    program.bind();
    let view = s.camera.view();
    let proj = s.camera.projection(&cx.scene.scene.bounds, cx.aspect());
    program.set_mat4("uInvProjection", &proj.inverse());
    program.set_mat3("uEnvFromEye", &Mat3::from_mat4(view).transpose());
    program.set_i32("uSky", SKY_UNIT as i32);
    program.set_f32("uIblIntensity", pbr.ibl_intensity);
    // (FRAME_RGBM: its uBehind sampler must not share the cube map's unit 0.)
    cx.set_rgbm_blend(&program);
    program.set_f32("uExposure", 2f32.powf(s.lighting.output.exposure_ev));
    // At the far plane (z = 1): LEQUAL against the cleared depth of 1 passes, and the
    // model drawn afterwards with LESS covers it.
    cx.draw_quad(&state)?;
    cx.gpu.apply(&RenderState::default());
    cx.res.background_drawn = true;
    Ok(format!("background(env level {level})"))
}
