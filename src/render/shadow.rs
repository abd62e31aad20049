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
use crate::light::Light;
use crate::scene::Vertex;
use crate::shader::cache::{ProgramKey, ProgramKind};
use crate::Result;
use glam::Mat4;

pub(crate) struct ShadowMap {
    pub texture: Texture2d,
    fbo: Option<Framebuffer>,
    /// Light view-projection (local coordinates → light clip space).
    pub view_proj: Mat4,
    pub projection: ShadowProjection,
    /// Index of the light this map belongs to.
    pub light: usize,
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
    let mut notes = Vec::new();
    for (i, light) in s.lights.iter().enumerate() {
        let Some((view_proj, projection)) = light_view_proj(light, &bounds) else {
            notes.push(format!("light {i} inside the scene: no shadow"));
            continue;
        };
        let texture = Texture2d::depth(&r.gpu, size, true)?;
        let fbo = if use_fbo {
            Some(Framebuffer::depth_only(&r.gpu, &texture)?)
        } else {
            None
        };
        maps.push(ShadowMap {
            texture,
            fbo,
            view_proj,
            projection,
            light: i,
        });
    }
    let program = r.programs.get(ProgramKey::simple(ProgramKind::Depth))?;
    stats.program(ProgramKey::simple(ProgramKind::Depth).label());
    let gpu = r.gpu.clone();
    program.bind();
    for map in &maps {
        match &map.fbo {
            Some(fbo) => fbo.bind(),
            None => {
                gpu.bind_target(target.fbo, target.width, target.height);
                gpu.color_writes(false);
            }
        }
        gpu.viewport(size, size);
        gpu.clear(None);
        gpu.depth(true, true);
        gpu.blend(false);
        gpu.cull(Cull::None);
        gpu.polygon_offset(Some((s.shadows.slope_bias, s.shadows.slope_bias)));
        program.set_mat4("uLightMvp", &map.view_proj);
        for m in r.meshes.iter().filter(|m| !m.translucent) {
            m.mesh.draw();
            stats.draw_calls += 1;
            stats.triangles += m.triangles;
        }
        gpu.polygon_offset(None);
        if map.fbo.is_none() {
            map.texture.copy_from_framebuffer();
            gpu.color_writes(true);
        }
    }
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
    stats.shadow = if notes.is_empty() {
        "rendered".into()
    } else {
        format!("rendered; {}", notes.join("; "))
    };
    r.gpu.check_error("shadow pass")?;
    r.shadow = ShadowPass {
        maps,
        key: Some(key),
    };
    Ok(())
}

/// The matrix from eye space to a map's texture space: bias · lightVP · view⁻¹.
pub fn eye_to_shadow(view_proj: &Mat4, view: &Mat4) -> Mat4 {
    frusta::bias_matrix() * *view_proj * view.inverse()
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
