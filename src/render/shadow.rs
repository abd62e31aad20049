//! Pass 1, shadow depth. Each shadow-casting light gets a depth texture rendered from the
//! light, either through a framebuffer object with the texture as depth attachment, or — on
//! drivers without framebuffer objects — by drawing into the target's own depth buffer and
//! copying it with glCopyTexSubImage2D (the map is then at most the target's size, and the
//! lit pass clears and draws the frame afterwards). Maps are reused while the lights, the
//! settings and the geometry are unchanged.
use super::frusta::{self, light_view_proj, ShadowProjection};
use super::{FrameSettings, FrameStats, Renderer, Target};
use crate::gpu::framebuffer::Framebuffer;
use crate::gpu::mesh::GpuMesh;
use crate::gpu::state::Cull;
use crate::gpu::texture::Texture2d;
use crate::light::{Light, LightKind};
use crate::scene::Vertex;
use crate::shader::cache::{ProgramKey, ProgramKind};
use crate::Result;
use glam::Mat4;

pub(crate) struct ShadowMap {
    pub texture: Texture2d,
    fbo: Option<Framebuffer>,
    /// Light view-projections (local coordinates → light clip space): one, or six faces.
    pub views: Vec<Mat4>,
    pub projection: ShadowProjection,
    /// Side of one view's square in texels.
    pub face: u32,
}

impl ShadowMap {
    /// Eye space → texture space of each view (atlas tile included): what the lit pass needs.
    pub fn eye_to_texture(&self, view: &Mat4) -> Vec<Mat4> {
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
    size: u32,
    slope_bias: f32,
}

#[derive(Default)]
pub(crate) struct ShadowPass {
    pub maps: Vec<ShadowMap>,
    key: Option<ShadowKey>,
}

impl ShadowPass {
    pub fn invalidate(&mut self) {
        self.key = None;
    }
}

/// Why there is no shadow pass this frame, if there is none.
fn skip_reason(r: &Renderer, s: &FrameSettings) -> Option<&'static str> {
    let caps = &r.gpu.caps;
    if !s.shadows.enabled {
        Some("off (--no-shadows)")
    } else if s.lights.is_empty() {
        Some("off (no lights)")
    } else if !caps.depth_texture || !caps.shadow_compare {
        Some("off (no depth textures or shadow compare: shadows off)")
    } else {
        None
    }
}

/// The map size actually used: the request, limited by the driver and, on the copy path,
/// by the target's size (the light's view is drawn into the target first).
pub fn effective_size(r: &Renderer, s: &FrameSettings, target: &Target) -> u32 {
    let caps = &r.gpu.caps;
    let mut size = s.shadows.size.clamp(16, caps.max_texture_size.max(16));
    if caps.fbo {
        size = size.min(caps.max_viewport.0.min(caps.max_viewport.1).max(16));
    } else {
        size = size.min(target.width).min(target.height);
    }
    size
}

/// Runs the depth pass if needed; afterwards `r.shadow.maps` holds one map per casting light.
pub(crate) fn run(
    r: &mut Renderer,
    s: &FrameSettings,
    target: &Target,
    stats: &mut FrameStats,
) -> Result<()> {
    if let Some(reason) = skip_reason(r, s) {
        stats.shadow = reason.into();
        r.shadow.maps.clear();
        r.shadow.key = None;
        return Ok(());
    }
    let size = effective_size(r, s, target);
    let key = ShadowKey {
        lights: s.lights.clone(),
        size,
        slope_bias: s.shadows.slope_bias,
    };
    if r.shadow.key.as_ref() == Some(&key) {
        stats.shadow = format!("reused ({} map(s))", r.shadow.maps.len());
        return Ok(());
    }
    let use_fbo = r.gpu.caps.fbo;
    let bounds = r.scene.bounds;
    let mut maps = Vec::new();
    // Depth textures (and their FBOs) of the right size are kept from the last pass:
    // allocating a 2048² map costs more than drawing into it on llvmpipe.
    let mut old: Vec<Option<ShadowMap>> = std::mem::take(&mut r.shadow.maps)
        .into_iter()
        .map(Some)
        .collect();
    for light in &s.lights {
        let (views, projection, face, w, h) = match (light_view_proj(light, &bounds), light.kind) {
            (Some((vp, kind)), _) => (vec![vp], kind, size, size, size),
            (None, LightKind::Point(p)) => {
                // Six faces at half the size keep the atlas (3×2 faces) near the texel count
                // of one full-size map.
                let face = (size / 2).max(16);
                (
                    frusta::cube_faces(p, &bounds).to_vec(),
                    ShadowProjection::Cube,
                    face,
                    face * 3,
                    face * 2,
                )
            }
            (None, LightKind::Directional(_)) => unreachable!("directional lights always fit"),
        };
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
                let texture = Texture2d::depth(&r.gpu, w, h)?;
                let fbo = if use_fbo {
                    Some(Framebuffer::depth_only(&r.gpu, &texture)?)
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
        });
    }
    let key_depth = ProgramKey::simple(ProgramKind::Depth);
    let program = r.programs.get(key_depth)?;
    stats.program(key_depth.label());
    let gpu = r.gpu.clone();
    program.bind();
    gpu.depth(true, true);
    gpu.blend(false);
    gpu.cull(Cull::None);
    gpu.polygon_offset(Some((s.shadows.slope_bias, s.shadows.slope_bias)));
    for map in &maps {
        if let Some(fbo) = &map.fbo {
            fbo.bind();
            gpu.clear(None);
        } else {
            gpu.bind_target(target.fbo, target.width, target.height);
            gpu.color_writes(false);
        }
        for (f, vp) in map.views.iter().enumerate() {
            let (tx, ty) = if map.views.len() > 1 {
                ((f as u32 % 3) * map.face, (f as u32 / 3) * map.face)
            } else {
                (0, 0)
            };
            if map.fbo.is_some() {
                gpu.viewport(tx, ty, map.face, map.face);
            } else {
                gpu.viewport(0, 0, map.face, map.face);
                gpu.clear(None);
            }
            program.set_mat4("uLightMvp", vp);
            for m in r.meshes.iter().filter(|m| !m.translucent) {
                m.mesh.draw();
                stats.draw_calls += 1;
                stats.triangles += m.triangles;
            }
            if map.fbo.is_none() {
                map.texture.copy_from_framebuffer(tx, ty, map.face);
            }
        }
    }
    gpu.polygon_offset(None);
    gpu.color_writes(true);
    let kinds: Vec<String> = maps
        .iter()
        .map(|m| format!("{:?}", m.projection).to_lowercase())
        .collect();
    stats.passes.push(format!(
        "shadow({} map(s) [{}], {size}², {})",
        maps.len(),
        kinds.join(","),
        if use_fbo { "fbo" } else { "copy" }
    ));
    stats.shadow = "rendered".into();
    r.gpu.check_error("shadow pass")?;
    r.shadow = ShadowPass {
        maps,
        key: Some(key),
    };
    Ok(())
}

fn quad(r: &Renderer) -> Result<GpuMesh> {
    let v = |x: f32, y: f32| Vertex {
        position: [x, y, 0.0],
        normal: [0.0, 0.0, 1.0],
        uv: [(x + 1.0) * 0.5, (y + 1.0) * 0.5],
    };
    GpuMesh::new(
        &r.gpu,
        &[v(-1., -1.), v(1., -1.), v(1., 1.), v(-1., 1.)],
        &[0, 1, 2, 0, 2, 3],
    )
}

/// 3. Teaching view: light 0's depth map as grey over the whole target.
pub(crate) fn show_map(r: &mut Renderer, target: &Target, stats: &mut FrameStats) -> Result<()> {
    if r.shadow.maps.is_empty() {
        return Err(crate::Error::Usage(format!(
            "--show shadow-map: there is no shadow map this frame (shadow pass {})",
            stats.shadow
        )));
    }
    if r.quad.is_none() {
        r.quad = Some(quad(r)?);
    }
    let key = ProgramKey::simple(ProgramKind::ShowDepth);
    let program = r.programs.get(key)?;
    stats.program(key.label());
    let map = &r.shadow.maps[0];
    map.texture.set_compare(false);
    map.texture.bind(0);
    program.bind();
    program.set_i32("uDepth", 0);
    r.gpu.bind_target(target.fbo, target.width, target.height);
    r.gpu.depth(false, false);
    r.gpu.blend(false);
    if let Some(q) = &r.quad {
        q.draw();
    }
    map.texture.set_compare(true);
    stats.draw_calls += 1;
    stats.passes.push("show(shadow-map)".into());
    Ok(())
}
