//! Pass 2, lit (legacy tier): every mesh with the Phong (or Gouraud) program matching its
//! features; opaque meshes first, then translucent ones back to front with blending (each
//! drawn back faces first, then front faces, so a glass shows its far wall behind its near
//! wall).
use super::frusta::ShadowProjection;
use super::{FrameSettings, FrameStats, Renderer, Shading, Target};
use crate::gpu::program::Program;
use crate::gpu::state::Cull;
use crate::light::LightKind;
use crate::shader::cache::{ProgramKey, ProgramKind};
use crate::Result;
use glam::{Mat3, Mat4, Vec2, Vec3, Vec4};

/// Texture unit of shadow map i is SHADOW_UNIT + i; unit 0 is the diffuse map.
const SHADOW_UNIT: u32 = 1;

pub(crate) fn run(
    r: &mut Renderer,
    s: &FrameSettings,
    target: &Target,
    stats: &mut FrameStats,
) -> Result<()> {
    let aspect = target.width as f32 / target.height.max(1) as f32;
    let view = s.camera.view();
    let proj = s.camera.projection(&r.scene.bounds, aspect);
    let normal_matrix = Mat3::from_mat4(view);
    let gpu = r.gpu.clone();
    gpu.bind_target(target.fbo, target.width, target.height);
    gpu.clear(Some(s.background.to_array()));
    gpu.depth(true, true);
    gpu.cull(Cull::None);
    gpu.blend(false);
    let lights = s.lights.len() as u8;
    // The shader pairs shadow map i with light i; every light has a map when shadows run.
    let maps = &r.shadow.maps;
    let shadows = maps.len() as u8;
    let cube_mask = maps
        .iter()
        .enumerate()
        .filter(|(_, m)| m.projection == ShadowProjection::Cube)
        .fold(0u8, |acc, (i, _)| acc | 1 << i);
    let stride = if cube_mask != 0 { 6 } else { 1 };
    let light_pos: Vec<Vec4> = s
        .lights
        .iter()
        .map(|l| match l.kind {
            LightKind::Point(p) => view.transform_point3(p).extend(1.0),
            LightKind::Directional(d) => view.transform_vector3(-d).normalize().extend(0.0),
        })
        .collect();
    let mut shadow = ShadowUniforms::default();
    for (i, m) in maps.iter().enumerate() {
        m.texture.bind(SHADOW_UNIT + i as u32);
        stats.textures_bound += 1;
        for (f, mat) in m.eye_to_texture(&view).into_iter().enumerate() {
            shadow.matrices.push((i * stride + f, mat));
        }
        shadow.texels.push(Vec2::new(
            1.0 / m.texture.width as f32,
            1.0 / m.texture.height as f32,
        ));
        // A map texel covers about 2r/face of the scene (frusta are fitted to the bounding
        // sphere), so the normal offset is given in texels and converted here.
        shadow
            .normal_offsets
            .push(s.shadows.normal_offset * 2.0 * r.scene.bounds.radius() / m.face as f32);
    }
    shadow.eye_to_world = Mat3::from_mat4(view).transpose();
    // Off-screen meshes cost a program bind and a draw call each for nothing: a bounding
    // sphere test against the six frustum planes is cheaper. (Back faces are lit, not
    // culled: open meshes show both sides.)
    let planes = frustum_planes(&(proj * view));
    let visible: Vec<usize> = (0..r.meshes.len())
        .filter(|&i| {
            let m = &r.meshes[i];
            planes
                .iter()
                .all(|p| p.truncate().dot(m.center) + p.w >= -m.radius * p.truncate().length())
        })
        .collect();
    stats.culled = (r.meshes.len() - visible.len()) as u32;
    let mut order: Vec<usize> = visible
        .iter()
        .copied()
        .filter(|&i| !r.meshes[i].translucent)
        .collect();
    let mut translucent: Vec<(f32, usize)> = visible
        .iter()
        .copied()
        .filter(|&i| r.meshes[i].translucent)
        .map(|i| (view.transform_point3(r.meshes[i].center).z, i))
        .collect();
    // Most negative eye-space z is farthest: draw those first.
    translucent.sort_by(|a, b| a.0.total_cmp(&b.0));
    let first_translucent = order.len();
    order.extend(translucent.iter().map(|&(_, i)| i));

    let mut bound_texture = None;
    let mut frame_uniforms_set: Vec<ProgramKey> = Vec::new();
    for (n, &i) in order.iter().enumerate() {
        let dm = &r.meshes[i];
        let key = ProgramKey {
            kind: ProgramKind::Lit,
            lights,
            shadows,
            pcf: s.shadows.pcf,
            cube_mask,
            textured: dm.texture.is_some(),
            gouraud: s.shading == Shading::Gouraud,
        };
        let program = r.programs.get(key)?;
        program.bind();
        // A program keeps its uniforms: the per-frame ones are set once per program per frame,
        // only the material changes from mesh to mesh.
        if !frame_uniforms_set.contains(&key) {
            frame_uniforms_set.push(key);
            stats.program(key.label());
            set_frame_uniforms(
                &program,
                s,
                &view,
                &proj,
                &normal_matrix,
                &light_pos,
                &shadow,
            );
        }
        let mat = &r.scene.materials[dm.material];
        program.set_vec3("uKa", Vec3::from(mat.ambient));
        program.set_vec3("uKd", Vec3::from(mat.diffuse));
        program.set_vec3("uKs", Vec3::from(mat.specular));
        program.set_vec3("uKe", Vec3::from(mat.emissive));
        program.set_f32("uNs", mat.shininess);
        program.set_f32("uOpacity", mat.opacity);
        if let Some(t) = dm.texture {
            if bound_texture != Some(t) {
                r.textures[t].bind(0);
                bound_texture = Some(t);
                stats.textures_bound += 1;
            }
            program.set_i32("uDiffuseMap", 0);
        }
        if n == first_translucent {
            gpu.blend(true);
            gpu.depth(true, false);
        }
        if dm.translucent {
            for face in [Cull::Front, Cull::Back] {
                gpu.cull(face);
                dm.mesh.draw();
                stats.draw_calls += 1;
                stats.triangles += dm.triangles;
            }
        } else {
            dm.mesh.draw();
            stats.draw_calls += 1;
            stats.triangles += dm.triangles;
        }
    }
    gpu.blend(false);
    gpu.cull(Cull::None);
    gpu.depth(true, true);
    stats.passes.push("lit".into());
    Ok(())
}

/// Shadow lookup parameters, per light; matrices as (uniform array index, matrix).
#[derive(Default)]
struct ShadowUniforms {
    matrices: Vec<(usize, Mat4)>,
    texels: Vec<Vec2>,
    normal_offsets: Vec<f32>,
    eye_to_world: Mat3,
}

fn set_frame_uniforms(
    p: &Program,
    s: &FrameSettings,
    view: &Mat4,
    proj: &Mat4,
    normal_matrix: &Mat3,
    light_pos: &[Vec4],
    shadow: &ShadowUniforms,
) {
    p.set_mat4("uModelView", view);
    p.set_mat4("uProjection", proj);
    p.set_mat3("uNormalMatrix", normal_matrix);
    p.set_vec3("uAmbient", s.lighting.ambient.as_vec3());
    let t = s.lighting.terms;
    let on = |b: bool| if b { 1.0 } else { 0.0 };
    p.set_vec3(
        "uTerms",
        Vec3::new(on(t.ambient), on(t.diffuse), on(t.specular)),
    );
    p.set_f32("uWrap", on(s.lighting.wrap));
    for (i, (pos, l)) in light_pos.iter().zip(&s.lights).enumerate() {
        p.set_vec4(&format!("uLightPos[{i}]"), *pos);
        p.set_vec3(&format!("uLightColor[{i}]"), l.color);
    }
    for (i, m) in &shadow.matrices {
        p.set_mat4(&format!("uShadowMatrix[{i}]"), m);
    }
    for (i, (texel, offset)) in shadow.texels.iter().zip(&shadow.normal_offsets).enumerate() {
        p.set_i32(&format!("uShadowMap{i}"), SHADOW_UNIT as i32 + i as i32);
        p.set_vec2(&format!("uShadowTexel[{i}]"), *texel);
        p.set_f32(&format!("uShadowNormalOffset[{i}]"), *offset);
    }
    p.set_mat3("uEyeToWorld", &shadow.eye_to_world);
    p.set_f32("uShadowBias", s.shadows.bias);
}

/// The six clip planes (a, b, c, d with a·x + b·y + c·z + d >= 0 inside) of a
/// view-projection matrix (Gribb & Hartmann).
fn frustum_planes(m: &Mat4) -> [Vec4; 6] {
    let r = [m.row(0), m.row(1), m.row(2), m.row(3)];
    [
        r[3] + r[0],
        r[3] - r[0],
        r[3] + r[1],
        r[3] - r[1],
        r[3] + r[2],
        r[3] - r[2],
    ]
}
