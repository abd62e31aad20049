//! Pass "background": in the PBR tier, the environment behind the model (a full-screen quad at
//! the far plane reading one specular level: sharp, or blurred with `--env-blur`). Otherwise
//! the lit pass clears to the background colour and this pass does not run.
use super::{FrameCx, Outcome, Pass, Shading};
use crate::gpu::state::{DepthFunc, RenderState};
use crate::shader::cache::ProgramKey;
use crate::Result;
use glam::Mat3;

pub(crate) struct Background;

pub(crate) fn skybox_key(rgbm: bool, tonemap: i32) -> ProgramKey {
    ProgramKey::new("skybox", "skybox.vert", "skybox.frag")
        .switch("IBL_RGBM", "rgbm", rgbm)
        .count("TONEMAP", "tm", tonemap)
}

/// Texture unit the skybox reads its cube from.
const SKY_UNIT: u32 = 0;

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
        let ibl = cx.res.ibl.ensure(cx.gpu)?;
        let rgbm = ibl.rgbm;
        let n = ibl.specular.len();
        let level =
            ((pbr.skybox_blur.clamp(0.0, 1.0) * (n - 1) as f32).round() as usize).min(n - 1);
        ibl.specular[level].bind(SKY_UNIT);
        cx.stats.textures_bound += 1;
        let key = skybox_key(rgbm, s.lighting.output.tonemap.code());
        let program = cx.program(&key)?;
        program.bind();
        let view = s.camera.view();
        let proj = s.camera.projection(&cx.scene.scene.bounds, cx.aspect());
        program.set_mat4("uInvProjection", &proj.inverse());
        program.set_mat3("uEnvFromEye", &Mat3::from_mat4(view).transpose());
        program.set_i32("uSky", SKY_UNIT as i32);
        program.set_f32("uIblIntensity", pbr.ibl_intensity);
        program.set_f32("uExposure", 2f32.powf(s.lighting.output.exposure_ev));
        cx.bind_target();
        cx.clear(Some(s.background.to_array()));
        cx.quad()?;
        // At the far plane (z = 1): LEQUAL against the cleared depth of 1 passes, and the
        // model drawn afterwards with LESS covers it.
        cx.gpu.apply(&RenderState {
            depth: Some(DepthFunc::LessEqual),
            depth_write: false,
            ..Default::default()
        });
        if let Some(q) = &cx.res.quad {
            q.draw();
        }
        cx.stats.draw_calls += 1;
        cx.gpu.apply(&RenderState::default());
        cx.res.background_drawn = true;
        Ok(Outcome::Ran(format!("background(env level {level})")))
    }
}
